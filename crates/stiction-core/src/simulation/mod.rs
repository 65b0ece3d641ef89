//! A resumable simulation: initialize, `advance_to(t)` (stopping exactly at the events inside),
//! set a model input (an event at that instant when it jumps), read any variable by name, save
//! and restore the whole state, cancel from another thread. `simulate` is a loop over it.
//!
//! Continuous phases are integrated by diffsol step by step; zero crossings are located on its
//! dense output (`locate`); at each event the event iteration finds the consistent discrete
//! state and the integrator restarts. The integrator is *not* restarted where a piece of
//! `advance_to` ends, so a run advanced in pieces is bit-identical to one call.

mod auto;
pub(crate) mod chatter;
mod dense;
mod event;
mod grid;
mod guard;
mod initial_state;
mod integrator;
mod locate;
mod observer;
mod record_all;
mod redrive;
mod reset;
mod samples;
mod saved;
mod scan;
#[cfg(test)]
mod split_eval_tests;
mod state_bytes;
mod stepper;
mod tune;
mod watch;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::{cell::RefCell, rc::Rc, time::Instant};

use diffsol::OdeSolverMethod;

use initial_state::initialization_log;
pub use initial_state::{check_model, initial_state, initial_state_and_guesses};
pub use observer::{each_row, Observer};
pub use record_all::run_recording_all;
pub use saved::{InputChange, SimState};
pub use state_bytes::{ByteReader, ByteWriter, ReadResult, STATE_BYTES_VERSION};
pub use stepper::Cursor;
pub use tune::ParameterChange;

use dense::Stages;
use integrator::{with_solver, IntegratorCell};
use stepper::Stepper;

use crate::assembly::{assemble, CompiledModel};
use crate::engine::eval::{consistent_speeds, evaluate, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::engine::{iterate, EventPoint, ModeCache};
use crate::error::{ModelError, SimError};
use crate::linalg::LinearSolver;
use crate::model::ModelSpec;
use crate::result::{row_values, SimResult};
use crate::system::System;

/// Assembles and simulates a model with its `[experiment]` settings.
pub fn simulate(spec: &ModelSpec) -> Result<SimResult, SimError> {
    run(Arc::new(assemble(spec)?))
}

/// Simulates an assembled system from start to stop (a sweep assembles once, runs many times).
pub fn run(sys: Arc<System>) -> Result<SimResult, SimError> {
    let mut sim = Simulation::new(sys)?;
    sim.run()?;
    Ok(sim.into_result())
}

/// What the right-hand side reads: the frozen discrete state, its factored mode matrix and the
/// workspace. Changed only between steps, at events.
pub(crate) struct Phase {
    /// The system the right-hand side evaluates: the stepper's (a parameter change swaps both).
    sys: Arc<System>,
    disc: DiscreteState,
    /// The first time event not handled yet: signals switch there only once it is handled
    /// (Modelica freezes `time >= t0` between events), wherever the integrator evaluates.
    horizon: f64,
    mm: Rc<ModeMatrix>,
    ws: Workspace,
    rhs_calls: usize,
    probe: Vec<f64>,
    /// f at (`f0_t`, `f0_x`), kept for the Jacobian–vector products of one Jacobian (diffsol
    /// asks for its columns one by one at one point); `f0_t` is NaN once the mode changes.
    f0: Vec<f64>,
    f0_t: f64,
    f0_x: Vec<f64>,
    /// Jacobians the implicit methods built (points where their columns were differenced).
    jacobians: usize,
    /// For `project`, so that `ws` keeps what the stepper evaluated last.
    scratch: Option<Workspace>,
    /// (t, x) of the workspace's last evaluation (the right-hand side's or `evaluate_here`'s)
    /// and its evaluation count right after it (`holds`).
    rhs_t: f64,
    rhs_x: Vec<f64>,
    rhs_stamp: usize,
    /// Tsit45's stage derivatives of the step being taken (its dense output, `dense.rs`).
    stages: Stages,
}

impl Phase {
    /// Writes the algebraic speeds of the shafts without inertia of the current mode, and the
    /// prescribed motions, into `x`.
    fn project(&mut self, sys: &System, t: f64, x: &mut [f64]) {
        if self.mm.massless.is_some() || sys.prescribes() {
            let ws = self.scratch.get_or_insert_with(|| Workspace::new(sys));
            consistent_speeds(sys, &self.mm, &self.disc, t, x, self.horizon, ws);
        }
    }

    /// Whether the workspace holds the evaluation at (t, x) in the current mode (taken there,
    /// nothing evaluated since; modes change only at events, which evaluate): an explicit
    /// step's last stage is its end (first same as last), so the scan's end sample need not
    /// evaluate again, and the restart after an event starts from the event's right row.
    fn holds(&self, t: f64, x: &[f64]) -> bool {
        self.rhs_t == t && self.ws.rhs_evals == self.rhs_stamp && self.rhs_x[..] == x[..]
    }

    /// Notes that the workspace was just evaluated at (t, x) (`holds`).
    fn evaluated_at(&mut self, t: f64, x: &[f64]) {
        (self.rhs_t, self.rhs_stamp) = (t, self.ws.rhs_evals);
        self.rhs_x.copy_from_slice(x);
    }
}

/// Cancels a running simulation from another thread; the run stops after its current step
/// with `SimError::Cancelled`.
#[derive(Clone, Debug)]
pub struct CancelHandle(Arc<AtomicBool>);

impl CancelHandle {
    /// A flag no run uses yet; `Simulation::share_cancel` makes runs stop on it.
    pub fn new() -> Self {
        CancelHandle(Arc::new(AtomicBool::new(false)))
    }

    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

impl Default for CancelHandle {
    fn default() -> Self {
        Self::new()
    }
}

pub struct Simulation {
    cell: IntegratorCell,
    stepper: Stepper,
    started: Instant,
    /// Every input event so far: with the model, what a saved state replays (`saved.rs`).
    input_events: Vec<InputChange>,
    /// The compiled model and the parameter changes so far, for a run made from a model
    /// (`from_model`): what `set_parameters` builds on (`tune.rs`).
    tuning: Option<tune::Tuning>,
}

/// A run keeps its rows' states in memory: refuse what cannot fit. (Every variable at once is
/// checked when asked for: `SimResult::check_table`.)
fn check_memory(sys: &System) -> Result<(), SimError> {
    let exp = &sys.experiment;
    let rows = (exp.stop_time - exp.start_time) / exp.interval + 2.0 * sys.time_events.len() as f64;
    let width = (sys.state_len() + 3) as f64;
    if rows * width > crate::result::MAX_TABLE_VALUES {
        return Err(ModelError::File(format!(
            "experiment: Interval = {} gives about {:.0} rows of {} values, more than fits in memory; use a larger Interval",
            exp.interval, rows, width
        ))
        .into());
    }
    Ok(())
}

impl Simulation {
    /// Initializes a run of an assembled system: start values, MSL initialization
    /// (`initial() = true`) and the event it triggers at the start time.
    pub fn new(sys: Arc<System>) -> Result<Self, SimError> {
        Self::with_modes(sys, ModeCache::default())
    }

    /// The same with every mode factored from scratch by `solver` (the dense LU is the test
    /// oracle of the banded, incremental path large drivetrains take).
    pub fn with_linear_solver(
        sys: Arc<System>,
        solver: Box<dyn LinearSolver>,
    ) -> Result<Self, SimError> {
        Self::with_modes(sys, ModeCache::new(solver))
    }

    fn with_modes(sys: Arc<System>, mut cache: ModeCache) -> Result<Self, SimError> {
        let started = Instant::now();
        check_memory(&sys)?;
        let exp = sys.experiment.clone();
        let t0 = exp.start_time;
        let x0 = initial_state(&sys)?;
        let mut disc = DiscreteState::initial(&sys);
        let mut ws = Workspace::new(&sys);
        // Past the last time event the horizon is StopTime: a switch merged into it (too close
        // to separate, so it has no event of its own) must not act early, 1e-10 s before it.
        let first_horizon = (sys.time_events.first().copied()).unwrap_or(sys.experiment.stop_time);
        for initial in [true, false] {
            let at = EventPoint {
                t: t0,
                x: &x0,
                horizon: first_horizon,
                initial,
            };
            iterate(&sys, &mut cache, &mut disc, &at, &mut ws)?;
        }
        let log = initialization_log(&sys, &disc, t0);
        let mm = cache.get(&sys, &disc, t0)?;
        let mut x0 = x0;
        consistent_speeds(&sys, &mm, &disc, t0, &mut x0, first_horizon, &mut ws);
        let n = sys.state_len();
        let phase = Rc::new(RefCell::new(Phase {
            sys: sys.clone(),
            horizon: first_horizon,
            disc,
            mm,
            ws,
            rhs_calls: 0,
            probe: vec![0.0; n],
            f0: vec![0.0; n],
            f0_t: f64::NAN,
            f0_x: vec![0.0; n],
            jacobians: 0,
            scratch: None,
            rhs_t: f64::NAN,
            rhs_x: vec![0.0; n],
            rhs_stamp: usize::MAX,
            stages: Stages::default(),
        }));
        let problem =
            integrator::problem(&sys, &phase, t0, x0.clone(), exp.tolerance, &exp.solver)?;
        let mut cell = integrator::integrator(problem, &exp.solver)?;
        let mut stepper = Stepper::new(sys, phase, cache, x0);
        stepper.log = log;
        stepper.stage_dense = cell.with_dependent(|_, integ| integ.polynomial_dense_output());
        cell.with_dependent_mut(|_, integ| with_solver!(integ, s => stepper.start(s)))?;
        Ok(Simulation {
            cell,
            stepper,
            started,
            input_events: Vec::new(),
            tuning: None,
        })
    }

    /// Assembles a model and initializes a run of it; its tunable parameters can change
    /// during the run (`set_parameters`).
    pub fn from_spec(spec: &ModelSpec) -> Result<Self, SimError> {
        Self::from_model(CompiledModel::new(spec.clone())?)
    }

    /// Initializes a run of a compiled model, keeping the model so that its tunable
    /// parameters can change during the run (`set_parameters`).
    pub fn from_model(model: CompiledModel) -> Result<Self, SimError> {
        let mut sim = Self::new(model.system())?;
        sim.tuning = Some(tune::Tuning::new(model));
        Ok(sim)
    }

    pub fn system(&self) -> &Arc<System> {
        &self.stepper.sys
    }

    /// The time the run was advanced to.
    pub fn time(&self) -> f64 {
        self.stepper.now
    }

    /// Whether the run reached StopTime.
    pub fn finished(&self) -> bool {
        self.stepper.finished
    }

    /// Advances to `t` (at most StopTime): grid rows, state and time events on the way.
    pub fn advance_to(&mut self, t: f64) -> Result<(), SimError> {
        let exp = &self.stepper.sys.experiment;
        let now = self.stepper.now;
        if !t.is_finite() || t < now {
            return Err(SimError::Usage(format!(
                "advance_to({t}): the time must be finite and not before the current time {now}"
            )));
        }
        if t > exp.stop_time * (1.0 + 1e-12) + 1e-12 {
            return Err(SimError::Usage(format!(
                "advance_to({t}): past StopTime = {}",
                exp.stop_time
            )));
        }
        let t = t.min(exp.stop_time);
        // A pause within round-off of the next time event (or of StopTime) is taken at it, the
        // event handled, as a pause exactly there is: `t += 0.01` reaches 0.09999999999999999
        // before a Ramp's start at 0.1, and an input or parameter event a hair before the
        // integrator's stop could not restart it (issue 29).
        let (events, next) = (&self.stepper.sys.time_events, self.stepper.next_te);
        let at = (events.get(next..).unwrap_or_default().iter().copied())
            .find(|&te| te >= t)
            .unwrap_or(exp.stop_time);
        let t = if t < at && crate::signals::same_instant(t, at) {
            at
        } else {
            t
        };
        loop {
            let Simulation { cell, stepper, .. } = &mut *self;
            let switch = cell.with_dependent_mut(|_, integ| {
                let (order, implicit) = (integ.order(), integ.implicit());
                with_solver!(integ, s => stepper.advance(s, t, order, implicit))
            })?;
            if !switch {
                return Ok(());
            }
            self.switch_to_implicit()?;
        }
    }

    /// Advances towards `t` for at most about `budget` of wall-clock time (it pauses between
    /// two integrator steps); returns whether `t` was reached. A caller that must stay
    /// responsive (Ctrl-C in Python) loops over it: the result is that of one `advance_to`.
    pub fn advance_for(&mut self, t: f64, budget: std::time::Duration) -> Result<bool, SimError> {
        self.stepper.deadline = Some(Instant::now() + budget);
        let outcome = self.advance_to(t);
        self.stepper.deadline = None;
        outcome?;
        Ok(self.stepper.finished
            || self.stepper.now >= t.min(self.stepper.sys.experiment.stop_time))
    }

    /// Runs to StopTime.
    pub fn run(&mut self) -> Result<(), SimError> {
        self.advance_to(self.stepper.sys.experiment.stop_time)
    }

    /// The model inputs and their current values.
    pub fn inputs(&self) -> Vec<(String, f64)> {
        let phase = self.stepper.phase.borrow();
        self.stepper
            .sys
            .inputs
            .iter()
            .zip(&phase.disc.inputs)
            .map(|(i, v)| (i.name.clone(), *v))
            .collect()
    }

    /// Sets a model input from the current time on. A new value is an event at this instant
    /// (left and right rows, the event iteration); the same value changes nothing.
    pub fn set_input(&mut self, name: &str, value: f64) -> Result<(), SimError> {
        let sys = self.stepper.sys.clone();
        let Some(k) = sys.inputs.iter().position(|i| i.name == name) else {
            let known: Vec<&str> = sys.inputs.iter().map(|i| i.name.as_str()).collect();
            return Err(SimError::Usage(format!(
                "'{name}' is not an input of the model (inputs: {})",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            )));
        };
        if !value.is_finite() {
            return Err(SimError::Usage(format!(
                "input {name}: {value} is not a finite number"
            )));
        }
        if self.stepper.phase.borrow().disc.inputs[k] == value {
            return Ok(());
        }
        let Simulation { cell, stepper, .. } = self;
        cell.with_dependent_mut(|_, integ| {
            let (order, implicit) = (integ.order(), integ.implicit());
            with_solver!(integ, s => stepper.set_input(s, k, value, name, order, implicit))
        })?;
        let time = self.stepper.now;
        (self.input_events).push(InputChange {
            time,
            input: k,
            value,
        });
        Ok(())
    }

    /// Names of every variable, as in the result (`time` first).
    pub fn names(&self) -> Vec<String> {
        std::iter::once("time".to_string())
            .chain(self.stepper.sys.outputs.iter().map(|(n, _)| n.clone()))
            .collect()
    }

    /// Every variable at the current time, in the order of `names`.
    pub fn values(&mut self) -> Result<Vec<f64>, SimError> {
        let Simulation { cell, stepper, .. } = self;
        let x =
            cell.with_dependent_mut(|_, integ| with_solver!(integ, s => stepper.state_now(s)))?;
        let t = stepper.now;
        let sys = stepper.sys.clone();
        let mut phase = stepper.phase.borrow_mut();
        let Phase {
            disc,
            mm,
            ws,
            horizon,
            ..
        } = &mut *phase;
        evaluate(&sys, mm, disc, t, &x, *horizon, ws);
        Ok(row_values(&sys, ws, disc))
    }

    /// One variable at the current time, by its MSL name (`J1.w`, `clutch1.mode`, …).
    pub fn get(&mut self, name: &str) -> Result<f64, SimError> {
        let Some(column) = self.names().iter().position(|n| n == name) else {
            return Err(SimError::Usage(format!("unknown variable '{name}'")));
        };
        Ok(self.values()?[column])
    }

    pub fn cancel_handle(&self) -> CancelHandle {
        CancelHandle(self.stepper.cancel.clone())
    }

    /// Makes `handle` this run's cancel flag: a sweep stops every run it has going with one.
    pub fn share_cancel(&mut self, handle: &CancelHandle) {
        self.stepper.cancel = handle.0.clone();
    }

    /// Stops the run at its next step (from this or any thread, through a `CancelHandle`).
    pub fn cancel(&self) {
        self.cancel_handle().cancel();
    }

    /// Hands every row and mode change from now on to `observer`; set before the run
    /// advances, it also receives the start row.
    pub fn set_observer(&mut self, observer: Box<dyn Observer>) {
        self.stepper.observer = Some(observer);
        if self.stepper.now == self.stepper.sys.experiment.start_time {
            self.stepper.notify_start_row();
        }
    }

    /// Whether `advance_to` returns right after a state event (a friction element changing
    /// mode), with `time()` there, before its target; advanced on, the run is the same.
    pub fn set_stop_at_events(&mut self, on: bool) {
        self.stepper.stop_at_events = on;
    }

    /// Whether rows are kept for `into_result` (a sweep computing metrics keeps none).
    pub fn set_recording(&mut self, recording: bool) {
        self.stepper.recording = recording;
    }

    /// Back to the start: initialized anew, with the same observer and recording setting.
    pub fn reset(&mut self) -> Result<(), SimError> {
        let mut fresh = self.fresh()?;
        fresh.stepper.observer = self.stepper.observer.take();
        fresh.stepper.notify_start_row();
        fresh.stepper.recording = self.stepper.recording;
        fresh.stepper.stop_at_events = self.stepper.stop_at_events;
        fresh.stepper.cancel = self.stepper.cancel.clone();
        fresh.stepper.cancel.store(false, Ordering::Relaxed);
        *self = fresh;
        Ok(())
    }

    /// The recorded rows, the event log and the run's statistics.
    pub fn into_result(mut self) -> SimResult {
        let earlier = self.tuning.take().map(|t| t.segments).unwrap_or_default();
        let mut all = self.stepper.stiffness.retired;
        self.cell
            .with_dependent_mut(|_, integ| with_solver!(integ, s => all.add(s.get_statistics())));
        let st = self.stepper;
        let delivering = st.guard.delivering(&st.sys);
        let mut stats = st.stats;
        stats.steps = all.steps;
        stats.rejected_steps = all.rejected;
        stats.lu_setups = all.lu_setups;
        stats.solver_switches = st.stiffness.switches;
        stats.rhs_evals = st.phase.borrow().rhs_calls;
        stats.jacobian_evals = st.phase.borrow().jacobians;
        stats.factorizations = st.cache.factorizations;
        stats.wall_ms = self.started.elapsed().as_secs_f64() * 1e3;
        let mut result = SimResult::new(st.sys, st.trajectory, st.discs, st.log, stats)
            .with_earlier_systems(earlier);
        result.delivering = delivering;
        result
    }
}
