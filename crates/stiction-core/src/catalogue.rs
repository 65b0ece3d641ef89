//! The component catalogue: for every registered type its MSL class, description, parameters
//! (default, unit, range, description), ports with their kind and the condition that enables
//! them, and the result variables with units. Built from the registry and from the parameter
//! declarations each constructor reads (`model::Params` in catalogue mode), so nothing here is
//! written twice; the Python classes, stubs, `stiction describe` and docs/components.md are
//! generated from it.

use std::path::PathBuf;

use crate::assembly::assemble;
use crate::components::{self, Domain, Entry, PortKind, Ports};
use crate::model::{
    ComponentSpec, Experiment, InputSpec, ModelSpec, ParamInfo, ParamKind, PortRef,
};

/// A port of a component type.
#[derive(Debug, Clone, PartialEq)]
pub struct PortInfo {
    pub name: String,
    pub kind: PortKind,
    /// A flange's domain (rotational or translational); Rotational for other ports.
    pub domain: Domain,
    /// The Boolean parameter that enables a conditional port (`useSupport`, `useHeatPort`).
    pub enabled_by: Option<String>,
}

impl PortInfo {
    /// `a flange`, `a translational flange`, `a signal input` …
    pub fn describe(&self) -> &'static str {
        match (self.kind, self.domain) {
            (PortKind::Mechanical, Domain::Translational) => "a translational flange",
            (kind, _) => kind.describe(),
        }
    }
}

/// A result variable of a component type, relative to the instance (`w`, `flange_a.tau`).
#[derive(Debug, Clone, PartialEq)]
pub struct VariableInfo {
    pub name: String,
    /// Modelica unit; `""` for Integers and Booleans (`mode`, `locked`).
    pub unit: &'static str,
}

/// Everything the reference says about one component type.
#[derive(Debug, Clone, PartialEq)]
pub struct TypeInfo {
    pub name: &'static str,
    pub class: &'static str,
    pub description: &'static str,
    pub params: Vec<ParamInfo>,
    pub ports: Vec<PortInfo>,
    pub variables: Vec<VariableInfo>,
}

/// The catalogue of every registered component type, in registry order.
pub fn catalogue() -> Vec<TypeInfo> {
    components::registry().iter().map(describe_entry).collect()
}

fn describe_entry(entry: &Entry) -> TypeInfo {
    let (params, plain) = components::declared(entry, false);
    let (_, full) = components::declared(entry, true);
    let booleans: Vec<&ParamInfo> = params
        .iter()
        .filter(|p| p.kind == ParamKind::Boolean)
        .collect();
    let ports = port_list(&full)
        .into_iter()
        .map(|(name, kind)| {
            let conditional = !plain.all().contains(&name);
            let enabled_by = booleans
                .iter()
                .find(|b| conditional && enables(entry, &b.name, name))
                .map(|b| b.name.clone());
            PortInfo {
                name: name.to_string(),
                kind,
                domain: full.domain_of(name),
                enabled_by,
            }
        })
        .collect();
    TypeInfo {
        name: entry.name,
        class: entry.class,
        description: entry.description,
        variables: variables(entry, &params, &full, translational_type(entry, &full)),
        params,
        ports,
    }
}

fn port_list(ports: &Ports) -> Vec<(&'static str, PortKind)> {
    ports
        .all()
        .into_iter()
        .map(|p| (p, ports.kind_of(p).expect("declared port")))
        .collect()
}

/// Whether setting only `boolean` to true makes `port` appear.
fn enables(entry: &Entry, boolean: &str, port: &str) -> bool {
    let mut spec = instance(entry, &[]);
    spec.params.insert(boolean.into(), true.into());
    let params = crate::model::Params::catalogue(&spec, false);
    (entry.make)(&params)
        .map(|c| c.ports().all().contains(&port))
        .unwrap_or(false)
}

fn instance(entry: &Entry, params: &[ParamInfo]) -> ComponentSpec {
    let mut table = toml::Table::new();
    for p in params {
        match p.kind {
            // every conditional port enabled; but `exact = true` (a prescribed motion that
            // follows its input exactly) needs the input's derivative, which a model input
            // lacks: the variables are the same names either way; InitializeFlange refuses
            // `use_a_start = true` in a run (its port is listed all the same)
            ParamKind::Boolean => {
                let on = p.name != "exact" && p.name != "use_a_start";
                table.insert(p.name.clone(), on.into());
            }
            ParamKind::Real if p.required => {
                table.insert(p.name.clone(), 1.0.into());
            }
            // a friction element's wear with a pad: its `wearVolume` and `thickness` listed
            ParamKind::Record if p.name == "wear" => {
                let wear = "model = \"energy\"\nalpha = 0\nA = 1\nthickness = 1";
                table.insert(
                    p.name.clone(),
                    toml::from_str::<toml::Table>(wear).expect("valid").into(),
                );
            }
            _ => {}
        }
    }
    ComponentSpec {
        name: "x".into(),
        type_name: entry.name.into(),
        params: table,
    }
}

/// The result variables of one instance with every conditional port enabled: a model of that
/// component alone (its signal inputs declared model inputs, a heat port that needs somewhere
/// to send its heat given a fixed temperature) is assembled and its outputs read.
/// Whether a component is translational: its flanges are all translational (a Mass's `a` is
/// in m/s2, an Inertia's in rad/s2; a wheel's flanges say their domain in their names).
fn translational(ports: &Ports) -> bool {
    !ports.mech.is_empty() && ports.mech.iter().all(|p| ports.translational.contains(p))
}

/// A component whose own variables are translational: all its flanges are, or it is one of
/// MSL's Translational classes with a rotational flange too (a Vehicle's `flangeR`).
fn translational_type(entry: &Entry, ports: &Ports) -> bool {
    translational(ports) || entry.name.starts_with("Translational.")
}

fn variables(
    entry: &Entry,
    params: &[ParamInfo],
    ports: &Ports,
    translational: bool,
) -> Vec<VariableInfo> {
    let system = assemble(&alone(entry, params, ports, false))
        .or_else(|_| assemble(&alone(entry, params, ports, true)))
        .unwrap_or_else(|e| panic!("{} alone does not assemble: {e}", entry.name));
    system
        .outputs
        .iter()
        .filter_map(|(name, _)| name.strip_prefix("x."))
        .map(|name| VariableInfo {
            name: name.to_string(),
            unit: unit_in(ports, name, translational),
        })
        .collect()
}

fn alone(entry: &Entry, params: &[ParamInfo], ports: &Ports, heat_boundary: bool) -> ModelSpec {
    let port = |component: &str, port: &str| PortRef {
        component: component.into(),
        port: port.into(),
    };
    let own = instance(entry, params);
    // the instance's own ports: a Boolean the instance leaves false (`use_a_start`) has none
    let ports = &components::create(&own, &PathBuf::from("."))
        .map(|c| c.ports())
        .unwrap_or_else(|_| ports.clone());
    let mut components = vec![own];
    let mut connections = Vec::new();
    // a friction element's flanges must be connected: an inertia on each
    for (k, flange) in ports.must_connect.iter().enumerate() {
        let name = format!("inertia{k}");
        let mut t = toml::Table::new();
        let type_name = match ports.domain_of(flange) {
            Domain::Rotational => "Inertia",
            Domain::Translational => "Translational.Mass",
        };
        let mass = if type_name == "Inertia" { "J" } else { "m" };
        t.insert(mass.into(), 1.0.into());
        components.push(ComponentSpec {
            name: name.clone(),
            type_name: type_name.into(),
            params: t,
        });
        connections.push((port("x", flange), port(&name, "flange_a")));
    }
    if heat_boundary {
        for (k, heat) in ports.heat.iter().enumerate() {
            let name = format!("boundary{k}");
            let mut t = toml::Table::new();
            t.insert("T".into(), 293.15.into());
            components.push(ComponentSpec {
                name: name.clone(),
                type_name: "FixedTemperature".into(),
                params: t,
            });
            connections.push((port("x", heat), port(&name, "port")));
        }
    }
    ModelSpec {
        name: "catalogue".into(),
        experiment: Experiment::default(),
        components,
        connections,
        inputs: ports
            .signal_in
            .iter()
            .map(|p| InputSpec {
                port: port("x", p),
                start: 0.0,
            })
            .collect(),
        base_dir: PathBuf::from("."),
        written: Vec::new(),
        variables: Vec::new(),
        parameters: Vec::new(),
    }
}

/// A variable's unit where its port (`flangeT.f`) or its component says the domain: a
/// converter's (`IdealRollingWheel`, `SlipWheel`) translational flange and own variables are
/// translational, its rotational flange's rotational.
fn unit_in(ports: &Ports, name: &str, translational: bool) -> &'static str {
    let port = name.split_once('.').map(|(p, _)| p);
    let mixed = !ports.translational.is_empty();
    match port {
        Some(p) if ports.mech.contains(&p) => match ports.translational.contains(&p) {
            true => translational_unit(name),
            false => variable_unit(name),
        },
        _ if translational || mixed => translational_unit(name),
        _ => variable_unit(name),
    }
}

/// The unit of a result variable from its MSL name (the last part: `flange_a.tau` → `tau`).
pub fn variable_unit(name: &str) -> &'static str {
    let last = name.rsplit('.').next().unwrap_or(name);
    match last {
        // a prescribed motion's inputs (`Move`'s u = {phi, w, a})
        "phi" | "phi_rel" | "phi_a" | "phi_b" | "phi_ref" | "u[1]" => "rad",
        "w" | "w_rel" | "w_a" | "w_b" | "w_ref" | "u[2]" => "rad/s",
        "a" | "a_rel" | "a_a" | "a_b" | "a_ref" | "u[3]" => "rad/s2",
        // InitializeFlange's inputs and flange variables
        "phi_start" | "phi_flange" => "rad",
        "w_start" | "w_flange" => "rad/s",
        "a_start" => "rad/s2",
        "tau" | "tau_c" | "tau_d" | "sa" | "tau0" | "tau0_max" | "tauLoss" | "tau_eta"
        | "tau_bf1" | "tau_bf2" | "tau_bf_a" | "tauLossMax_p" | "tauLossMin_m" => "N.m",
        "s" | "s_rel" | "s0" => "m",
        "v" | "v_rel" => "m/s",
        // the General adaptors' generic names (potential p, flow f) on a rotational flange
        "p" => "rad",
        "pder" => "rad/s",
        "pder2" => "rad/s2",
        "f" => "N.m",
        "lossPower" | "Q_flow" | "power" => "W",
        "T" => "K",
        "dT" => "K",
        "der_T" => "K/s",
        "fn" => "N",
        "mu" | "eta_mf1" | "eta_mf2" | "f_normalized" | "u" | "y" | "u1" | "u2" => "1",
        // a table's outputs (TimeTable's several columns, CombiTable1Ds's always)
        n if n.starts_with("y[") => "1",
        "Gc" => "W/K",
        // a friction element's wear (docs/wear.md)
        "wearVolume" => "m3",
        "thickness" => "m",
        _ => "",
    }
}

/// The unit of a translational component's variable: the accelerations are linear and a force
/// `f` is in N (a rotational `f` is the General adaptors' flow, a torque); every other name
/// (`s`, `v`, `lossPower`) has one unit in both domains.
pub fn translational_unit(name: &str) -> &'static str {
    let last = name.rsplit('.').next().unwrap_or(name);
    match last {
        "a" | "a_rel" | "a_ref" | "u[3]" => "m/s2",
        "f" | "f_c" | "f_d" | "f_input" | "sa" | "f0" | "f0_max" | "fN" => "N",
        "s_ref" | "u[1]" => "m",
        "v_ref" | "vWind" | "u[2]" => "m/s",
        // the General adaptors' generic names on a translational flange
        "p" => "m",
        "pder" => "m/s",
        "pder2" => "m/s2",
        "inclination" | "cr" => "1",
        // SlipWheel's slip speed R·w − v
        "v_slip" => "m/s",
        "a_slip" => "m/s2",
        _ => variable_unit(name),
    }
}

/// Variables that are Integers or Booleans and rightly have no unit.
#[cfg(test)]
const UNITLESS: &[&str] = &[
    "mode",
    "locked",
    "free",
    "stuck",
    "startForward",
    "startBackward",
    "tau_etaPos",
    "tau_aPos",
    "ideal",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_and_variable_is_documented() {
        // (the toy element of the engine's tests is no MSL class)
        for t in catalogue()
            .into_iter()
            .filter(|t| !t.class.starts_with("stiction.Tests"))
        {
            // stiction's own components (beyond MSL) say so in their class
            let own = t.class == format!("stiction.{}", t.name);
            assert!(t.class.starts_with("Modelica.") || own, "{}", t.name);
            for p in &t.params {
                let what = format!("{}.{}", t.name, p.name);
                assert!(!p.description.is_empty(), "{what}: no description");
                assert!(
                    p.default.is_some() || p.required || p.kind == ParamKind::String,
                    "{what}"
                );
                if p.kind.is_numeric() {
                    assert!(!p.unit.is_empty(), "{what}: no unit");
                }
            }
            for v in &t.variables {
                let last = v.name.rsplit('.').next().unwrap();
                assert!(
                    !v.unit.is_empty() || UNITLESS.contains(&last),
                    "{}.{}: no unit",
                    t.name,
                    v.name
                );
            }
        }
    }
}
