//! `_core.CompiledModel`: a model compiled once, its variants (parameters, start values,
//! experiment settings by MSL name) and sweeps over them, run in the core with the GIL released.

use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant};

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use stiction_core::CompiledModel;
use stiction_core::System;
use stiction_core::{run_recording_all, CancelHandle};
use stiction_core::{run_variants, Outcome, Override, Plan};
use stiction_core::{ModelSpec, Simulation};

use crate::toml_doc::{named_spec, plain_counts, table_to_py, ParsedModel};
use crate::{advance_interruptibly, guarded, model_err, py_error, RawResult};

/// `run_recording_all` with the GIL released, checking for signals about every 50 ms between
/// its slices: Ctrl-C raises `KeyboardInterrupt`, as `advance_interruptibly` does.
fn run_recording_all_interruptibly(py: Python<'_>, sys: Arc<System>) -> PyResult<RawResult> {
    let mut interrupted = None;
    let mut last = Instant::now();
    let outcome = py.detach(|| {
        let between = || {
            if last.elapsed() < Duration::from_millis(50) {
                return true;
            }
            last = Instant::now();
            let signals = Python::attach(|py| py.check_signals());
            interrupted = signals.err();
            interrupted.is_none()
        };
        guarded(|| run_recording_all(sys, between))
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    Ok(RawResult::new(outcome?))
}

/// A Python value as the model file would hold it: a number, a Boolean, a string, a (nested)
/// list, or a table such as `{"start": 1.0, "fixed": True}`.
pub(crate) fn to_toml(value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in dict.iter() {
            table.insert(k.extract()?, to_toml(&v)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value
            .try_iter()?
            .map(|item| to_toml(&item?))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    // NumPy scalars and arrays: a float, or a list through `tolist()`
    if value.hasattr("tolist")? {
        let plain = value.call_method0("tolist")?;
        if !plain.is(value) {
            return to_toml(&plain);
        }
    }
    Err(py_error(
        "ModelError",
        format!("cannot use {value} as a parameter value (a number, bool, string, list or table)"),
    ))
}

fn overrides(dict: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<Override>> {
    let Some(dict) = dict else {
        return Ok(Vec::new());
    };
    dict.iter()
        .map(|(k, v)| Ok((k.extract::<String>()?, to_toml(&v)?)))
        .collect()
}

/// A sweep's variants: columns (`{name: [value per variant]}`, as `stiction.sweep` sends a
/// batch) or a list of `{name: value}` (variants of top-level parameters, whose names vary).
fn variants_of(variants: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<Override>>> {
    let Ok(columns) = variants.cast::<PyDict>() else {
        return variants
            .try_iter()?
            .map(|v| overrides(Some(v?.cast::<PyDict>()?)))
            .collect();
    };
    let mut rows: Vec<Vec<Override>> = Vec::new();
    for (name, values) in columns.iter() {
        let name: String = name.extract()?;
        let values = values.cast::<PyList>()?;
        if rows.is_empty() {
            rows = (0..values.len())
                .map(|_| Vec::with_capacity(columns.len()))
                .collect();
        }
        if values.len() != rows.len() {
            return Err(py_error(
                "ModelError",
                format!(
                    "override column '{name}' has {} values, not {}",
                    values.len(),
                    rows.len()
                ),
            ));
        }
        for (row, value) in rows.iter_mut().zip(values.iter()) {
            row.push((name.clone(), to_toml(&value)?));
        }
    }
    Ok(rows)
}

/// A compiled model. Pickles as its model text (see the Python wrapper).
#[pyclass(frozen, module = "stiction._core", name = "CompiledModel")]
pub struct PyCompiled(CompiledModel);

/// What `sweep` returns: metrics (variants × metrics), trajectories (one variants × grid array
/// per output), each variant's error or None, and its wall time.
type SweepArrays<'py> = (
    Bound<'py, PyArray2<f64>>,
    Vec<Bound<'py, PyArray2<f64>>>,
    Vec<Option<String>>,
    Bound<'py, PyArray1<f64>>,
);

/// What `load_model` gives: a plain file compiled (own name, counts of components and
/// connections, the compile), or the Python document and the engine's description of it.
type Loaded<'py> = (
    Option<(Option<String>, usize, usize, PyCompiled)>,
    Option<Bound<'py, PyAny>>,
    Option<ParsedModel>,
);

/// A model file's text, parsed once for both readers. A plain file (`plain_counts`) that the
/// engine compiles comes back compiled, `(Some(…), None, None)`, without a Python object made
/// (a ladder of 100 inertias loaded and run unchanged: 2.5 ms of 4). Any other comes back as
/// `(None, doc, parsed)`: the objects `parse_toml` gives and, from the same parse, the engine's
/// description of the model for a compile (named `name` when the file names none), None when
/// the engine refuses it or when top-level `parameters` or `declarations` make the Python
/// model's engine text other than the file. `(None, None, None)` for text that is not TOML.
#[pyfunction]
pub fn load_model<'py>(
    py: Python<'py>,
    text: &str,
    base_dir: &str,
    name: &str,
) -> PyResult<Loaded<'py>> {
    let parsed = py.detach(|| {
        let table = text.parse::<toml::Table>().ok()?;
        let plain = PyCompiled::plain(&table, base_dir, name);
        Some((table, plain))
    });
    let Some((table, plain)) = parsed else {
        return Ok((None, None, None));
    };
    if plain.is_some() {
        return Ok((plain, None, None));
    }
    let doc = table_to_py(py, &table)?;
    let as_written = !table.contains_key("parameters") && !table.contains_key("declarations");
    let parsed = (doc.is_some() && as_written)
        .then(|| named_spec(&table, base_dir, name))
        .flatten()
        .map(ParsedModel::new);
    Ok((None, doc, parsed))
}

impl PyCompiled {
    /// A model file's table compiled as it stands, when it is plain (`toml_doc::plain_counts`):
    /// its own name if it has one, its counts of components and connections, and the compile.
    /// None for any other file and for one the engine refuses: the caller builds the Python
    /// model, whose checks give their messages.
    pub(crate) fn plain(
        doc: &toml::Table,
        base_dir: &str,
        name: &str,
    ) -> Option<(Option<String>, usize, usize, Self)> {
        let counts = plain_counts(doc)?;
        let spec = named_spec(doc, base_dir, name)?;
        let own = doc
            .get("name")
            .and_then(toml::Value::as_str)
            .map(str::to_string);
        let compiled = CompiledModel::new(spec).ok()?;
        Some((own, counts.0, counts.1, Self(compiled)))
    }
}

#[pymethods]
impl PyCompiled {
    #[new]
    #[pyo3(signature = (model_toml, base_dir = "."))]
    fn new(py: Python<'_>, model_toml: &str, base_dir: &str) -> PyResult<Self> {
        let spec = ModelSpec::from_toml(model_toml, base_dir).map_err(model_err)?;
        let compiled = py.detach(|| CompiledModel::new(spec)).map_err(model_err)?;
        Ok(Self(compiled))
    }

    /// The model of a file `load_model` read (None when a compile took it already).
    #[staticmethod]
    fn from_parsed(py: Python<'_>, parsed: &ParsedModel) -> PyResult<Option<Self>> {
        let Some(spec) = parsed.take() else {
            return Ok(None);
        };
        let compiled = py.detach(|| CompiledModel::new(spec)).map_err(model_err)?;
        Ok(Some(Self(compiled)))
    }

    /// Every name a variant may set: `component.parameter`, then the experiment settings.
    fn parameter_names(&self) -> Vec<String> {
        self.0.parameter_names()
    }

    /// The output grid's times (where sweep trajectories are kept).
    fn grid(&self) -> Vec<f64> {
        let e = &self.0.spec().experiment;
        (0..=e.grid_len()).map(|k| e.grid_time(k)).collect()
    }

    /// A variant with these overrides (each checked now, naming component and parameter).
    #[pyo3(signature = (values = None))]
    fn variant(&self, py: Python<'_>, values: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let values = overrides(values)?;
        let pairs: Vec<(&str, toml::Value)> = values
            .iter()
            .map(|(n, v)| (n.as_str(), v.clone()))
            .collect();
        let variant = py.detach(|| self.0.with(&pairs)).map_err(model_err)?;
        Ok(Self(variant))
    }

    /// Runs this model to its StopTime (Ctrl-C raises `KeyboardInterrupt` promptly). With
    /// `record_all`, every variable is computed while the run goes on, on the other cores.
    #[pyo3(signature = (record_all = false))]
    fn simulate(&self, py: Python<'_>, record_all: bool) -> PyResult<RawResult> {
        let sys = self.0.system();
        if record_all {
            return run_recording_all_interruptibly(py, sys);
        }
        let mut sim = guarded(|| Simulation::new(sys))?;
        let stop = sim.system().experiment.stop_time;
        advance_interruptibly(py, &mut sim, stop)?;
        Ok(RawResult::new(sim.into_result()))
    }

    /// Checks metrics and outputs before a sweep (ModelError naming the bad one).
    fn check_plan(&self, metrics: Vec<String>, outputs: Vec<String>) -> PyResult<()> {
        Plan::new(&self.0, &metrics, &outputs).map_err(model_err)?;
        Ok(())
    }

    /// Runs `variants` (columns `{name: [values]}` or a list of `{name: value}`) on
    /// `workers` threads (all cores: None).
    #[pyo3(signature = (variants, metrics, outputs, workers = None))]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        variants: &Bound<'py, PyAny>,
        metrics: Vec<String>,
        outputs: Vec<String>,
        workers: Option<usize>,
    ) -> PyResult<SweepArrays<'py>> {
        let plan = Plan::new(&self.0, &metrics, &outputs).map_err(model_err)?;
        let variants = variants_of(variants)?;
        let outcomes = sweep_interruptibly(py, |cancel| {
            run_variants(&self.0, &variants, &plan, workers, cancel)
        })?;
        let n = outcomes.len();
        let flat: Vec<f64> = outcomes.iter().flat_map(|o| o.metrics.clone()).collect();
        let metrics = PyArray1::from_vec(py, flat).reshape([n, plan.metrics.len()])?;
        let points = self.0.spec().experiment.grid_len() + 1;
        let trajectories = (0..plan.outputs.len())
            .map(|k| {
                let flat: Vec<f64> = (outcomes.iter())
                    .flat_map(|o| {
                        // a variant that failed (or has another grid) fills its row with NaN
                        let mut row = o.trajectories.get(k).cloned().unwrap_or_default();
                        row.resize(points, f64::NAN);
                        row
                    })
                    .collect();
                PyArray1::from_vec(py, flat).reshape([n, points])
            })
            .collect::<PyResult<Vec<_>>>()?;
        let status = outcomes.iter().map(|o| o.error.clone()).collect();
        let wall = PyArray1::from_vec(py, outcomes.iter().map(|o| o.wall_s).collect());
        Ok((metrics, trajectories, status, wall))
    }
}

/// Runs a sweep on a thread of its own while this one, every 50 ms, checks for signals with
/// the GIL: Ctrl-C cancels the runs under way (they stop at their next step) and raises
/// `KeyboardInterrupt` once they have stopped. The sweep's thread says when it is done, so
/// no batch waits out a polling interval.
fn sweep_interruptibly<F>(py: Python<'_>, sweep: F) -> PyResult<Vec<Outcome>>
where
    F: FnOnce(&CancelHandle) -> Vec<Outcome> + Send,
{
    let cancel = CancelHandle::new();
    let done = (Mutex::new(false), Condvar::new());
    std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            let outcomes = guarded(|| Ok(sweep(&cancel)));
            *done.0.lock().unwrap_or_else(PoisonError::into_inner) = true;
            done.1.notify_all();
            outcomes
        });
        let mut interrupted = None;
        loop {
            if py.detach(|| wait_for(&done, Duration::from_millis(50))) {
                break;
            }
            if interrupted.is_none() {
                if let Err(signal) = py.check_signals() {
                    cancel.cancel();
                    interrupted = Some(signal);
                }
            }
        }
        let outcomes = worker.join().unwrap_or_else(|_| {
            Err(py_error(
                "SimulationError",
                "internal error in the engine (please report): a sweep thread ended abnormally"
                    .into(),
            ))
        });
        match interrupted {
            Some(signal) => Err(signal),
            None => outcomes,
        }
    })
}

/// Waits until `done` is set or `at_most` has passed; whether it is set.
fn wait_for(done: &(Mutex<bool>, Condvar), at_most: Duration) -> bool {
    let guard = done.0.lock().unwrap_or_else(PoisonError::into_inner);
    let (guard, _) = (done.1)
        .wait_timeout_while(guard, at_most, |finished| !*finished)
        .unwrap_or_else(PoisonError::into_inner);
    *guard
}
