//! The events of a run as the stepper handles them: state, time and input events, each with
//! its left and right rows and the event iteration, and the integrator restarted after it.

use diffsol::{NonLinearOp, OdeEquations, OdeSolverMethod, Vector};

use super::integrator::{integrator_error, Eqn};
use super::stepper::{EventKind, Stepper};
use super::Phase;
use crate::engine::eval::{derivative, heat_and_energy};
use crate::engine::{indicators, iterate, speed_rates, EventPoint};
use crate::error::SimError;
use crate::result::EventRecord;

impl Stepper {
    /// Left row (unless one was recorded at t already), the change the event brings, event
    /// iteration, right row, log. `horizon` is the first time event still to come once this
    /// event is handled.
    pub(super) fn handle_event(
        &mut self,
        t: f64,
        horizon: f64,
        kind: EventKind,
        cause: &str,
    ) -> Result<(), SimError> {
        self.hump_back = None; // the indicators change meaning with the mode
        self.skip_grid_at(t);
        if !(matches!(kind, EventKind::Input(..) | EventKind::Parameter) && self.last_row == t) {
            self.record_here(t);
        }
        if matches!(kind, EventKind::State) {
            self.apply_resets();
        }
        let changes = {
            let mut guard = self.phase.borrow_mut();
            guard.horizon = horizon;
            guard.f0_t = f64::NAN; // the mode may change
            let Phase { disc, ws, .. } = &mut *guard;
            if let EventKind::Input(k, value) = kind {
                disc.inputs[k] = value;
            }
            let at = EventPoint {
                t,
                x: &self.x,
                horizon,
                initial: false,
            };
            iterate(&self.sys, &mut self.cache, disc, &at, ws)?
        };
        self.disc_recorded = false;
        let disc = self.phase.borrow().disc.clone();
        let mm = self.cache.get(&self.sys, &disc, t)?;
        self.phase.borrow_mut().mm = mm;
        self.record_here(t);
        for c in changes {
            let record = EventRecord {
                time: c.time,
                component: c.component,
                old_mode: c.old_mode,
                new_mode: c.new_mode,
                cause: cause.to_string(),
            };
            if let Some(observer) = self.observer.as_mut() {
                observer.event(&record);
            }
            let chattering = self.chatter.record(&record.component, t, cause);
            self.log.push(record);
            chattering?;
        }
        match kind {
            EventKind::State => self.stats.state_events += 1,
            EventKind::Time => self.stats.time_events += 1,
            EventKind::Input(..) | EventKind::Parameter => self.stats.input_events += 1,
        }
        self.evaluate_right_row(t);
        self.z_prev.copy_from_slice(&self.z);
        // the rates in the new mode, so that a speed rising from the event and falling back
        // within the first step is searched too (a freewheel released for half a millisecond)
        let guard = self.phase.borrow();
        speed_rates(&self.sys, &guard.disc, &guard.ws, &mut self.dz);
        Ok(())
    }

    /// `evaluate_here(t, true)` at the event's right row: when the event iteration left the
    /// workspace holding `evaluate_switching` of the settled state at this very state (nothing
    /// evaluated since, and the right row's projection changed no speed: no shaft without
    /// inertia, no prescribed motion), only the heat flows and energies are added to it.
    fn evaluate_right_row(&mut self, t: f64) {
        let mut guard = self.phase.borrow_mut();
        let Phase { disc, mm, ws, .. } = &mut *guard;
        let held = ws.settled_at == Some(ws.rhs_evals) && mm.massless.is_none() && !self.prescribes;
        if !held {
            drop(guard);
            self.evaluate_here(t, true);
            return;
        }
        heat_and_energy(&self.sys, disc, &self.x, ws);
        indicators(&self.sys, disc, ws, &mut self.z);
        guard.evaluated_at(t, &self.x);
    }

    /// The state resets the switching elements ask for at a state event (a hard stop reached:
    /// MSL's `reinit`), applied to the state before the event iteration. The kinetic energy a
    /// reset removes is counted as dissipated, so that the energy balance still closes.
    fn apply_resets(&mut self) {
        let n = self.sys.nodes;
        for k in 0..self.sys.switching.len() {
            let (phi, w) = self.x[..2 * n].split_at(n);
            let Some(r) = self.sys.switching[k].reset(phi, w) else {
                continue;
            };
            let loss = crate::engine::eval::Layout::of(&self.sys).loss();
            self.move_node(r.node, (r.phi, r.w), (loss, 1.0));
        }
    }

    /// Puts `node` at angle `phi` and speed `w`, the nodes joined to it through relative
    /// states moved along (`reset::carried`); the kinetic energy each node loses is booked,
    /// times `sign`, into state `book` (dissipated at a hard stop, negative work for a reinit).
    pub(super) fn move_node(
        &mut self,
        node: usize,
        (phi, w): (f64, f64),
        (book, sign): (usize, f64),
    ) {
        let n = self.sys.nodes;
        let (dphi, dw) = (phi - self.x[node], w - self.x[n + node]);
        for at in super::reset::carried(&self.sys, node) {
            let m: f64 = (self.sys.masses.iter())
                .filter(|(_, on, _)| *on == at)
                .map(|(_, _, m)| m)
                .sum();
            let w_old = self.x[n + at];
            let w_new = if at == node { w } else { w_old + dw };
            self.x[book] += sign * (0.5 * m * (w_old * w_old - w_new * w_new));
            self.x[at] = if at == node { phi } else { self.x[at] + dphi };
            self.x[n + at] = w_new;
        }
    }

    /// Restarts the integrator at (t, self.x) after an event.
    pub fn restart<'a, S>(
        &mut self,
        solver: &mut S,
        t: f64,
        order: usize,
        implicit: bool,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.restart_at(solver, t, order, implicit, true)
    }

    /// Restarts the integrator at (t, self.x); with `rewind`, t lies in the last step and the
    /// integrator is first taken back there, otherwise (the "auto" change of method,
    /// between two steps) it starts there.
    // Alike in shape only (the signature of every method over the solver), not in logic.
    pub fn restart_at<'a, S>(
        &mut self,
        solver: &mut S,
        t: f64,
        order: usize,
        implicit: bool,
        rewind: bool,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let now = solver.state().t;
        let h_before = solver.state().h.abs();
        if rewind && (now - t).abs() > 1e-12 * t.abs().max(1.0) {
            solver
                .state_mut_back(t)
                .map_err(|e| integrator_error(t, e))?;
        }
        let problem = solver.problem();
        {
            let mut state = solver.state_mut();
            *state.t = t;
            state.y.inner_mut().as_mut_slice().copy_from_slice(&self.x);
            // An event evaluated its right row last: the derivative there is that evaluation's.
            let phase = self.phase.borrow();
            if phase.holds(t, &self.x) {
                derivative(&self.sys, &phase.ws, state.dy.inner_mut().as_mut_slice());
                drop(phase);
            } else {
                drop(phase);
                problem.eqn.rhs().call_inplace(state.y, t, state.dy);
            }
            state.set_step_size(problem.h0, &problem.atol, problem.rtol, &problem.eqn, order);
            // The step size the integrator had found before the event is a better first guess
            // than the start heuristic (which overshoots and is rejected, event after event).
            if h_before > 0.0 && h_before < state.h.abs() {
                *state.h = h_before.copysign(*state.h);
            }
        }
        if implicit {
            // the Jacobian belongs to the old mode
            let _ = solver.checkpoint();
        }
        self.t_prev = t;
        self.pending = None;
        self.poly.clear();
        if self.stop > t {
            solver
                .set_stop_time(self.stop)
                .map_err(|e| integrator_error(t, e))?;
        }
        Ok(())
    }

    /// The integrator reached its stop: a time event, or the end of the run.
    pub(super) fn time_event<'a, S>(
        &mut self,
        solver: &mut S,
        tied: Option<String>,
        order: usize,
        implicit: bool,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let events = &self.sys.time_events;
        if self.next_te >= events.len() {
            self.finished = true; // reached StopTime
            return Ok(());
        }
        let t_event = self.stop;
        self.next_te += 1;
        let horizon = events
            .get(self.next_te)
            .copied()
            .unwrap_or(self.sys.experiment.stop_time);
        let next_stop = events
            .get(self.next_te)
            .copied()
            .unwrap_or(self.sys.experiment.stop_time);
        let cause = match &tied {
            Some(c) => format!("time event; {c}"),
            None => "time event".to_string(),
        };
        self.handle_event(t_event, horizon, EventKind::Time, &cause)?;
        self.stop = next_stop;
        self.restart(solver, t_event, order, implicit)
    }

    /// Takes the run back to `now` for an event there (an input's or a parameter's): the
    /// pending step is dropped and the state at `now` is the event's. Returns `now`.
    pub(super) fn back_to_now<'a, S>(&mut self, solver: &mut S) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let t = self.now;
        let x = self.state_now(solver)?;
        self.x.copy_from_slice(&x);
        self.pending = None;
        self.t_prev = t;
        Ok(t)
    }

    /// Sets model input `k` at the current time: the integrator goes back to `now` (a pending
    /// step is discarded), and the new value acts from there through an event.
    // Alike in shape only (the signature of every method over the solver), not in logic.
    pub fn set_input<'a, S>(
        &mut self,
        solver: &mut S,
        k: usize,
        value: f64,
        name: &str,
        order: usize,
        implicit: bool,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let t = self.back_to_now(solver)?;
        let horizon = self.phase.borrow().horizon;
        let cause = format!("input {name} set to {value}");
        self.handle_event(t, horizon, EventKind::Input(k, value), &cause)?;
        if self.finished {
            return Ok(());
        }
        self.restart(solver, t, order, implicit)
    }
}
