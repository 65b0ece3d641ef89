//! MSL's `Components.GeneralTorqueToAngleAdaptor` and `GeneralAngleToTorqueAdaptor`: the
//! flange adaptors of `adaptors.rs` in the generic form of `Blocks.Interfaces.Adaptors`
//! (potential `p`, its derivatives `pder`, `pder2`, flow `f`; `use_pder`, `use_pder2`, the
//! second only with the first). The flow-derivative connectors are disabled (`final use_fder =
//! false` in MSL), so they are neither ports nor parameters here.

use super::adaptors::{conditional_input, InputTorque};
use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Accel, Builder, Held, NodeRef, Out, Prescribed, Rel};

const USE_PDER_OUT: &str = "use_pder true: enable the output pder (angular velocity)";
const USE_PDER2_OUT: &str =
    "use_pder2 true: enable the output pder2 (angular acceleration; only with use_pder)";
const USE_PDER_IN: &str = "use_pder true: enable the input pder (angular velocity)";
const USE_PDER2_IN: &str =
    "use_pder2 true: enable the input pder2 (angular acceleration; only with use_pder)";

/// Input f = flange.tau; outputs p = flange.phi, pder = w, pder2 = a.
struct GeneralTorqueToAngle {
    use_pder: bool,
    use_pder2: bool,
}

impl Component for GeneralTorqueToAngle {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange"],
            signal_in: vec!["f"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let nf = b.node("flange")?;
        let rel = Rel::of(&[(nf, 1.0)]);
        let f = b.signal_in("f")?;
        let law = b.add_law(rel.clone(), Box::new(InputTorque(f)));
        b.output("f", Out::LawTau(law, 1.0));
        b.output("p", Out::Angle(rel.clone()));
        if self.use_pder {
            b.output("pder", Out::Speed(rel.clone()));
            if self.use_pder2 {
                b.output("pder2", Out::Accel(rel));
            }
        }
        b.flange("flange", nf, Some(Out::LawTau(law, 1.0)))
    }
}

/// Inputs p = flange.phi (pder, pder2 its derivatives); output f = −flange.tau.
struct GeneralAngleToTorque {
    use_pder: bool,
    use_pder2: bool,
}

impl GeneralAngleToTorque {
    fn has_pder2(&self) -> bool {
        self.use_pder && self.use_pder2
    }
}

impl Component for GeneralAngleToTorque {
    fn ports(&self) -> Ports {
        let mut signal_in = vec!["p"];
        if self.use_pder {
            signal_in.push("pder");
        }
        if self.has_pder2() {
            signal_in.push("pder2");
        }
        Ports {
            mech: vec!["flange"],
            signal_in,
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let nf = b.node("flange")?;
        let NodeRef::Node(node) = nf else {
            return Err(
                b.error("port 'flange': held by ground, so no motion can be prescribed to it")
            );
        };
        let prescribed = Prescribed {
            node,
            held: Held::Angle {
                phi: b.signal_in("p")?,
                w: match self.use_pder {
                    true => Some(conditional_input(b, "pder", "use_pder")?),
                    false => None,
                },
            },
            accel: match self.has_pder2() {
                true => Accel::Signal(conditional_input(b, "pder2", "use_pder2")?),
                false => Accel::Zero,
            },
        };
        let rel = Rel::of(&[(nf, 1.0)]);
        let k = b.add_prescribed(rel.clone(), prescribed)?;
        // as AngleToTorqueAdaptor: the inputs fix the flange's angle and speed from the start
        let from_inputs = InitValue::fixed(0.0);
        b.init_angle(rel.clone(), from_inputs, "p");
        b.init_speed(rel.clone(), from_inputs, "pder");
        b.output("f", Out::ConstraintTau(k, -1.0));
        b.output("p", Out::Angle(rel.clone()));
        if self.use_pder {
            b.output("pder", Out::Speed(rel.clone()));
        }
        if self.has_pder2() {
            b.output("pder2", Out::Accel(rel));
        }
        b.flange("flange", nf, Some(Out::ConstraintTau(k, 1.0)))
    }
}

fn general_torque_to_angle(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(GeneralTorqueToAngle {
        use_pder: p.boolean(USE_PDER_OUT, true)?,
        use_pder2: p.boolean(USE_PDER2_OUT, true)?,
    }))
}

fn general_angle_to_torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(GeneralAngleToTorque {
        use_pder: p.boolean(USE_PDER_IN, true)?,
        use_pder2: p.boolean(USE_PDER2_IN, true)?,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "GeneralTorqueToAngleAdaptor",
        "Modelica.Mechanics.Rotational.Components.GeneralTorqueToAngleAdaptor",
        "Signal adaptor for a rotational flange with angle, speed, and acceleration as outputs and torque as input (especially useful for FMUs)",
        general_torque_to_angle,
    ),
    Entry::new(
        "GeneralAngleToTorqueAdaptor",
        "Modelica.Mechanics.Rotational.Components.GeneralAngleToTorqueAdaptor",
        "Signal adaptor for a rotational flange with torque as output and angle, speed and acceleration as input (especially useful for FMUs)",
        general_angle_to_torque,
    ),
];
