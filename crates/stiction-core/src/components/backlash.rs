//! MSL ElastoBacklash's torque law (spec §5.6): a spring/damper behind a backlash of total
//! width `b`, with soft contact: no pulling torque, and the damper's share never above the
//! spring's (`tau = tau_c + min(tau_c, tau_d)` in forward contact).
//!
//! Every switch of the law is a relation frozen between events: the two contacts
//! (`phi_diff > b/2`, `phi_diff < −b/2`) as in MSL, and — with damping — the two switches
//! inside a contact, which MSL writes with `noEvent`. Stepping over those kinks without an
//! event costs the integrator its order: one damped contact left a drivetrain 1.2 % of a
//! speed's range off at Tolerance 1e-6 and still 0.2 % at 1e-8
//! (`tests/data/damped_backlash.toml`). Located as events, the run converges at the method's
//! order to the same solution.

use crate::system::{EnergyRole, ForceLaw, LawCtx};

/// The relations: the two contacts, then (with damping) the two switches inside a contact.
const FORWARD_CONTACT: usize = 0;
const BACKWARD_CONTACT: usize = 1;
const PUSHING: usize = 2;
const DAMPER_BELOW: usize = 3;

pub struct BacklashLaw {
    c: f64,
    d: f64,
    b_max: f64,
    phi_rel0: f64,
}

/// What a contact carries: nothing (open, or separating faster than the spring pushes: no
/// pulling torque), the spring torque twice (the damper's share capped at the spring's), or
/// spring and damper.
enum Carry {
    Nothing,
    SpringTwice,
    SpringAndDamper,
}

impl BacklashLaw {
    pub fn new(c: f64, d: f64, b: f64, phi_rel0: f64) -> Self {
        Self {
            c,
            d,
            b_max: b / 2.0,
            phi_rel0,
        }
    }

    /// `|b| ≤ 1e-10`: a plain spring/damper (MSL's bEps).
    fn rigid(&self) -> bool {
        self.b_max <= 0.5e-10
    }

    /// Without damping the law has no kinks inside a contact: two relations.
    fn damped(&self) -> bool {
        self.d > 0.0
    }

    /// (tau_c, tau_d, contact): contact is +1 (phi_diff > bMax), −1 (< bMin) or 0.
    fn parts(&self, x: &LawCtx) -> (f64, f64, i8) {
        let phi_diff = x.phi_rel - self.phi_rel0;
        let tau_d = self.d * x.w_rel;
        if self.rigid() {
            return (self.c * phi_diff, tau_d, 0);
        }
        if x.relations[FORWARD_CONTACT] {
            (self.c * (phi_diff - self.b_max), tau_d, 1)
        } else if x.relations[BACKWARD_CONTACT] {
            (self.c * (phi_diff + self.b_max), tau_d, -1)
        } else {
            (0.0, tau_d, 0)
        }
    }

    /// The values of the switches inside a contact, oriented by the contact's direction:
    /// positive while the contact pushes, and while the damper's share is below the spring's.
    fn switch_values(tau_c: f64, tau_d: f64, contact: i8) -> (f64, f64) {
        let s = f64::from(contact);
        (s * (tau_c + tau_d), s * (tau_c - tau_d))
    }

    fn carry(&self, x: &LawCtx) -> (f64, f64, Carry) {
        let (tau_c, tau_d, contact) = self.parts(x);
        if self.rigid() {
            return (tau_c, tau_d, Carry::SpringAndDamper);
        }
        if contact == 0 {
            return (tau_c, tau_d, Carry::Nothing);
        }
        let (pushing, damper_below) = if self.damped() {
            (x.relations[PUSHING], x.relations[DAMPER_BELOW])
        } else {
            let (p, b) = Self::switch_values(tau_c, tau_d, contact);
            (p > 0.0, b > 0.0)
        };
        let carry = match (pushing, damper_below) {
            (false, _) => Carry::Nothing,
            (true, true) => Carry::SpringAndDamper,
            (true, false) => Carry::SpringTwice,
        };
        (tau_c, tau_d, carry)
    }
}

impl ForceLaw for BacklashLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        match self.carry(x) {
            (_, _, Carry::Nothing) => 0.0,
            (tau_c, _, Carry::SpringTwice) => tau_c + tau_c,
            (tau_c, tau_d, Carry::SpringAndDamper) => tau_c + tau_d,
        }
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Conservative
    }
    fn potential(&self, x: &LawCtx) -> f64 {
        let (tau_c, _, _) = self.parts(x);
        0.5 * tau_c * tau_c / self.c
    }
    fn loss_power(&self, x: &LawCtx, _tau: f64) -> f64 {
        match self.carry(x) {
            (_, _, Carry::Nothing) => 0.0,
            (tau_c, _, Carry::SpringTwice) => tau_c * x.w_rel,
            (_, tau_d, Carry::SpringAndDamper) => tau_d * x.w_rel,
        }
    }
    /// Where the contact opens with the spring still compressed (MSL sets the torque to 0), the
    /// spring's energy is lost too: `tau·w − dV/dt` counts it.
    fn dissipation(&self, x: &LawCtx, tau: f64) -> f64 {
        let (tau_c, _, _) = self.parts(x);
        (tau - tau_c) * x.w_rel
    }
    fn relation_count(&self) -> usize {
        match (self.rigid(), self.damped()) {
            (true, _) => 0,
            (false, false) => 2,
            (false, true) => 4,
        }
    }
    fn relation_values(&self, x: &LawCtx, z: &mut [f64]) {
        let phi_diff = x.phi_rel - self.phi_rel0;
        z[FORWARD_CONTACT] = phi_diff - self.b_max;
        z[BACKWARD_CONTACT] = -self.b_max - phi_diff;
        if self.damped() {
            // outside a contact both are 0: the relations keep their values until one starts
            let (tau_c, tau_d, contact) = self.parts(x);
            (z[PUSHING], z[DAMPER_BELOW]) = Self::switch_values(tau_c, tau_d, contact);
        }
    }
    fn relation_label(&self, i: usize) -> &'static str {
        match i {
            FORWARD_CONTACT => "contact at phi_rel - phi_rel0 = b/2",
            BACKWARD_CONTACT => "contact at phi_rel - phi_rel0 = -b/2",
            PUSHING => "the contact stops or starts pushing (the damper would pull)",
            _ => "the damper's share reaches the spring's",
        }
    }
}
