//! What the engine can tell about a model without running it: the component catalogue, the
//! parameter check, the experiment in force, the initialization report and the sources of time
//! events. Thin conversions; the logic is in the core.

use std::collections::HashMap;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use stiction_core::same_instant;
use stiction_core::ParamKind;
use stiction_core::{catalogue as core_catalogue, TypeInfo};

use crate::toml_doc::value_to_py;
use crate::{guarded, model_err, parse};

/// A parameter default (TOML data) as a Python value; a date or time (no default is one) as
/// its TOML text.
fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    match value_to_py(py, v)? {
        Some(value) => Ok(value),
        None => Ok(v.to_string().into_pyobject(py)?.into_any()),
    }
}

/// One component type of the catalogue as a dict (see `stiction.catalogue`).
fn type_info<'py>(py: Python<'py>, t: &TypeInfo) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("name", t.name)?;
    out.set_item("msl_class", t.class)?;
    out.set_item("description", t.description)?;
    let params = PyList::empty(py);
    for p in &t.params {
        let d = PyDict::new(py);
        d.set_item("name", &p.name)?;
        d.set_item("kind", p.kind.label())?;
        if let ParamKind::Choice(options) = &p.kind {
            d.set_item("choices", options)?;
        }
        let default = match &p.default {
            Some(v) => Some(toml_to_py(py, v)?),
            None => None,
        };
        d.set_item("default", default)?;
        d.set_item("required", p.required)?;
        d.set_item("unit", &p.unit)?;
        d.set_item("description", &p.description)?;
        d.set_item("range", &p.range)?;
        d.set_item("tunable", p.tunable())?;
        params.append(d)?;
    }
    out.set_item("parameters", params)?;
    let ports = PyList::empty(py);
    for p in &t.ports {
        let kind = p.describe().trim_start_matches("a ");
        ports.append((&p.name, kind, &p.enabled_by))?;
    }
    out.set_item("ports", ports)?;
    let vars: Vec<(&str, &str)> = t
        .variables
        .iter()
        .map(|v| (v.name.as_str(), v.unit))
        .collect();
    out.set_item("variables", vars)?;
    Ok(out)
}

/// The component catalogue: one dict per registered type, in registry order.
#[pyfunction]
fn catalogue(py: Python<'_>) -> PyResult<Py<PyList>> {
    let out = PyList::empty(py);
    for t in core_catalogue() {
        out.append(type_info(py, &t)?)?;
    }
    Ok(out.unbind())
}

/// Checks every component's parameters (names, types, ranges, tables) without assembling.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = "."))]
fn check_parameters(model_toml: &str, base_dir: &str) -> PyResult<()> {
    let spec = parse(model_toml, base_dir, &HashMap::new(), None)?;
    for c in &spec.components {
        stiction_core::create_component(c, &spec.base_dir).map_err(model_err)?;
    }
    Ok(())
}

/// For each given event time, the components whose time events fall on it (`same_instant`, the
/// rule the run merges them by), as `"press (Step)"`: which signal fired a time event.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir, overrides, times))]
fn time_event_sources(
    model_toml: &str,
    base_dir: &str,
    overrides: HashMap<String, f64>,
    times: Vec<f64>,
) -> PyResult<Vec<Vec<String>>> {
    let spec = parse(model_toml, base_dir, &overrides, None)?;
    let (start, stop) = (spec.experiment.start_time, spec.experiment.stop_time);
    let mut own = Vec::new();
    for c in &spec.components {
        let component = stiction_core::create_component(c, &spec.base_dir).map_err(model_err)?;
        let label = format!("{} ({})", c.name, c.type_name);
        own.extend(
            component
                .time_events(start, stop)
                .into_iter()
                .map(|t| (t, label.clone())),
        );
    }
    Ok(times
        .iter()
        .map(|&t| {
            let hits = own.iter().filter(|(te, _)| same_instant(*te, t));
            let mut names: Vec<String> = hits.map(|(_, n)| n.clone()).collect();
            names.dedup();
            names
        })
        .collect())
}

/// The experiment a run uses: `{StartTime, StopTime, Interval, Tolerance, Solver, defaults}`,
/// `defaults` naming the settings neither the model nor an override gave.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = ".", overrides = None, solver = None))]
fn experiment<'py>(
    py: Python<'py>,
    model_toml: &str,
    base_dir: &str,
    overrides: Option<HashMap<String, f64>>,
    solver: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let e = parse(model_toml, base_dir, &overrides.unwrap_or_default(), solver)?.experiment;
    let d = PyDict::new(py);
    d.set_item("StartTime", e.start_time)?;
    d.set_item("StopTime", e.stop_time)?;
    d.set_item("Interval", e.interval)?;
    d.set_item("Tolerance", e.tolerance)?;
    d.set_item("Solver", &e.solver)?;
    d.set_item("defaults", e.defaults())?;
    Ok(d)
}

/// Every start value: `(variable, start, "fixed" | "guessed" | "computed", initial value)`.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = "."))]
fn initialization(model_toml: &str, base_dir: &str) -> PyResult<Vec<(String, f64, String, f64)>> {
    let spec = parse(model_toml, base_dir, &HashMap::new(), None)?;
    let values = guarded(|| {
        let sys = stiction_core::assemble(&spec)?;
        Ok(stiction_core::initialization_report(&sys)?)
    })?;
    Ok(values
        .into_iter()
        .map(|v| (v.variable, v.start, v.status.label().to_string(), v.value))
        .collect())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(catalogue, m)?)?;
    m.add_function(wrap_pyfunction!(experiment, m)?)?;
    m.add_function(wrap_pyfunction!(check_parameters, m)?)?;
    m.add_function(wrap_pyfunction!(time_event_sources, m)?)?;
    m.add_function(wrap_pyfunction!(initialization, m)?)?;
    Ok(())
}
