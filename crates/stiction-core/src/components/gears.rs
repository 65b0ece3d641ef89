//! `IdealGear` (spec §5.7) and `IdealPlanetary` (§5.8): kinematic gears, permanent constraints
//! whose multipliers are the gear torques.

use super::decl::USE_SUPPORT;
use super::{with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out, Rel};

// The two-flange components (IdealGear, LossyGear, Brake) declare their ports alike in
// shape; each adds its own (signal, heat), so there is no one shape to share.
struct IdealGear {
    ratio: f64,
    use_support: bool,
}

impl Component for IdealGear {
    fn ports(&self) -> Ports {
        Ports {
            mech: with_support(&["flange_a", "flange_b"], self.use_support),
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
        b.init_constraint(Rel::of(&[(na, 1.0), (nb, -r), (ns, r - 1.0)]));
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

/// The transmission ratio of a gear (IdealGear, LossyGear): not zero.
pub fn gear_ratio(p: &Params) -> ModelResult<f64> {
    let ratio = p.real(
        "ratio [1] Transmission ratio flange_a.phi/flange_b.phi",
        1.0,
    )?;
    p.nonzero("ratio", ratio)
}

fn ideal_gear(p: &Params) -> ModelResult<Box<dyn Component>> {
    let ratio = gear_ratio(p)?;
    Ok(Box::new(IdealGear {
        ratio,
        use_support: p.boolean(USE_SUPPORT, false)?,
    }))
}

/// `(1 + ratio)·carrier = sun + ratio·ring`; no inertia, no support.
struct IdealPlanetary {
    ratio: f64,
}

impl Component for IdealPlanetary {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["sun", "carrier", "ring"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (sun, carrier, ring) = (b.node("sun")?, b.node("carrier")?, b.node("ring")?);
        let r = self.ratio;
        // Multiplier λ: sun.tau = −λ, ring.tau = −ratio·λ, carrier.tau = (1 + ratio)·λ, so
        // ring.tau = ratio·sun.tau and carrier.tau = −(1 + ratio)·sun.tau.
        let row = || Rel::of(&[(sun, -1.0), (ring, -r), (carrier, 1.0 + r)]);
        let k = b.add_constraint(row(), false)?;
        b.init_constraint(row());
        b.flange("sun", sun, Some(Out::ConstraintTau(k, -1.0)))?;
        b.flange("carrier", carrier, Some(Out::ConstraintTau(k, 1.0 + r)))?;
        b.flange("ring", ring, Some(Out::ConstraintTau(k, -r)))?;
        Ok(())
    }
}

fn ideal_planetary(p: &Params) -> ModelResult<Box<dyn Component>> {
    let ratio = p.positive(
        "ratio",
        p.real(
            "ratio [1] Number of ring teeth / number of sun teeth",
            100.0 / 50.0,
        )?,
    )?;
    Ok(Box::new(IdealPlanetary { ratio }))
}

// Registries are alike in shape in every family: one line per type.
pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "IdealGear",
        "Modelica.Mechanics.Rotational.Components.IdealGear",
        "Ideal gear without inertia",
        ideal_gear,
    ),
    Entry::new(
        "IdealPlanetary",
        "Modelica.Mechanics.Rotational.Components.IdealPlanetary",
        "Planetary gear (sun, carrier, ring) without inertia",
        ideal_planetary,
    ),
];
