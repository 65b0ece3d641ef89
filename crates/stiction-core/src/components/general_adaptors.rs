//! MSL's `Components.GeneralTorqueToAngleAdaptor` and `GeneralAngleToTorqueAdaptor`, and
//! Translational's `GeneralForceToPositionAdaptor` and `GeneralPositionToForceAdaptor`: the
//! flange adaptors of `adaptors.rs` in the generic form of `Blocks.Interfaces.Adaptors`
//! (potential `p`, its derivatives `pder`, `pder2`, flow `f`; `use_pder`, `use_pder2`, the
//! second only with the first). The flow-derivative connectors are disabled (`final use_fder =
//! false` in MSL), so they are neither ports nor parameters here. The translational pair is
//! the rotational one on a translational flange (`s`, `v`, `a`, `f` in MSL's names).

use super::adaptors::{AngleToTorque, Names, TorqueToAngle};
use super::{Component, Entry};
use crate::error::ModelResult;
use crate::model::Params;

/// The `use_pder`/`use_pder2` declarations of one domain, for outputs and for inputs.
struct Flags {
    pder_out: &'static str,
    pder2_out: &'static str,
    pder_in: &'static str,
    pder2_in: &'static str,
}

const ROTATIONAL: Flags = Flags {
    pder_out: "use_pder true: enable the output pder (angular velocity)",
    pder2_out: "use_pder2 true: enable the output pder2 (angular acceleration; only with use_pder)",
    pder_in: "use_pder true: enable the input pder (angular velocity)",
    pder2_in: "use_pder2 true: enable the input pder2 (angular acceleration; only with use_pder)",
};

const TRANSLATIONAL: Flags = Flags {
    pder_out: "use_pder true: enable the output pder (velocity)",
    pder2_out: "use_pder2 true: enable the output pder2 (acceleration; only with use_pder)",
    pder_in: "use_pder true: enable the input pder (velocity)",
    pder2_in: "use_pder2 true: enable the input pder2 (acceleration; only with use_pder)",
};

const GENERAL: Names = Names {
    flow: "f",
    angle: "p",
    speed: "pder",
    accel: "pder2",
    translational: false,
};

const GENERAL_TRANSLATIONAL: Names = Names {
    translational: true,
    ..GENERAL
};

/// Input f = flange.tau (flange.f); outputs p = flange.phi (flange.s), pder, pder2 (pder2 only
/// with pder).
fn flow_to_potential(
    p: &Params,
    names: &'static Names,
    flags: &Flags,
) -> ModelResult<Box<dyn Component>> {
    let use_pder = p.boolean(flags.pder_out, true)?;
    let use_pder2 = p.boolean(flags.pder2_out, true)?;
    Ok(Box::new(TorqueToAngle {
        names,
        speed: use_pder,
        accel: use_pder && use_pder2,
    }))
}

/// Inputs p = flange.phi (flange.s), pder, pder2 its derivatives (pder2 only with pder);
/// output f = −flange.tau (−flange.f).
fn potential_to_flow(
    p: &Params,
    names: &'static Names,
    flags: &Flags,
) -> ModelResult<Box<dyn Component>> {
    let use_pder = p.boolean(flags.pder_in, true)?;
    let use_pder2 = p.boolean(flags.pder2_in, true)?;
    Ok(Box::new(AngleToTorque {
        names,
        speed_in: use_pder.then_some("use_pder"),
        accel_in: (use_pder && use_pder2).then_some("use_pder2"),
        report_all: false,
    }))
}

fn general_torque_to_angle(p: &Params) -> ModelResult<Box<dyn Component>> {
    flow_to_potential(p, &GENERAL, &ROTATIONAL)
}

fn general_angle_to_torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    potential_to_flow(p, &GENERAL, &ROTATIONAL)
}

fn general_force_to_position(p: &Params) -> ModelResult<Box<dyn Component>> {
    flow_to_potential(p, &GENERAL_TRANSLATIONAL, &TRANSLATIONAL)
}

fn general_position_to_force(p: &Params) -> ModelResult<Box<dyn Component>> {
    potential_to_flow(p, &GENERAL_TRANSLATIONAL, &TRANSLATIONAL)
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
    Entry::new(
        "Translational.GeneralForceToPositionAdaptor",
        "Modelica.Mechanics.Translational.Components.GeneralForceToPositionAdaptor",
        "Signal adaptor for a Translational flange with position, speed, and acceleration as outputs and force as input (especially useful for FMUs)",
        general_force_to_position,
    ),
    Entry::new(
        "Translational.GeneralPositionToForceAdaptor",
        "Modelica.Mechanics.Translational.Components.GeneralPositionToForceAdaptor",
        "Signal adaptor for a Translational flange with force as output and position, speed and acceleration as input (especially useful for FMUs)",
        general_position_to_force,
    ),
];
