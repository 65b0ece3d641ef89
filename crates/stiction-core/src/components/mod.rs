//! The component library. Each family lives in its own module; a component declares its ports
//! (with MSL's conditional `support` and `heatPort`) and, once the ports are resolved to nodes,
//! contributes masses, force laws, constraints, friction elements, start values and the output
//! variables it reports under its MSL names. Adding a component = one file + one registry line.

pub mod adaptors;
pub mod backlash;
pub mod backlash2;
pub mod blocks;
pub mod compliant;
pub mod disc;
pub mod eddy_current;
pub mod elasto_gap;
pub mod friction;
pub mod gearbox;
pub mod gears;
pub mod general_adaptors;
pub mod heat;
pub mod inertia;
pub mod initialize_flange;
pub mod motion;
pub mod relative_states;
pub mod sensors;
pub mod sources;
pub mod torque2;
pub mod translational;

#[cfg(test)]
mod toys;

use std::path::Path;

use crate::error::{ModelError, ModelResult};
use crate::model::{ComponentSpec, ParamInfo, Params};
use crate::system::Builder;
pub use crate::system::{Domain, PortKind};

/// The ports a component has once its conditional connectors are decided.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Ports {
    pub mech: Vec<&'static str>,
    /// The mechanical ports that are translational (`s`, `f`); the others are rotational.
    pub translational: Vec<&'static str>,
    /// Mechanical ports that are rigidly one (an Inertia's two flanges, a Brake's shaft).
    pub joins: Vec<(&'static str, &'static str)>,
    /// Where joined ports sit relative to one another: a port's coordinate minus the
    /// component's own (a Mass's flanges at ∓L/2 from its center); 0 if not listed.
    pub offsets: Vec<(&'static str, f64)>,
    /// Mechanical ports held at a fixed angle (Fixed's flange).
    pub ground: Vec<(&'static str, f64)>,
    pub signal_in: Vec<&'static str>,
    pub signal_out: Vec<&'static str>,
    pub heat: Vec<&'static str>,
    /// Mechanical ports that must reach something outside the component (a friction
    /// element's): alone, such a port's shaft has no inertia and nothing determines its
    /// motion once the element slips, so the assembly refuses it by name.
    pub must_connect: Vec<&'static str>,
    /// Flanges inside a composite component (a Gearbox's shaft between its parts, named
    /// `lossyGear.flange_b`): each gets a node as any flange does, but nothing outside can
    /// connect to it, and it is not listed among the component's ports.
    pub internal: Vec<&'static str>,
}

impl Ports {
    pub fn kind_of(&self, port: &str) -> Option<PortKind> {
        if self.mech.contains(&port) {
            Some(PortKind::Mechanical)
        } else if self.signal_in.contains(&port) {
            Some(PortKind::SignalIn)
        } else if self.signal_out.contains(&port) {
            Some(PortKind::SignalOut)
        } else if self.heat.contains(&port) {
            Some(PortKind::Heat)
        } else {
            None
        }
    }

    /// The domain of a port (Rotational unless listed as translational).
    pub fn domain_of(&self, port: &str) -> Domain {
        if self.translational.contains(&port) {
            Domain::Translational
        } else {
            Domain::Rotational
        }
    }

    /// The offset of a port from its component's coordinate (see `offsets`).
    pub fn offset_of(&self, port: &str) -> f64 {
        (self.offsets.iter())
            .find(|(p, _)| *p == port)
            .map_or(0.0, |(_, d)| *d)
    }

    pub fn all(&self) -> Vec<&'static str> {
        let mut all = self.mech.clone();
        all.extend(&self.signal_in);
        all.extend(&self.signal_out);
        all.extend(&self.heat);
        all
    }
}

/// Flanges plus the conditional `support` (MSL `useSupport`).
pub fn with_support(flanges: &[&'static str], use_support: bool) -> Vec<&'static str> {
    let mut mech = flanges.to_vec();
    if use_support {
        mech.push("support");
    }
    mech
}

/// The conditional `heatPort` (MSL `useHeatPort`).
pub fn heat_port(enabled: bool) -> Vec<&'static str> {
    if enabled {
        vec!["heatPort"]
    } else {
        vec![]
    }
}

/// Declarations of the parameters that MSL's partial base classes give many components
/// (`PartialElementary…AndSupport2`, `PartialElementaryConditionalHeatPort…`,
/// `PartialCompliantWithRelativeStates`, `PartialFriction`, `SignalSource`): written once, as
/// MSL declares them once.
pub mod decl {
    pub const USE_SUPPORT: &str =
        "useSupport true: enable the support connector (else the housing is fixed at angle 0)";
    pub const USE_HEAT_PORT: &str =
        "useHeatPort true: enable the heatPort connector (else the loss power goes nowhere)";
    pub const PHI_REL: &str =
        "phi_rel [rad] Relative rotation angle flange_b.phi - flange_a.phi (start value)";
    pub const W_REL: &str = "w_rel [rad/s] Relative angular velocity der(phi_rel) (start value)";
    pub const PEAK: &str =
        "peak [1] Peak for maximum friction torque at w = 0: tau0_max = peak*tau0";
    pub const W_SMALL: &str =
        "w_small [rad/s] Relative speed above which a speed jump reverses sliding directly";
    pub const OFFSET: &str = "offset [1] Offset of the output signal y";
    pub const START_TIME: &str = "startTime [s] Output y = offset for time < startTime";
}

/// The most time events one component may schedule in a run.
pub const MAX_TIME_EVENTS: usize = 1_000_000;

/// What every component does. Components are plain data, shared by the threads of a sweep.
pub trait Component: Send + Sync {
    fn ports(&self) -> Ports;
    /// Contributes to the system; called once the ports are resolved to nodes.
    fn build(&self, b: &mut Builder) -> ModelResult<()>;
    /// Time instants in `[from, until]` where this component's equations change (time events),
    /// at most `MAX_TIME_EVENTS` of them (more is reported as an error by the assembly).
    fn time_events(&self, _from: f64, _until: f64) -> Vec<f64> {
        Vec::new()
    }
}

/// Builds a component from its parameters.
pub type Constructor = fn(&Params) -> ModelResult<Box<dyn Component>>;

/// One registered component type: its name in model files, its MSL class, a one-line
/// description and its constructor (which declares the parameters as it reads them).
#[derive(Clone, Copy)]
pub struct Entry {
    pub name: &'static str,
    pub class: &'static str,
    pub description: &'static str,
    pub make: Constructor,
}

impl Entry {
    /// A registry line: `Entry::new("Brake", "Modelica.…Brake", "Brake based on …", brake)`.
    pub const fn new(
        name: &'static str,
        class: &'static str,
        description: &'static str,
        make: Constructor,
    ) -> Self {
        Self {
            name,
            class,
            description,
            make,
        }
    }
}

/// Every component type, family by family: listed once, then shared (a model of 2 750
/// components listed them for each of its components when it was created).
pub fn registry() -> &'static [Entry] {
    static REGISTRY: std::sync::OnceLock<Vec<Entry>> = std::sync::OnceLock::new();
    REGISTRY.get_or_init(list_registry)
}

fn list_registry() -> Vec<Entry> {
    let mut r: Vec<Entry> = Vec::new();
    r.extend(inertia::REGISTRY);
    r.extend(compliant::REGISTRY);
    r.extend(gears::REGISTRY);
    r.extend(sources::REGISTRY);
    r.extend(sensors::REGISTRY);
    r.extend(adaptors::REGISTRY);
    r.extend(motion::REGISTRY);
    r.extend(eddy_current::REGISTRY);
    r.extend(torque2::REGISTRY);
    r.extend(disc::REGISTRY);
    r.extend(relative_states::REGISTRY);
    r.extend(general_adaptors::REGISTRY);
    r.extend(initialize_flange::REGISTRY);
    r.extend(gearbox::REGISTRY);
    r.extend(friction::REGISTRY);
    r.extend(friction::lossy_gear::REGISTRY);
    r.extend(blocks::REGISTRY);
    r.extend(heat::REGISTRY);
    r.extend(translational::registry());
    #[cfg(test)]
    r.extend(toys::REGISTRY);

    r
}

/// Builds one component from its specification, validating every parameter.
pub fn create(spec: &ComponentSpec, base_dir: &Path) -> ModelResult<Box<dyn Component>> {
    let registry = registry();
    let Some(entry) = registry.iter().find(|e| e.name == spec.type_name) else {
        let mut names: Vec<&str> = registry.iter().map(|e| e.name).collect();
        names.sort();
        return Err(ModelError::Component {
            component: spec.name.clone(),
            message: format!(
                "unknown component type '{}' (known: {})",
                spec.type_name,
                names.join(", ")
            ),
        });
    };
    let params = Params::new(spec, base_dir);
    let component = (entry.make)(&params)?;
    params.finish(&[])?;
    Ok(component)
}

/// A type's parameters (as its constructor declares them) and its ports; `booleans` is the
/// value of every Boolean parameter, so `true` shows the conditional ports as well.
pub fn declared(entry: &Entry, booleans: bool) -> (Vec<ParamInfo>, Ports) {
    let spec = ComponentSpec {
        name: "x".into(),
        type_name: entry.name.into(),
        params: toml::Table::new(),
    };
    let params = Params::catalogue(&spec, booleans);
    let component = (entry.make)(&params).expect("catalogue mode accepts the defaults");
    (params.infos(), component.ports())
}
