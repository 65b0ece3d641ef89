//! `Modelica.Mechanics.Rotational.Sensors`: ideal sensors whose outputs are signals, usable as
//! the inputs of blocks and of other components (a brake driven by a measured speed). Absolute
//! sensors sit on one flange and relative ones between two, carrying no torque
//! (`flange.tau = 0`); TorqueSensor, PowerSensor and MultiSensor join their two flanges rigidly
//! (`flange_a.phi = flange_b.phi`) by a permanent constraint whose multiplier is the cut torque
//! `tau = flange_a.tau = −flange_b.tau`. Angles and speeds are known with the state; an
//! acceleration, a cut torque and a power only after the solve (`signals::Stage`).

use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::signals::Measure;
use crate::system::{Builder, NodeRef, Out, Rel};

/// Which sensor: what it measures and where.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Angle,
    Speed,
    Acc,
    RelAngle,
    RelSpeed,
    RelAcc,
    Torque,
    Power,
    Multi,
}

impl Kind {
    fn absolute(self) -> bool {
        matches!(self, Kind::Angle | Kind::Speed | Kind::Acc)
    }

    fn cut(self) -> bool {
        matches!(self, Kind::Torque | Kind::Power | Kind::Multi)
    }

    /// The output connectors, in MSL's declaration order (Translational: `s`, `v`, `f`, …).
    fn outputs(self, translational: bool) -> Vec<&'static str> {
        if translational {
            return match self {
                Kind::Angle => vec!["s"],
                Kind::Speed => vec!["v"],
                Kind::Acc => vec!["a"],
                Kind::RelAngle => vec!["s_rel"],
                Kind::RelSpeed => vec!["v_rel"],
                Kind::RelAcc => vec!["a_rel"],
                Kind::Torque => vec!["f"],
                Kind::Power => vec!["power"],
                Kind::Multi => vec!["power", "v", "f"],
            };
        }
        match self {
            Kind::Angle => vec!["phi"],
            Kind::Speed => vec!["w"],
            Kind::Acc => vec!["a"],
            Kind::RelAngle => vec!["phi_rel"],
            Kind::RelSpeed => vec!["w_rel"],
            Kind::RelAcc => vec!["a_rel"],
            Kind::Torque => vec!["tau"],
            Kind::Power => vec!["power"],
            Kind::Multi => vec!["power", "w", "tau"],
        }
    }
}

/// One sensor in either domain: a translational sensor measures `s`, `v`, `a` and `f` by the
/// same rows and stages as the rotational one measures `phi`, `w`, `a` and `tau`.
pub(crate) struct Sensor {
    pub(crate) kind: Kind,
    pub(crate) translational: bool,
}

impl Component for Sensor {
    fn ports(&self) -> Ports {
        let mech = match self.kind.absolute() {
            true => vec!["flange"],
            false => vec!["flange_a", "flange_b"],
        };
        Ports {
            translational: if self.translational {
                mech.clone()
            } else {
                vec![]
            },
            mech,
            signal_out: self.kind.outputs(self.translational),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let kind = self.kind;
        let names = kind.outputs(self.translational);
        if kind.absolute() {
            let node = b.node("flange")?;
            let rel = Rel::of(&[(node, 1.0)]);
            b.flange("flange", node, Some(Out::Const(0.0)))?;
            let measure = match kind {
                Kind::Angle => Measure::Angle(rel),
                Kind::Speed => Measure::Speed(rel),
                _ => Measure::Accel(rel),
            };
            return b.add_sensor(names[0], measure);
        }
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        if kind.cut() {
            return cut_sensor(b, &names, na, nb);
        }
        b.flange("flange_a", na, Some(Out::Const(0.0)))?;
        b.flange("flange_b", nb, Some(Out::Const(0.0)))?;
        // phi_rel = flange_b.phi − flange_a.phi
        let rel = Rel::between(na, nb);
        let measure = match kind {
            Kind::RelAngle => Measure::Angle(rel),
            Kind::RelSpeed => Measure::Speed(rel),
            _ => Measure::Accel(rel),
        };
        b.add_sensor(names[0], measure)
    }
}

/// The rigid row `phi_a − phi_b = 0`, whose multiplier λ is `flange_a.tau` (force on the nodes
/// = −λ·row: −λ on flange_a's shaft, the torque the sensor takes from it), and the outputs.
fn cut_sensor(
    b: &mut Builder,
    names: &[&'static str],
    na: NodeRef,
    nb: NodeRef,
) -> ModelResult<()> {
    let row = || Rel::of(&[(na, 1.0), (nb, -1.0)]);
    let k = b.add_constraint(row(), false)?;
    b.init_constraint(row());
    b.flange("flange_a", na, Some(Out::ConstraintTau(k, 1.0)))?;
    b.flange("flange_b", nb, Some(Out::ConstraintTau(k, -1.0)))?;
    let w = Rel::of(&[(na, 1.0)]);
    for &port in names {
        let measure = match port {
            "tau" | "f" => Measure::Torque(k, 1.0),
            "w" | "v" => Measure::Speed(w.clone()),
            _ => Measure::Power(k, 1.0, w.clone()),
        };
        b.add_sensor(port, measure)?;
    }
    Ok(())
}

fn rotational(kind: Kind) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Sensor {
        kind,
        translational: false,
    }))
}

// One constructor per type: the registry names a function, and sensors have no parameters.
fn angle(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::Angle)
}
fn speed(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::Speed)
}
fn acc(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::Acc)
}
fn rel_angle(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::RelAngle)
}
fn rel_speed(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::RelSpeed)
}
fn rel_acc(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::RelAcc)
}
fn torque(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::Torque)
}
fn power(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::Power)
}
fn multi(_: &Params) -> ModelResult<Box<dyn Component>> {
    rotational(Kind::Multi)
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "AngleSensor",
        "Modelica.Mechanics.Rotational.Sensors.AngleSensor",
        "Ideal sensor to measure the absolute flange angle",
        angle,
    ),
    Entry::new(
        "SpeedSensor",
        "Modelica.Mechanics.Rotational.Sensors.SpeedSensor",
        "Ideal sensor to measure the absolute flange angular velocity",
        speed,
    ),
    Entry::new(
        "AccSensor",
        "Modelica.Mechanics.Rotational.Sensors.AccSensor",
        "Ideal sensor to measure the absolute flange angular acceleration",
        acc,
    ),
    Entry::new(
        "RelAngleSensor",
        "Modelica.Mechanics.Rotational.Sensors.RelAngleSensor",
        "Ideal sensor to measure the relative angle between two flanges",
        rel_angle,
    ),
    Entry::new(
        "RelSpeedSensor",
        "Modelica.Mechanics.Rotational.Sensors.RelSpeedSensor",
        "Ideal sensor to measure the relative angular velocity between two flanges",
        rel_speed,
    ),
    Entry::new(
        "RelAccSensor",
        "Modelica.Mechanics.Rotational.Sensors.RelAccSensor",
        "Ideal sensor to measure the relative angular acceleration between two flanges",
        rel_acc,
    ),
    Entry::new(
        "TorqueSensor",
        "Modelica.Mechanics.Rotational.Sensors.TorqueSensor",
        "Ideal sensor to measure the torque between two flanges (= flange_a.tau)",
        torque,
    ),
    Entry::new(
        "PowerSensor",
        "Modelica.Mechanics.Rotational.Sensors.PowerSensor",
        "Ideal sensor to measure the power between two flanges (= flange_a.tau*der(flange_a.phi))",
        power,
    ),
    Entry::new(
        "MultiSensor",
        "Modelica.Mechanics.Rotational.Sensors.MultiSensor",
        "Ideal sensor to measure the absolute angular velocity, torque and power between two flanges",
        multi,
    ),
];
