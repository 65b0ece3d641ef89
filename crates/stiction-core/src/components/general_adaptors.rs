//! MSL's `Components.GeneralTorqueToAngleAdaptor` and `GeneralAngleToTorqueAdaptor`: the
//! flange adaptors of `adaptors.rs` in the generic form of `Blocks.Interfaces.Adaptors`
//! (potential `p`, its derivatives `pder`, `pder2`, flow `f`; `use_pder`, `use_pder2`, the
//! second only with the first). The flow-derivative connectors are disabled (`final use_fder =
//! false` in MSL), so they are neither ports nor parameters here.

use super::adaptors::{AngleToTorque, Names, TorqueToAngle};
use super::{Component, Entry};
use crate::error::ModelResult;
use crate::model::Params;

const USE_PDER_OUT: &str = "use_pder true: enable the output pder (angular velocity)";
const USE_PDER2_OUT: &str =
    "use_pder2 true: enable the output pder2 (angular acceleration; only with use_pder)";
const USE_PDER_IN: &str = "use_pder true: enable the input pder (angular velocity)";
const USE_PDER2_IN: &str =
    "use_pder2 true: enable the input pder2 (angular acceleration; only with use_pder)";

const GENERAL: Names = Names {
    flow: "f",
    angle: "p",
    speed: "pder",
    accel: "pder2",
};

/// Input f = flange.tau; outputs p = flange.phi, pder = w, pder2 = a (pder2 only with pder).
fn general_torque_to_angle(p: &Params) -> ModelResult<Box<dyn Component>> {
    let use_pder = p.boolean(USE_PDER_OUT, true)?;
    let use_pder2 = p.boolean(USE_PDER2_OUT, true)?;
    Ok(Box::new(TorqueToAngle {
        names: &GENERAL,
        speed: use_pder,
        accel: use_pder && use_pder2,
    }))
}

/// Inputs p = flange.phi (pder, pder2 its derivatives, pder2 only with pder); output
/// f = −flange.tau.
fn general_angle_to_torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    let use_pder = p.boolean(USE_PDER_IN, true)?;
    let use_pder2 = p.boolean(USE_PDER2_IN, true)?;
    Ok(Box::new(AngleToTorque {
        names: &GENERAL,
        speed_in: use_pder.then_some("use_pder"),
        accel_in: (use_pder && use_pder2).then_some("use_pder2"),
        report_all: false,
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
