//! `stiction._core`: the Python face of the Rust engine. Converts in and out, releases the GIL
//! while simulating, and turns every error — and any panic — into a Python exception.

use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use numpy::{PyArray1, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use stiction_core::{ModelError, ModelSpec, SimError, SimResult};

create_exception!(
    _core,
    ModelError_,
    PyValueError,
    "The model is invalid; the message names the component and the parameter or port."
);
create_exception!(
    _core,
    SimulationError,
    PyRuntimeError,
    "A valid model could not be simulated (singular system, no consistent mode, …)."
);

fn model_err(e: ModelError) -> PyErr {
    ModelError_::new_err(e.to_string())
}

fn sim_err(e: SimError) -> PyErr {
    match e {
        SimError::Model(m) => model_err(m),
        other => SimulationError::new_err(other.to_string()),
    }
}

fn parse(
    model_toml: &str,
    base_dir: &str,
    overrides: &HashMap<String, f64>,
) -> PyResult<ModelSpec> {
    let mut spec = ModelSpec::from_toml(model_toml, base_dir).map_err(model_err)?;
    for (key, value) in overrides {
        spec.experiment.set(key, *value).map_err(model_err)?;
    }
    spec.experiment.validate().map_err(model_err)?;
    Ok(spec)
}

/// Runs engine code without letting a panic cross into Python.
fn guarded<T>(f: impl FnOnce() -> Result<T, SimError>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r.map_err(sim_err),
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(SimulationError::new_err(format!(
                "internal error in the engine (please report): {what}"
            )))
        }
    }
}

fn to_python(py: Python<'_>, r: SimResult) -> PyResult<Py<PyDict>> {
    let out = PyDict::new(py);
    let cols = r.names.len();
    let rows = r.rows();
    let data = PyArray1::from_vec(py, r.data).reshape([rows, cols])?;
    out.set_item("names", PyList::new(py, &r.names)?)?;
    out.set_item("data", data)?;
    let events = PyList::empty(py);
    for e in &r.events {
        events.append((
            e.time,
            e.component.as_str(),
            e.old_mode,
            e.new_mode,
            e.cause.as_str(),
        ))?;
    }
    out.set_item("events", events)?;
    let stats = PyDict::new(py);
    stats.set_item("steps", r.stats.steps)?;
    stats.set_item("rejected_steps", r.stats.rejected_steps)?;
    stats.set_item("rhs_evals", r.stats.rhs_evals)?;
    stats.set_item("events", r.stats.state_events + r.stats.time_events)?;
    stats.set_item("state_events", r.stats.state_events)?;
    stats.set_item("time_events", r.stats.time_events)?;
    stats.set_item("factorizations", r.stats.factorizations)?;
    stats.set_item("wall_ms", r.stats.wall_ms)?;
    out.set_item("stats", stats)?;
    Ok(out.unbind())
}

/// Simulates a model given as TOML text; `overrides` replace `[experiment]` settings.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = ".", overrides = None))]
fn simulate(
    py: Python<'_>,
    model_toml: &str,
    base_dir: &str,
    overrides: Option<HashMap<String, f64>>,
) -> PyResult<Py<PyDict>> {
    let spec = parse(model_toml, base_dir, &overrides.unwrap_or_default())?;
    let result = py.detach(|| guarded(|| stiction_core::simulate(&spec)))?;
    to_python(py, result)
}

/// Validates a model (parameters, ports, connections, initial values) without simulating.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = "."))]
fn check(model_toml: &str, base_dir: &str) -> PyResult<()> {
    let spec = parse(model_toml, base_dir, &HashMap::new())?;
    guarded(|| {
        let sys = stiction_core::system::assemble(&spec)?;
        stiction_core::solver::initial_state(&sys)?;
        Ok(())
    })
}

/// `{type: {"parameters": [...], "ports": [...]}}` for every component type.
#[pyfunction]
fn component_types(py: Python<'_>) -> PyResult<Py<PyDict>> {
    let out = PyDict::new(py);
    for (name, params, ports) in stiction_core::components::schema() {
        let entry = PyDict::new(py);
        entry.set_item("parameters", params)?;
        entry.set_item("ports", ports)?;
        out.set_item(name, entry)?;
    }
    Ok(out.unbind())
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(component_types, m)?)?;
    m.add("ModelError", m.py().get_type::<ModelError_>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    Ok(())
}
