//! The FMU's variables as an instance holds them: each bound to what it stands for in the
//! model, with its values (one, or a table's elements row after row), and the model file's
//! form of the values a host set (what `CompiledModel::with` takes).

use stiction_core::CompiledModel;

use crate::layout::{parse_element, Kind, Layout, VarSpec};
use crate::snapshot::Fallible;

pub struct Var {
    pub kind: Kind,
    pub name: String,
    pub start: Vec<f64>,
    pub value: Vec<f64>,
    /// An output's column in `Simulation::values` (time: 0).
    pub column: usize,
}

impl Var {
    /// Whether the value is read from the run (else it is the one set).
    pub fn is_computed(&self) -> bool {
        matches!(
            self.kind,
            Kind::Output | Kind::Independent | Kind::Start { .. } | Kind::FlagStart
        )
    }

    /// The parameter of the model file the variable sets (an element: its table).
    pub fn parameter(&self) -> &str {
        match self.kind {
            Kind::Element { .. } => parse_element(&self.name).map_or(&self.name, |(t, _, _)| t),
            _ => &self.name,
        }
    }

    fn changed(&self) -> bool {
        (self.value.iter().zip(&self.start)).any(|(v, s)| v.to_bits() != s.to_bits())
    }
}

/// Binds the variable table to the model: each variable's column or parameter must exist.
pub fn bind(layout: Layout, model: &CompiledModel) -> Fallible<Vec<Var>> {
    let names: Vec<String> = (model.system().outputs.iter())
        .map(|(n, _)| n.clone())
        .collect();
    let params = model.parameter_names();
    let inputs: Vec<String> = (model.system().inputs.iter())
        .map(|i| i.name.clone())
        .collect();
    let bind_one = |v: VarSpec| {
        let column = |name: &str| names.iter().position(|n| n == name).map(|k| k + 1);
        let known = match v.kind {
            Kind::Output | Kind::Start { .. } | Kind::FlagStart => column(&v.name),
            Kind::Parameter | Kind::Flag | Kind::Table { .. } => {
                params.contains(&v.name).then_some(0)
            }
            Kind::Element { .. } => parse_element(&v.name)
                .and_then(|(table, _, _)| params.iter().any(|p| p == table).then_some(0)),
            Kind::Input => inputs.contains(&v.name).then_some(0),
            Kind::Independent => Some(0), // `time` is column 0 of `Simulation::values`
        };
        let column = known.ok_or(format!("'{}' is not a {:?} of the model", v.name, v.kind))?;
        Ok(Var {
            kind: v.kind,
            name: v.name,
            value: v.start.clone(),
            start: v.start,
            column,
        })
    };
    layout.vars.into_iter().map(bind_one).collect()
}

/// A start value as the model file writes it: a guess keeps `fixed = false`.
fn start_value(fixed: bool, value: f64) -> toml::Value {
    if fixed {
        return toml::Value::Float(value);
    }
    let mut t = toml::map::Map::new();
    t.insert("start".into(), toml::Value::Float(value));
    t.insert("fixed".into(), toml::Value::Boolean(false));
    toml::Value::Table(t)
}

/// A table as the model file writes it: rows `[x, y…]`.
fn table(rows: usize, cols: usize, values: &[f64]) -> toml::Value {
    let row =
        |r: usize| toml::Value::Array((0..cols).map(|c| values[r * cols + c].into()).collect());
    toml::Value::Array((0..rows).map(row).collect())
}

/// The model-file value of a set-up variable (an element: none, its table is `elements`).
pub fn setting(kind: Kind, value: &[f64]) -> Option<toml::Value> {
    Some(match kind {
        Kind::Start { fixed } => start_value(fixed, value[0]),
        Kind::Flag | Kind::FlagStart => toml::Value::Boolean(value[0] != 0.0),
        Kind::Table { rows, cols } => table(rows, cols, value),
        Kind::Element { .. } | Kind::Input | Kind::Output | Kind::Independent => return None,
        Kind::Parameter => toml::Value::Float(value[0]),
    })
}

/// The table the FMI 2.0 elements named `name[i,j]` make, with the values `value` gives.
fn elements<'a>(vars: &'a [Var], name: &str, value: impl Fn(usize) -> &'a [f64]) -> toml::Value {
    let of_table = || (vars.iter().enumerate()).filter(|(_, v)| v.parameter() == name);
    let index = |v: &Var| match v.kind {
        Kind::Element { row, col } => (row, col),
        _ => (0, 0),
    };
    let rows = of_table().map(|(_, v)| index(v).0).max().unwrap_or(0);
    let cols = of_table().map(|(_, v)| index(v).1).max().unwrap_or(0);
    let mut values = vec![0.0; rows * cols];
    for (k, v) in of_table() {
        let (r, c) = index(v);
        values[(r - 1) * cols + c - 1] = value(k)[0];
    }
    table(rows, cols, &values)
}

/// The model-file values of `parameters` (each a parameter or a table of FMI 2.0 elements)
/// with the variables' values `values`.
pub fn settings_of(
    vars: &[Var],
    values: &[Vec<f64>],
    parameters: &[String],
) -> Vec<(String, toml::Value)> {
    let one = |p: &String| {
        let whole = (vars.iter().zip(values))
            .find(|(v, _)| v.name == *p)
            .and_then(|(v, value)| setting(v.kind, value));
        let value = whole.unwrap_or_else(|| elements(vars, p, |k| &values[k]));
        (p.clone(), value)
    };
    parameters.iter().map(one).collect()
}

/// Every set-up value that differs from the FMU's start, as the model file writes it.
pub fn overrides(vars: &[Var]) -> Vec<(String, toml::Value)> {
    let mut out: Vec<(String, toml::Value)> = Vec::new();
    for v in vars.iter().filter(|v| v.kind.is_setup() && v.changed()) {
        let value = match setting(v.kind, &v.value) {
            Some(value) => value,
            None if out.iter().any(|(n, _)| n == v.parameter()) => continue,
            None => elements(vars, v.parameter(), |k| &vars[k].value),
        };
        out.push((v.parameter().to_string(), value));
    }
    out
}
