//! `stiction._core`: the Python face of the Rust engine. Converts in and out, releases the GIL
//! while simulating, and turns every error — and any panic — into a Python exception.

mod compare;
mod compiled;
mod info;
mod state;
mod table_memory;
mod toml_doc;

// mimalloc: see Cargo.toml (the compile of a model allocates and frees in the tens of thousands)
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::OnceLock;

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyKeyError, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use stiction_core::CancelHandle;
use stiction_core::MatParameter;

use state::PyState;
use stiction_core::{ModelError as CoreModelError, ModelSpec, SimError, SimResult, Simulation};

/// An exception of the class named `kind` in `stiction.errors` (one Python class per error
/// kind; the classes live in Python so both sides raise the same ones).
fn py_error(kind: &str, message: String) -> PyErr {
    Python::attach(|py| {
        let made = py
            .import("stiction.errors")
            .and_then(|m| m.getattr(kind))
            .and_then(|cls| cls.call1((message.clone(),)));
        match made {
            Ok(instance) => PyErr::from_value(instance),
            Err(_) => PyRuntimeError::new_err(message),
        }
    })
}

fn model_err(e: CoreModelError) -> PyErr {
    py_error("ModelError", e.to_string())
}

fn sim_err(e: SimError) -> PyErr {
    py_error(e.kind(), e.to_string())
}

fn parse(
    model_toml: &str,
    base_dir: &str,
    overrides: &HashMap<String, f64>,
    solver: Option<&str>,
) -> PyResult<ModelSpec> {
    let mut spec = ModelSpec::from_toml(model_toml, base_dir).map_err(model_err)?;
    for (key, value) in overrides {
        spec.experiment.set(key, *value).map_err(model_err)?;
    }
    if let Some(solver) = solver {
        spec.experiment.set_solver(solver);
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
            Err(py_error(
                "SimulationError",
                format!("internal error in the engine (please report): {what}"),
            ))
        }
    }
}

/// The outcome of one run. Variables are computed from the recorded states when first asked for
/// (see `SimResult`); `table()` gives all of them at once.
#[pyclass(frozen, module = "stiction._core")]
struct RawResult {
    result: SimResult,
    /// The whole table once asked for: a NumPy array over the engine's vector (no copy), and
    /// later columns are read from it rather than computed again.
    table: OnceLock<Py<PyArray2<f64>>>,
}

impl RawResult {
    fn new(result: SimResult) -> Self {
        Self {
            result,
            table: OnceLock::new(),
        }
    }
}

#[pymethods]
impl RawResult {
    #[getter]
    fn names(&self) -> Vec<String> {
        self.result.names.clone()
    }

    #[getter]
    fn rows(&self) -> usize {
        self.result.rows()
    }

    #[getter]
    fn events(&self) -> Vec<(f64, String, i8, i8, String)> {
        self.result
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

    /// Switching elements whose loss power went negative beyond the event band at the end of
    /// some step: the runs whose energy audit Python checks (and warns about).
    #[getter]
    fn delivering(&self) -> Vec<String> {
        self.result.delivering.clone()
    }

    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.result.stats;
        let d = PyDict::new(py);
        d.set_item("steps", s.steps)?;
        d.set_item("rejected_steps", s.rejected_steps)?;
        d.set_item("lu_setups", s.lu_setups)?;
        d.set_item("jacobian_evals", s.jacobian_evals)?;
        d.set_item("solver_switches", s.solver_switches)?;
        d.set_item("rhs_evals", s.rhs_evals)?;
        d.set_item("events", s.state_events + s.time_events + s.input_events)?;
        d.set_item("input_events", s.input_events)?;
        d.set_item("state_events", s.state_events)?;
        d.set_item("time_events", s.time_events)?;
        d.set_item("factorizations", s.factorizations)?;
        d.set_item("wall_ms", s.wall_ms)?;
        Ok(d)
    }

    /// One variable over all rows; KeyError for an unknown name.
    fn column<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        if let Some(table) = self.table.get() {
            let c = (self.result.names.iter().position(|n| n == name))
                .ok_or_else(|| PyKeyError::new_err(name.to_string()))?;
            let values = table.bind(py).readonly().as_array().column(c).to_vec();
            return Ok(PyArray1::from_vec(py, values));
        }
        let values = py
            .detach(|| self.result.column(name))
            .ok_or_else(|| PyKeyError::new_err(name.to_string()))?;
        Ok(PyArray1::from_vec(py, values))
    }

    /// Whether `column(name)` computes variable `name` alone, not as a column of `table()`:
    /// an angle, a speed, a mode, a flag, the kinetic energy, or one that needs the mode solve
    /// in few rows (a clutch's torque: only while locked). KeyError for an unknown name.
    fn is_direct(&self, name: &str) -> PyResult<bool> {
        (self.result.is_alone(name)).ok_or_else(|| PyKeyError::new_err(name.to_string()))
    }

    /// Per row, whether a locked element holds the speed variable `name` (its own relative
    /// speed, or a shaft it holds against ground): the rows where `first` and `time_of` read
    /// that speed as 0. All false for any other variable.
    fn held_rows(&self, name: &str) -> Vec<bool> {
        self.result.held_rows(name)
    }

    /// A metric of this run (`max(J1.w)`, `time_of(clutch2.locked)`, …), as a sweep computes it.
    fn metric(&self, text: &str) -> PyResult<f64> {
        self.result.metric(text).map_err(model_err)
    }

    /// The energy audit per element: one dict of `stiction.audit.ElementBalance`'s fields for
    /// every component with flanges.
    fn audit<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let audits = py.detach(|| guarded(|| Ok(self.result.audit())))?;
        let row = |a: stiction_core::ElementAudit| -> PyResult<Bound<'py, PyDict>> {
            let d = PyDict::new(py);
            d.set_item("component", a.component)?;
            d.set_item("passive", a.passive)?;
            for (key, value) in [
                ("residual", a.residual),
                ("scale", a.scale),
                ("torque", a.torque),
                ("min_dissipation", a.min_dissipation),
                ("energy_in", a.energy_in),
                ("dissipated", a.dissipated),
                ("reset_loss", a.reset_loss),
                ("withheld", a.withheld),
                ("slip_bound", a.slip_bound),
            ] {
                d.set_item(key, value)?;
            }
            Ok(d)
        };
        audits.into_iter().map(row).collect()
    }

    /// All variables as a `rows × len(names)` array (the same array at every call).
    fn table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if let Some(table) = self.table.get() {
            return Ok(table.bind(py).clone());
        }
        let values = py.detach(|| self.result.table_vec()).map_err(sim_err)?;
        let shape = [self.result.rows(), self.result.names.len()];
        let table = table_memory::table_array(py, values, shape)?;
        Ok(self
            .table
            .get_or_init(|| table.clone().unbind())
            .bind(py)
            .clone())
    }
}

/// The values of a C-contiguous `rows × names` array, or a clear error.
fn table_values<'a>(data: &'a PyReadonlyArray2<'_, f64>, names: usize) -> PyResult<&'a [f64]> {
    if data.shape()[1] != names {
        return Err(PyValueError::new_err(format!(
            "data has {} columns for {names} names",
            data.shape()[1]
        )));
    }
    data.as_slice()
        .map_err(|_| PyValueError::new_err("data must be a C-contiguous float64 array"))
}

/// An I/O error as Python's OSError (errno, message, file name), as `open` raises it.
fn os_error(e: std::io::Error, path: &str) -> PyErr {
    PyOSError::new_err((
        e.raw_os_error().unwrap_or(0),
        e.to_string(),
        path.to_string(),
    ))
}

/// Writes `data` (rows × names) as an MSL-style CSV; `integer` marks mode and flag columns.
#[pyfunction]
fn write_csv(
    py: Python<'_>,
    path: &str,
    names: Vec<String>,
    integer: Vec<bool>,
    data: PyReadonlyArray2<'_, f64>,
) -> PyResult<()> {
    let values = table_values(&data, names.len())?;
    py.detach(|| {
        let file = std::fs::File::create(path)?;
        stiction_core::write_csv(file, &names, &integer, values)
    })
    .map_err(|e| os_error(e, path))
}

/// Writes `data` (rows × names, `time` first) and `parameters` (name, description, value) as a
/// Dymola/OpenModelica result file (MATLAB v4).
#[pyfunction]
// Alike in shape to write_csv (the arguments of a file writer); what they share is
// `table_values` and `os_error`.
fn write_mat(
    py: Python<'_>,
    path: &str,
    names: Vec<String>,
    descriptions: Vec<String>,
    data: PyReadonlyArray2<'_, f64>,
    parameters: Vec<(String, String, f64)>,
) -> PyResult<()> {
    let values = table_values(&data, names.len())?;
    let params: Vec<MatParameter> = parameters
        .into_iter()
        .map(|(name, description, value)| MatParameter {
            name,
            description,
            value,
        })
        .collect();
    py.detach(|| {
        let file = std::fs::File::create(path)?;
        stiction_core::write_mat(file, &names, &descriptions, values, &params)
    })
    .map_err(|e| os_error(e, path))
}

/// Simulates a model given as TOML text; `overrides` replace `[experiment]` settings.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = ".", overrides = None, solver = None))]
fn simulate(
    py: Python<'_>,
    model_toml: &str,
    base_dir: &str,
    overrides: Option<HashMap<String, f64>>,
    solver: Option<&str>,
) -> PyResult<RawResult> {
    let spec = parse(model_toml, base_dir, &overrides.unwrap_or_default(), solver)?;
    let mut sim = guarded(|| Simulation::from_spec(&spec))?;
    let stop = sim.system().experiment.stop_time;
    advance_interruptibly(py, &mut sim, stop)?;
    Ok(RawResult::new(sim.into_result()))
}

/// Validates a model (parameters, ports, connections, initial values and, with `motion`, that
/// every shaft's motion is determined) without simulating.
#[pyfunction]
#[pyo3(signature = (model_toml, base_dir = ".", motion = true))]
fn check(model_toml: &str, base_dir: &str, motion: bool) -> PyResult<()> {
    let spec = parse(model_toml, base_dir, &HashMap::new(), None)?;
    guarded(|| {
        let sys = stiction_core::assemble(&spec)?;
        if motion {
            stiction_core::check_model(&sys)?;
        } else {
            stiction_core::initial_state(&sys)?;
        }
        Ok(())
    })
}

/// Advances `sim` to `t` with the GIL released, in slices of about 50 ms of wall-clock time,
/// checking for signals between them: Ctrl-C raises `KeyboardInterrupt` within a slice. The
/// result is that of one uninterrupted call (the slices pause between integrator steps).
fn advance_interruptibly(py: Python<'_>, sim: &mut Simulation, t: f64) -> PyResult<()> {
    let slice = std::time::Duration::from_millis(50);
    loop {
        let on_this_thread = OnThisThread(&mut *sim);
        let reached = py.detach(move || {
            let sim = on_this_thread;
            guarded(|| sim.0.advance_for(t, slice))
        })?;
        py.check_signals()?;
        if reached {
            return Ok(());
        }
    }
}

/// Moves a value into `Python::detach` that is not `Send` (a `Simulation` holds `Rc`s).
/// SAFETY: `detach` runs the closure on the calling thread, and the `unsendable` pyclass that
/// owns the value is only ever used from the thread that created it.
struct OnThisThread<T>(T);
unsafe impl<T> Send for OnThisThread<T> {}

/// A resumable run: advance to a time, set inputs, read variables, save and restore state.
#[pyclass(unsendable, module = "stiction._core", name = "Simulation")]
struct PySimulation(Option<Simulation>);

impl PySimulation {
    fn sim(&mut self) -> PyResult<&mut Simulation> {
        self.0.as_mut().ok_or_else(|| {
            py_error(
                "UsageError",
                "the simulation was closed by result()".to_string(),
            )
        })
    }
}

#[pymethods]
impl PySimulation {
    #[new]
    #[pyo3(signature = (model_toml, base_dir = ".", overrides = None, solver = None))]
    fn new(
        model_toml: &str,
        base_dir: &str,
        overrides: Option<HashMap<String, f64>>,
        solver: Option<&str>,
    ) -> PyResult<Self> {
        let spec = parse(model_toml, base_dir, &overrides.unwrap_or_default(), solver)?;
        let sim = guarded(|| Simulation::from_spec(&spec))?;
        Ok(Self(Some(sim)))
    }

    #[getter]
    fn time(&mut self) -> PyResult<f64> {
        Ok(self.sim()?.time())
    }

    #[getter]
    fn stop_time(&mut self) -> PyResult<f64> {
        Ok(self.sim()?.system().experiment.stop_time)
    }

    #[getter]
    fn finished(&mut self) -> PyResult<bool> {
        Ok(self.sim()?.finished())
    }

    /// Advances to `t` with the GIL released; Ctrl-C raises `KeyboardInterrupt` promptly.
    fn advance_to(&mut self, py: Python<'_>, t: f64) -> PyResult<()> {
        advance_interruptibly(py, self.sim()?, t)
    }

    fn inputs(&mut self) -> PyResult<Vec<(String, f64)>> {
        Ok(self.sim()?.inputs())
    }

    fn set_input(&mut self, name: &str, value: f64) -> PyResult<()> {
        let sim = self.sim()?;
        guarded(|| sim.set_input(name, value))
    }

    /// Sets an inertia's (or mass's) speed at the current time, as an event.
    fn reinit_speed(&mut self, mass: &str, w: f64) -> PyResult<()> {
        let sim = self.sim()?;
        guarded(|| sim.reinit_speed(mass, w))
    }

    /// Advances until `name` reaches `level` (at most to `t_max`), with the GIL released.
    fn advance_until(
        &mut self,
        py: Python<'_>,
        name: &str,
        level: f64,
        t_max: f64,
    ) -> PyResult<bool> {
        let on_this_thread = OnThisThread(self.sim()?);
        let reached = py.detach(move || {
            let sim = on_this_thread;
            guarded(|| sim.0.advance_until(name, level, t_max))
        })?;
        py.check_signals()?;
        Ok(reached)
    }

    /// Whether rows are kept for `result()` (a long driven run keeps none).
    fn set_recording(&mut self, recording: bool) -> PyResult<()> {
        self.sim()?.set_recording(recording);
        Ok(())
    }

    /// Sets tunable parameters (`{"brake.fn_max": 200.0}`) from now on, at one event.
    fn set_parameters(&mut self, values: &Bound<'_, PyDict>) -> PyResult<()> {
        let mut pairs: Vec<(String, toml::Value)> = Vec::new();
        for (name, value) in values.iter() {
            pairs.push((name.extract()?, compiled::to_toml(&value)?));
        }
        let refs: Vec<(&str, toml::Value)> =
            pairs.iter().map(|(n, v)| (n.as_str(), v.clone())).collect();
        let sim = self.sim()?;
        guarded(|| sim.set_parameters(&refs))
    }

    fn names(&mut self) -> PyResult<Vec<String>> {
        Ok(self.sim()?.names())
    }

    fn values(&mut self) -> PyResult<Vec<f64>> {
        let sim = self.sim()?;
        guarded(|| sim.values())
    }

    fn get(&mut self, name: &str) -> PyResult<f64> {
        let sim = self.sim()?;
        guarded(|| sim.get(name))
    }

    fn cancel_handle(&mut self) -> PyResult<PyCancelHandle> {
        Ok(PyCancelHandle(self.sim()?.cancel_handle()))
    }

    fn state(&mut self) -> PyResult<PyState> {
        let sim = self.sim()?;
        Ok(PyState(guarded(|| sim.state())?))
    }

    fn set_state(&mut self, state: &PyState) -> PyResult<()> {
        let sim = self.sim()?;
        guarded(|| sim.set_state(&state.0))
    }

    fn reset(&mut self) -> PyResult<()> {
        let sim = self.sim()?;
        guarded(|| sim.reset())
    }

    /// The rows recorded so far; the simulation is closed.
    fn result(&mut self) -> PyResult<RawResult> {
        let sim = self
            .0
            .take()
            .ok_or_else(|| py_error("UsageError", "result() was called already".to_string()))?;
        Ok(RawResult::new(sim.into_result()))
    }
}

/// Cancels a running simulation from any thread.
#[pyclass(frozen, module = "stiction._core", name = "CancelHandle")]
struct PyCancelHandle(CancelHandle);

#[pymethods]
impl PyCancelHandle {
    fn cancel(&self) {
        self.0.cancel();
    }
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(toml_doc::parse_toml, m)?)?;
    m.add_function(wrap_pyfunction!(compiled::load_model, m)?)?;
    m.add_class::<toml_doc::ParsedModel>()?;
    m.add_function(wrap_pyfunction!(write_csv, m)?)?;
    m.add_function(wrap_pyfunction!(write_mat, m)?)?;
    info::register(m)?;
    compare::register(m)?;
    m.add_class::<RawResult>()?;
    m.add_class::<PySimulation>()?;
    m.add_class::<PyCancelHandle>()?;
    m.add_class::<PyState>()?;
    m.add_class::<compiled::PyCompiled>()?;
    // The exception classes are Python's (`stiction.errors`); re-exported here for old code.
    let errors = m.py().import("stiction.errors")?;
    for name in ["ModelError", "SimulationError"] {
        m.add(name, errors.getattr(name)?)?;
    }
    Ok(())
}
