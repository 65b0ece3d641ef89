//! TOML data as Python objects, in one place: `parse_toml` (model-file text into the objects
//! `tomllib` gives, parsed by the engine's TOML parser; the pure-Python one took 0.3 s for a
//! model of thousands of components) and `value_to_py`, which the catalogue's parameter
//! defaults go through too.

use std::sync::{Mutex, PoisonError};

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pyo3::IntoPyObjectExt;
use stiction_core::ModelSpec;

/// Parses TOML text into Python dicts, lists and scalars as `tomllib.loads` does (tables keep
/// their order), tens of times faster than the pure-Python parser on a model of thousands of
/// components. None for what it does not turn into the same objects (invalid TOML, a date or
/// time): the caller falls back to `tomllib`, which gives the error message or the datetime.
#[pyfunction]
pub fn parse_toml<'py>(py: Python<'py>, text: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
    let Ok(table) = text.parse::<toml::Table>() else {
        return Ok(None);
    };
    table_to_py(py, &table)
}

/// A model file's engine description, read from the same parse as the Python objects
/// (`load_model`); a compile takes it once (`CompiledModel.from_parsed`).
#[pyclass(frozen, module = "stiction._core", name = "ParsedModel")]
pub struct ParsedModel(Mutex<Option<ModelSpec>>);

impl ParsedModel {
    /// The description of a model, for one compile to take.
    pub fn new(spec: ModelSpec) -> Self {
        Self(Mutex::new(Some(spec)))
    }

    /// The description, the first time only.
    pub fn take(&self) -> Option<ModelSpec> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner).take()
    }
}

/// The engine's description of a model file's table, named `name` when the file names none;
/// None when the engine refuses it.
pub fn named_spec(table: &toml::Table, base_dir: &str, name: &str) -> Option<ModelSpec> {
    let mut spec = ModelSpec::from_table(table, base_dir).ok()?;
    if !table.contains_key("name") {
        spec.name = name.to_string();
    }
    Some(spec)
}

/// A TOML value as the Python object `tomllib` gives (tables as dicts in their order); None
/// for a date or time, which `tomllib` turns into a datetime and this does not.
pub fn value_to_py<'py>(
    py: Python<'py>,
    value: &toml::Value,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    toml_to_py(py, value)
}

pub fn table_to_py<'py>(
    py: Python<'py>,
    table: &toml::Table,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let dict = PyDict::new(py);
    for (key, value) in table {
        match toml_to_py(py, value)? {
            Some(v) => dict.set_item(key, v)?,
            None => return Ok(None),
        }
    }
    Ok(Some(dict.into_any()))
}

fn toml_to_py<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Option<Bound<'py, PyAny>>> {
    Ok(Some(match value {
        toml::Value::String(s) => s.into_bound_py_any(py)?,
        toml::Value::Integer(i) => i.into_bound_py_any(py)?,
        toml::Value::Float(f) => f.into_bound_py_any(py)?,
        toml::Value::Boolean(b) => b.into_bound_py_any(py)?,
        toml::Value::Datetime(_) => return Ok(None),
        toml::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                match toml_to_py(py, item)? {
                    Some(v) => list.append(v)?,
                    None => return Ok(None),
                }
            }
            list.into_any()
        }
        toml::Value::Table(table) => return table_to_py(py, table),
    }))
}

/// The counts of components and connections of a model file whose whole content the engine
/// reads as the Python model would hold it, and that nothing of the Python checks at load
/// refuses where the engine would not: only `format` (1), `name`, `connect`, `experiment` and
/// `components`; every parameter a number or a Boolean (held as written, no unit to convert);
/// no port joined to itself and no pair joined twice. None for any other file: the Python
/// model is built at load, as always, and says what is wrong.
pub fn plain_counts(doc: &toml::Table) -> Option<(usize, usize)> {
    let mut counts = (0, 0);
    for (key, value) in doc {
        match key.as_str() {
            "format" => (value.as_integer() == Some(1)).then_some(())?,
            "name" => value
                .as_str()
                .is_some_and(|s| !s.is_empty())
                .then_some(())?,
            "experiment" => plain_experiment(value)?,
            "components" => counts.0 = plain_components(value)?,
            "connect" => counts.1 = plain_connections(value)?,
            _ => return None,
        }
    }
    Some(counts)
}

fn plain_experiment(value: &toml::Value) -> Option<()> {
    let table = value.as_table()?;
    let ok = table.iter().all(|(key, v)| match v {
        toml::Value::String(_) => key == "Solver",
        toml::Value::Integer(_) | toml::Value::Float(_) => key != "Solver",
        _ => false,
    });
    ok.then_some(())
}

fn plain_components(value: &toml::Value) -> Option<usize> {
    let table = value.as_table()?;
    let plain = |entry: &toml::Value| {
        entry.as_table().is_some_and(|params| {
            params.get("type").is_some_and(toml::Value::is_str)
                && params.iter().all(|(key, v)| {
                    key == "type"
                        || (!key.is_empty()
                            && matches!(
                                v,
                                toml::Value::Integer(_)
                                    | toml::Value::Float(_)
                                    | toml::Value::Boolean(_)
                            ))
                })
        })
    };
    table.values().all(plain).then_some(table.len())
}

fn plain_connections(value: &toml::Value) -> Option<usize> {
    let pairs = value.as_array()?;
    let mut seen = std::collections::HashSet::with_capacity(pairs.len());
    for pair in pairs {
        let [a, b] = pair.as_array()?.as_slice() else {
            return None;
        };
        let (a, b) = (a.as_str()?, b.as_str()?);
        // Python refuses a port joined to itself and a pair joined twice, either way round
        if a == b || !seen.insert(if a < b { (a, b) } else { (b, a) }) {
            return None;
        }
    }
    Some(pairs.len())
}
