//! TOML data as Python objects, in one place: `parse_toml` (model-file text into the objects
//! `tomllib` gives, parsed by the engine's TOML parser; the pure-Python one took 0.3 s for a
//! model of thousands of components) and `value_to_py`, which the catalogue's parameter
//! defaults go through too.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pyo3::IntoPyObjectExt;

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

/// A TOML value as the Python object `tomllib` gives (tables as dicts in their order); None
/// for a date or time, which `tomllib` turns into a datetime and this does not.
pub fn value_to_py<'py>(
    py: Python<'py>,
    value: &toml::Value,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    toml_to_py(py, value)
}

fn table_to_py<'py>(py: Python<'py>, table: &toml::Table) -> PyResult<Option<Bound<'py, PyAny>>> {
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
