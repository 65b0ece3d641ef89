//! MSL `Components.Disc`: two flanges rigidly one without inertia, flange_b turned by the fixed
//! angle `deltaPhi` against flange_a. Not a join of the two shafts (their angles differ, and a
//! spring on either side sees its own): a permanent constraint `phi_a − phi_b + deltaPhi = 0`
//! that holds for angles from the start and for speeds throughout.

use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out, Rel};

struct Disc {
    delta_phi: f64,
}

impl Component for Disc {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        // multiplier λ: flange_a.tau = λ, flange_b.tau = −λ (0 = flange_a.tau + flange_b.tau)
        let row = || {
            let mut r = Rel::of(&[(na, 1.0), (nb, -1.0)]);
            r.offset += self.delta_phi;
            r
        };
        let k = b.add_constraint(row(), false)?;
        b.init_constraint(row());
        // phi = (phi_a + phi_b)/2: the middle of the disc
        let phi = Rel::of(&[(na, 0.5), (nb, 0.5)]);
        b.output("phi", Out::Angle(phi));
        b.flange("flange_a", na, Some(Out::ConstraintTau(k, 1.0)))?;
        b.flange("flange_b", nb, Some(Out::ConstraintTau(k, -1.0)))?;
        Ok(())
    }
}

fn disc(p: &Params) -> ModelResult<Box<dyn Component>> {
    let delta_phi = p.real(
        "deltaPhi [rad] Fixed rotation of flange_b with respect to flange_a (= flange_b.phi - flange_a.phi)",
        0.0,
    )?;
    Ok(Box::new(Disc { delta_phi }))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "Disc",
    "Modelica.Mechanics.Rotational.Components.Disc",
    "Rigid component without inertia, flange_b rotated by a fixed angle against flange_a",
    disc,
)];
