//! The run's loop state and its steps: one integrator step at a time, the crossings in it, the
//! output grid, and the events (state, time and input events) with the integrator restarted
//! after each. A step is taken whole and then *processed* up to the time asked for; what lies
//! beyond stays pending, so advancing in pieces processes exactly the steps one call would.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use diffsol::{OdeSolverMethod, OdeSolverStopReason, Vector, VectorCommon};

use super::chatter::ChatterWatch;
use super::integrator::{integrator_error, Eqn, V};
use super::{Observer, Phase};
use crate::engine::eval::{evaluate, DiscreteState};
use crate::engine::{indicator_count, indicator_label, indicators, ModeCache};
use crate::error::SimError;
use crate::result::{EventRecord, RowView, Stats, Trajectory};
use crate::system::System;

/// The most state events and steps a run may take (a runaway, not a model, needs more).
const MAX_STEPS: usize = 5_000_000;

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
    pub(super) log: Vec<EventRecord>,
    pub(super) observer: Option<Box<dyn Observer>>,
    pub(super) z_prev: Vec<f64>,
    pub(super) z: Vec<f64>,
    /// Indicators at the previous sample while scanning a step.
    pub(super) z_scan: Vec<f64>,
    /// Rates of the speed indicators at the current and the previous sample.
    pub(super) dz: Vec<f64>,
    pub(super) dz_scan: Vec<f64>,
    /// The last interior sample of the previous step (time, indicators), for humps across the
    /// step boundary; cleared at events.
    pub(super) hump_back: Option<(f64, Vec<f64>)>,
    pub(super) dz_probe: Vec<f64>,
    /// State buffer (interpolated or current).
    pub(super) x: Vec<f64>,
    /// diffsol's vector for dense output, reused.
    pub(super) dense: Option<V>,
    pub(super) grid_k: usize,
    pub(super) stats: Stats,
    /// Where processing stands: the integrator's time unless a step is pending.
    pub(super) t_prev: f64,
    /// The time the user advanced to (≤ the integrator's).
    pub(super) now: f64,
    /// The integrator's stop: the next time event, or StopTime.
    pub(super) stop: f64,
    pub(super) next_te: usize,
    pub(super) pending: Option<Pending>,
    pub(super) finished: bool,
    /// Time of the last recorded row (an input event there reuses it as its left row).
    pub(super) last_row: f64,
    pub(super) cancel: Arc<AtomicBool>,
    /// When the run began (for the `timeout` limit).
    pub(super) started: Instant,
    /// `advance_for`: pause between steps once this instant has passed.
    pub(super) deadline: Option<Instant>,
    /// Mode changes per element, to tell chattering from many legitimate events.
    pub(super) chatter: ChatterWatch,
    pub(super) candidates: Vec<(usize, f64, f64)>,
}

impl Stepper {
    pub fn new(
        sys: Arc<System>,
        phase: Rc<RefCell<Phase>>,
        cache: ModeCache,
        x0: Vec<f64>,
    ) -> Self {
        let nz = indicator_count(&sys);
        let t0 = sys.experiment.start_time;
        let chatter = ChatterWatch::new(&sys.experiment);
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
            log: Vec::new(),
            observer: None,
            z_prev: vec![0.0; nz],
            z: vec![0.0; nz],
            z_scan: vec![0.0; nz],
            dz: vec![f64::NAN; nz],
            dz_scan: vec![f64::NAN; nz],
            hump_back: None,
            dz_probe: vec![f64::NAN; nz],
            x: x0,
            dense: None,
            grid_k: 1,
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
            candidates: Vec::new(),
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

    /// Continues from a saved cursor with `self.x` holding the state at its time.
    pub fn set_cursor(&mut self, c: &Cursor) {
        self.now = c.now;
        self.t_prev = c.now;
        self.stop = c.stop;
        self.next_te = c.next_te;
        self.grid_k = c.grid_k;
        self.finished = c.finished;
        self.pending = None;
        self.last_row = f64::NAN;
    }

    fn grid_time(&self, k: usize) -> f64 {
        self.sys.experiment.grid_time(k)
    }

    pub(super) fn grid_len(&self) -> usize {
        self.sys.experiment.grid_len()
    }

    /// Evaluates at (t, self.x) in the current discrete state; fills `z` if asked.
    pub fn evaluate_here(&mut self, t: f64, with_indicators: bool) {
        let mut guard = self.phase.borrow_mut();
        let Phase {
            disc,
            mm,
            ws,
            horizon,
            ..
        } = &mut *guard;
        evaluate(&self.sys, mm, disc, t, &self.x, *horizon, ws);
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
        if self.discs.last() != Some(&guard.disc) {
            self.discs.push(guard.disc.clone());
        }
        let id = (self.discs.len() - 1) as u32;
        self.trajectory.push(t, guard.horizon, id, &self.x);
    }

    /// The state at t from the dense output of the last step, into `out`.
    pub fn interpolate<'a, S>(
        &mut self,
        solver: &S,
        t: f64,
        out: &mut [f64],
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let n = out.len();
        let y = self
            .dense
            .get_or_insert_with(|| V::zeros(n, *solver.state().y.context()));
        solver
            .interpolate_inplace(t, y)
            .map_err(|e| integrator_error(t, e))?;
        out.copy_from_slice(y.inner().as_slice());
        Ok(())
    }

    /// Loads the state at t (dense output of the last step) into `self.x`.
    pub fn load<'a, S>(&mut self, solver: &S, t: f64) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let mut x = std::mem::take(&mut self.x);
        let r = self.interpolate(solver, t, &mut x);
        self.x = x;
        r
    }

    /// The state at the time the user advanced to.
    pub fn state_now<'a, S>(&mut self, solver: &S) -> Result<Vec<f64>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let mut x = solver.state().y.inner().as_slice().to_vec();
        if self.pending.is_some() {
            self.interpolate(solver, self.now, &mut x)?;
        } else if !self.finished || self.now == self.t_prev {
            x.copy_from_slice(&self.x);
        }
        Ok(x)
    }

    /// Records the grid points in (last recorded, limit] (or up to but excluding `limit`).
    fn emit_grid<'a, S>(
        &mut self,
        solver: &S,
        limit: f64,
        inclusive: bool,
        t_step_end: f64,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let eps = 1e-12 * limit.abs().max(1.0);
        while self.grid_k <= self.grid_len() {
            let tg = self.grid_time(self.grid_k);
            let due = if inclusive {
                tg <= limit + eps
            } else {
                tg < limit - eps
            };
            if !due {
                break;
            }
            self.load(solver, tg.min(t_step_end))?;
            self.record_here(tg);
            self.grid_k += 1;
        }
        Ok(())
    }

    /// Records the grid points up to `target` while a step is processed only that far, leaving
    /// out one that coincides with the `event` ahead (its two event rows will stand for it, as
    /// when the step is processed at once).
    fn emit_grid_before<'a, S>(
        &mut self,
        solver: &S,
        target: f64,
        event: f64,
        t_step_end: f64,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let eps = 1e-12 * event.abs().max(1.0);
        let limit = if (target - event).abs() <= eps {
            target.min(event - 2.0 * eps)
        } else {
            target
        };
        self.emit_grid(solver, limit, true, t_step_end)
    }

    /// Skips grid points that coincide with an event (the two event rows stand for them).
    pub(super) fn skip_grid_at(&mut self, t: f64) {
        let eps = 1e-12 * t.abs().max(1.0);
        while self.grid_k <= self.grid_len() && (self.grid_time(self.grid_k) - t).abs() <= eps {
            self.grid_k += 1;
        }
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
        let limits = &self.sys.experiment.limits;
        let limit = |limit: String| Err(SimError::Limit { time: t, limit });
        let steps = solver.get_statistics().number_of_steps;
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
        S: OdeSolverMethod<'a, Eqn>,
    {
        let reason = solver
            .step()
            .map_err(|e| integrator_error(self.t_prev, e))?;
        let t_now = solver.state().t;
        self.check_progress(solver, t_now)?;
        let stop = self.stop;
        // At a pending time event the signals keep their left limits (the horizon).
        let at_time_event = self.next_te < self.sys.time_events.len()
            && (t_now - stop).abs() <= 1e-12 * stop.abs().max(1.0);
        let mut candidates = std::mem::take(&mut self.candidates);
        let found = self.scan_step(solver, self.t_prev, t_now, &mut candidates);
        self.candidates = candidates;
        let located = match found? {
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

    /// Processes steps until `target` is reached (or StopTime): grid rows, state and time
    /// events. A step that reaches past `target` is taken whole and stays pending.
    pub fn advance<'a, S>(
        &mut self,
        solver: &mut S,
        target: f64,
        order: usize,
        implicit: bool,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        while !self.finished {
            if self.pending.is_none() {
                if self.t_prev >= target {
                    break;
                }
                if self.deadline.is_some_and(|d| Instant::now() >= d) {
                    // paused between two steps: resuming is the same as never stopping
                    self.now = self.now.max(self.t_prev);
                    return Ok(());
                }
                self.take_step(solver)?;
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
        Ok(())
    }
}
