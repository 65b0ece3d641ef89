//! MSL `Sources.Torque2`: the input torque `tau` drives flange_b and reacts on flange_a
//! (`flange_a.tau = tau`, `flange_b.tau = −tau`), a torque between two shafts.

use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, EnergyRole, ForceLaw, LawCtx, Out, Rel};

/// Along `flange_b − flange_a` the element torque is `flange_b.tau = −tau`.
struct InputTorque(usize);

impl ForceLaw for InputTorque {
    fn tau(&self, x: &LawCtx) -> f64 {
        -x.signals[self.0]
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Source
    }
}

/// `Torque2`, or with translational flanges MSL's `Translational.Sources.Force2` (input `f`).
pub(crate) struct Torque2 {
    pub(crate) translational: bool,
}

impl Torque2 {
    fn input(&self) -> &'static str {
        if self.translational {
            "f"
        } else {
            "tau"
        }
    }
}

impl Component for Torque2 {
    fn ports(&self) -> Ports {
        let mech = vec!["flange_a", "flange_b"];
        Ports {
            translational: if self.translational {
                mech.clone()
            } else {
                vec![]
            },
            mech,
            signal_in: vec![self.input()],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        let slot = b.signal_in(self.input())?;
        let law = b.add_law(Rel::between(na, nb), Box::new(InputTorque(slot)));
        b.output(self.input(), Out::Signal(slot));
        b.flange("flange_a", na, Some(Out::LawTau(law, -1.0)))?;
        b.flange("flange_b", nb, Some(Out::LawTau(law, 1.0)))?;
        Ok(())
    }
}

fn torque2(_p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Torque2 {
        translational: false,
    }))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "Torque2",
    "Modelica.Mechanics.Rotational.Sources.Torque2",
    "Input signal acting as torque on two flanges",
    torque2,
)];
