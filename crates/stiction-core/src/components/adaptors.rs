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

/// What an adaptor's connectors are called: the plain adaptors' (`tau`, `phi`, `w`, `a`) or the
/// General ones' (`f`, `p`, `pder`, `pder2`, `general_adaptors.rs`), and the domain of its
/// flange (the translational General adaptors are the same build on a translational flange).
/// One implementation serves all.
pub(super) struct Names {
    pub flow: &'static str,
    pub angle: &'static str,
    pub speed: &'static str,
    pub accel: &'static str,
    pub translational: bool,
}

const PLAIN: Names = Names {
    flow: "tau",
    angle: "phi",
    speed: "w",
    accel: "a",
    translational: false,
};

/// The ports of an adaptor: its one flange, in its domain, and its inputs.
fn adaptor_ports(names: &Names, signal_in: Vec<&'static str>) -> Ports {
    let mech = vec!["flange"];
    Ports {
        translational: if names.translational {
            mech.clone()
        } else {
            vec![]
        },
        mech,
        signal_in,
        ..Ports::default()
    }
}

/// Torque in, motion out: a torque source on the flange that reports the flange's angle, and
/// its speed and acceleration where their outputs are enabled (MSL: 0 and not reported else).
pub(super) struct TorqueToAngle {
    pub names: &'static Names,
    pub speed: bool,
    pub accel: bool,
}

impl Component for TorqueToAngle {
    fn ports(&self) -> Ports {
        adaptor_ports(self.names, vec![self.names.flow])
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let n = self.names;
        let nf = b.node("flange")?;
        let rel = Rel::of(&[(nf, 1.0)]);
        let flow = b.signal_in(n.flow)?;
        let law = b.add_law(rel.clone(), Box::new(InputTorque(flow)));
        b.output(n.flow, Out::LawTau(law, 1.0));
        b.output(n.angle, Out::Angle(rel.clone()));
        if self.speed {
            b.output(n.speed, Out::Speed(rel.clone()));
        }
        if self.accel {
            b.output(n.accel, Out::Accel(rel));
        }
        b.flange("flange", nf, Some(Out::LawTau(law, 1.0)))
    }
}

fn torque_to_angle(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(TorqueToAngle {
        names: &PLAIN,
        speed: p.boolean(TTA_USE_W, true)?,
        accel: p.boolean(TTA_USE_A, true)?,
    }))
}

/// Motion in, torque out: a prescribed motion of the flange that reports the torque it needs.
pub(super) struct AngleToTorque {
    pub names: &'static Names,
    /// The Boolean parameter that enables the speed input, and the acceleration input's (None:
    /// that input is disabled).
    pub speed_in: Option<&'static str>,
    pub accel_in: Option<&'static str>,
    /// The plain adaptor reports the flange's speed and acceleration even without their inputs.
    pub report_all: bool,
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
        let n = self.names;
        let mut signal_in = vec![n.angle];
        if self.speed_in.is_some() {
            signal_in.push(n.speed);
        }
        if self.accel_in.is_some() {
            signal_in.push(n.accel);
        }
        adaptor_ports(n, signal_in)
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let n = self.names;
        let nf = b.node("flange")?;
        let NodeRef::Node(node) = nf else {
            return Err(
                b.error("port 'flange': held by ground, so no motion can be prescribed to it")
            );
        };
        let prescribed = Prescribed {
            node,
            held: Held::Angle {
                phi: b.signal_in(n.angle)?,
                w: match self.speed_in {
                    Some(parameter) => Some(conditional_input(b, n.speed, parameter)?),
                    None => None,
                },
            },
            accel: match self.accel_in {
                Some(parameter) => Accel::Signal(conditional_input(b, n.accel, parameter)?),
                None => Accel::Zero,
            },
        };
        let rel = Rel::of(&[(nf, 1.0)]);
        let k = b.add_prescribed(rel.clone(), prescribed)?;
        // The inputs fix the flange's angle and speed from the start (their values replace these
        // zeros once the signals are known), so another fixed start on it is over-determined.
        let from_inputs = InitValue::fixed(0.0);
        b.init_angle(rel.clone(), from_inputs, n.angle);
        b.init_speed(rel.clone(), from_inputs, n.speed);
        // MSL: tau = torqueSensor.tau = −flange.tau, the torque that drives the flange
        b.output(n.flow, Out::ConstraintTau(k, -1.0));
        b.output(n.angle, Out::Angle(rel.clone()));
        if self.report_all || self.speed_in.is_some() {
            b.output(n.speed, Out::Speed(rel.clone()));
        }
        if self.report_all || self.accel_in.is_some() {
            b.output(n.accel, Out::Accel(rel));
        }
        b.flange("flange", nf, Some(Out::ConstraintTau(k, 1.0)))
    }
}

// Alike in shape to `torque_to_angle` (two flags, each MSL's own declaration).
fn angle_to_torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    let use_w = p.boolean(ATT_USE_W, true)?;
    let use_a = p.boolean(ATT_USE_A, true)?;
    // MSL: the `w` connector exists when `use_w or use_a`
    let speed_in = match (use_w, use_a) {
        (_, true) => Some("use_a"),
        (true, false) => Some("use_w"),
        (false, false) => None,
    };
    Ok(Box::new(AngleToTorque {
        names: &PLAIN,
        speed_in,
        accel_in: use_a.then_some("use_a"),
        report_all: true,
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
