//! `Inertia` (gives its node mass, holds the absolute start values) and `Fixed` (grounds a node).

use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, Out, Rel};

struct Inertia {
    j: f64,
    phi: InitValue,
    w: InitValue,
}

impl Component for Inertia {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            joins: vec![("flange_a", "flange_b")],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.node("flange_a")?;
        b.add_mass(node, self.j);
        let rel = Rel::of(&[(node, 1.0)]);
        b.init_angle(rel.clone(), self.phi, "phi");
        b.init_speed(rel.clone(), self.w, "w");
        b.output("phi", Out::Angle(rel.clone()));
        b.output("w", Out::Speed(rel.clone()));
        b.output("a", Out::Accel(rel.clone()));
        b.flange("flange_a", node, None)?;
        b.flange("flange_b", node, None)?;
        // J·a = flange_a.tau + flange_b.tau
        b.flange_group(
            &["flange_a", "flange_b"],
            Some(Out::Scaled(Box::new(Out::Accel(rel)), self.j)),
        )
    }
}

fn inertia(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Inertia {
        j: p.at_least("J", p.real("J [kg.m2] Moment of inertia", 1.0)?, 0.0)?,
        phi: p.init(
            "phi [rad] Absolute rotation angle of the component (start value)",
            0.0,
        )?,
        w: p.init(
            "w [rad/s] Absolute angular velocity of the component (start value)",
            0.0,
        )?,
    }))
}

struct Fixed {
    phi0: f64,
}

impl Component for Fixed {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange"],
            ground: vec![("flange", self.phi0)],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.node("flange")?;
        b.flange("flange", node, None)?;
        b.flange_group(&["flange"], None)
    }
}

fn fixed(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Fixed {
        phi0: p.real("phi0 [rad] Fixed offset angle of the housing", 0.0)?,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Inertia",
        "Modelica.Mechanics.Rotational.Components.Inertia",
        "1D-rotational component with inertia",
        inertia,
    ),
    Entry::new(
        "Fixed",
        "Modelica.Mechanics.Rotational.Components.Fixed",
        "Flange fixed in the housing at a given angle",
        fixed,
    ),
];
