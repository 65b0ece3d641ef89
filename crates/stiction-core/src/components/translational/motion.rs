//! Translational prescribed-motion sources (`Sources.Speed`, `Position`, `Accelerate`, `Move`):
//! the rotational ones (`components::motion`) with a translational flange — one prescribed row
//! whose multiplier is the force the source delivers, `exact` or filtered as there.

use crate::components::motion::{accelerate_of, move_of, position_of, speed_of};
use crate::components::{Component, Entry};
use crate::error::ModelResult;
use crate::model::Params;

fn speed(p: &Params) -> ModelResult<Box<dyn Component>> {
    speed_of(p, true)
}

fn position(p: &Params) -> ModelResult<Box<dyn Component>> {
    position_of(p, true)
}

fn accelerate(p: &Params) -> ModelResult<Box<dyn Component>> {
    accelerate_of(p, true)
}

fn move_(p: &Params) -> ModelResult<Box<dyn Component>> {
    move_of(p, true)
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Translational.Speed",
        "Modelica.Mechanics.Translational.Sources.Speed",
        "Forced movement of a flange according to a reference speed",
        speed,
    ),
    Entry::new(
        "Translational.Position",
        "Modelica.Mechanics.Translational.Sources.Position",
        "Forced movement of a flange according to a reference position",
        position,
    ),
    Entry::new(
        "Translational.Accelerate",
        "Modelica.Mechanics.Translational.Sources.Accelerate",
        "Forced movement of a flange according to an acceleration signal",
        accelerate,
    ),
    Entry::new(
        "Translational.Move",
        "Modelica.Mechanics.Translational.Sources.Move",
        "Forced movement of a flange according to a position, velocity and acceleration signal",
        move_,
    ),
];
