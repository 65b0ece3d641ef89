//! Modelica.Mechanics.Translational on the rotational engine: the same nodes, rows, laws and
//! events, with flanges whose domain is translational (`s` [m], `f` [N]); and the Rotational
//! components that join the two domains (`IdealRollingWheel`, `IdealGearR2T`). Translational
//! types are named `Translational.<MSL name>` where the rotational library has the same name
//! (`Translational.Fixed`), and so, for one rule, all of them.

pub mod compliant;
pub mod conversion;
pub mod friction;
pub mod mass;
pub mod motion;
pub mod sensors;
pub mod slip_wheel;
pub mod sources;
pub mod stop;
pub mod vehicle;

use super::Entry;

/// Every type of the translational family and the converters.
pub fn registry() -> Vec<Entry> {
    let mut r = Vec::new();
    r.extend(mass::REGISTRY);
    r.extend(compliant::REGISTRY);
    r.extend(friction::REGISTRY);
    r.extend(stop::REGISTRY);
    r.extend(sources::REGISTRY);
    r.extend(conversion::REGISTRY);
    r.extend(slip_wheel::REGISTRY);
    r.extend(sensors::REGISTRY);
    r.extend(motion::REGISTRY);
    r.extend(vehicle::REGISTRY);
    r
}
