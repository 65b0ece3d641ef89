//! Translational `Spring`, `Damper`, `SpringDamper` and `ElastoGap` — the rotational compliant
//! elements (`components::compliant::Compliant`) under MSL's translational names (`s_rel`,
//! `v_rel`, `f`) — and `Rod`, a massless rigid connection with a length.

use crate::components::compliant::{read_linear, Compliant, TRANSLATIONAL};
use crate::components::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, EnergyRole, ForceLaw, LawCtx, Out};

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
    pub fn new(e: &Compliant, n: f64) -> Self {
        Self {
            c: e.c,
            d: e.d,
            s_rel0: e.phi_rel0,
            n,
        }
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

fn spring(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(read_linear(p, true, false, &TRANSLATIONAL)?))
}

fn damper(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(read_linear(p, false, true, &TRANSLATIONAL)?))
}

fn spring_damper(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(read_linear(p, true, true, &TRANSLATIONAL)?))
}

fn elasto_gap(p: &Params) -> ModelResult<Box<dyn Component>> {
    let mut e = read_linear(p, true, true, &TRANSLATIONAL)?;
    let n = p.real(
        "n [1] Exponent of spring force ( f_c = -c*|s_rel-s_rel0|^n )",
        1.0,
    )?;
    e.gap = Some(p.at_least("n", n, 1.0)?);
    Ok(Box::new(e))
}

/// MSL's Rod: `flange_b.s − flange_a.s = L`, `flange_a.f + flange_b.f = 0` (PartialRigid
/// without mass): the two flanges are one node, L apart.
struct Rod {
    length: f64,
}

impl Component for Rod {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            translational: vec!["flange_a", "flange_b"],
            joins: vec![("flange_a", "flange_b")],
            offsets: vec![
                ("flange_a", -self.length / 2.0),
                ("flange_b", self.length / 2.0),
            ],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.node("flange_a")?;
        let mut center = b.rel(&[("flange_a", 1.0)])?;
        center.offset += self.length / 2.0;
        b.output("s", Out::Angle(center));
        b.flange("flange_a", node, None)?;
        let node_b = b.node("flange_b")?;
        b.flange("flange_b", node_b, None)?;
        // no mass: what one flange takes, the other passes on
        b.flange_group(&["flange_a", "flange_b"], Some(Out::Const(0.0)))
    }
}

fn rod(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Rod {
        length: p.real(
            "L [m] Length of component, from left flange to right flange (= flange_b.s - flange_a.s)",
            0.0,
        )?,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Translational.Spring",
        "Modelica.Mechanics.Translational.Components.Spring",
        "Linear 1D translational spring",
        spring,
    ),
    Entry::new(
        "Translational.Damper",
        "Modelica.Mechanics.Translational.Components.Damper",
        "Linear 1D translational damper",
        damper,
    ),
    Entry::new(
        "Translational.SpringDamper",
        "Modelica.Mechanics.Translational.Components.SpringDamper",
        "Linear 1D translational spring and damper in parallel",
        spring_damper,
    ),
    Entry::new(
        "Translational.ElastoGap",
        "Modelica.Mechanics.Translational.Components.ElastoGap",
        "1D translational spring damper combination with gap",
        elasto_gap,
    ),
    Entry::new(
        "Translational.Rod",
        "Modelica.Mechanics.Translational.Components.Rod",
        "Rod without inertia",
        rod,
    ),
];
