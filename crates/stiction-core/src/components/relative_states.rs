//! MSL `Components.RelativeStates`: no torque (`flange_a.tau = flange_b.tau = 0`), only the
//! relative angle and speed between its flanges as variables, with their start values. In
//! MSL it makes them the preferred states; here every node angle and speed is a state, so what
//! it adds is the start values (`phi_rel = {start = …, fixed = true}` fixes the pair's
//! relative angle at the start, as MSL's initial equation does) and the result variables.

use super::decl::{PHI_REL, W_REL};
use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, Out, Rel};

struct RelativeStates {
    phi_rel: InitValue,
    w_rel: InitValue,
}

impl Component for RelativeStates {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        let rel = Rel::between(na, nb);
        b.init_angle(rel.clone(), self.phi_rel, "phi_rel");
        b.init_speed(rel.clone(), self.w_rel, "w_rel");
        b.output("phi_rel", Out::Angle(rel.clone()));
        b.output("w_rel", Out::Speed(rel.clone()));
        b.output("a_rel", Out::Accel(rel));
        b.flange("flange_a", na, Some(Out::Const(0.0)))?;
        b.flange("flange_b", nb, Some(Out::Const(0.0)))
    }
}

fn relative_states(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(RelativeStates {
        phi_rel: p.init(PHI_REL, 0.0)?,
        w_rel: p.init(W_REL, 0.0)?,
    }))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "RelativeStates",
    "Modelica.Mechanics.Rotational.Components.RelativeStates",
    "Definition of relative state variables",
    relative_states,
)];
