//! Reading one component's parameters: typed getters with defaults and range checks, and a final
//! check that no unknown parameter was given. Every error names the component and the parameter.
//!
//! Each getter takes the parameter's declaration, `"name [unit] description"`, so what the
//! reference says about a parameter sits on the line that reads it. Run in catalogue mode
//! (`Params::catalogue`), a constructor records every declaration with its default and range:
//! that record is the component catalogue (`crate::catalogue`), the one source of the Python
//! classes, their docstrings and stubs, `stiction describe` and docs/components.md.

use std::cell::RefCell;
use std::path::Path;

use super::decl::{decl_name, parse_decl, ParamInfo, ParamKind};
use crate::error::{ModelError, ModelResult};
use crate::model::ComponentSpec;

/// A start value as Modelica has it: `fixed` ones are initial equations, others are guesses.
/// `nominal` is the variable's scale, as Modelica's attribute: the integrator controls the
/// states the variable is made of to an absolute error of Tolerance·nominal (1: Tolerance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitValue {
    pub start: f64,
    pub fixed: bool,
    pub nominal: f64,
}

impl InitValue {
    /// A fixed start value (an initial equation) of nominal 1.
    pub fn fixed(start: f64) -> Self {
        Self {
            start,
            fixed: true,
            nominal: 1.0,
        }
    }

    /// A guess for the initialization, of nominal 1.
    pub fn guess(start: f64) -> Self {
        Self {
            fixed: false,
            ..Self::fixed(start)
        }
    }
}

/// The value a parameter or start value set anew (a sweep, an FMU host, `params=`) takes: a start
/// value keeps the `nominal` the model gave its variable, which scales the error control and is
/// no part of the value.
pub fn overriding(old: Option<&toml::Value>, new: &toml::Value) -> toml::Value {
    let nominal = match old {
        Some(toml::Value::Table(t)) => t.get("nominal"),
        _ => None,
    };
    let Some(nominal) = nominal else {
        return new.clone();
    };
    let mut table = match new {
        toml::Value::Table(t) if t.contains_key("nominal") => return new.clone(),
        toml::Value::Table(t) => t.clone(),
        toml::Value::Float(_) | toml::Value::Integer(_) => {
            let mut t = toml::map::Map::new();
            t.insert("start".into(), new.clone());
            t.insert("fixed".into(), toml::Value::Boolean(true));
            t
        }
        _ => return new.clone(),
    };
    table.insert("nominal".into(), nominal.clone());
    toml::Value::Table(table)
}

pub struct Params<'a> {
    spec: &'a ComponentSpec,
    /// Folder that relative file names are resolved against.
    pub base_dir: &'a Path,
    // the names declared (`&'static`: the declarations are constants, no copy per component;
    // a Vec: a component declares a dozen or so, and a set's nodes cost more than the scan)
    used: RefCell<Vec<&'static str>>,
    /// Catalogue mode records each declaration; required values default to 1 and nothing is
    /// range-checked. `Some(on)`: Booleans not given default to `on` (to show conditional ports).
    catalogue: Option<bool>,
    infos: RefCell<Vec<ParamInfo>>,
}

impl<'a> Params<'a> {
    pub fn new(spec: &'a ComponentSpec, base_dir: &'a Path) -> Self {
        Self {
            spec,
            base_dir,
            used: RefCell::new(Vec::new()),
            catalogue: None,
            infos: RefCell::new(Vec::new()),
        }
    }

    /// Catalogue mode: records every parameter the constructor reads; Booleans the spec does
    /// not set read as `booleans` (true: every conditional port shows).
    pub fn catalogue(spec: &'a ComponentSpec, booleans: bool) -> Self {
        Self {
            catalogue: Some(booleans),
            ..Self::new(spec, Path::new("."))
        }
    }

    /// The parameters recorded in catalogue mode, in the order the constructor read them.
    pub fn infos(&self) -> Vec<ParamInfo> {
        self.infos.borrow().clone()
    }

    fn schema(&self) -> bool {
        self.catalogue.is_some()
    }

    /// Records a declaration (in catalogue mode) and marks the parameter used; gives its name.
    fn declare(
        &self,
        decl: &'static str,
        kind: ParamKind,
        default: Option<toml::Value>,
    ) -> &'static str {
        if !self.schema() {
            // only the name is needed outside the catalogue: no scan of the description
            let name = decl_name(decl);
            self.used.borrow_mut().push(name);
            return name;
        }
        let (name, unit, description) = parse_decl(decl);
        if !self.infos.borrow().iter().any(|i| i.name == name) {
            self.infos.borrow_mut().push(ParamInfo {
                name: name.to_string(),
                kind,
                required: default.is_none(),
                default,
                unit: unit.to_string(),
                description: description.to_string(),
                range: None,
            });
        }
        self.used.borrow_mut().push(name);
        name
    }

    /// Marks a declared parameter known without reading it (outside catalogue mode): for a
    /// family of parameters a component skips when none of them is given.
    pub fn mark_used(&self, decl: &'static str) {
        debug_assert!(!self.schema(), "the catalogue reads every declaration");
        self.used.borrow_mut().push(decl_name(decl));
    }

    /// Records the valid range of a parameter (catalogue mode) for a check done by hand.
    pub fn range(&self, name: &str, range: &str) {
        if let Some(info) = self.infos.borrow_mut().iter_mut().find(|i| i.name == name) {
            info.range = Some(range.to_string());
        }
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
    pub fn real(&self, decl: &'static str, default: f64) -> ModelResult<f64> {
        let name = self.declare(decl, ParamKind::Real, Some(default.into()));
        match self.get(name) {
            Some(v) => self.number(name, v),
            None => Ok(default),
        }
    }

    /// A real parameter MSL declares without a default value: the user must give it.
    pub fn required(&self, decl: &'static str) -> ModelResult<f64> {
        let name = self.declare(decl, ParamKind::Real, None);
        match self.get(name) {
            Some(v) => self.number(name, v),
            None if self.schema() => Ok(1.0),
            None => Err(self.error(name, "required parameter missing (MSL gives it no default)")),
        }
    }

    pub fn at_least(&self, name: &str, value: f64, min: f64) -> ModelResult<f64> {
        if self.schema() {
            self.range(name, &format!(">= {min}"));
        }
        if value < min && !self.schema() {
            return Err(self.error(name, format!("must be >= {min}, got {value}")));
        }
        Ok(value)
    }

    /// Every value of a table (each column but the first, its abscissa) at least `min`; the
    /// catalogue's range reads `"{what} >= {min}"` (`coefficients >= 0`), which Python's
    /// construct-time check reads the same way.
    pub fn table_at_least(
        &self,
        name: &str,
        rows: &[Vec<f64>],
        min: f64,
        what: &str,
    ) -> ModelResult<()> {
        if self.schema() {
            self.range(name, &format!("{what} >= {min}"));
            return Ok(());
        }
        for row in rows {
            if let Some(v) = row[1..].iter().find(|&&v| v < min) {
                let cells: Vec<String> = row.iter().map(|c| c.to_string()).collect();
                return Err(self.error(
                    name,
                    format!(
                        "{what} must be >= {min}, got {v} in row [{}]",
                        cells.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Whether the constructor runs in catalogue mode (nothing is range-checked).
    pub fn in_catalogue(&self) -> bool {
        self.schema()
    }

    pub fn positive(&self, name: &str, value: f64) -> ModelResult<f64> {
        self.range(name, "> 0");
        if value <= 0.0 && !self.schema() {
            return Err(self.error(name, format!("must be > 0, got {value}")));
        }
        Ok(value)
    }

    /// A ratio that must not be 0 (a gear's).
    pub fn nonzero(&self, name: &str, value: f64) -> ModelResult<f64> {
        self.range(name, "!= 0");
        if value == 0.0 && !self.schema() {
            return Err(self.error(name, "must not be 0"));
        }
        Ok(value)
    }

    pub fn boolean(&self, decl: &'static str, default: bool) -> ModelResult<bool> {
        let name = self.declare(decl, ParamKind::Boolean, Some(default.into()));
        match self.get(name) {
            Some(v) => v
                .as_bool()
                .ok_or_else(|| self.error(name, format!("expected true or false, got {v}"))),
            None => Ok(self.catalogue.unwrap_or(default)),
        }
    }

    /// A string without a default (TimeTable's `file`).
    pub fn string(&self, decl: &'static str) -> ModelResult<Option<String>> {
        let name = self.declare(decl, ParamKind::String, None);
        self.optional_string(name)
    }

    fn optional_string(&self, name: &str) -> ModelResult<Option<String>> {
        match self.get(name) {
            Some(v) => v
                .as_str()
                .map(|s| Some(s.to_string()))
                .ok_or_else(|| self.error(name, format!("expected a string, got {v}"))),
            None => Ok(None),
        }
    }

    /// A choice among named options (e.g. SignTorque's `reg`).
    pub fn choice(
        &self,
        decl: &'static str,
        options: &[&str],
        default: &str,
    ) -> ModelResult<String> {
        let kind = ParamKind::Choice(options.iter().map(|o| o.to_string()).collect());
        let name = self.declare(decl, kind, Some(default.into()));
        let value = self
            .optional_string(name)?
            .unwrap_or_else(|| default.to_string());
        if !options.contains(&value.as_str()) {
            return Err(self.error(name, format!("must be one of {options:?}, got \"{value}\"")));
        }
        Ok(value)
    }

    /// A list of numbers, e.g. `offset = [0, 1.5]`; a bare number is a list of one.
    pub fn vector(&self, decl: &'static str, default: &[f64]) -> ModelResult<Vec<f64>> {
        let value = toml::Value::Array(default.iter().map(|&x| x.into()).collect());
        let name = self.declare(decl, ParamKind::Vector, Some(value));
        match self.get(name) {
            None => Ok(default.to_vec()),
            Some(toml::Value::Array(cells)) => cells.iter().map(|c| self.number(name, c)).collect(),
            Some(v) => Ok(vec![self.number(name, v)?]),
        }
    }

    /// A record of named values (`wear = { model = "energy", alpha = 1e-13 }`), None when not
    /// given; its keys are the reader's to check.
    pub fn record(&self, decl: &'static str) -> ModelResult<Option<&'a toml::Table>> {
        let empty = toml::Value::Table(toml::Table::new());
        let name = self.declare(decl, ParamKind::Record, Some(empty));
        match self.get(name) {
            None => Ok(None),
            Some(toml::Value::Table(t)) => Ok(Some(t)),
            Some(v) => Err(self.error(name, format!("expected a table {{ … }}, got {v}"))),
        }
    }

    /// The number of cells in the first row of a given matrix parameter (how wide a table the
    /// user wrote), None if it is not given or not a matrix.
    pub fn matrix_width(&self, name: &str) -> Option<usize> {
        let rows = self.get(name)?.as_array()?;
        Some(rows.first()?.as_array()?.len())
    }

    /// A matrix with a fixed number of columns, e.g. `mu_pos = [[0, 0.5], [10, 0.4]]`. A flat
    /// list `[0.5, 0.4]` is refused (was it one row or one column?) with the matrix it may mean;
    /// so is a ragged one.
    pub fn matrix(
        &self,
        decl: &'static str,
        columns: usize,
        default: &[&[f64]],
    ) -> ModelResult<Vec<Vec<f64>>> {
        // the default as a TOML value only for the catalogue, the one reader of it (every
        // clutch of a model made it, and dropped it)
        let value = self.schema().then(|| {
            toml::Value::Array(
                default
                    .iter()
                    .map(|r| toml::Value::Array(r.iter().map(|&x| x.into()).collect()))
                    .collect(),
            )
        });
        let name = self.declare(decl, ParamKind::Table(columns), value);
        let Some(v) = self.get(name) else {
            return Ok(default.iter().map(|r| r.to_vec()).collect());
        };
        let example = || matrix_example(columns); // for a message only
        let shape_err = || {
            self.error(
                name,
                format!(
                    "expected a matrix of rows with {columns} columns, like {}",
                    example()
                ),
            )
        };
        let rows = v.as_array().ok_or_else(shape_err)?;
        if rows.iter().any(|r| !r.is_array()) {
            return Err(self.error(name, flat_message(v, rows, columns, &example())));
        }
        let mut out = Vec::with_capacity(rows.len());
        for row in rows {
            let cells = row.as_array().ok_or_else(shape_err)?;
            if cells.len() != columns {
                return Err(self.error(
                    name,
                    format!(
                        "every row must have {columns} columns, found {row} with {}; \
                         expected the form {}",
                        cells.len(),
                        example()
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

    /// A start value: a bare number is a fixed start value, `{ start = …, fixed = …, nominal = … }`
    /// says more.
    pub fn init(&self, decl: &'static str, default_start: f64) -> ModelResult<InitValue> {
        self.init_with(decl, default_start, false)
    }

    /// A start value that MSL declares fixed (`phi(start = 0, fixed = true)`): fixed unless
    /// the model says `fixed = false`.
    pub fn init_fixed(&self, decl: &'static str, default_start: f64) -> ModelResult<InitValue> {
        self.init_with(decl, default_start, true)
    }

    fn init_with(
        &self,
        decl: &'static str,
        default_start: f64,
        default_fixed: bool,
    ) -> ModelResult<InitValue> {
        let name = self.declare(decl, ParamKind::Start, Some(default_start.into()));
        match self.get(name) {
            None => Ok(InitValue {
                start: default_start,
                fixed: default_fixed,
                nominal: 1.0,
            }),
            Some(toml::Value::Table(t)) => {
                for key in t.keys() {
                    if !["start", "fixed", "nominal"].contains(&key.as_str()) {
                        return Err(self
                            .error(name, format!("unknown key '{key}' (start, fixed, nominal)")));
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
                    None => default_fixed,
                };
                let nominal = match t.get("nominal") {
                    Some(v) => self.nominal(name, v)?,
                    None => 1.0,
                };
                Ok(InitValue {
                    start,
                    fixed,
                    nominal,
                })
            }
            Some(v) => Ok(InitValue::fixed(self.number(name, v)?)),
        }
    }

    /// A start value's `nominal`: a positive finite number.
    fn nominal(&self, name: &str, v: &toml::Value) -> ModelResult<f64> {
        let nominal = self.number(name, v)?;
        if nominal.is_finite() && nominal > 0.0 {
            Ok(nominal)
        } else {
            Err(self.error(name, format!("'nominal' must be positive, got {nominal}")))
        }
    }

    /// The start value of a Boolean (`stuck = { start = false, fixed = true }` or `stuck = false`):
    /// it becomes the `pre()` value at initialization.
    pub fn boolean_start(&self, decl: &'static str, default: bool) -> ModelResult<bool> {
        let name = self.declare(decl, ParamKind::BooleanStart, Some(default.into()));
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
            if !used.contains(&key.as_str()) && !known_extra.contains(&key.as_str()) {
                // sorted and each once, as the set it was listed from had them
                let mut known: Vec<&str> = used.clone();
                known.sort_unstable();
                known.dedup();
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

/// `[[x1, y1], [x2, y2]]` with as many entries per row as the table has columns.
fn matrix_example(columns: usize) -> String {
    let row = |k: usize| {
        let cells: Vec<String> = (1..=columns)
            .map(|c| {
                format!(
                    "{}{k}",
                    ["x", "y", "z", "u", "v"].get(c - 1).unwrap_or(&"c")
                )
            })
            .collect();
        format!("[{}]", cells.join(", "))
    };
    format!("[{}, {}, …]", row(1), row(2))
}

/// The message for a flat list: what the matrix form looks like, with the user's numbers when
/// they fill whole rows.
fn flat_message(v: &toml::Value, items: &[toml::Value], columns: usize, example: &str) -> String {
    let what = if items.iter().any(|x| x.is_array()) {
        "mixes rows and single numbers"
    } else {
        "is a flat list"
    };
    let mut text = format!(
        "{v} {what}, but a table is a matrix (a list of rows with {columns} columns): {example}"
    );
    if !items.is_empty()
        && items.len().is_multiple_of(columns)
        && items.iter().all(|x| !x.is_array())
    {
        let rows: Vec<String> = items
            .chunks(columns)
            .map(|r| {
                let cells: Vec<String> = r.iter().map(|x| x.to_string()).collect();
                format!("[{}]", cells.join(", "))
            })
            .collect();
        text += &format!("; as rows, {v} reads [{}]", rows.join(", "));
    }
    text
}
