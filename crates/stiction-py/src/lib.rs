//! `stiction._core`: the Python face of the Rust engine. Converts in and out, releases the GIL
//! while simulating, and turns every error — and any panic — into a Python exception.

use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyKeyError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use stiction_core::{ModelError as CoreModelError, ModelSpec, SimError, SimResult};

create_exception!(
    _core,
    ModelError,
    PyValueError,
    "The model is invalid; the message names the component and the parameter or port."
);
create_exception!(
    _core,
    SimulationError,
    PyRuntimeError,
    "A valid model could not be simulated (singular system, no consistent mode, …)."
);

fn model_err(e: CoreModelError) -> PyErr {
    ModelError::new_err(e.to_string())
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

/// The outcome of one run. Variables are computed from the recorded states when first asked for
/// (see `SimResult`); `table()` gives all of them at once.
#[pyclass(frozen, module = "stiction._core")]
struct RawResult(SimResult);

#[pymethods]
impl RawResult {
    #[getter]
    fn names(&self) -> Vec<String> {
        self.0.names.clone()
    }

    #[getter]
    fn rows(&self) -> usize {
        self.0.rows()
    }

    #[getter]
    fn events(&self) -> Vec<(f64, String, i8, i8, String)> {
        self.0
            .events
            .iter()
            .map(|e| {
                (
                    e.time,
                    e.component.clone(),
                    e.old_mode,
                    e.new_mode,
                    e.cause.clone(),
                )
            })
            .collect()
    }

    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.0.stats;
        let d = PyDict::new(py);
        d.set_item("steps", s.steps)?;
        d.set_item("rejected_steps", s.rejected_steps)?;
        d.set_item("rhs_evals", s.rhs_evals)?;
        d.set_item("events", s.state_events + s.time_events)?;
        d.set_item("state_events", s.state_events)?;
        d.set_item("time_events", s.time_events)?;
        d.set_item("factorizations", s.factorizations)?;
        d.set_item("wall_ms", s.wall_ms)?;
        Ok(d)
    }

    /// One variable over all rows; KeyError for an unknown name.
    fn column<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let values = py
            .detach(|| self.0.column(name))
            .ok_or_else(|| PyKeyError::new_err(name.to_string()))?;
        Ok(PyArray1::from_vec(py, values))
    }

    /// All variables as a `rows × len(names)` array.
    fn table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let table = py.detach(|| self.0.table());
        PyArray1::from_slice(py, table).reshape([self.0.rows(), self.0.names.len()])
    }
}

/// Simulates a model given as TOML text; `overrides` replace `[experiment]` settings.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = ".", overrides = None))]
fn simulate(
    py: Python<'_>,
    model_toml: &str,
    base_dir: &str,
    overrides: Option<HashMap<String, f64>>,
) -> PyResult<RawResult> {
    let spec = parse(model_toml, base_dir, &overrides.unwrap_or_default())?;
    let result = py.detach(|| guarded(|| stiction_core::simulate(&spec)))?;
    Ok(RawResult(result))
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
    m.add_class::<RawResult>()?;
    m.add("ModelError", m.py().get_type::<ModelError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    Ok(())
}
