//! Force laws: elements whose torque is a function of time, their relative angle and speed, and
//! their signal inputs (springs, dampers, torque sources). Relations a law compares (e.g. `|w| ≥ w0`
//! of SignTorque) are frozen between events as Modelica requires, and monitored as zero crossings.

/// What a law sees when it is evaluated.
pub struct LawCtx<'a> {
    pub t: f64,
    /// First time event not handled yet (see `signals::reached`).
    pub horizon: f64,
    pub phi_rel: f64,
    pub w_rel: f64,
    /// All signal values; a law keeps the slots of its own inputs.
    pub signals: &'a [f64],
    /// This law's frozen relations (`relation_count()` of them).
    pub relations: &'a [bool],
}

/// How a law exchanges energy with the drivetrain (for the energy audit).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnergyRole {
    /// Stores energy: contributes `potential()`.
    Conservative,
    /// Dissipates `loss_power()`.
    Dissipative,
    /// Does external work on the drivetrain.
    Source,
}

/// The most relations one force law has (an ElastoBacklash: two contacts, two switches).
pub const MAX_LAW_RELATIONS: usize = 4;

pub trait ForceLaw: Send + Sync {
    /// The element torque: the law exerts `−tau·row` on the nodes (for a two-flange element,
    /// `tau = flange_b.tau`; a torque source returns minus its accelerating torque).
    fn tau(&self, c: &LawCtx) -> f64;
    fn role(&self) -> EnergyRole;
    fn potential(&self, _c: &LawCtx) -> f64 {
        0.0
    }
    /// MSL's `lossPower`: reported, and sent to the heat port.
    fn loss_power(&self, _c: &LawCtx, _tau: f64) -> f64 {
        0.0
    }
    /// The power the element takes out of the drivetrain for good (`tau·w_rel − dV/dt`), for the
    /// energy audit. Equal to `loss_power` except where MSL's lossPower leaves some out.
    fn dissipation(&self, c: &LawCtx, tau: f64) -> f64 {
        self.loss_power(c, tau)
    }
    /// `(c, d)` when the torque is `c·phi_rel + d·w_rel + g(t)` (a spring, a damper): the
    /// stiffness and damping that determine the speed of a shaft without inertia.
    fn linear(&self) -> Option<(f64, f64)> {
        None
    }
    /// At most `MAX_LAW_RELATIONS` (the event scans keep them on the stack).
    fn relation_count(&self) -> usize {
        0
    }
    /// Relation i is true iff `z_i > 0` (or `≥ 0`; the boundary is measure zero).
    fn relation_values(&self, _c: &LawCtx, _z: &mut [f64]) {}
    fn relation_label(&self, _i: usize) -> &'static str {
        "relation"
    }
}
