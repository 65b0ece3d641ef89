//! A compiled model: the model description, its components and its resolved topology, kept so
//! that a variant — other parameter values, start values or experiment settings, named the MSL
//! way (`clutch1.fn_max`, `J1.w`, `StopTime`) — costs only the components it changes and one
//! build, not a parse and a new assembly. A value that changes the structure (`useSupport`,
//! `useHeatPort`: other ports) resolves the topology anew; nothing is silently ignored.
//! Cloning is a handful of reference counts: one per thread of a sweep.

use std::sync::Arc;

use super::{build, create_components, Topology};
use crate::components::{self, Component};
use crate::error::{ModelError, ModelResult};
use crate::model::ModelSpec;
use crate::system::System;

/// The experiment settings a variant may change, by their MSL names.
const EXPERIMENT: &[&str] = &["StartTime", "StopTime", "Interval", "Tolerance", "Solver"];

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
        let schema = components::schema();
        let mut names = Vec::new();
        for c in &self.spec.components {
            if let Some((_, params, _)) = schema.iter().find(|(t, _, _)| *t == c.type_name) {
                names.extend(params.iter().map(|p| format!("{}.{p}", c.name)));
            }
        }
        names.extend(EXPERIMENT.iter().map(|s| s.to_string()));
        names
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
        let mut changed: Vec<usize> = Vec::new();
        for (name, value) in overrides {
            match name.split_once('.') {
                Some((component, parameter)) => {
                    let ci = self.component_index(component)?;
                    let params = &mut spec.components[ci].params;
                    params.insert(parameter.to_string(), value.clone());
                    changed.push(ci);
                }
                None => set_experiment(&mut spec, name, value)?,
            }
        }
        spec.experiment.validate()?;
        changed.sort_unstable();
        changed.dedup();
        let mut comps: Vec<Arc<dyn Component>> = (*self.components).clone();
        for &ci in &changed {
            comps[ci] = components::create(&spec.components[ci], &spec.base_dir)?.into();
        }
        let same_ports = changed
            .iter()
            .all(|&ci| comps[ci].ports() == self.topology.port_decls[ci]);
        let (topology, how) = if same_ports {
            (self.topology.clone(), Recompiled::Build)
        } else {
            let topology = Topology::resolve(&spec, &comps)?;
            (Arc::new(topology), Recompiled::Topology)
        };
        let system = build(&spec, &topology, &comps)?;
        let variant = Self {
            spec: Arc::new(spec),
            components: Arc::new(comps),
            topology,
            system: Arc::new(system),
        };
        Ok((variant, how))
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

fn set_experiment(spec: &mut ModelSpec, name: &str, value: &toml::Value) -> ModelResult<()> {
    let error = |message: String| ModelError::File(format!("experiment: {message}"));
    if name == "Solver" {
        let solver = value
            .as_str()
            .ok_or_else(|| error("Solver must be a string".into()))?;
        spec.experiment.solver = solver.to_string();
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
    spec.experiment.set(name, number)
}
