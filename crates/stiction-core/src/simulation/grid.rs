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
    // Alike in shape only (the signature of every method over the solver), not in logic.
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
        let due = |tg: f64| {
            if inclusive {
                tg <= limit + eps
            } else {
                tg < limit - eps
            }
        };
        let first = self.grid_k;
        let end = self.due_end(first, limit, due);
        if end == first {
            return Ok(());
        }
        let plain = self.plain_rows();
        let read_at = |tg: f64| tg.min(t_step_end);
        let covered = self.poly.covers(read_at(self.grid_time(first)))
            && self.poly.covers(read_at(self.grid_time(end - 1)));
        if let (Some(horizon), true) = (plain, covered) {
            self.push_plain_rows(first..end, t_step_end, horizon);
            return Ok(());
        }
        if covered && self.observed_alone() {
            self.observe_rows(first..end, t_step_end);
            return Ok(());
        }
        for k in first..end {
            let tg = self.grid_time(k);
            self.load(solver, read_at(tg))?;
            match plain {
                Some(horizon) => {
                    // what `record_here` does for such a row, without its checks
                    let id = (self.discs.len() - 1) as u32;
                    self.trajectory.push(tg, horizon, id, &self.x);
                    self.last_row = tg;
                }
                None => self.record_here(tg),
            }
            self.grid_k = k + 1;
        }
        Ok(())
    }

    /// The first grid index from `first` on that is not `due` (the grid's end at the latest):
    /// from the index `limit` falls at, corrected by the very test a walk from `first` makes
    /// (the grid times rise with the index, so the due ones come first), instead of walking
    /// row by row (a step holds tens of rows).
    fn due_end(&self, first: usize, limit: f64, due: impl Fn(f64) -> bool) -> usize {
        let exp = &self.sys.experiment;
        let guess = ((limit - exp.start_time) / exp.interval).floor();
        // `as` saturates (NaN to 0); the walks below make any guess exact
        let mut end = (guess as usize).clamp(first, self.grid_len() + 1);
        while end > first && !due(self.grid_time(end - 1)) {
            end -= 1;
        }
        while end <= self.grid_len() && due(self.grid_time(end)) {
            end += 1;
        }
        end
    }

    /// What `record_here` does for the grid rows `rows`, inside the step's quartic, when
    /// they need nothing but their states pushed (`plain_rows`): one block of rows, each state
    /// evaluated in place (a run records thousands of rows, a step tens).
    fn push_plain_rows(&mut self, rows: std::ops::Range<usize>, t_step_end: f64, horizon: f64) {
        let id = (self.discs.len() - 1) as u32;
        let (poly, experiment) = (&self.poly, &self.sys.experiment);
        let count = rows.len();
        let ks = rows.clone();
        self.trajectory.push_block(count, (horizon, id), |ts, xs| {
            for (k, t) in ks.zip(ts.iter_mut()) {
                *t = experiment.grid_time(k);
            }
            poly.eval_rows(ts, t_step_end, xs)
        });
        self.last_row = self.grid_time(rows.end - 1);
        self.grid_k = rows.end;
    }

    /// Whether rows go to the observer alone (a sweep's run: nothing recorded) and need
    /// nothing but their states (as in `plain_rows`: no speeds to project).
    fn observed_alone(&self) -> bool {
        !self.recording
            && self.observer.is_some()
            && self.phase.borrow().mm.massless.is_none()
            && !self.prescribes
    }

    /// What `record_here` does for the grid rows `rows` when they go to the observer alone
    /// (`observed_alone`): the states evaluated as one block inside the step's quartic, as
    /// `push_plain_rows` does (the same arithmetic: the rows are those of a recorded run bit
    /// for bit), then shown as one block; `x` left at the last row, as loading each would.
    /// An observer that reads a few states (`Observer::states_read`) has those alone
    /// evaluated: a sweep's metrics over two speeds read a quarter of CoupledClutches' states,
    /// at every one of its 3000 grid rows.
    // Out of line: a recorded run's `emit_grid` stays as small as it was.
    #[inline(never)]
    fn observe_rows(&mut self, rows: std::ops::Range<usize>, t_step_end: f64) {
        let n = self.x.len();
        let (mut ts, mut xs) = std::mem::take(&mut self.observed);
        ts.clear();
        ts.extend(rows.clone().map(|k| self.grid_time(k)));
        // no zeroing: every value read is written below (the unread states are never read)
        let len = ts.len() * n;
        if xs.len() < len {
            xs.resize(len, 0.0);
        }
        let states = self.observer.as_ref().and_then(|o| o.states_read());
        match states {
            Some(states) => self
                .poly
                .eval_rows_of(&ts, t_step_end, &mut xs[..len], states),
            None => {
                self.poly.eval_rows(&ts, t_step_end, &mut xs[..len]);
            }
        }
        let phase = self.phase.borrow();
        if let Some(observer) = self.observer.as_mut() {
            observer.grid_rows(&ts, &xs[..len], &phase.disc, phase.horizon);
        }
        drop(phase);
        if let Some(&t) = ts.last() {
            // the whole state at the last row (the block may hold some states only)
            self.poly.eval(t.min(t_step_end), &mut self.x);
            self.last_row = t;
        }
        self.grid_k = rows.end;
        self.observed = (ts, xs);
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
    // Alike in shape only (the signature of every method over the solver), not in logic.
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
