//! The run's loop state and its steps: one integrator step at a time, the crossings in it, the
//! output grid, and the events (state, time and input events) with the integrator restarted
//! after each. A step is taken whole and then *processed* up to the time asked for; what lies
//! beyond stays pending, so advancing in pieces processes exactly the steps one call would.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use diffsol::{OdeSolverMethod, OdeSolverStopReason, VectorCommon};

use super::auto::StiffnessWatch;
use super::chatter::ChatterWatch;
use super::dense::StepPoly;
use super::guard::Guard;
use super::integrator::{integrator_error, Eqn, StepBudget, V};
use super::samples::StepSamples;
use super::watch::Watch;
use super::{Observer, Phase};
use crate::engine::eval::{evaluate, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::engine::{indicator_count, indicator_label, indicators, wear_indicator, ModeCache};
use crate::error::SimError;
use crate::result::{EventRecord, RowView, Stats, Trajectory};
use crate::system::System;

/// An evaluation of the system at one instant: `evaluate`, or `evaluate_switching`.
pub(super) type Evaluation =
    fn(&System, &ModeMatrix, &DiscreteState, f64, &[f64], f64, &mut Workspace);

/// The most state events and steps a run may take (a runaway, not a model, needs more).
const MAX_STEPS: usize = 5_000_000;
/// The longest step, a quarter of the signals' shortest time scale. A locked drivetrain's
/// states do not move, so the integrator would take steps longer than a 5 Hz drive's period,
/// and the crossing scan's samples could not follow a static limit that the drive crosses and
/// recovers between them (found by the soak: a brake holding 0.33 N·m beyond its limit for
/// 55 ms, tests/data/missed_breakaway.toml).
pub(super) fn max_step(sys: &System) -> f64 {
    sys.signals.time_scale() / 4.0
}

/// Why a step of length 0 stops the run.
const ZERO_STEP: &str = "the step size fell to 0: the derivatives are too large for floating point (a force or an input far beyond the model's scale?)";

/// A step taken but not yet processed to its end.
pub(super) struct Pending {
    pub(super) t_now: f64,
    pub(super) tstop: bool,
    pub(super) at_time_event: bool,
    /// A crossing inside the step, with its cause, unless it is handled with the time event.
    pub(super) located: Option<(f64, String)>,
    /// The cause of a crossing that coincides with the pending time event.
    pub(super) tied_cause: Option<String>,
}

/// What changes the discrete state at an event besides the relations.
pub(super) enum EventKind {
    State,
    Time,
    /// A model input set to a new value (input index, value).
    Input(usize, f64),
    /// Parameters set to new values (`tune.rs`; the system was swapped before).
    Parameter,
}

/// Where a run stands, apart from its continuous and discrete state (part of a saved state).
#[derive(Debug, Clone, PartialEq)]
pub struct Cursor {
    pub now: f64,
    pub stop: f64,
    pub next_te: usize,
    pub grid_k: usize,
    pub finished: bool,
}

pub(super) struct Stepper {
    pub(super) sys: Arc<System>,
    pub(super) phase: Rc<RefCell<Phase>>,
    pub(super) cache: ModeCache,
    pub(super) trajectory: Trajectory,
    pub(super) recording: bool,
    /// Every discrete state the run went through; rows refer to them by index.
    pub(super) discs: Vec<DiscreteState>,
    /// Whether the last of `discs` is known to be the current discrete state (cleared where
    /// it changes: events, restored states), so a row need not compare them.
    pub(super) disc_recorded: bool,
    pub(super) log: Vec<EventRecord>,
    pub(super) observer: Option<Box<dyn Observer>>,
    /// The grid times and states of a step's rows shown to the observer alone (`observe_rows`).
    pub(super) observed: (Vec<f64>, Vec<f64>),
    pub(super) z_prev: Vec<f64>,
    pub(super) z: Vec<f64>,
    pub(super) z_scan: Vec<f64>, // indicators at the previous sample while scanning a step
    /// Rates of the speed indicators at the current and the previous sample.
    pub(super) dz: Vec<f64>,
    pub(super) dz_scan: Vec<f64>,
    /// The time of the last interior sample of the previous step (its indicators in `z_back`),
    /// for humps across the step boundary; cleared at events.
    pub(super) hump_back: Option<f64>,
    pub(super) z_back: Vec<f64>,
    pub(super) dz_probe: Vec<f64>,
    /// The current step's samples, and whether a search probed elsewhere since they were taken.
    pub(super) samples: StepSamples,
    pub(super) probed: bool,
    /// State buffer (interpolated or current).
    pub(super) x: Vec<f64>,
    /// diffsol's vector for dense output, reused.
    pub(super) dense: Option<V>,
    /// The pending step's dense output from its stages (`dense.rs`), when the method is
    /// Tsit45 (`stage_dense`); the start state of the step being taken.
    pub(super) poly: StepPoly,
    pub(super) stage_dense: bool,
    pub(super) y0: Vec<f64>,
    pub(super) grid_k: usize,
    /// The index of the last grid point.
    pub(super) grid_last: usize,
    pub(super) stats: Stats,
    /// Where processing stands: the integrator's time unless a step is pending.
    pub(super) t_prev: f64,
    pub(super) now: f64,  // the time the user advanced to (≤ the integrator's)
    pub(super) stop: f64, // the integrator's stop: the next time event, or StopTime
    pub(super) next_te: usize,
    pub(super) pending: Option<Pending>,
    pub(super) finished: bool,
    /// Time of the last recorded row (an input event there reuses it as its left row).
    pub(super) last_row: f64,
    pub(super) cancel: Arc<AtomicBool>,
    pub(super) started: Instant, // when the run began (for the `timeout` limit)
    /// `advance_for`: pause between steps once this instant has passed.
    pub(super) deadline: Option<Instant>,
    pub(super) chatter: ChatterWatch, // mode changes per element: chattering or many events
    pub(super) stiffness: StiffnessWatch, // Solver = "auto": held back by stability?
    pub(super) candidates: Vec<(usize, f64, f64)>,
    /// `advance` returns right after a state event (FMI 3.0's early return).
    pub(super) stop_at_events: bool,
    /// The longest step: a quarter of the signals' shortest time scale (`max_step`).
    pub(super) max_step: f64,
    /// Whether the system has prescribed motions (rows then project their speeds).
    pub(super) prescribes: bool,
    /// What every step's end is checked for besides crossings (`guard.rs`).
    pub(super) guard: Guard,
    /// A level `advance_until` waits for (`redrive.rs`); none in an ordinary run.
    pub(super) watch: Option<Watch>,
    /// How many times a speed was set from outside (`reinit_speed`).
    pub(super) reinits: usize,
}

impl Stepper {
    pub fn new(
        sys: Arc<System>,
        phase: Rc<RefCell<Phase>>,
        cache: ModeCache,
        x0: Vec<f64>,
    ) -> Self {
        let nz = indicator_count(&sys);
        let max_step = max_step(&sys);
        let sys_prescribes = sys.prescribes();
        let guard = Guard::new(&sys);
        let t0 = sys.experiment.start_time;
        let chatter = ChatterWatch::new(&sys.experiment);
        let grid_last = sys.experiment.grid_len();
        let stiffness = StiffnessWatch::new(sys.experiment.solver == "auto", x0.len());
        let stop = sys
            .time_events
            .first()
            .copied()
            .unwrap_or(sys.experiment.stop_time);
        Stepper {
            trajectory: Trajectory {
                width: x0.len(),
                ..Trajectory::default()
            },
            sys,
            phase,
            cache,
            recording: true,
            discs: Vec::new(),
            disc_recorded: false,
            log: Vec::new(),
            observer: None,
            observed: (Vec::new(), Vec::new()),
            z_prev: vec![0.0; nz],
            z: vec![0.0; nz],
            z_scan: vec![0.0; nz],
            dz: vec![f64::NAN; nz],
            dz_scan: vec![f64::NAN; nz],
            hump_back: None,
            z_back: vec![0.0; nz],
            dz_probe: vec![f64::NAN; nz],
            samples: StepSamples::default(),
            probed: false,
            x: x0,
            dense: None,
            poly: StepPoly::default(),
            stage_dense: false,
            y0: Vec::new(),
            grid_k: 1,
            grid_last,
            stats: Stats::default(),
            t_prev: t0,
            now: t0,
            stop,
            next_te: 0,
            pending: None,
            finished: false,
            last_row: f64::NAN,
            cancel: Arc::new(AtomicBool::new(false)),
            started: Instant::now(),
            deadline: None,
            chatter,
            stiffness,
            candidates: Vec::new(),
            stop_at_events: false,
            max_step,
            prescribes: sys_prescribes,
            guard,
            watch: None,
            reinits: 0,
        }
    }

    pub fn cursor(&self) -> Cursor {
        Cursor {
            now: self.now,
            stop: self.stop,
            next_te: self.next_te,
            grid_k: self.grid_k,
            finished: self.finished,
        }
    }

    /// Evaluates at (t, self.x) in the current discrete state; fills `z` if asked.
    pub fn evaluate_here(&mut self, t: f64, with_indicators: bool) {
        self.evaluate_with(evaluate, t, with_indicators);
        self.phase.borrow_mut().evaluated_at(t, &self.x);
    }

    /// `eval` (`evaluate`, or `evaluate_switching` for a probe) at (t, self.x) in the current
    /// discrete state; fills `z` if asked. Not noted as evaluated: the caller says whether the
    /// workspace then holds the derivative.
    pub(super) fn evaluate_with(&mut self, eval: Evaluation, t: f64, with_indicators: bool) {
        let mut guard = self.phase.borrow_mut();
        let Phase {
            disc,
            mm,
            ws,
            horizon,
            ..
        } = &mut *guard;
        eval(&self.sys, mm, disc, t, &self.x, *horizon, ws);
        if with_indicators {
            indicators(&self.sys, disc, ws, &mut self.z);
        }
    }

    /// Shows the observer the start row (recorded at initialization, before it was set).
    pub(super) fn notify_start_row(&mut self) {
        let guard = self.phase.borrow();
        if let Some(observer) = self.observer.as_mut() {
            observer.row(&RowView {
                t: self.last_row,
                x: &self.x,
                disc: &guard.disc,
                horizon: guard.horizon,
            });
        }
    }

    /// Records a row at (t, self.x) in the current discrete state (its consistent speeds).
    pub fn record_here(&mut self, t: f64) {
        self.last_row = t;
        self.phase.borrow_mut().project(&self.sys, t, &mut self.x);
        let guard = self.phase.borrow();
        if let Some(observer) = self.observer.as_mut() {
            observer.row(&RowView {
                t,
                x: &self.x,
                disc: &guard.disc,
                horizon: guard.horizon,
            });
        }
        if !self.recording {
            return;
        }
        if !self.disc_recorded {
            if self.discs.last() != Some(&guard.disc) {
                self.discs.push(guard.disc.clone());
            }
            self.disc_recorded = true;
        }
        if self.trajectory.rows() == 0 {
            self.trajectory.reserve(expected_rows(&self.sys));
        }
        let id = (self.discs.len() - 1) as u32;
        self.trajectory.push(t, guard.horizon, id, &self.x);
    }

    /// Stops a run that cannot succeed, with a reason, instead of running away: a non-finite
    /// state (overflow, a singular mode), more events or steps than any sensible model needs, or
    /// a cancellation.
    fn check_progress<'a, S>(&self, solver: &S, t: f64) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        if self.cancel.load(Ordering::Relaxed) {
            return Err(SimError::Cancelled { time: t });
        }
        if solver.state().y.inner().iter().any(|v| !v.is_finite()) {
            return Err(SimError::NonFiniteState { time: t });
        }
        if t <= self.t_prev {
            // diffsol's starting step is 0 when the derivatives' norm overflows (a brake
            // pressed with 1e200): its zero steps would be accepted for ever
            return Err(integrator_error(t, ZERO_STEP));
        }
        let limits = &self.sys.experiment.limits;
        let limit = |limit: String| Err(SimError::Limit { time: t, limit });
        let steps = solver.get_statistics().number_of_steps + self.stiffness.retired.steps;
        match (limits.max_events, limits.max_steps, limits.timeout) {
            (Some(max), _, _) if self.stats.state_events > max => {
                limit(format!("max_events = {max}"))
            }
            (_, Some(max), _) if steps > max => limit(format!("max_steps = {max}")),
            (_, _, Some(s)) if self.started.elapsed().as_secs_f64() > s => {
                limit(format!("timeout = {s} s"))
            }
            _ if steps > MAX_STEPS => Err(SimError::StepLimit {
                time: t,
                limit: MAX_STEPS,
            }),
            _ => Ok(()),
        }
    }

    /// Records the first row at the start time and arms the integrator's first stop.
    pub fn start<'a, S>(&mut self, solver: &mut S) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let t0 = self.t_prev;
        self.record_here(t0);
        self.evaluate_here(t0, true);
        self.z_prev.copy_from_slice(&self.z);
        solver
            .set_stop_time(self.stop)
            .map_err(|e| integrator_error(t0, e))
    }

    /// Takes one integrator step and scans it for crossings; the step becomes pending.
    fn take_step<'a, S>(&mut self, solver: &mut S) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn> + StepBudget,
    {
        solver.renew_budget();
        solver.limit_step(self.max_step);
        self.record_stages(solver, true);
        let reason = solver.step();
        self.record_stages(solver, false);
        let reason = reason.map_err(|e| integrator_error(self.t_prev, e))?;
        let t_now = solver.state().t;
        self.check_progress(solver, t_now)?;
        let (x_now, h) = (solver.state().y.inner().as_slice(), t_now - self.t_prev);
        self.stiffness
            .watch(&self.sys, &self.phase, t_now, x_now, h);
        let stop = self.stop;
        // At a pending time event the signals keep their left limits (the horizon).
        let at_time_event = self.next_te < self.sys.time_events.len()
            && (t_now - stop).abs() <= 1e-12 * stop.abs().max(1.0);
        let mut candidates = std::mem::take(&mut self.candidates);
        let found = self.scan_step(solver, self.t_prev, t_now, &mut candidates);
        self.candidates = candidates;
        let found = found?;
        if let Some(k) = found.and_then(|(_, i)| wear_indicator(&self.sys, i)) {
            let wear = &self.sys.wear[k];
            let (volume, thickness_min) = wear.limit.expect("only a limit fires");
            return Err(SimError::WearLimit {
                time: found.expect("found").0,
                element: wear.name.clone(),
                thickness_min,
                volume,
            });
        }
        if found.is_none() {
            if let Some(k) = self.guard.negative {
                return Err(self.negative_characteristic(solver, self.t_prev, t_now, k));
            }
            self.guard.keep();
        }
        let located = match found {
            Some((t_e, i)) => Some((
                t_e,
                indicator_label(&self.sys, &self.phase.borrow().disc, i),
            )),
            None => None,
        };
        // A crossing at the pending time event is handled with it (one event iteration).
        let tie = |t_e: f64| at_time_event && stop - t_e <= 1e-12 * stop.abs().max(1.0);
        let (located, tied_cause) = match located {
            Some((t_e, cause)) if tie(t_e) => (None, Some(cause)),
            other => (other, None),
        };
        self.pending = Some(Pending {
            t_now,
            tstop: matches!(reason, OdeSolverStopReason::TstopReached),
            at_time_event,
            located,
            tied_cause,
        });
        Ok(())
    }

    /// Records the stages of a Tsit45 step (`begin` before it, else after it) and forms its
    /// dense output from them.
    fn record_stages<'a, S>(&mut self, solver: &S, begin: bool)
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.poly.clear();
        if !self.stage_dense {
            return;
        }
        let state = solver.state();
        let stages = &mut self.phase.borrow_mut().stages;
        if begin {
            self.y0.clear();
            self.y0.extend_from_slice(state.y.inner().as_slice());
            stages.begin(state.dy.inner().as_slice());
        } else if stages.end() {
            let end = (state.t, state.y.inner().as_slice());
            self.poly.set((self.t_prev, &self.y0), end, stages);
        }
    }

    /// Processes steps until `target` is reached (or StopTime): grid rows, state and time
    /// events. A step that reaches past `target` is taken whole and stays pending. Returns
    /// `true` when it stopped between two steps for the "auto" switch to the implicit method.
    pub fn advance<'a, S>(
        &mut self,
        solver: &mut S,
        mut target: f64,
        order: usize,
        implicit: bool,
    ) -> Result<bool, SimError>
    where
        S: OdeSolverMethod<'a, Eqn> + StepBudget,
    {
        while !self.finished {
            if self.pending.is_none() {
                if self.stiffness.switch_due {
                    return Ok(true);
                }
                if self.t_prev >= target {
                    break;
                }
                if self.deadline.is_some_and(|d| Instant::now() >= d) {
                    // paused between two steps: resuming is the same as never stopping
                    self.now = self.now.max(self.t_prev);
                    return Ok(false);
                }
                self.take_step(solver)?;
            }
            if self.watch.is_some() {
                target = self.watched_target(solver, target)?; // `advance_until` (redrive.rs)
            }
            let p = self.pending.as_ref().expect("a step is pending");
            let t_now = p.t_now;
            if let Some((t_e, _)) = p.located {
                if t_e > target {
                    self.emit_grid_before(solver, target, t_e, t_now)?;
                    break;
                }
                let (t_e, cause) = self
                    .pending
                    .take()
                    .and_then(|p| p.located)
                    .expect("located");
                self.emit_grid(solver, t_e, false, t_now)?;
                self.load(solver, t_e)?;
                let horizon = self.phase.borrow().horizon;
                self.handle_event(t_e, horizon, EventKind::State, &cause)?;
                self.restart(solver, t_e, order, implicit)?;
                if self.stop_at_events && t_e < target {
                    // the run stands at the event, restarted: going on is as never stopping
                    self.now = t_e;
                    return Ok(false);
                }
                continue;
            }
            if t_now > target {
                let boundary = if p.at_time_event {
                    t_now
                } else {
                    f64::INFINITY
                };
                self.emit_grid_before(solver, target, boundary, t_now)?;
                break;
            }
            let p = self.pending.take().expect("a step is pending");
            // A grid point on a time event is replaced by the event's two rows.
            self.emit_grid(solver, t_now, !p.at_time_event, t_now)?;
            self.x.copy_from_slice(solver.state().y.inner().as_slice());
            self.z_prev.copy_from_slice(&self.z);
            self.t_prev = t_now;
            if p.tstop || t_now >= self.stop {
                self.time_event(solver, p.tied_cause, order, implicit)?;
            }
        }
        self.now = if self.finished {
            target.min(self.t_prev)
        } else {
            target
        };
        Ok(false)
    }
}

/// The rows a run of `sys` is expected to record (reserved up front).
pub(super) fn expected_rows(sys: &System) -> usize {
    // the grid, both sides of each time event, and room for events: a 16th of the grid
    // (HeatLosses' 161 state events add 322 rows to 20 001; regrowing the buffer past the
    // reservation copied all of it, a twentieth of that run)
    let grid = sys.experiment.grid_len();
    grid + (grid / 16).max(201) + 2 * sys.time_events.len()
}
