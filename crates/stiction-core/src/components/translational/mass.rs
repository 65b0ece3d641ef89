//! Translational `Mass` (gives its node mass, holds the absolute start values) and `Fixed`
//! (grounds a node at a position): Rotational's Inertia and Fixed with translational flanges.

use crate::components::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, Out};

struct Mass {
    m: f64,
    length: f64,
    s: InitValue,
    v: InitValue,
}

impl Component for Mass {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            translational: vec!["flange_a", "flange_b"],
            joins: vec![("flange_a", "flange_b")],
            // MSL's PartialRigid: flange_a.s = s - L/2, flange_b.s = s + L/2
            offsets: vec![
                ("flange_a", -self.length / 2.0),
                ("flange_b", self.length / 2.0),
            ],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.node("flange_a")?;
        // ½·m·v² is the kinetic energy the audit counts, as ½·J·w² for an Inertia
        b.add_mass(node, self.m);
        // the center s: half a length beyond flange_a (speeds and accelerations are the node's)
        let mut center = b.rel(&[("flange_a", 1.0)])?;
        center.offset += self.length / 2.0;
        b.init_angle(center.clone(), self.s, "s");
        b.init_speed(center.clone(), self.v, "v");
        b.output("s", Out::Angle(center.clone()));
        b.output("v", Out::Speed(center.clone()));
        b.output("a", Out::Accel(center.clone()));
        // each flange at its own place (a held Mass's flanges are grounds L apart)
        b.flange("flange_a", node, None)?;
        let node_b = b.node("flange_b")?;
        b.flange("flange_b", node_b, None)?;
        // m·a = flange_a.f + flange_b.f
        b.flange_group(
            &["flange_a", "flange_b"],
            Some(Out::Scaled(Box::new(Out::Accel(center)), self.m)),
        )
    }
}

fn mass(p: &Params) -> ModelResult<Box<dyn Component>> {
    let m = p.positive("m", p.real("m [kg] Mass of the sliding mass", 1.0)?)?;
    let length = p.real(
        "L [m] Length of component, from left flange to right flange (= flange_b.s - flange_a.s)",
        0.0,
    )?;
    Ok(Box::new(Mass {
        m,
        length,
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
