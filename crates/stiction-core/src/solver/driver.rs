//! The simulation run. diffsol integrates each continuous phase step by step; after every step
//! the zero-crossing indicators are checked at its end, and a crossing is located on diffsol's
//! dense output by Illinois regula falsi that always returns the instant just *after* the
//! crossing (so the event iteration sees the relation already changed, as Modelica requires).
//! diffsol's own root finder is not used: it reports any sign change to a tolerance we do not
//! control, while MSL semantics need the directional, frozen-relation crossings below.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use std::time::Instant;

use diffsol::{
    NalgebraLU, NalgebraMat, NalgebraVec, NonLinearOp, OdeBuilder, OdeEquations, OdeSolverMethod,
    OdeSolverStopReason, Vector, VectorCommon,
};

use super::initial_state;
use crate::components::friction::logic::UNKNOWN;
use crate::components::friction::lossy_gear::GearState;
use crate::components::friction::FrictionState;
use crate::error::SimError;
use crate::events::{
    indicator_count, indicator_label, indicators, iterate, speed_rates, ModeCache, ModeChange,
};
use crate::result::{EventRecord, SimResult, Stats, Trajectory};
use crate::system::eval::{derivative, evaluate, DiscreteState, Workspace};
use crate::system::kkt::ModeMatrix;
use crate::system::System;

type M = NalgebraMat<f64>;
type V = NalgebraVec<f64>;
type LS = NalgebraLU<f64>;

/// What the right-hand side reads: the frozen discrete state, its factored mode matrix and the
/// workspace. Changed only between steps, at events.
struct Phase {
    disc: DiscreteState,
    /// The first time event not handled yet: signals switch there only once it is handled
    /// (Modelica freezes `time >= t0` between events), wherever the integrator evaluates.
    horizon: f64,
    mm: Rc<ModeMatrix>,
    ws: Workspace,
    rhs_calls: usize,
    probe: Vec<f64>,
    f0: Vec<f64>,
}

fn numerical(time: f64, e: impl std::fmt::Display) -> SimError {
    SimError::Numerical {
        time,
        message: format!("integrator: {e}"),
    }
}

pub fn run(sys: Arc<System>) -> Result<SimResult, SimError> {
    let started = Instant::now();
    let exp = sys.experiment.clone();
    let t0 = exp.start_time;
    // Rows are kept in memory (states, and all variables once asked for): refuse what cannot fit.
    let rows = (exp.stop_time - exp.start_time) / exp.interval + 2.0 * sys.time_events.len() as f64;
    let width = (sys.outputs.len() + 1).max(sys.state_len() + 3) as f64;
    if rows * width > 3.0e8 {
        return Err(crate::error::ModelError::File(format!(
            "experiment: Interval = {} gives about {:.0} rows of {} values, more than fits in memory; use a larger Interval",
            exp.interval, rows, width
        ))
        .into());
    }
    let x0 = initial_state(&sys)?;
    let mut cache = ModeCache::default();
    let mut disc = DiscreteState {
        friction: sys.frictions.iter().map(FrictionState::initial).collect(),
        gears: vec![GearState::INITIAL; sys.lossy_gears.len()],
        relations: vec![false; sys.relation_count],
    };
    let mut ws = Workspace::new(&sys);
    // MSL initialization (initial() = true), then the event it triggers at t0.
    let first_horizon = sys.time_events.first().copied().unwrap_or(f64::INFINITY);
    for initial in [true, false] {
        iterate(
            &sys,
            &mut cache,
            &mut disc,
            t0,
            &x0,
            initial,
            first_horizon,
            &mut ws,
        )?;
    }
    let mut log: Vec<EventRecord> = disc
        .friction
        .iter()
        .zip(&sys.frictions)
        .map(|(st, fe)| EventRecord {
            time: t0,
            component: fe.name.clone(),
            old_mode: UNKNOWN,
            new_mode: st.pre.mode,
            cause: "initialization".into(),
        })
        .collect();
    // A LossyGear starts from pre(mode) = Free; an ideal one stays there.
    log.extend(
        disc.gears
            .iter()
            .zip(&sys.lossy_gears)
            .filter(|(st, _)| st.pre.mode != GearState::INITIAL.pre.mode)
            .map(|(st, g)| EventRecord {
                time: t0,
                component: g.name.clone(),
                old_mode: GearState::INITIAL.pre.mode,
                new_mode: st.pre.mode,
                cause: "initialization".into(),
            }),
    );

    let mm = cache.get(&sys, &disc, t0)?;
    let n = sys.state_len();
    let phase = Rc::new(RefCell::new(Phase {
        horizon: first_horizon,
        disc,
        mm,
        ws,
        rhs_calls: 0,
        probe: vec![0.0; n],
        f0: vec![0.0; n],
    }));

    let (ph, sy) = (phase.clone(), sys.clone());
    let rhs = move |x: &[f64], _p: &[f64], t: f64, y: &mut [f64]| {
        let mut guard = ph.borrow_mut();
        let Phase {
            disc,
            mm,
            ws,
            rhs_calls,
            horizon,
            ..
        } = &mut *guard;
        *rhs_calls += 1;
        evaluate(&sy, mm, disc, t, x, *horizon, ws);
        derivative(&sy, ws, y);
    };
    // Jacobian-vector products for the implicit methods, by forward differences.
    let (ph, sy) = (phase.clone(), sys.clone());
    let jac_vec = move |x: &[f64], _p: &[f64], t: f64, v: &[f64], y: &mut [f64]| {
        let mut guard = ph.borrow_mut();
        let Phase {
            disc,
            mm,
            ws,
            rhs_calls,
            probe,
            f0,
            horizon,
        } = &mut *guard;
        let horizon = *horizon;
        let vnorm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        if vnorm == 0.0 {
            y.fill(0.0);
            return;
        }
        let xnorm = x.iter().map(|a| a * a).sum::<f64>().sqrt();
        let eps = f64::EPSILON.sqrt() * (1.0 + xnorm) / vnorm;
        *rhs_calls += 2;
        evaluate(&sy, mm, disc, t, x, horizon, ws);
        derivative(&sy, ws, f0);
        for i in 0..x.len() {
            probe[i] = x[i] + eps * v[i];
        }
        evaluate(&sy, mm, disc, t, probe, horizon, ws);
        derivative(&sy, ws, y);
        for i in 0..y.len() {
            y[i] = (y[i] - f0[i]) / eps;
        }
    };
    let x_init = x0.clone();
    let problem = OdeBuilder::<M>::new()
        .t0(t0)
        .rtol(exp.tolerance)
        .atol([exp.tolerance])
        .rhs_implicit(rhs, jac_vec)
        .init(
            move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&x_init),
            n,
        )
        .build()
        .map_err(|e| numerical(t0, e))?;

    let mut driver = Driver {
        sys: sys.clone(),
        phase,
        cache,
        trajectory: Trajectory {
            width: n,
            ..Trajectory::default()
        },
        discs: Vec::new(),
        log: std::mem::take(&mut log),
        z_prev: vec![0.0; indicator_count(&sys)],
        z: vec![0.0; indicator_count(&sys)],
        z_scan: vec![0.0; indicator_count(&sys)],
        dz: vec![f64::NAN; indicator_count(&sys)],
        dz_scan: vec![f64::NAN; indicator_count(&sys)],
        dz_probe: vec![f64::NAN; indicator_count(&sys)],
        x: x0,
        dense: None,
        grid_k: 1,
        stats: Stats::default(),
        implicit: exp.solver != "tsit45",
    };
    let solver_stats = match exp.solver.as_str() {
        "bdf" => driver.drive(problem.bdf::<LS>().map_err(|e| numerical(t0, e))?, 1)?,
        "esdirk34" => driver.drive(problem.esdirk34::<LS>().map_err(|e| numerical(t0, e))?, 3)?,
        _ => driver.drive(problem.tsit45().map_err(|e| numerical(t0, e))?, 4)?,
    };
    let mut stats = driver.stats;
    stats.steps = solver_stats.0;
    stats.rejected_steps = solver_stats.1;
    stats.rhs_evals = driver.phase.borrow().rhs_calls;
    stats.factorizations = driver.cache.factorizations;
    stats.wall_ms = started.elapsed().as_secs_f64() * 1e3;
    Ok(SimResult::new(
        sys,
        driver.trajectory,
        driver.discs,
        driver.log,
        stats,
    ))
}

struct Driver {
    sys: Arc<System>,
    phase: Rc<RefCell<Phase>>,
    cache: ModeCache,
    trajectory: Trajectory,
    /// Every discrete state the run went through; rows refer to them by index.
    discs: Vec<DiscreteState>,
    log: Vec<EventRecord>,
    z_prev: Vec<f64>,
    z: Vec<f64>,
    /// Indicators at the previous sample while scanning a step.
    z_scan: Vec<f64>,
    /// Rates of the speed indicators at the current and the previous sample.
    dz: Vec<f64>,
    dz_scan: Vec<f64>,
    dz_probe: Vec<f64>,
    /// State buffer (interpolated or current).
    x: Vec<f64>,
    /// diffsol's vector for dense output, reused.
    dense: Option<V>,
    grid_k: usize,
    stats: Stats,
    implicit: bool,
}

impl Driver {
    fn grid_time(&self, k: usize) -> f64 {
        let e = &self.sys.experiment;
        (e.start_time + k as f64 * e.interval).min(e.stop_time)
    }

    fn grid_len(&self) -> usize {
        let e = &self.sys.experiment;
        ((e.stop_time - e.start_time) / e.interval - 1e-9).ceil() as usize
    }

    /// Evaluates at (t, self.x) in the current discrete state; fills `z` if asked.
    fn evaluate_here(&mut self, t: f64, with_indicators: bool) {
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

    fn record_here(&mut self, t: f64) {
        let guard = self.phase.borrow();
        let horizon = guard.horizon;
        if self.discs.last() != Some(&guard.disc) {
            self.discs.push(guard.disc.clone());
        }
        let id = (self.discs.len() - 1) as u32;
        self.trajectory.push(t, horizon, id, &self.x);
    }

    fn load<'a, Eqn, S>(&mut self, solver: &S, t: f64) -> Result<(), SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        let n = self.x.len();
        let y = self
            .dense
            .get_or_insert_with(|| V::zeros(n, *solver.state().y.context()));
        solver
            .interpolate_inplace(t, y)
            .map_err(|e| numerical(t, e))?;
        self.x.copy_from_slice(y.inner().as_slice());
        Ok(())
    }

    /// Records the grid points in (last recorded, limit] (or up to but excluding `limit`).
    fn emit_grid<'a, Eqn, S>(
        &mut self,
        solver: &S,
        limit: f64,
        inclusive: bool,
        t_step_end: f64,
    ) -> Result<(), SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
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

    /// Skips grid points that coincide with an event (the two event rows stand for them).
    fn skip_grid_at(&mut self, t: f64) {
        let eps = 1e-12 * t.abs().max(1.0);
        while self.grid_k <= self.grid_len() && (self.grid_time(self.grid_k) - t).abs() <= eps {
            self.grid_k += 1;
        }
    }

    /// The indicator `i` at time t on the dense output of the last step.
    fn indicator_at<'a, Eqn, S>(&mut self, solver: &S, t: f64, i: usize) -> Result<f64, SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.load(solver, t)?;
        self.evaluate_here(t, true);
        Ok(self.z[i])
    }

    /// Stops a run that cannot succeed, with a reason, instead of running away: a non-finite
    /// state (overflow, a singular mode), or more events or steps than any sensible model needs
    /// (chattering, a relation that flips on round-off).
    fn check_progress<'a, Eqn, S>(&self, solver: &S, t: f64) -> Result<(), SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        const MAX_EVENTS: usize = 50_000;
        const MAX_STEPS: usize = 5_000_000;
        let fail = |message: String| Err(SimError::Numerical { time: t, message });
        if solver.state().y.inner().iter().any(|v| !v.is_finite()) {
            return fail(
                "the state became infinite or NaN (overflow, or a mode without a solution)".into(),
            );
        }
        if self.stats.state_events > MAX_EVENTS {
            let last = self
                .log
                .last()
                .map_or(String::new(), |e| format!("; last: {}", e.cause));
            return fail(format!(
                "more than {MAX_EVENTS} state events: the model chatters{last}"
            ));
        }
        if solver.get_statistics().number_of_steps > MAX_STEPS {
            return fail(format!(
                "more than {MAX_STEPS} integration steps: the model is too stiff or chatters"
            ));
        }
        Ok(())
    }

    /// Looks for a crossing in the last step at three interior points of the dense output and
    /// at its end — a relation that flips and flips back within one step (a freewheel touching
    /// lock for a millisecond) is still seen. Leaves the indicators at the step end in `z`.
    fn scan_step<'a, Eqn, S>(
        &mut self,
        solver: &S,
        t_prev: f64,
        t_now: f64,
        candidates: &mut Vec<(usize, f64, f64)>,
    ) -> Result<Option<(f64, usize)>, SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        const SAMPLES: usize = 4;
        self.z_scan.copy_from_slice(&self.z_prev);
        // the rates at the step's start: those of the last sample (NaN right after an event)
        self.dz_scan.copy_from_slice(&self.dz);
        let mut a = t_prev;
        for k in 1..=SAMPLES {
            let t = if k == SAMPLES {
                self.x.copy_from_slice(solver.state().y.inner().as_slice());
                t_now
            } else {
                let t = t_prev + (t_now - t_prev) * k as f64 / SAMPLES as f64;
                self.load(solver, t)?;
                t
            };
            self.evaluate_here(t, true);
            {
                let guard = self.phase.borrow();
                speed_rates(&self.sys, &guard.disc, &guard.ws, &mut self.dz);
            }
            candidates.clear();
            for (i, (&za, &zb)) in self.z_scan.iter().zip(&self.z).enumerate() {
                if za <= 0.0 && zb > 0.0 {
                    candidates.push((i, za, zb));
                }
            }
            if !candidates.is_empty() {
                return self.locate(solver, a, t, candidates).map(Some);
            }
            // A speed indicator that rises and falls back between two samples: find its peak.
            if let Some((t_peak, i)) = self.peak_between(solver, a, t)? {
                let z_a = self.z_scan[i];
                let z_peak = self.indicator_at(solver, t_peak, i)?;
                if z_peak > 0.0 {
                    candidates.clear();
                    candidates.push((i, z_a, z_peak));
                    return self.locate(solver, a, t_peak, candidates).map(Some);
                }
                // restore the sample at t
                if k == SAMPLES {
                    self.x.copy_from_slice(solver.state().y.inner().as_slice());
                } else {
                    self.load(solver, t)?;
                }
                self.evaluate_here(t, true);
            }
            self.z_scan.copy_from_slice(&self.z);
            self.dz_scan.copy_from_slice(&self.dz);
            a = t;
        }
        Ok(None)
    }

    /// The highest point between samples `a` and `b` of a speed indicator whose rate goes from
    /// positive (at a, in `dz_scan`) to negative (at b, in `dz`) while it stays ≤ 0 at both ends:
    /// the rate's zero, by bisection on the dense output.
    fn peak_between<'a, Eqn, S>(
        &mut self,
        solver: &S,
        a: f64,
        b: f64,
    ) -> Result<Option<(f64, usize)>, SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        let Some(i) = (0..self.dz.len()).find(|&i| {
            self.dz_scan[i] > 0.0 && self.dz[i] < 0.0 && self.z_scan[i] <= 0.0 && self.z[i] <= 0.0
        }) else {
            return Ok(None);
        };
        let (mut lo, mut hi) = (a, b);
        for _ in 0..60 {
            if hi - lo <= 1e-9 * (b - a) {
                break;
            }
            let mid = 0.5 * (lo + hi);
            self.load(solver, mid)?;
            self.evaluate_here(mid, false);
            let rate = {
                let guard = self.phase.borrow();
                let mut dz = std::mem::take(&mut self.dz_probe);
                speed_rates(&self.sys, &guard.disc, &guard.ws, &mut dz);
                let r = dz[i];
                self.dz_probe = dz;
                r
            };
            if rate > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(Some((0.5 * (lo + hi), i)))
    }

    /// Earliest instant in (a, b] at which one of `candidates` becomes > 0: Illinois regula falsi
    /// on each, keeping the bracket so the returned time lies just after the crossing.
    fn locate<'a, Eqn, S>(
        &mut self,
        solver: &S,
        a: f64,
        b: f64,
        candidates: &[(usize, f64, f64)],
    ) -> Result<(f64, usize), SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        let tol = 4.0 * f64::EPSILON * b.abs().max(1.0) + 1e-15;
        let mut best = (b, candidates[0].0);
        for (n, &(i, za0, zb0)) in candidates.iter().enumerate() {
            let (mut ta, mut za) = (a, za0);
            let (mut tb, mut zb) = (best.0, zb0);
            if n > 0 && tb < b {
                zb = self.indicator_at(solver, tb, i)?;
                if zb <= 0.0 {
                    continue; // crosses after the best found so far
                }
            }
            let mut side = 0;
            for iteration in 0..200 {
                if tb - ta <= tol {
                    break;
                }
                let mut tm = if iteration % 4 == 3 || zb == za {
                    0.5 * (ta + tb)
                } else {
                    (ta * zb - tb * za) / (zb - za)
                };
                if !(tm > ta && tm < tb) {
                    tm = 0.5 * (ta + tb);
                }
                let zm = self.indicator_at(solver, tm, i)?;
                if zm > 0.0 {
                    tb = tm;
                    zb = zm;
                    if side == -1 {
                        za *= 0.5;
                    }
                    side = -1;
                } else {
                    ta = tm;
                    za = zm;
                    if side == 1 {
                        zb *= 0.5;
                    }
                    side = 1;
                }
            }
            if tb < best.0 || n == 0 {
                best = (tb, i);
            }
        }
        Ok(best)
    }

    /// Left row, event iteration, right row, log; leaves the new discrete state in the phase.
    /// `horizon` is the first time event still to come once this event is handled.
    fn handle_event(
        &mut self,
        t: f64,
        horizon: f64,
        time_event: bool,
        cause: &str,
    ) -> Result<(), SimError> {
        self.skip_grid_at(t);
        self.record_here(t);
        self.phase.borrow_mut().horizon = horizon;
        let changes: Vec<ModeChange> = {
            let mut guard = self.phase.borrow_mut();
            let Phase { disc, ws, .. } = &mut *guard;
            iterate(
                &self.sys,
                &mut self.cache,
                disc,
                t,
                &self.x,
                false,
                horizon,
                ws,
            )?
        };
        let disc = self.phase.borrow().disc.clone();
        let mm = self.cache.get(&self.sys, &disc, t)?;
        self.phase.borrow_mut().mm = mm;
        self.record_here(t);
        for c in changes {
            self.log.push(EventRecord {
                time: c.time,
                component: c.component,
                old_mode: c.old_mode,
                new_mode: c.new_mode,
                cause: cause.to_string(),
            });
        }
        if time_event {
            self.stats.time_events += 1;
        } else {
            self.stats.state_events += 1;
        }
        self.evaluate_here(t, true);
        self.z_prev.copy_from_slice(&self.z);
        self.dz.fill(f64::NAN);
        Ok(())
    }

    /// Restarts the integrator at (t, self.x) after an event.
    fn restart<'a, Eqn, S>(&mut self, solver: &mut S, t: f64, order: usize) -> Result<(), SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        let now = solver.state().t;
        let h_before = solver.state().h.abs();
        if (now - t).abs() > 1e-12 * t.abs().max(1.0) {
            solver.state_mut_back(t).map_err(|e| numerical(t, e))?;
        }
        let problem = solver.problem();
        {
            let mut state = solver.state_mut();
            *state.t = t;
            state.y.inner_mut().as_mut_slice().copy_from_slice(&self.x);
            problem.eqn.rhs().call_inplace(state.y, t, state.dy);
            state.set_step_size(problem.h0, &problem.atol, problem.rtol, &problem.eqn, order);
            // The step size the integrator had found before the event is a better first guess
            // than the start heuristic (which overshoots and is rejected, event after event).
            if h_before > 0.0 && h_before < state.h.abs() {
                *state.h = h_before.copysign(*state.h);
            }
        }
        if self.implicit {
            // the Jacobian belongs to the old mode
            let _ = solver.checkpoint();
        }
        Ok(())
    }

    fn drive<'a, Eqn, S>(&mut self, mut solver: S, order: usize) -> Result<(usize, usize), SimError>
    where
        Eqn: OdeEquations<T = f64, V = V, C = diffsol::NalgebraContext> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        let exp = self.sys.experiment.clone();
        let t_end = exp.stop_time;
        let time_events = self.sys.time_events.clone();
        let mut next_te = 0;
        let mut t_prev = exp.start_time;
        self.record_here(t_prev);
        self.evaluate_here(t_prev, true);
        self.z_prev.copy_from_slice(&self.z);
        let mut stop = time_events.first().copied().unwrap_or(t_end);
        solver
            .set_stop_time(stop)
            .map_err(|e| numerical(t_prev, e))?;
        let mut candidates: Vec<(usize, f64, f64)> = Vec::new();
        loop {
            let reason = solver.step().map_err(|e| numerical(t_prev, e))?;
            let t_now = solver.state().t;
            self.check_progress(&solver, t_now)?;
            // At a pending time event the signals keep their left limits (the horizon).
            let at_time_event =
                next_te < time_events.len() && (t_now - stop).abs() <= 1e-12 * stop.abs().max(1.0);
            let mut located = None;
            if let Some((t_e, i)) = self.scan_step(&solver, t_prev, t_now, &mut candidates)? {
                let cause = indicator_label(&self.sys, &self.phase.borrow().disc, i);
                located = Some((t_e, cause));
            }
            self.x.copy_from_slice(solver.state().y.inner().as_slice());
            // A crossing at the pending time event is handled with it (one event iteration).
            let tie = |t_e: f64| at_time_event && stop - t_e <= 1e-12 * stop.abs().max(1.0);
            let tied_cause = match located.take() {
                Some((t_e, cause)) if tie(t_e) => Some(cause),
                other => {
                    located = other;
                    None
                }
            };
            if let Some((t_e, cause)) = located {
                self.emit_grid(&solver, t_e, false, t_now)?;
                self.load(&solver, t_e)?;
                let horizon = self.phase.borrow().horizon;
                self.handle_event(t_e, horizon, false, &cause)?;
                self.restart(&mut solver, t_e, order)?;
                if stop > t_e {
                    solver.set_stop_time(stop).map_err(|e| numerical(t_e, e))?;
                }
                t_prev = t_e;
                continue;
            }
            // A grid point on a time event is replaced by the event's two rows.
            self.emit_grid(&solver, t_now, !at_time_event, t_now)?;
            self.x.copy_from_slice(solver.state().y.inner().as_slice());
            self.z_prev.copy_from_slice(&self.z);
            t_prev = t_now;
            if matches!(reason, OdeSolverStopReason::TstopReached) || t_now >= stop {
                if next_te >= time_events.len() {
                    break; // reached StopTime
                }
                let t_event = stop;
                next_te += 1;
                let horizon = time_events.get(next_te).copied().unwrap_or(f64::INFINITY);
                let cause = match &tied_cause {
                    Some(c) => format!("time event; {c}"),
                    None => "time event".to_string(),
                };
                self.handle_event(t_event, horizon, true, &cause)?;
                stop = time_events.get(next_te).copied().unwrap_or(t_end);
                self.restart(&mut solver, t_event, order)?;
                solver
                    .set_stop_time(stop)
                    .map_err(|e| numerical(t_now, e))?;
            }
        }
        let s = solver.get_statistics();
        Ok((s.number_of_steps, s.number_of_error_test_failures))
    }
}
