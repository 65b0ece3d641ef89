//! MSL's Translational ElastoGap contact as a force law (`Compliant` uses it when `gap` is set;
//! the component is `Translational.ElastoGap` in components/translational/compliant.rs).

use crate::system::{EnergyRole, ForceLaw, LawCtx};

/// MSL's ElastoGap: a spring-damper that only pushes. In contact (`s_rel < s_rel0`)
/// `f_c = −c·|s_rel − s_rel0|^n`, the damper force is bounded by it (`|f_d| ≤ |f_c|`, so the
/// force is continuous at touch-down and never pulls), `f = f_c + f_d`; out of contact 0.
/// MSL writes it with `noEvent`: no events, as here.
pub(crate) struct GapLaw {
    c: f64,
    d: f64,
    s_rel0: f64,
    n: f64,
}

impl GapLaw {
    pub fn new(c: f64, d: f64, s_rel0: f64, n: f64) -> Self {
        Self { c, d, s_rel0, n }
    }

    /// `(f_c, f_d)` at a relative position and speed.
    fn forces(&self, s_rel: f64, v_rel: f64) -> (f64, f64) {
        let gap = s_rel - self.s_rel0;
        if gap >= 0.0 {
            return (0.0, 0.0);
        }
        let f_c = -self.c * gap.abs().powf(self.n);
        let f_d2 = self.d * v_rel;
        // f_c <= 0: the damper force lies in [f_c, −f_c]
        (f_c, f_d2.clamp(f_c, -f_c))
    }
}

impl ForceLaw for GapLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        let (f_c, f_d) = self.forces(x.phi_rel, x.w_rel);
        f_c + f_d
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Conservative
    }
    /// The work stored by the contact spring: `c·|s_rel − s_rel0|^(n+1)/(n+1)` in contact.
    fn potential(&self, x: &LawCtx) -> f64 {
        let gap = x.phi_rel - self.s_rel0;
        if gap >= 0.0 {
            0.0
        } else {
            self.c * gap.abs().powf(self.n + 1.0) / (self.n + 1.0)
        }
    }
    fn loss_power(&self, x: &LawCtx, _tau: f64) -> f64 {
        self.forces(x.phi_rel, x.w_rel).1 * x.w_rel
    }
}
