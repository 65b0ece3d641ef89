//! MSL's flange adaptors (`Components.TorqueToAngleAdaptor`, `Components.AngleToTorqueAdaptor`):
//! a flange seen as signals, so a drivetrain can be cut at a flange into input/output blocks —
//! FMUs, as MSL's `Examples.GenerationOfFMUs` does. The torque side is a torque source that
//! reports its flange's motion; the angle side a prescribed motion (`system::Prescribed`, as
//! MSL builds it from `Sources.Move`) that reports the torque it needs.

use super::{Component, Entry, Ports};
use crate::error::{ModelError, ModelResult};
use crate::model::{InitValue, Params};
use crate::system::{
    Accel, Builder, EnergyRole, ForceLaw, Held, LawCtx, NodeRef, Out, Prescribed, Rel,
};

const TTA_USE_W: &str = "use_w true: enable the output connector w (angular velocity)";
const TTA_USE_A: &str = "use_a true: enable the output connector a (angular acceleration)";
const ATT_USE_W: &str = "use_w true: enable the input connector w (angular velocity)";
const ATT_USE_A: &str = "use_a true: enable the input connector a (angular acceleration)";

/// MSL `flange.tau = tau`: the input is the flange's cut torque, so it acts on the shaft as −tau.
pub(super) struct InputTorque(pub(super) usize);

impl ForceLaw for InputTorque {
    fn tau(&self, x: &LawCtx) -> f64 {
        x.signals[self.0]
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Source
    }
}

struct TorqueToAngle {
    use_w: bool,
    use_a: bool,
}

impl Component for TorqueToAngle {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange"],
            signal_in: vec!["tau"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let nf = b.node("flange")?;
        let rel = Rel::of(&[(nf, 1.0)]);
        let tau = b.signal_in("tau")?;
        let law = b.add_law(rel.clone(), Box::new(InputTorque(tau)));
        b.output("tau", Out::LawTau(law, 1.0));
        b.output("phi", Out::Angle(rel.clone()));
        // MSL: w = 0 and a = 0 when their connectors are disabled; they are not reported then
        if self.use_w {
            b.output("w", Out::Speed(rel.clone()));
        }
        if self.use_a {
            b.output("a", Out::Accel(rel));
        }
        b.flange("flange", nf, Some(Out::LawTau(law, 1.0)))
    }
}

fn torque_to_angle(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(TorqueToAngle {
        use_w: p.boolean(TTA_USE_W, true)?,
        use_a: p.boolean(TTA_USE_A, true)?,
    }))
}

struct AngleToTorque {
    use_w: bool,
    use_a: bool,
}

impl AngleToTorque {
    /// MSL: the `w` connector exists when `use_w or use_a`.
    fn has_w(&self) -> bool {
        self.use_w || self.use_a
    }
}

/// An enabled input that nothing drives: name the parameter that enabled it.
pub(super) fn conditional_input(
    b: &mut Builder,
    port: &str,
    parameter: &str,
) -> ModelResult<usize> {
    let name = b.name().to_string();
    b.signal_in(port).map_err(|_| ModelError::Component {
        component: name,
        message: format!(
            "parameter '{parameter}' = true enables input '{port}', which is not connected \
             (connect a signal or declare it a model input, or set {parameter} = false)"
        ),
    })
}

impl Component for AngleToTorque {
    fn ports(&self) -> Ports {
        let mut signal_in = vec!["phi"];
        if self.has_w() {
            signal_in.push("w");
        }
        if self.use_a {
            signal_in.push("a");
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
        let w_parameter = if self.use_a { "use_a" } else { "use_w" };
        let prescribed = Prescribed {
            node,
            held: Held::Angle {
                phi: b.signal_in("phi")?,
                w: match self.has_w() {
                    true => Some(conditional_input(b, "w", w_parameter)?),
                    false => None,
                },
            },
            accel: match self.use_a {
                true => Accel::Signal(conditional_input(b, "a", "use_a")?),
                false => Accel::Zero,
            },
        };
        let rel = Rel::of(&[(nf, 1.0)]);
        let k = b.add_prescribed(rel.clone(), prescribed)?;
        // The inputs fix the flange's angle and speed from the start (their values replace these
        // zeros once the signals are known), so another fixed start on it is over-determined.
        let from_inputs = InitValue::fixed(0.0);
        b.init_angle(rel.clone(), from_inputs, "phi");
        b.init_speed(rel.clone(), from_inputs, "w");
        // MSL: tau = torqueSensor.tau = −flange.tau, the torque that drives the flange
        b.output("tau", Out::ConstraintTau(k, -1.0));
        b.output("phi", Out::Angle(rel.clone()));
        b.output("w", Out::Speed(rel.clone()));
        b.output("a", Out::Accel(rel));
        b.flange("flange", nf, Some(Out::ConstraintTau(k, 1.0)))
    }
}

// Alike in shape to `torque_to_angle` (two flags, each MSL's own declaration).
fn angle_to_torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(AngleToTorque {
        use_w: p.boolean(ATT_USE_W, true)?,
        use_a: p.boolean(ATT_USE_A, true)?,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "TorqueToAngleAdaptor",
        "Modelica.Mechanics.Rotational.Components.TorqueToAngleAdaptor",
        "Signal adaptor for a Rotational flange with angle, speed, and acceleration as outputs and torque as input (especially useful for FMUs)",
        torque_to_angle,
    ),
    Entry::new(
        "AngleToTorqueAdaptor",
        "Modelica.Mechanics.Rotational.Components.AngleToTorqueAdaptor",
        "Signal adaptor for a Rotational flange with torque as output and angle, speed, and optionally acceleration as inputs (especially useful for FMUs)",
        angle_to_torque,
    ),
];
