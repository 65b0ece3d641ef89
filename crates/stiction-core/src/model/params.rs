//! Reading one component's parameters: typed getters with defaults and range checks, and a final
//! check that no unknown parameter was given. Every error names the component and the parameter.

use std::cell::RefCell;
use std::collections::BTreeSet;
use std::path::Path;

use crate::error::{ModelError, ModelResult};
use crate::model::ComponentSpec;

/// A start value as Modelica has it: `fixed` ones are initial equations, others are guesses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitValue {
    pub start: f64,
    pub fixed: bool,
}

pub struct Params<'a> {
    spec: &'a ComponentSpec,
    /// Folder that relative file names are resolved against.
    pub base_dir: &'a Path,
    used: RefCell<BTreeSet<String>>,
    /// Schema mode lists a type's parameters and ports: required values default to 1,
    /// Booleans to true (so conditional ports show), and nothing is range-checked.
    schema: bool,
}

impl<'a> Params<'a> {
    pub fn new(spec: &'a ComponentSpec, base_dir: &'a Path) -> Self {
        Self {
            spec,
            base_dir,
            used: RefCell::new(BTreeSet::new()),
            schema: false,
        }
    }

    pub fn schema(spec: &'a ComponentSpec) -> Self {
        Self {
            schema: true,
            ..Self::new(spec, Path::new("."))
        }
    }

    /// The parameter names read so far (all of them, once a constructor has run).
    pub fn names(&self) -> Vec<String> {
        self.used.borrow().iter().cloned().collect()
    }

    pub fn component(&self) -> &str {
        &self.spec.name
    }

    pub fn error(&self, parameter: &str, message: impl Into<String>) -> ModelError {
        ModelError::Parameter {
            component: self.spec.name.clone(),
            type_name: self.spec.type_name.clone(),
            parameter: parameter.to_string(),
            message: message.into(),
        }
    }

    /// Whether the user gave this parameter.
    pub fn has(&self, name: &str) -> bool {
        self.spec.params.contains_key(name)
    }

    fn get(&self, name: &str) -> Option<&'a toml::Value> {
        self.used.borrow_mut().insert(name.to_string());
        self.spec.params.get(name)
    }

    fn number(&self, name: &str, v: &toml::Value) -> ModelResult<f64> {
        let x = v
            .as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .ok_or_else(|| self.error(name, format!("expected a number, got {v}")))?;
        if !x.is_finite() {
            return Err(self.error(name, format!("must be finite, got {x}")));
        }
        Ok(x)
    }

    /// A real parameter with a default (MSL's default where it has one).
    pub fn real(&self, name: &str, default: f64) -> ModelResult<f64> {
        match self.get(name) {
            Some(v) => self.number(name, v),
            None => Ok(default),
        }
    }

    /// A real parameter MSL declares without a default value: the user must give it.
    pub fn required(&self, name: &str) -> ModelResult<f64> {
        match self.get(name) {
            Some(v) => self.number(name, v),
            None if self.schema => Ok(1.0),
            None => Err(self.error(name, "required parameter missing (MSL gives it no default)")),
        }
    }

    pub fn at_least(&self, name: &str, value: f64, min: f64) -> ModelResult<f64> {
        if value < min && !self.schema {
            return Err(self.error(name, format!("must be >= {min}, got {value}")));
        }
        Ok(value)
    }

    pub fn positive(&self, name: &str, value: f64) -> ModelResult<f64> {
        if value <= 0.0 && !self.schema {
            return Err(self.error(name, format!("must be > 0, got {value}")));
        }
        Ok(value)
    }

    pub fn boolean(&self, name: &str, default: bool) -> ModelResult<bool> {
        match self.get(name) {
            Some(v) => v
                .as_bool()
                .ok_or_else(|| self.error(name, format!("expected true or false, got {v}"))),
            None => Ok(default || self.schema),
        }
    }

    pub fn string(&self, name: &str) -> ModelResult<Option<String>> {
        match self.get(name) {
            Some(v) => v
                .as_str()
                .map(|s| Some(s.to_string()))
                .ok_or_else(|| self.error(name, format!("expected a string, got {v}"))),
            None => Ok(None),
        }
    }

    /// A choice among named options (e.g. SignTorque's `reg`).
    pub fn choice(&self, name: &str, options: &[&str], default: &str) -> ModelResult<String> {
        let value = self.string(name)?.unwrap_or_else(|| default.to_string());
        if !options.contains(&value.as_str()) {
            return Err(self.error(name, format!("must be one of {options:?}, got \"{value}\"")));
        }
        Ok(value)
    }

    /// A matrix with a fixed number of columns, e.g. `mu_pos = [[0, 0.5], [10, 0.4]]`.
    /// A flat list `[0, 0.5]` is one row, as Modelica writes `[0, 0.5]`.
    pub fn matrix(
        &self,
        name: &str,
        columns: usize,
        default: &[&[f64]],
    ) -> ModelResult<Vec<Vec<f64>>> {
        let Some(v) = self.get(name) else {
            return Ok(default.iter().map(|r| r.to_vec()).collect());
        };
        let shape_err = || {
            self.error(
                name,
                format!(
                    "expected a table of rows with {columns} columns, like [[0, 0.5], [10, 0.4]]"
                ),
            )
        };
        let rows = v.as_array().ok_or_else(shape_err)?;
        let rows: Vec<&toml::Value> = if rows.iter().all(|r| !r.is_array()) {
            vec![v]
        } else {
            rows.iter().collect()
        };
        let mut out = Vec::with_capacity(rows.len());
        for row in rows {
            let cells = row.as_array().ok_or_else(shape_err)?;
            if cells.len() != columns {
                return Err(self.error(
                    name,
                    format!(
                        "every row must have {columns} columns, found a row with {}",
                        cells.len()
                    ),
                ));
            }
            out.push(
                cells
                    .iter()
                    .map(|c| self.number(name, c))
                    .collect::<ModelResult<Vec<f64>>>()?,
            );
        }
        if out.is_empty() {
            return Err(shape_err());
        }
        Ok(out)
    }

    /// A start value: a bare number is a fixed start value, `{ start = …, fixed = … }` says both.
    pub fn init(&self, name: &str, default_start: f64) -> ModelResult<InitValue> {
        match self.get(name) {
            None => Ok(InitValue {
                start: default_start,
                fixed: false,
            }),
            Some(toml::Value::Table(t)) => {
                for key in t.keys() {
                    if key != "start" && key != "fixed" {
                        return Err(self.error(name, format!("unknown key '{key}' (start, fixed)")));
                    }
                }
                let start = match t.get("start") {
                    Some(v) => self.number(name, v)?,
                    None => default_start,
                };
                let fixed = match t.get("fixed") {
                    Some(v) => v
                        .as_bool()
                        .ok_or_else(|| self.error(name, "'fixed' must be true or false"))?,
                    None => false,
                };
                Ok(InitValue { start, fixed })
            }
            Some(v) => Ok(InitValue {
                start: self.number(name, v)?,
                fixed: true,
            }),
        }
    }

    /// The start value of a Boolean (`stuck = { start = false, fixed = true }` or `stuck = false`):
    /// it becomes the `pre()` value at initialization.
    pub fn boolean_start(&self, name: &str, default: bool) -> ModelResult<bool> {
        match self.get(name) {
            None => Ok(default),
            Some(toml::Value::Boolean(b)) => Ok(*b),
            Some(toml::Value::Table(t)) => {
                for key in t.keys() {
                    if key != "start" && key != "fixed" {
                        return Err(self.error(name, format!("unknown key '{key}' (start, fixed)")));
                    }
                }
                match (t.get("start"), t.get("fixed")) {
                    (Some(toml::Value::Boolean(b)), None | Some(toml::Value::Boolean(_))) => Ok(*b),
                    (None, None | Some(toml::Value::Boolean(_))) => Ok(default),
                    _ => Err(self.error(name, "'start' and 'fixed' must be true or false")),
                }
            }
            Some(v) => Err(self.error(
                name,
                format!("expected true/false or {{ start = …, fixed = … }}, got {v}"),
            )),
        }
    }

    /// Call last: any parameter the component did not ask for is unknown to it.
    pub fn finish(&self, known_extra: &[&str]) -> ModelResult<()> {
        let used = self.used.borrow();
        for key in self.spec.params.keys() {
            if !used.contains(key) && !known_extra.contains(&key.as_str()) {
                let mut known: Vec<&str> = used.iter().map(String::as_str).collect();
                known.extend_from_slice(known_extra);
                return Err(self.error(
                    key,
                    format!(
                        "unknown parameter for {} (known: {})",
                        self.spec.type_name,
                        known.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }
}
