//! Output variables as small expressions over one evaluated instant, so each component states
//! what it reports under which MSL name, and the result module evaluates them row by row.

use super::Rel;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionVar {
    Tau,
    Mu,
    Fn,
    Sa,
    Tau0,
    Tau0Max,
    LossPower,
    Mode,
    Locked,
    StartForward,
    StartBackward,
    Free,
    /// OneWayClutch: `stuck = locked ∨ w_rel ≤ 0`, kept as mode Stuck.
    Stuck,
    W,
    A,
    Phi,
}

/// Variables of a LossyGear.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GearVar {
    TauA,
    TauB,
    TauSupport,
    W,
    A,
    Sa,
    TauLoss,
    TauEta,
    Eta1,
    Eta2,
    Tbf1,
    Tbf2,
    TbfA,
    LossMaxP,
    LossMinM,
    LossPower,
    Mode,
    Locked,
    StartForward,
    StartBackward,
    TauEtaPos,
    Ideal,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnergyVar {
    Kinetic,
    Potential,
    Dissipated,
    Work,
}

#[derive(Debug, Clone)]
pub enum Out {
    Angle(Rel),
    Speed(Rel),
    Accel(Rel),
    /// Torque of a force law, times a factor (sign conventions of the ports).
    LawTau(usize, f64),
    LawLoss(usize),
    ConstraintTau(usize, f64),
    Friction(usize, FrictionVar),
    Gear(usize, GearVar),
    Scaled(Box<Out>, f64),
    Signal(usize),
    /// Cut torque of a mechanical port (global port index).
    FlangeTau(usize),
    HeatT(usize),
    HeatDerT(usize),
    HeatDiff(usize, usize),
    HeatLinkFlow(usize, f64),
    /// Net heat flowing into a node from everything else, times a factor.
    HeatNodeInflow(usize, f64),
    /// A capacitor's share of its node's heat inflow.
    HeatCapacitorFlow(usize, f64),
    Energy(EnergyVar),
    Const(f64),
}
