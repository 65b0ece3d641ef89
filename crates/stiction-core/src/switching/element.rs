//! The one abstraction every switching element implements — everything with stick/slip or
//! quadrant logic (Brake, Clutch, BearingFriction, OneWayClutch, LossyGear). The engine holds
//! them in one list and drives them only through this trait: their rows in the linear system,
//! their values before and after the solve, their relations and Boolean rules (MSL's
//! `PartialFriction` for the friction family, the quadrant rules for the LossyGear), their
//! zero-crossing indicators and the labels of those, and the result variables they report.
//! A new switching element is one file implementing this trait plus its constructor.

use super::logic::Discrete;
use super::relation::RelationSet;
use crate::rel::Rel;

/// A result variable of a switching element (its MSL name is the constructor's choice).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SwitchVar {
    Phi,
    W,
    A,
    /// A friction element's `tau`, a LossyGear's `tau_a`.
    Tau,
    Sa,
    LossPower,
    Tau0,
    Tau0Max,
    Fn,
    Mu,
    TauB,
    TauSupport,
    TauLoss,
    TauEta,
    Eta1,
    Eta2,
    Tbf1,
    Tbf2,
    TbfA,
    Mode,
    Locked,
    StartForward,
    StartBackward,
    Free,
    /// OneWayClutch: `stuck = locked ∨ w_rel ≤ 0`, kept as mode Stuck.
    Stuck,
    /// LossyGear: `tau_etaPos`, the driving side.
    TauEtaPos,
}

/// Zero-crossing indicators per element: the engine reserves this many slots for each.
pub const INDICATORS: usize = 3;

/// An indicator that never fires in the current state.
pub const NEVER: f64 = -1.0;

/// The sign that turns a sliding or starting element's relative acceleration into the rate of
/// its speed indicator (±w: the speed falling towards 0, or rising from it).
pub fn slip_rate_sign(pre: Discrete) -> Option<f64> {
    use super::logic::{BACKWARD, FORWARD, STUCK};
    if pre.mode == FORWARD || (pre.mode == STUCK && pre.start_backward) {
        Some(-1.0)
    } else if pre.mode == BACKWARD || (pre.mode == STUCK && pre.start_forward) {
        Some(1.0)
    } else {
        None
    }
}

/// A state reset an element asks for at a state event (MSL's `reinit`): node `node` is put at
/// position `phi` with speed `w`, before the event iteration works out the new mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeReset {
    pub node: usize,
    pub phi: f64,
    pub w: f64,
}

/// The discrete state of a switching element between events.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SwitchState {
    /// `pre()` of mode and start flags.
    pub pre: Discrete,
    /// Its relative motion is held by a row of the linear system.
    pub locked: bool,
    /// It transmits nothing (a friction element with no normal force).
    pub free: bool,
    /// The values of its relations (they change only at events).
    pub rel: RelationSet,
}

/// How an element's part of the linear system depends on its discrete state: whether it is
/// locked, and the slope of a torque-dependent loss (a rolling LossyGear; 0 for the others).
/// The factored matrix of a mode is keyed by these.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeKey {
    pub locked: bool,
    pub slope: f64,
}

/// How a row's multiplier acts on the nodes: along the row itself, the row plus `s·ℓ`, or only
/// along `ℓ` (a stuck LossyGear's loss torque).
#[derive(Debug, Clone, Copy)]
pub enum Column<'a> {
    Same,
    Plus(&'a Rel, f64),
    Only(&'a Rel),
}

/// What the engine knows before the linear solve: node angles and speeds, signals.
pub struct Kinematics<'a> {
    pub phi: &'a [f64],
    pub w: &'a [f64],
    pub signals: &'a [f64],
}

/// `(rel.angle(phi), rel.dot(w))` in one pass over the terms, each the same sum as apart
/// (from the neutral element `sum` starts with, terms in order): an evaluation asks both of
/// every law and element.
#[inline]
pub fn angle_and_speed(rel: &Rel, phi: &[f64], w: &[f64]) -> (f64, f64) {
    // one bounds check per term serves both (the same length)
    let w = &w[..phi.len()];
    let zero: f64 = std::iter::empty::<f64>().sum();
    let (mut angle, mut speed) = (zero, zero);
    for &(i, c) in &rel.terms {
        angle += c * phi[i];
        speed += c * w[i];
    }
    (angle + rel.offset, speed)
}

/// What the linear solve gives an element: the node accelerations and its multipliers.
pub struct Solved<'a> {
    pub a: &'a [f64],
    /// The multiplier of its permanent row, if it has one.
    pub permanent: Option<f64>,
    /// The multiplier of its lock row: None when not locked or when the row depends on others
    /// (it then carries no torque, spec §7.9).
    pub lock: Option<f64>,
    /// The mode's rows hold its relative motion fixed (its speed cannot change).
    pub held: bool,
}

/// How a variable of a switching element is known without the linear solve in one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BeforeSolve {
    /// It reads the solve.
    Never,
    /// This value in every row (a free clutch's torque: 0).
    Constant(f64),
    /// `forces` sets it.
    Forces,
    /// `forces` then `solved` set it, the same whatever the solve gave (`Solved`).
    Solved,
}

/// The values of one switching element at an instant. The first group every element has; the
/// others are filled by the elements that have them (friction: normal force and `mu`; LossyGear:
/// the flange torques, the loss torque and efficiencies).
#[derive(Debug, Clone, Copy, Default)]
pub struct ElementValues {
    pub phi: f64,
    pub w: f64,
    pub a: f64,
    /// The element torque: a friction element's `tau`, a LossyGear's `tau_a`.
    pub tau: f64,
    pub sa: f64,
    pub loss: f64,
    /// `tau·w_rel` that `loss` leaves out (a OneWayClutch while stuck; 0 for the others).
    pub withheld: f64,
    /// The mode's rows hold this element's relative speed fixed.
    pub held: bool,
    /// The static limits `sa` is compared with: friction `tau0`, `tau0_max`; a LossyGear's
    /// `tauLossMin_m`, `tauLossMax_p`.
    pub tau0: f64,
    pub tau0_max: f64,
    pub fn_: f64,
    pub mu: f64,
    pub tau_b: f64,
    pub tau_support: f64,
    pub tau_loss: f64,
    pub tau_eta: f64,
    pub losses: Losses,
    /// The torque-dependent loss slope at this speed (compared with the factored `ModeKey`).
    pub slope: f64,
}

/// Efficiencies and bearing friction at one speed (a LossyGear's).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Losses {
    pub eta1: f64,
    pub eta2: f64,
    pub tbf1: f64,
    pub tbf2: f64,
    pub tbf_a: f64,
}

/// A switching element as the engine drives it.
pub trait SwitchingElement: Send + Sync {
    fn name(&self) -> &str;
    /// `pre()` of its discrete state at initialization; by default MSL's initial `pre()`
    /// (mode unknown, no start flags), neither locked nor free, every relation false.
    fn initial_state(&self) -> SwitchState {
        SwitchState {
            pre: Discrete::INITIAL,
            locked: false,
            free: false,
            rel: RelationSet::default(),
        }
    }
    /// The mode the initialization log reports as the one before the start.
    fn log_start_mode(&self) -> i8 {
        self.initial_state().pre.mode
    }
    /// The heat node its loss power goes to (none by default).
    fn heat_node(&self) -> Option<usize> {
        None
    }
    /// Refuses a start its own logic forbids (a one-way clutch turning backward, a mass
    /// outside its stops): the reason, given its relative position and speed at the start.
    fn check_start(&self, _phi: f64, _w: f64) -> Result<(), String> {
        Ok(())
    }
    /// Whether its characteristic can turn negative during a run (a friction table whose
    /// linear extrapolation past its last row reaches 0): the run then checks
    /// `negative_characteristic` at the end of every step. False by default.
    fn may_turn_negative(&self) -> bool {
        false
    }
    /// At these values, why the element's characteristic is negative where its physics
    /// forbids it (a friction coefficient extrapolated below 0 at the slip reached): the
    /// message, naming the element, the slip speed and the table; None while it is not.
    fn negative_characteristic(&self, _st: &SwitchState, _v: &ElementValues) -> Option<String> {
        None
    }

    /// At a state event, the reset of a node's position and speed it asks for (a hard stop
    /// reached); None by default. `phi`, `w`: the node positions and speeds at the event.
    fn reset(&self, _phi: &[f64], _w: &[f64]) -> Option<NodeReset> {
        None
    }

    // ---- its rows in the linear system
    /// The relative motion it locks (and whose speed it watches). `forces` sets its values'
    /// `phi` to `motion().angle(phi)`, which the result table reads for that relative angle.
    fn motion(&self) -> &Rel;
    /// A row it keeps in every mode (a LossyGear's kinematic row), with its column.
    fn permanent_row(&self, _key: ModeKey) -> Option<(&Rel, Column<'_>)> {
        None
    }
    /// How its lock row's multiplier acts on the nodes.
    fn lock_column(&self) -> Column<'_> {
        Column::Same
    }
    /// Lock rows of a lower rank are kept first when locks depend on each other.
    fn lock_rank(&self) -> u8 {
        0
    }
    fn mode_key(&self, st: &SwitchState) -> ModeKey {
        ModeKey {
            locked: st.locked,
            slope: 0.0,
        }
    }
    /// Where a change of the loss slope acts (`ℓ`); None for an element without one.
    fn slope_column(&self) -> Option<&Rel> {
        None
    }

    // ---- its values
    /// Before the solve: the values that need no accelerations, and its generalized forces
    /// (added to `f`).
    fn forces(&self, st: &SwitchState, k: &Kinematics, v: &mut ElementValues, f: &mut [f64]);
    /// After the solve.
    fn solved(&self, st: &SwitchState, s: &Solved, v: &mut ElementValues);

    /// Whether continuous variable `var` is known without the linear solve in state `st`, so
    /// that a result computes it without the row's mode solve. `Never` (unknown) by default.
    fn before_solve(&self, _st: &SwitchState, _var: SwitchVar) -> BeforeSolve {
        BeforeSolve::Never
    }
    /// The signal slots `forces` reads; None (by default): unknown, any of them.
    fn signal_slots(&self) -> Option<Vec<usize>> {
        None
    }

    // ---- its Boolean rules
    /// Whether it transmits nothing at these signals (`free`).
    fn is_free(&self, _signals: &[f64]) -> bool {
        false
    }
    /// Its relations at `v`, from their previous values (from none at initialization); by
    /// default one, `w > 0`.
    fn relations(&self, previous: RelationSet, v: &ElementValues, initial: bool) -> RelationSet {
        previous.update(&[v.w], initial)
    }
    /// The relations that are start conditions on `sa` (all false: a stuck element locks);
    /// none by default.
    fn start_relations(&self) -> &'static [usize] {
        &[]
    }
    /// Relations a union of two candidate sets takes from the first only (a LossyGear's
    /// driving side).
    fn own_relations(&self) -> &'static [usize] {
        &[]
    }
    /// (F1), (F2): `startForward`, `startBackward`.
    fn start_flags(&self, pre: Discrete, r: RelationSet, initial: bool) -> (bool, bool);
    /// (F3).
    fn locked(&self, free: bool, pre: Discrete, sf: bool, sb: bool) -> bool;
    /// (F5).
    fn mode(&self, free: bool, pre: Discrete, sf: bool, sb: bool, r: RelationSet) -> i8;

    // ---- its zero crossings
    /// Its `INDICATORS` indicators: each goes from ≤ 0 to above 0 where something changes.
    fn indicators(&self, st: &SwitchState, v: &ElementValues, signals: &[f64], z: &mut [f64]);
    /// Its indicator 1 from the relative speed `w` alone, when in state `st` that indicator is a
    /// signed relative speed (a sliding element's slip reaching zero) and so needs no solve:
    /// crossings of it are located without evaluating the whole system at every probe. The
    /// same value `indicators` gives at that `w`; None when it depends on more.
    fn slip_indicator(&self, _st: &SwitchState, _w: f64) -> Option<f64> {
        None
    }
    /// The rate of its indicator 1 when that is a signed relative speed (see `crossings`).
    fn speed_rate(&self, st: &SwitchState, v: &ElementValues) -> Option<f64>;
    /// What indicator `slot` means in this state, for the event log.
    fn indicator_label(&self, st: &SwitchState, slot: usize) -> &'static str;

    // ---- its result variables
    /// The value of a result variable. Only a mode or flag may differ from
    /// `common_variable`: the result table reads continuous ones through `value_field`.
    fn variable(&self, st: &SwitchState, v: &ElementValues, var: SwitchVar) -> f64 {
        common_variable(st, v, var)
    }
}

/// The variables every element reports the same way; NaN for one it does not have.
pub fn common_variable(st: &SwitchState, v: &ElementValues, var: SwitchVar) -> f64 {
    use SwitchVar as V;
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    match var {
        V::Phi => v.phi,
        V::W => v.w,
        V::A => v.a,
        V::Tau => v.tau,
        V::Sa => v.sa,
        V::LossPower => v.loss,
        V::Tau0 => v.tau0,
        V::Tau0Max => v.tau0_max,
        V::Fn => v.fn_,
        V::Mu => v.mu,
        V::TauB => v.tau_b,
        V::TauSupport => v.tau_support,
        V::TauLoss => v.tau_loss,
        V::TauEta => v.tau_eta,
        V::Eta1 => v.losses.eta1,
        V::Eta2 => v.losses.eta2,
        V::Tbf1 => v.losses.tbf1,
        V::Tbf2 => v.losses.tbf2,
        V::TbfA => v.losses.tbf_a,
        V::Mode => st.pre.mode as f64,
        V::Locked => flag(st.locked),
        V::StartForward => flag(st.pre.start_forward),
        V::StartBackward => flag(st.pre.start_backward),
        V::Free => flag(st.free),
        V::Stuck => flag(st.pre.mode == super::logic::STUCK),
        V::TauEtaPos => f64::NAN,
    }
}

/// A continuous variable as the field of the values it is (what `common_variable` returns for
/// it), None for a discrete one. Every element's continuous variables are the common ones (an
/// element overrides `variable` only for a mode or flag), so the result table reads them
/// through this without a virtual call per cell.
#[cfg(test)]
pub fn value_field(var: SwitchVar) -> Option<fn(&ElementValues) -> f64> {
    use SwitchVar as V;
    let field: fn(&ElementValues) -> f64 = match var {
        V::Phi => |v| v.phi,
        V::W => |v| v.w,
        V::A => |v| v.a,
        V::Tau => |v| v.tau,
        V::Sa => |v| v.sa,
        V::LossPower => |v| v.loss,
        V::Tau0 => |v| v.tau0,
        V::Tau0Max => |v| v.tau0_max,
        V::Fn => |v| v.fn_,
        V::Mu => |v| v.mu,
        V::TauB => |v| v.tau_b,
        V::TauSupport => |v| v.tau_support,
        V::TauLoss => |v| v.tau_loss,
        V::TauEta => |v| v.tau_eta,
        V::Eta1 => |v| v.losses.eta1,
        V::Eta2 => |v| v.losses.eta2,
        V::Tbf1 => |v| v.losses.tbf1,
        V::Tbf2 => |v| v.losses.tbf2,
        V::TbfA => |v| v.losses.tbf_a,
        _ => return None,
    };
    Some(field)
}

/// The discrete variables: a function of the state alone (no evaluation needed).
pub fn is_discrete(var: SwitchVar) -> bool {
    use SwitchVar as V;
    matches!(
        var,
        V::Mode
            | V::Locked
            | V::StartForward
            | V::StartBackward
            | V::Free
            | V::Stuck
            | V::TauEtaPos
    )
}
