//! MSL ElastoBacklash2's torque law: a spring/damper behind a backlash of total width `b`,
//! with hard contact. Unlike ElastoBacklash (`backlash.rs`) the damper acts in full from the
//! first instant of contact, so the torque jumps by `d·w_rel` there, and it is set to 0 while
//! the contact would pull (`tau_c + tau_d ≤ 0` forward). MSL writes every switch without
//! `noEvent`: each is a relation frozen between events (state events at contact, at release,
//! and where the contact stops or starts pushing).
//!
//! MSL replaces the characteristic by a monotone one during initialization; that only changes
//! the torque reported at the initial instant when an angle is not fixed, which stiction's
//! initialization (it fixes or guesses states, not torques) does not need.

use crate::system::{EnergyRole, ForceLaw, LawCtx};

const FORWARD_CONTACT: usize = 0;
const BACKWARD_CONTACT: usize = 1;
/// Only with damping: without it the spring torque has the contact's sign throughout.
const PUSHING: usize = 2;

/// MSL's bEps: a backlash this small is none (a plain spring/damper).
const B_EPS: f64 = 1e-10;

pub struct HardBacklashLaw {
    c: f64,
    d: f64,
    b_max: f64,
    phi_rel0: f64,
    rigid: bool,
}

impl HardBacklashLaw {
    pub fn new(c: f64, d: f64, b: f64, phi_rel0: f64) -> Self {
        Self {
            c,
            d,
            b_max: b / 2.0,
            phi_rel0,
            rigid: b.abs() <= B_EPS,
        }
    }

    fn damped(&self) -> bool {
        self.d > 0.0
    }

    /// (tau_c, tau_d, contact): contact is +1 (phi_diff > bMax), −1 (< bMin) or 0; the damper
    /// torque counts only in contact (MSL's tau_d is d·w_rel throughout, but unused outside).
    fn parts(&self, x: &LawCtx) -> (f64, f64, i8) {
        let phi_diff = x.phi_rel - self.phi_rel0;
        let tau_d = self.d * x.w_rel;
        if self.rigid {
            (self.c * phi_diff, tau_d, 0)
        } else if x.relations[FORWARD_CONTACT] {
            (self.c * (phi_diff - self.b_max), tau_d, 1)
        } else if x.relations[BACKWARD_CONTACT] {
            (self.c * (phi_diff + self.b_max), tau_d, -1)
        } else {
            (0.0, 0.0, 0)
        }
    }

    /// Whether the element carries `tau_c + tau_d` (else its torque is 0).
    fn carries(&self, x: &LawCtx, tau_c: f64, tau_d: f64, contact: i8) -> bool {
        if self.rigid {
            return true;
        }
        if contact == 0 {
            return false;
        }
        if self.damped() {
            x.relations[PUSHING]
        } else {
            f64::from(contact) * (tau_c + tau_d) > 0.0
        }
    }
}

impl ForceLaw for HardBacklashLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        let (tau_c, tau_d, contact) = self.parts(x);
        if self.carries(x, tau_c, tau_d, contact) {
            tau_c + tau_d
        } else {
            0.0
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
        let (tau_c, tau_d, contact) = self.parts(x);
        if self.carries(x, tau_c, tau_d, contact) {
            tau_d * x.w_rel
        } else {
            0.0
        }
    }
    /// A contact released with the spring still compressed (torque set to 0) loses the
    /// spring's energy too: `tau·w − dV/dt` counts it.
    fn dissipation(&self, x: &LawCtx, tau: f64) -> f64 {
        let (tau_c, _, _) = self.parts(x);
        (tau - tau_c) * x.w_rel
    }
    fn linear(&self) -> Option<(f64, f64)> {
        self.rigid.then_some((self.c, self.d))
    }
    fn relation_count(&self) -> usize {
        match (self.rigid, self.damped()) {
            (true, _) => 0,
            (false, false) => 2,
            (false, true) => 3,
        }
    }
    fn relation_values(&self, x: &LawCtx, z: &mut [f64]) {
        let phi_diff = x.phi_rel - self.phi_rel0;
        z[FORWARD_CONTACT] = phi_diff - self.b_max;
        z[BACKWARD_CONTACT] = -self.b_max - phi_diff;
        if self.damped() {
            // the pushing torque of the contact on the angle's side, oriented by its
            // direction; the spring's stretch clipped at 0 so that in the gap the value
            // changes sign only with the speed, and equals the damper's push at contact
            let (s, stretch) = if phi_diff >= 0.0 {
                (1.0, (phi_diff - self.b_max).max(0.0))
            } else {
                (-1.0, (phi_diff + self.b_max).min(0.0))
            };
            z[PUSHING] = s * (self.c * stretch + self.d * x.w_rel);
        }
    }
    fn relation_label(&self, i: usize) -> &'static str {
        match i {
            FORWARD_CONTACT => "contact at phi_rel - phi_rel0 = b/2",
            BACKWARD_CONTACT => "contact at phi_rel - phi_rel0 = -b/2",
            _ => "the contact stops or starts pushing (tau_c + tau_d changes sign)",
        }
    }
}
