//! The output grid: the rows inside a processed step, read on the step's dense output.

use diffsol::{OdeSolverMethod, Vector, VectorCommon};

use super::integrator::{integrator_error, Eqn, V};
use super::stepper::Stepper;
use crate::error::SimError;

impl Stepper {
    pub(super) fn grid_time(&self, k: usize) -> f64 {
        self.sys.experiment.grid_time(k)
    }

    /// The experiment's `grid_len`, computed once per run (it takes a division and a `ceil`).
    pub(super) fn grid_len(&self) -> usize {
        self.grid_last
    }

    /// The state at t from the dense output of the last step, into `out`: Tsit45's from its
    /// stages (`dense.rs`), the implicit methods' from diffsol.
    pub fn interpolate<'a, S>(
        &mut self,
        solver: &S,
        t: f64,
        out: &mut [f64],
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        if self.poly.covers(t) {
            self.poly.eval(t, out);
            return Ok(());
        }
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
    pub(super) fn emit_grid<'a, S>(
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
        let plain = self.plain_rows();
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
            let t = tg.min(t_step_end);
            if let Some(horizon) = plain {
                self.push_plain_row(solver, (tg, t), horizon)?;
            } else {
                self.load(solver, t)?;
                self.record_here(tg);
            }
            self.grid_k += 1;
        }
        Ok(())
    }

    /// What `record_here` does for grid row `tg` (read at `t`) when it needs nothing but its
    /// state pushed (`plain_rows`); the state is written into the trajectory in place when the
    /// step's quartic holds it.
    fn push_plain_row<'a, S>(
        &mut self,
        solver: &S,
        (tg, t): (f64, f64),
        horizon: f64,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.last_row = tg;
        let id = (self.discs.len() - 1) as u32;
        if self.poly.covers(t) {
            let poly = &self.poly;
            self.trajectory
                .push_with(tg, horizon, id, |x| poly.extend_at(t, x));
        } else {
            self.load(solver, t)?;
            self.trajectory.push(tg, horizon, id, &self.x);
        }
        Ok(())
    }

    /// The horizon, when a row needs nothing but the state pushed (`record_here`'s other
    /// work does nothing): recording, no observer, the discrete state recorded, no speeds to
    /// project (no shaft without inertia in this mode, no prescribed motion). A run records
    /// thousands of grid rows, so these checks are made once per call of `emit_grid`.
    fn plain_rows(&self) -> Option<f64> {
        let phase = self.phase.borrow();
        let plain = self.recording
            && self.observer.is_none()
            && self.disc_recorded
            && self.trajectory.rows() > 0
            && phase.mm.massless.is_none()
            && !self.prescribes;
        plain.then_some(phase.horizon)
    }

    /// Records the grid points up to `target` while a step is processed only that far, leaving
    /// out one that coincides with the `event` ahead (its two event rows will stand for it, as
    /// when the step is processed at once).
    pub(super) fn emit_grid_before<'a, S>(
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
}
