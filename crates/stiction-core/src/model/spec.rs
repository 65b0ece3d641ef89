//! The model file format (design.md §4): `name`, `[experiment]`, `[components]`, `connect`.

use std::path::PathBuf;

use super::expr::DerivedSpec;
use super::names::{is_component_name, is_identifier, split_last};
use crate::error::{ModelError, ModelResult};

/// One component as written: its instance name, its type and its raw parameter values.
#[derive(Debug, Clone)]
pub struct ComponentSpec {
    pub name: String,
    pub type_name: String,
    pub params: toml::Table,
}

/// `comp.port`: the port is the last segment, the component the dotted path before it
/// (`front.clutch.flange_a`: component `front.clutch`, port `flange_a`).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PortRef {
    pub component: String,
    pub port: String,
}

impl PortRef {
    pub fn parse(text: &str) -> ModelResult<Self> {
        match split_last(text) {
            Some((c, p)) => Ok(Self {
                component: c.to_string(),
                port: p.to_string(),
            }),
            _ => Err(ModelError::Connection {
                connection: format!("'{text}'"),
                message: "a port is written 'component.port'".into(),
            }),
        }
    }
}

impl std::fmt::Display for PortRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{}", self.component, self.port)
    }
}

/// Simulation settings, MSL names. `Interval` is the output grid, `Tolerance` the solver's.
#[derive(Debug, Clone, PartialEq)]
pub struct Experiment {
    pub start_time: f64,
    pub stop_time: f64,
    pub interval: f64,
    pub tolerance: f64,
    pub solver: String,
    /// The settings the model file or an override gave; the others are the defaults.
    pub given: Vec<&'static str>,
    /// Limits the user may set: a run that reaches one stops with an error saying so.
    pub limits: Limits,
}

/// `max_events` (state events), `max_steps` (integrator steps), `timeout` (wall-clock seconds).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Limits {
    pub max_events: Option<usize>,
    pub max_steps: Option<usize>,
    pub timeout: Option<f64>,
}

impl Default for Experiment {
    fn default() -> Self {
        Self {
            start_time: 0.0,
            stop_time: 1.0,
            interval: 0.002,
            tolerance: 1e-6,
            solver: "auto".into(),
            limits: Limits::default(),
            given: Vec::new(),
        }
    }
}

impl Experiment {
    /// The settings in the order they are reported.
    pub const KEYS: [&'static str; 5] =
        ["StartTime", "StopTime", "Interval", "Tolerance", "Solver"];

    /// Applies one `StartTime`/`StopTime`/`Interval`/`Tolerance` override.
    pub fn set(&mut self, key: &str, value: f64) -> ModelResult<()> {
        let (name, slot) = match key {
            "StartTime" => ("StartTime", &mut self.start_time),
            "StopTime" => ("StopTime", &mut self.stop_time),
            "Interval" => ("Interval", &mut self.interval),
            "Tolerance" => ("Tolerance", &mut self.tolerance),
            "max_events" => {
                self.limits.max_events = Some(count(key, value)?);
                return Ok(());
            }
            "max_steps" => {
                self.limits.max_steps = Some(count(key, value)?);
                return Ok(());
            }
            "timeout" if value > 0.0 => {
                self.limits.timeout = Some(value);
                return Ok(());
            }
            "timeout" => {
                return Err(ModelError::File(
                    "experiment: timeout must be a positive number of seconds".into(),
                ))
            }
            _ => {
                return Err(ModelError::File(format!(
                    "experiment: unknown setting '{key}' (StartTime, StopTime, Interval, Tolerance, Solver, max_events, max_steps, timeout)"
                )))
            }
        };
        *slot = value;
        self.mark_given(name);
        Ok(())
    }

    /// The k-th point of the output grid.
    pub fn grid_time(&self, k: usize) -> f64 {
        (self.start_time + k as f64 * self.interval).min(self.stop_time)
    }

    /// The index of the last grid point (StopTime).
    pub fn grid_len(&self) -> usize {
        ((self.stop_time - self.start_time) / self.interval - 1e-9).ceil() as usize
    }

    /// Chooses the integrator (checked by `validate`).
    pub fn set_solver(&mut self, solver: &str) {
        self.solver = solver.to_string();
        self.mark_given("Solver");
    }

    fn mark_given(&mut self, name: &'static str) {
        if !self.given.contains(&name) {
            self.given.push(name);
        }
    }

    /// The settings left at their defaults (none given in the file or as an override).
    pub fn defaults(&self) -> Vec<&'static str> {
        Self::KEYS
            .into_iter()
            .filter(|k| !self.given.contains(k))
            .collect()
    }

    pub fn validate(&self) -> ModelResult<()> {
        let bad =
            |what: &str, why: &str| Err(ModelError::File(format!("experiment: {what} {why}")));
        for (name, v) in [
            ("StartTime", self.start_time),
            ("StopTime", self.stop_time),
            ("Interval", self.interval),
            ("Tolerance", self.tolerance),
        ] {
            if !v.is_finite() {
                return bad(name, "must be a finite number");
            }
        }
        if self.stop_time <= self.start_time {
            return bad("StopTime", "must be greater than StartTime");
        }
        if self.interval <= 0.0 {
            return bad("Interval", "must be positive");
        }
        if (self.stop_time - self.start_time) / self.interval > 5e7 {
            return bad("Interval", "gives more than 5e7 output points");
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return bad("Tolerance", "must be in (0, 1)");
        }
        if !["auto", "tsit45", "bdf", "esdirk34"].contains(&self.solver.as_str()) {
            return bad(
                "Solver",
                "must be one of \"auto\" (default: tsit45, esdirk34 once stiff), \"tsit45\" (non-stiff), \"bdf\", \"esdirk34\" (stiff)",
            );
        }
        Ok(())
    }
}

/// A limit that counts: a positive whole number.
fn count(key: &str, value: f64) -> ModelResult<usize> {
    if value >= 1.0 && value.fract() == 0.0 && value < 1e15 {
        Ok(value as usize)
    } else {
        Err(ModelError::File(format!(
            "experiment: {key} must be a positive whole number, got {value}"
        )))
    }
}

/// The model file format this version reads and writes. Readers accept every older version and
/// refuse a newer one by name.
pub const FORMAT_VERSION: i64 = 1;

/// A model input: an unconnected signal input port and its value until it is first set.
#[derive(Debug, Clone, PartialEq)]
pub struct InputSpec {
    pub port: PortRef,
    pub start: f64,
}

/// A whole model as read from a file or built in Python.
#[derive(Debug, Clone)]
pub struct ModelSpec {
    pub name: String,
    pub experiment: Experiment,
    pub components: Vec<ComponentSpec>,
    pub connections: Vec<(PortRef, PortRef)>,
    /// Signal inputs left unconnected on purpose: inputs of the model, set while it runs.
    pub inputs: Vec<InputSpec>,
    /// Folder that relative file names in parameters (time tables) are resolved against.
    pub base_dir: PathBuf,
    /// Component names in the order the model was written, when `components` was put in a
    /// canonical order (see `assembly::canonical`); empty otherwise.
    pub written: Vec<String>,
    /// Derived variables (`[variables]`, `slip = "J1.w - J2.w"`), in the order written: result
    /// variables computed from the others (`system::formula`).
    pub variables: Vec<DerivedSpec>,
    /// Named numbers the derived variables may read (`[parameters]`: the model's top-level
    /// parameters, evaluated); a variant may set one by its name.
    pub parameters: Vec<(String, f64)>,
}

impl ModelSpec {
    pub fn from_toml(text: &str, base_dir: impl Into<PathBuf>) -> ModelResult<Self> {
        Self::from_table(&parse_document(text)?, base_dir)
    }

    /// The model of an already parsed model file (`parse_document`): a caller that reads the
    /// document itself too (the Python package's loader) parses the text once.
    pub fn from_table(doc: &toml::Table, base_dir: impl Into<PathBuf>) -> ModelResult<Self> {
        let mut spec = ModelSpec {
            name: "model".into(),
            experiment: Experiment::default(),
            components: Vec::new(),
            connections: Vec::new(),
            inputs: Vec::new(),
            base_dir: base_dir.into(),
            written: Vec::new(),
            variables: Vec::new(),
            parameters: Vec::new(),
        };
        let mut connect: Option<&toml::Value> = None;
        let mut inputs: Option<&toml::Value> = None;
        for (key, value) in doc {
            match key.as_str() {
                "name" => {
                    spec.name = value
                        .as_str()
                        .ok_or_else(|| ModelError::File("'name' must be a string".into()))?
                        .to_string()
                }
                "experiment" => spec.experiment = read_experiment(value)?,
                "components" => {
                    let table = value
                        .as_table()
                        .ok_or_else(|| ModelError::File("'components' must be a table".into()))?;
                    for (name, comp) in table {
                        // `connect = [...]` written after `[components]` lands here in TOML.
                        if name == "connect" && comp.is_array() {
                            connect = Some(comp);
                            continue;
                        }
                        if name == "inputs" && comp.is_array() {
                            inputs = Some(comp);
                            continue;
                        }
                        spec.components.push(read_component(name, comp)?);
                    }
                }
                "connect" => connect = Some(value),
                "inputs" => inputs = Some(value),
                "format" => check_format(value)?,
                "variables" => spec.variables = read_variables(value)?,
                "parameters" => spec.parameters = read_parameters(value)?,
                other => {
                    return Err(ModelError::File(format!(
                        "unknown top-level key '{other}' (expected format, name, experiment, components, connect, inputs, variables, parameters)"
                    )))
                }
            }
        }
        if let Some(list) = connect {
            spec.connections = read_connections(list)?;
        }
        if let Some(list) = inputs {
            spec.inputs = read_inputs(list)?;
        }
        spec.experiment.validate()?;
        Ok(spec)
    }
}

/// A model file's TOML document (an error if the text is not TOML).
pub fn parse_document(text: &str) -> ModelResult<toml::Table> {
    text.parse().map_err(|e: toml::de::Error| {
        ModelError::File(format!("model file is not valid TOML: {e}"))
    })
}

fn check_format(value: &toml::Value) -> ModelResult<()> {
    match value.as_integer() {
        Some(v) if (1..=FORMAT_VERSION).contains(&v) => Ok(()),
        Some(v) if v > FORMAT_VERSION => Err(ModelError::File(format!(
            "model file format {v} is newer than this version of stiction reads (format {FORMAT_VERSION}); update stiction"
        ))),
        _ => Err(ModelError::File(format!(
            "'format' must be a format version, an integer from 1 to {FORMAT_VERSION}"
        ))),
    }
}

/// `inputs = ["brake.f_normalized", { port = "motor.tau", start = 2.0 }]`.
fn read_inputs(value: &toml::Value) -> ModelResult<Vec<InputSpec>> {
    let bad = || {
        ModelError::File(
            "'inputs' must be a list of ports like [\"brake.f_normalized\"] or { port = \"brake.f_normalized\", start = 0.0 }".into(),
        )
    };
    let list = value.as_array().ok_or_else(bad)?;
    list.iter()
        .map(|item| match item {
            toml::Value::String(port) => Ok(InputSpec {
                port: PortRef::parse(port)?,
                start: 0.0,
            }),
            toml::Value::Table(t) => {
                if let Some(key) = t.keys().find(|k| *k != "port" && *k != "start") {
                    return Err(ModelError::File(format!(
                        "inputs: unknown key '{key}' (port, start)"
                    )));
                }
                let port = t.get("port").and_then(|p| p.as_str()).ok_or_else(bad)?;
                let start = match t.get("start") {
                    None => 0.0,
                    Some(v) => v
                        .as_float()
                        .or_else(|| v.as_integer().map(|i| i as f64))
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| {
                            ModelError::File(format!("inputs: '{port}': start must be a number"))
                        })?,
                };
                Ok(InputSpec {
                    port: PortRef::parse(port)?,
                    start,
                })
            }
            _ => Err(bad()),
        })
        .collect()
}

/// `[variables]`: `name = "expression"`, each parsed; a name must be an identifier.
fn read_variables(value: &toml::Value) -> ModelResult<Vec<DerivedSpec>> {
    let bad = || {
        ModelError::File(
            "'variables' must be a table of expressions, e.g. dw = \"J1.w - J2.w\"".into(),
        )
    };
    let table = value.as_table().ok_or_else(bad)?;
    let mut out: Vec<DerivedSpec> = Vec::with_capacity(table.len());
    for (name, text) in table {
        if !is_identifier(name) {
            return Err(ModelError::File(format!(
                "variable '{name}': a variable's name is an identifier (letters, digits, _)"
            )));
        }
        out.push(DerivedSpec::parse(name, text.as_str().ok_or_else(bad)?)?);
    }
    Ok(out)
}

/// `[parameters]`: numbers by name (the engine's text has them evaluated).
fn read_parameters(value: &toml::Value) -> ModelResult<Vec<(String, f64)>> {
    let table = value
        .as_table()
        .ok_or_else(|| ModelError::File("'parameters' must be a table".into()))?;
    (table.iter())
        .map(|(name, v)| {
            let number = match v {
                toml::Value::Float(f) => Some(*f),
                toml::Value::Integer(i) => Some(*i as f64),
                toml::Value::Boolean(b) => Some(f64::from(u8::from(*b))),
                _ => None,
            };
            number.map(|x| (name.clone(), x)).ok_or_else(|| {
                ModelError::File(format!(
                    "parameter '{name}': the engine reads numbers (expressions are evaluated in Python)"
                ))
            })
        })
        .collect()
}

fn read_experiment(value: &toml::Value) -> ModelResult<Experiment> {
    let table = value
        .as_table()
        .ok_or_else(|| ModelError::File("'experiment' must be a table".into()))?;
    let mut exp = Experiment::default();
    for (key, v) in table {
        if key == "Solver" {
            let solver = v
                .as_str()
                .ok_or_else(|| ModelError::File("experiment: Solver must be a string".into()))?;
            exp.set_solver(solver);
            continue;
        }
        let number = v
            .as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .ok_or_else(|| ModelError::File(format!("experiment: {key} must be a number")))?;
        exp.set(key, number)?;
    }
    Ok(exp)
}

fn read_component(name: &str, value: &toml::Value) -> ModelResult<ComponentSpec> {
    let err = |message: &str| ModelError::Component {
        component: name.to_string(),
        message: message.to_string(),
    };
    if !is_component_name(name) {
        return Err(err(
            "a component name must be an identifier (letters, digits, _) or identifiers joined by dots (front.clutch)",
        ));
    }
    let table = value
        .as_table()
        .ok_or_else(|| err("must be a table like { type = \"Inertia\", J = 1.0 }"))?;
    let type_name = table
        .get("type")
        .and_then(|t| t.as_str())
        .ok_or_else(|| err("missing 'type' (e.g. type = \"Inertia\")"))?
        .to_string();
    let mut params = table.clone();
    params.remove("type");
    Ok(ComponentSpec {
        name: name.to_string(),
        type_name,
        params,
    })
}

fn read_connections(value: &toml::Value) -> ModelResult<Vec<(PortRef, PortRef)>> {
    let bad = || {
        ModelError::File(
            "'connect' must be a list of pairs like [\"J.flange_b\", \"brake.flange_a\"]".into(),
        )
    };
    let list = value.as_array().ok_or_else(bad)?;
    list.iter()
        .map(|pair| {
            let pair = pair.as_array().ok_or_else(bad)?;
            match pair.as_slice() {
                [a, b] => Ok((
                    PortRef::parse(a.as_str().ok_or_else(bad)?)?,
                    PortRef::parse(b.as_str().ok_or_else(bad)?)?,
                )),
                _ => Err(bad()),
            }
        })
        .collect()
}
