//! `IdealGear` (spec §5.7): `phi_a = ratio·phi_b` relative to the support, a permanent constraint.

use super::{Component, Constructor, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out, Rel};

struct IdealGear {
    ratio: f64,
    use_support: bool,
}

impl Component for IdealGear {
    fn ports(&self) -> Ports {
        let mut mech = vec!["flange_a", "flange_b"];
        if self.use_support {
            mech.push("support");
        }
        Ports {
            mech,
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb, ns) = (b.node("flange_a")?, b.node("flange_b")?, b.node("support")?);
        let r = self.ratio;
        // (phi_a − phi_s) − ratio·(phi_b − phi_s) = 0; multiplier λ: flange_a.tau = λ,
        // flange_b.tau = −ratio·λ, support.tau = −(1 − ratio)·λ.
        let row = Rel::of(&[(na, 1.0), (nb, -r), (ns, r - 1.0)]);
        let k = b.add_constraint(row, false)?;
        b.init_angle(
            Rel::of(&[(na, 1.0), (nb, -r), (ns, r - 1.0)]),
            fixed_zero(),
            "phi_a",
        );
        b.init_speed(
            Rel::of(&[(na, 1.0), (nb, -r), (ns, r - 1.0)]),
            fixed_zero(),
            "w_a",
        );
        b.output("phi_a", Out::Angle(Rel::of(&[(na, 1.0), (ns, -1.0)])));
        b.output("phi_b", Out::Angle(Rel::of(&[(nb, 1.0), (ns, -1.0)])));
        b.flange("flange_a", na, Some(Out::ConstraintTau(k, 1.0)))?;
        b.flange("flange_b", nb, Some(Out::ConstraintTau(k, -r)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::ConstraintTau(k, r - 1.0)))?;
        }
        Ok(())
    }
}

/// The constraint itself holds at the start: a fixed initial equation `row = 0`.
fn fixed_zero() -> crate::model::InitValue {
    crate::model::InitValue {
        start: 0.0,
        fixed: true,
    }
}

fn ideal_gear(p: &Params) -> ModelResult<Box<dyn Component>> {
    let ratio = p.real("ratio", 1.0)?;
    if ratio == 0.0 {
        return Err(p.error("ratio", "must not be 0"));
    }
    Ok(Box::new(IdealGear {
        ratio,
        use_support: p.boolean("useSupport", false)?,
    }))
}

pub const REGISTRY: &[(&str, Constructor)] = &[("IdealGear", ideal_gear)];
