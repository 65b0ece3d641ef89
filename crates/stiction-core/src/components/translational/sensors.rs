//! `Modelica.Mechanics.Translational.Sensors`: the rotational sensors (`components::sensors`)
//! with translational flanges — one implementation measures `s`, `v`, `a`, `f` and `power` as
//! it measures `phi`, `w`, `a` and `tau`, and its outputs are signals like theirs.

use crate::components::sensors::{Kind, Sensor};
use crate::components::{Component, Entry};
use crate::error::ModelResult;
use crate::model::Params;

fn sensor(kind: Kind) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Sensor {
        kind,
        translational: true,
    }))
}

// One constructor per type: the registry names a function, and sensors have no parameters.
fn position(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::Angle)
}
fn speed(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::Speed)
}
fn acc(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::Acc)
}
fn rel_position(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::RelAngle)
}
fn rel_speed(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::RelSpeed)
}
fn rel_acc(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::RelAcc)
}
fn force(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::Torque)
}
fn power(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::Power)
}
fn multi(_: &Params) -> ModelResult<Box<dyn Component>> {
    sensor(Kind::Multi)
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Translational.PositionSensor",
        "Modelica.Mechanics.Translational.Sensors.PositionSensor",
        "Ideal sensor to measure the absolute position",
        position,
    ),
    Entry::new(
        "Translational.SpeedSensor",
        "Modelica.Mechanics.Translational.Sensors.SpeedSensor",
        "Ideal sensor to measure the absolute velocity",
        speed,
    ),
    Entry::new(
        "Translational.AccSensor",
        "Modelica.Mechanics.Translational.Sensors.AccSensor",
        "Ideal sensor to measure the absolute acceleration",
        acc,
    ),
    Entry::new(
        "Translational.RelPositionSensor",
        "Modelica.Mechanics.Translational.Sensors.RelPositionSensor",
        "Ideal sensor to measure the relative position between two flanges",
        rel_position,
    ),
    Entry::new(
        "Translational.RelSpeedSensor",
        "Modelica.Mechanics.Translational.Sensors.RelSpeedSensor",
        "Ideal sensor to measure the relative speed between two flanges",
        rel_speed,
    ),
    Entry::new(
        "Translational.RelAccSensor",
        "Modelica.Mechanics.Translational.Sensors.RelAccSensor",
        "Ideal sensor to measure the relative acceleration between two flanges",
        rel_acc,
    ),
    Entry::new(
        "Translational.ForceSensor",
        "Modelica.Mechanics.Translational.Sensors.ForceSensor",
        "Ideal sensor to measure the force between two flanges (= flange_a.f)",
        force,
    ),
    Entry::new(
        "Translational.PowerSensor",
        "Modelica.Mechanics.Translational.Sensors.PowerSensor",
        "Ideal sensor to measure the power between two flanges (= flange_a.f*der(flange_a.s))",
        power,
    ),
    Entry::new(
        "Translational.MultiSensor",
        "Modelica.Mechanics.Translational.Sensors.MultiSensor",
        "Ideal sensor to measure the absolute velocity, force and power between two flanges",
        multi,
    ),
];
