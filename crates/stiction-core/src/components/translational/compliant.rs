//! Translational `Spring`, `Damper`, `SpringDamper` and `ElastoGap` — the rotational compliant
//! elements (`components::compliant::Compliant`) under MSL's translational names (`s_rel`,
//! `v_rel`, `f`; ElastoGap's contact law is `components::elasto_gap`) — and `Rod`, a massless rigid connection with a length.

use crate::components::compliant::{read_linear, TRANSLATIONAL};
use crate::components::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out};

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
