//! A compiled model: the model description, its components and its resolved topology, kept so
//! that a variant — other parameter values, start values or experiment settings, named the MSL
//! way (`clutch1.fn_max`, `J1.w`, `StopTime`) — costs only the components it changes and one
//! build, not a parse and a new assembly. A value that changes the structure (`useSupport`,
//! `useHeatPort`: other ports) resolves the topology anew; nothing is silently ignored.
//! Cloning is a handful of reference counts: one per thread of a sweep.

use std::sync::Arc;

use super::{build, build_with, create_components, SpecView, Topology};
use crate::components::{self, Component};
use crate::error::{ModelError, ModelResult};
use crate::model::{overriding, split_last, ComponentSpec, Experiment, ModelSpec};
use crate::system::System;

/// The components of a model, shared by its variants.
type Components = Vec<Arc<dyn Component>>;

/// The experiment settings a variant may change, by their MSL names.
const EXPERIMENT: &[&str] = &[
    "StartTime",
    "StopTime",
    "Interval",
    "Tolerance",
    "Solver",
    "max_events",
    "max_steps",
    "timeout",
];

#[derive(Clone)]
pub struct CompiledModel {
    spec: Arc<ModelSpec>,
    components: Arc<Vec<Arc<dyn Component>>>,
    topology: Arc<Topology>,
    system: Arc<System>,
}

/// How a variant was made: by a new build on the same topology, or with a new topology.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recompiled {
    Build,
    Topology,
}

impl CompiledModel {
    pub fn new(spec: ModelSpec) -> ModelResult<Self> {
        spec.experiment.validate()?;
        let spec = super::canonical_owned(spec);
        let components = create_components(&spec)?;
        let topology = Topology::resolve(&spec, &components)?;
        let system = build(&spec, &topology, &components)?;
        Ok(Self {
            spec: Arc::new(spec),
            components: Arc::new(components),
            topology: Arc::new(topology),
            system: Arc::new(system),
        })
    }

    pub fn spec(&self) -> &ModelSpec {
        &self.spec
    }

    /// The assembled system, shared by every run of this variant.
    pub fn system(&self) -> Arc<System> {
        self.system.clone()
    }

    /// Every parameter a variant may set: `component.parameter` for the parameters each
    /// component accepts (its defaults included), then the experiment settings.
    pub fn parameter_names(&self) -> Vec<String> {
        let registry = components::registry();
        let mut names = Vec::new();
        for c in &self.spec.components {
            if let Some(entry) = registry.iter().find(|e| e.name == c.type_name) {
                let (params, _) = components::declared(entry, false);
                names.extend(params.iter().map(|p| format!("{}.{}", c.name, p.name)));
            }
        }
        names.extend(EXPERIMENT.iter().map(|s| s.to_string()));
        names
    }

    /// Checks that `name` (`component.parameter`) may change in a running simulation: a
    /// parameter of a component of this model that leaves the compiled structure alone
    /// (`ParamInfo::tunable`). An experiment setting or a fixed parameter is refused, named.
    pub fn check_tunable(&self, name: &str) -> ModelResult<()> {
        let Some((component, parameter)) = split_last(name) else {
            return Err(ModelError::File(format!(
                "'{name}' is not a parameter (component.parameter): experiment settings are fixed in a running simulation"
            )));
        };
        let ci = self.component_index(component)?;
        let type_name = &self.spec.components[ci].type_name;
        let registry = components::registry();
        let entry = registry.iter().find(|e| e.name == type_name.as_str());
        let info = entry.and_then(|entry| {
            let (params, _) = components::declared(entry, false);
            params.into_iter().find(|p| p.name == parameter)
        });
        let error = |message: String| ModelError::Parameter {
            component: component.to_string(),
            type_name: type_name.clone(),
            parameter: parameter.to_string(),
            message,
        };
        match info.map(|p| p.fixed_because()) {
            None => Err(error("no such parameter".into())),
            Some(Some(why)) => Err(error(format!(
                "fixed ({why}): it cannot change in a running simulation"
            ))),
            Some(None) => Ok(()),
        }
    }

    /// A variant with `overrides` applied (each value as it would be written in the model
    /// file). Every name and value is checked before anything is built.
    pub fn with(&self, overrides: &[(&str, toml::Value)]) -> ModelResult<Self> {
        Ok(self.with_report(overrides)?.0)
    }

    /// `with`, also saying whether the topology had to be resolved anew.
    pub fn with_report(
        &self,
        overrides: &[(&str, toml::Value)],
    ) -> ModelResult<(Self, Recompiled)> {
        let mut spec = (*self.spec).clone();
        let mut numbers = std::mem::take(&mut spec.parameters);
        let changed = self.apply(
            (&mut spec.experiment, &mut numbers),
            overrides,
            |ci, parameter, value| {
                let params = &mut spec.components[ci].params;
                let value = overriding(params.get(parameter), value);
                params.insert(parameter.to_string(), value);
            },
        )?;
        spec.parameters = numbers;
        let (components, topology, how) = self.recompile(&spec, &changed)?;
        let system = build(&spec, &topology, &components)?;
        let variant = Self {
            spec: Arc::new(spec),
            components: Arc::new(components),
            topology,
            system: Arc::new(system),
        };
        Ok((variant, how))
    }

    /// Only the system of a variant: what a sweep runs (no copy of the model description
    /// beyond the components it changes).
    pub fn variant_system(&self, overrides: &[(&str, toml::Value)]) -> ModelResult<Arc<System>> {
        if overrides.is_empty() {
            return Ok(self.system.clone());
        }
        let mut experiment = self.spec.experiment.clone();
        let mut numbers = self.spec.parameters.clone();
        let mut edited: Vec<(usize, ComponentSpec)> = Vec::new();
        let changed = self.apply(
            (&mut experiment, &mut numbers),
            overrides,
            |ci, parameter, value| {
                let at = match edited.iter().position(|(k, _)| *k == ci) {
                    Some(at) => at,
                    None => {
                        edited.push((ci, self.spec.components[ci].clone()));
                        edited.len() - 1
                    }
                };
                let params = &mut edited[at].1.params;
                let value = overriding(params.get(parameter), value);
                params.insert(parameter.to_string(), value);
            },
        )?;
        debug_assert_eq!(changed.len(), edited.len());
        let (comps, same_ports) = self.recreate(edited.iter().map(|(ci, c)| (*ci, c)))?;
        if !same_ports {
            // a structural change: the general path
            return Ok(self.with(overrides)?.system());
        }
        let view = SpecView {
            name: &self.spec.name,
            experiment: &experiment,
            written: &self.spec.written,
            variables: &self.spec.variables,
            parameters: &numbers,
        };
        Ok(Arc::new(build_with(&view, &self.topology, &comps)?))
    }

    /// Applies overrides: experiment settings into `experiment`, the numbers derived
    /// variables read (`[parameters]`) into `numbers`, parameters through `set` (component
    /// index, parameter, value). Returns the changed components, sorted.
    fn apply(
        &self,
        (experiment, numbers): (&mut Experiment, &mut Vec<(String, f64)>),
        overrides: &[(&str, toml::Value)],
        mut set: impl FnMut(usize, &str, &toml::Value),
    ) -> ModelResult<Vec<usize>> {
        let mut changed: Vec<usize> = Vec::new();
        for (name, value) in overrides {
            match split_last(name) {
                Some((component, parameter)) => {
                    let ci = self.component_index(component)?;
                    set(ci, parameter, value);
                    changed.push(ci);
                }
                None => match numbers.iter_mut().find(|(n, _)| n == name) {
                    Some((_, number)) => *number = plain_number(name, value)?,
                    None => set_experiment(experiment, name, value)?,
                },
            }
        }
        experiment.validate()?;
        changed.sort_unstable();
        changed.dedup();
        Ok(changed)
    }

    /// The components of `spec` with `changed` ones created anew, and the topology they need.
    fn recompile(
        &self,
        spec: &ModelSpec,
        changed: &[usize],
    ) -> ModelResult<(Components, Arc<Topology>, Recompiled)> {
        let (comps, same_ports) =
            self.recreate(changed.iter().map(|&ci| (ci, &spec.components[ci])))?;
        if same_ports {
            return Ok((comps, self.topology.clone(), Recompiled::Build));
        }
        let topology = Topology::resolve(spec, &comps)?;
        Ok((comps, Arc::new(topology), Recompiled::Topology))
    }

    /// The components with the `edited` ones created anew from their specifications, and
    /// whether those still declare the ports the topology was resolved for.
    fn recreate<'a>(
        &self,
        edited: impl Iterator<Item = (usize, &'a ComponentSpec)>,
    ) -> ModelResult<(Components, bool)> {
        let mut comps: Components = (*self.components).clone();
        let mut same_ports = true;
        for (ci, component) in edited {
            comps[ci] = components::create(component, &self.spec.base_dir)?.into();
            same_ports &= comps[ci].ports() == self.topology.port_decls[ci];
        }
        Ok((comps, same_ports))
    }

    fn component_index(&self, name: &str) -> ModelResult<usize> {
        self.topology
            .names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| ModelError::Component {
                component: name.to_string(),
                message: format!(
                    "no such component (components: {})",
                    self.topology.names.join(", ")
                ),
            })
    }
}

/// A `[parameters]` number's new value.
fn plain_number(name: &str, value: &toml::Value) -> ModelResult<f64> {
    match value {
        toml::Value::Float(f) => Ok(*f),
        toml::Value::Integer(i) => Ok(*i as f64),
        toml::Value::Boolean(b) => Ok(f64::from(u8::from(*b))),
        _ => Err(ModelError::File(format!(
            "parameter '{name}' must be a number"
        ))),
    }
}

fn set_experiment(experiment: &mut Experiment, name: &str, value: &toml::Value) -> ModelResult<()> {
    let error = |message: String| ModelError::File(format!("experiment: {message}"));
    if name == "Solver" {
        let solver = value
            .as_str()
            .ok_or_else(|| error("Solver must be a string".into()))?;
        experiment.set_solver(solver);
        return Ok(());
    }
    if !EXPERIMENT.contains(&name) {
        return Err(error(format!(
            "'{name}' is neither an experiment setting ({}) nor written 'component.parameter'",
            EXPERIMENT.join(", ")
        )));
    }
    let number = value
        .as_float()
        .or_else(|| value.as_integer().map(|i| i as f64))
        .ok_or_else(|| error(format!("{name} must be a number")))?;
    experiment.set(name, number)
}
