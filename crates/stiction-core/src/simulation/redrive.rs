//! Re-driving a run from outside, what a virtual dynamometer does between and during its stops:
//! a mass's speed set anew at the current time (the dyno's motor spinning the inertia up: an
//! event, like MSL's `reinit`, whose kinetic energy counts as work supplied), and advancing
//! until a variable reaches a level, stopping at the crossing found on the integrator's dense
//! output (a stop to a final speed above zero, cooling down to a temperature), not at a polled
//! approximation of it. Neither costs a run that does not use them anything: the stepper looks
//! for a crossing only while one is watched.

use diffsol::OdeSolverMethod;

use super::integrator::{with_solver, Eqn};
use super::stepper::{EventKind, Stepper};
use super::watch::{first_crossing, Watch};
use super::Simulation;
use crate::engine::eval::Layout;
use crate::error::SimError;
use crate::result::{Probe, RowView};

impl Simulation {
    /// Sets the speed of inertia (or mass) `mass` to `w` at the current time, as an event:
    /// the left row keeps the old speed, the event iteration finds the modes the new one gives
    /// and the integrator restarts. Nodes joined to it through relative states move with it
    /// (as at a hard stop's reset). The kinetic energy it adds is counted as work supplied.
    /// A run re-driven so cannot be saved (`state`): its replay knows inputs and parameters only.
    pub fn reinit_speed(&mut self, mass: &str, w: f64) -> Result<(), SimError> {
        let sys = self.stepper.sys.clone();
        let Some(node) = (sys.masses.iter()).find(|(n, _, _)| n == mass).map(|m| m.1) else {
            return Err(SimError::Usage(format!(
                "reinit: '{mass}' is not an inertia or mass of the model"
            )));
        };
        if !w.is_finite() {
            return Err(SimError::Usage(format!(
                "reinit {mass}: {w} is not a finite speed"
            )));
        }
        let cause = format!("reinit {mass} speed to {w}");
        let Simulation { cell, stepper, .. } = self;
        cell.with_dependent_mut(|_, integ| {
            let (order, implicit) = (integ.order(), integ.implicit());
            with_solver!(integ, s => stepper.reinit(s, node, w, &cause, order, implicit))
        })
    }

    /// Advances until variable `name` reaches `level` (from the side it is on now), at most to
    /// `t_max`; returns whether it did. The run then stands at the crossing: inside a step,
    /// the instant where the dense output meets the level (to round-off), or at a state event
    /// where the variable jumps or lands on it (a speed reaching 0 where a brake sticks).
    pub fn advance_until(&mut self, name: &str, level: f64, t_max: f64) -> Result<bool, SimError> {
        let Some(column) = (self.stepper.sys.outputs.iter()).position(|(n, _)| n == name) else {
            return Err(SimError::Usage(format!("unknown variable '{name}'")));
        };
        if !level.is_finite() {
            return Err(SimError::Usage(format!(
                "advance_until {name}: level {level} is not finite"
            )));
        }
        let side = self.values()?[column + 1] - level;
        if side == 0.0 {
            return Ok(true);
        }
        let sys = self.stepper.sys.clone();
        self.stepper.watch = Some(Watch {
            x: vec![0.0; sys.state_len()],
            probe: Probe::new(sys, &[name.to_string()])?,
            level,
            side: side.signum(),
            hit: None,
        });
        let stop_at_events = std::mem::replace(&mut self.stepper.stop_at_events, true);
        let outcome = self.watch_until(column, level, side.signum(), t_max);
        self.stepper.stop_at_events = stop_at_events;
        self.stepper.watch = None;
        outcome
    }

    fn watch_until(
        &mut self,
        column: usize,
        level: f64,
        side: f64,
        t_max: f64,
    ) -> Result<bool, SimError> {
        loop {
            self.advance_to(t_max)?;
            if (self.stepper.watch.as_ref()).is_some_and(|w| w.hit.is_some()) {
                return Ok(true);
            }
            // at a state event (or t_max): the variable may have jumped onto or past the level
            if (self.values()?[column + 1] - level) * side <= 0.0 {
                return Ok(true);
            }
            if self.stepper.finished || self.stepper.now >= t_max {
                return Ok(false);
            }
        }
    }
}

impl Stepper {
    /// `reinit_speed` on the stepper: back to now, left row, the node moved, event, restart.
    // Alike in shape only (the signature of every method over the solver), not in logic.
    pub(super) fn reinit<'a, S>(
        &mut self,
        solver: &mut S,
        node: usize,
        w: f64,
        cause: &str,
        order: usize,
        implicit: bool,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let t = self.back_to_now(solver)?;
        if self.last_row != t {
            self.record_here(t); // the left row, with the speed before
        }
        let (phi, work) = (self.x[node], Layout::of(&self.sys).work());
        self.move_node(node, (phi, w), (work, -1.0)); // the energy given is work supplied
        self.reinits += 1;
        let horizon = self.phase.borrow().horizon;
        self.handle_event(t, horizon, EventKind::Parameter, cause)?;
        if self.finished {
            return Ok(());
        }
        self.restart(solver, t, order, implicit)
    }

    /// The time to process the pending step up to: `target`, or the crossing of the watched
    /// level before the step's event or end (the run then stops there).
    pub(super) fn watched_target<'a, S>(&mut self, solver: &S, target: f64) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let p = self.pending.as_ref().expect("a step is pending");
        let end = p.located.as_ref().map_or(p.t_now, |(t_e, _)| *t_e);
        let start = self.now.max(self.t_prev);
        Ok(self
            .watched_crossing(solver, start, end.min(target))?
            .unwrap_or(target))
    }

    /// The crossing of the watched level in [start, end] of the pending step, if any (the
    /// first instant at or past it, to round-off), found by regula falsi (Illinois) on the
    /// dense output.
    fn watched_crossing<'a, S>(
        &mut self,
        solver: &S,
        start: f64,
        end: f64,
    ) -> Result<Option<f64>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let Some(mut watch) = self.watch.take() else {
            return Ok(None);
        };
        let outcome = self.find_crossing(solver, &mut watch, start, end);
        if let Ok(Some(t)) = outcome {
            watch.hit = Some(t);
        }
        self.watch = Some(watch);
        outcome
    }

    fn find_crossing<'a, S>(
        &mut self,
        solver: &S,
        watch: &mut Watch,
        start: f64,
        end: f64,
    ) -> Result<Option<f64>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        if watch.hit.is_some() || end < start {
            return Ok(None);
        }
        first_crossing(|t| self.watched_value(solver, watch, t), start, end)
    }

    /// (value − level)·side at t inside the pending step: > 0 before the crossing.
    fn watched_value<'a, S>(
        &mut self,
        solver: &S,
        watch: &mut Watch,
        t: f64,
    ) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let mut x = std::mem::take(&mut watch.x);
        let r = self.interpolate(solver, t, &mut x);
        watch.x = x;
        r?;
        let phase = self.phase.borrow();
        let row = RowView {
            t,
            x: &watch.x,
            disc: &phase.disc,
            horizon: phase.horizon,
        };
        let v = watch.probe.values(&row)?[0];
        Ok((v - watch.level) * watch.side)
    }
}
