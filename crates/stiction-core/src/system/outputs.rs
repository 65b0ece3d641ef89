//! Output variables as small expressions over one evaluated instant, so each component states
//! what it reports under which MSL name, and the result module evaluates them row by row.

use std::sync::Arc;

use super::formula::Formula;
use super::Rel;
pub use crate::switching::element::SwitchVar;

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
    /// A variable of a switching element.
    Switch(usize, SwitchVar),
    Scaled(Box<Out>, f64),
    Signal(usize),
    /// Cut torque of a mechanical port (global port index).
    FlangeTau(usize),
    HeatT(usize),
    /// A worn volume (index among the worn elements) as `offset + scale·volume`.
    Wear(usize, f64, f64),
    HeatDerT(usize),
    HeatDiff(usize, usize),
    HeatLinkFlow(usize, f64),
    /// Net heat flowing into a node from everything else, times a factor.
    HeatNodeInflow(usize, f64),
    /// A capacitor's share of its node's heat inflow.
    HeatCapacitorFlow(usize, f64),
    Energy(EnergyVar),
    Const(f64),
    /// The time of the row.
    Time,
    /// A derived variable (`[variables]`): an expression over other outputs.
    Formula(Arc<Formula<Out>>),
}
