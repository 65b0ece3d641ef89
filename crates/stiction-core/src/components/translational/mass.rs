//! Translational `Mass` (gives its node mass, holds the absolute start values) and `Fixed`
//! (grounds a node at a position): Rotational's Inertia and Fixed with translational flanges.

use crate::components::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, Out, Rel};

struct Mass {
    m: f64,
    s: InitValue,
    v: InitValue,
}

impl Component for Mass {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            translational: vec!["flange_a", "flange_b"],
            joins: vec![("flange_a", "flange_b")],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.node("flange_a")?;
        // ½·m·v² is the kinetic energy the audit counts, as ½·J·w² for an Inertia
        b.add_mass(node, self.m);
        let rel = Rel::of(&[(node, 1.0)]);
        b.init_angle(rel.clone(), self.s, "s");
        b.init_speed(rel.clone(), self.v, "v");
        b.output("s", Out::Angle(rel.clone()));
        b.output("v", Out::Speed(rel.clone()));
        b.output("a", Out::Accel(rel.clone()));
        b.flange("flange_a", node, None)?;
        b.flange("flange_b", node, None)?;
        // m·a = flange_a.f + flange_b.f
        b.flange_group(
            &["flange_a", "flange_b"],
            Some(Out::Scaled(Box::new(Out::Accel(rel)), self.m)),
        )
    }
}

fn mass(p: &Params) -> ModelResult<Box<dyn Component>> {
    let m = p.positive("m", p.real("m [kg] Mass of the sliding mass", 1.0)?)?;
    let length = p.real(
        "L [m] Length of component, from left flange to right flange (= flange_b.s - flange_a.s)",
        0.0,
    )?;
    // The engine's flanges of one rigid set share one coordinate: a flange offset from its
    // node (flange_a.s = s - L/2) is not built yet, so a length is refused, not ignored.
    p.range("L", "[0, 0]");
    if length != 0.0 && !p.in_catalogue() {
        return Err(p.error(
            "L",
            format!("a length other than 0 is not supported yet (got {length}): the flanges of a Mass are at its center s"),
        ));
    }
    Ok(Box::new(Mass {
        m,
        s: p.init(
            "s [m] Absolute position of center of component (start value)",
            0.0,
        )?,
        v: p.init("v [m/s] Absolute velocity of component (start value)", 0.0)?,
    }))
}

struct Fixed {
    s0: f64,
}

impl Component for Fixed {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange"],
            translational: vec!["flange"],
            ground: vec![("flange", self.s0)],
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
        s0: p.real("s0 [m] Fixed offset position of housing", 0.0)?,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Translational.Mass",
        "Modelica.Mechanics.Translational.Components.Mass",
        "Sliding mass with inertia",
        mass,
    ),
    Entry::new(
        "Translational.Fixed",
        "Modelica.Mechanics.Translational.Components.Fixed",
        "Fixed flange",
        fixed,
    ),
];
