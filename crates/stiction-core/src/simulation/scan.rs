//! Scanning one integrator step for crossings. The step is sampled at its end (the
//! integrator's own last evaluation when the workspace still holds it) and its midpoint; when
//! every indicator stays clearly below zero over those (`quiet`) nothing more is needed. Else
//! the quarter points are sampled too, each sample evaluated once and kept; only then is it
//! decided whether the indicators without an analytic rate (a locked element's torque against
//! its static limit) need backward-difference rates, which double the evaluations. They do
//! when one of them comes near zero within the step, measured against how much it moves in the
//! step (`NEAR`). The intervals between samples are then searched in order: sign changes,
//! rates turning from rising to falling (a hump between two samples, `locate.rs`), and humps
//! across three samples.

use diffsol::{OdeSolverMethod, VectorCommon};

use super::integrator::Eqn;
use super::samples::{Hump, FD_STEP, SAMPLES};
use super::stepper::Stepper;
use crate::engine::{indicators, speed_rates};
use crate::error::SimError;
use crate::switching::element::NEVER;

/// An indicator without analytic rate is searched for humps between samples when its largest
/// sample in the step lies within `NEAR` times its spread over the step of zero. The quartic
/// through the five samples can rise at most 0.6 spreads above the largest sample (the
/// Lebesgue constant of five equidistant points is 2.2), so 3 leaves a wide margin for what
/// the quartic does not capture of a step the integrator resolved.
const NEAR: f64 = 3.0;

/// A step whose indicators all stay below zero by more than `QUIET` times their spread over
/// its start, midpoint and end (or the reach of their analytic rates over the whole step, if
/// larger) is not sampled at its quarter points. The parabola through three equidistant
/// samples rises at most a quarter spread above the largest (Lebesgue constant 1.25), and a
/// curve with those end rates at most an eighth of the reach between two samples, so `NEAR`'s
/// margin of 3 is ample here too.
const QUIET: f64 = NEAR;

/// The step's midpoint among the samples, taken in every step.
const MIDDLE: usize = SAMPLES / 2;

impl Stepper {
    /// Looks for a crossing in the last step (t_prev, t_now]; a relation that flips and flips
    /// back within one step (a freewheel touching lock for a millisecond) is still seen. Leaves
    /// the indicators and rates at the step end in `z` and `dz`, and its state in `x` (the
    /// workspace is left wherever the scan last evaluated: every reader evaluates first).
    pub(super) fn scan_step<'a, S>(
        &mut self,
        solver: &S,
        t_prev: f64,
        t_now: f64,
        candidates: &mut Vec<(usize, f64, f64)>,
    ) -> Result<Option<(f64, usize)>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let found = if self.sample_step(solver, t_prev, t_now)? {
            // nothing comes near zero: the last interior sample taken is the midpoint
            self.hump_back = Some(self.samples.t[MIDDLE]);
            self.z_back.copy_from_slice(self.samples.at(MIDDLE).0);
            None
        } else {
            let differences = self.needs_differences();
            self.search_samples(solver, candidates, differences)?
        };
        if found.is_none() {
            let (z, dz) = self.samples.at(SAMPLES);
            self.z.copy_from_slice(z);
            self.dz.copy_from_slice(dz);
            self.x.copy_from_slice(solver.state().y.inner().as_slice());
        }
        Ok(found)
    }

    /// Evaluates the samples of the step (feeding the grid rows' fit) and keeps their
    /// indicators and analytic rates; sample 0 is the step's start. The end and the midpoint
    /// come first; the quarter points only when an indicator may come near zero (`quiet`).
    /// Returns whether the step is quiet (the quarter points were left out).
    fn sample_step<'a, S>(&mut self, solver: &S, t_prev: f64, t_now: f64) -> Result<bool, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let nz = self.z.len();
        self.samples.z.resize((SAMPLES + 1) * nz, 0.0);
        self.samples.dz.resize((SAMPLES + 1) * nz, f64::NAN);
        for k in 0..=SAMPLES {
            self.samples.t[k] = if k == SAMPLES {
                t_now
            } else {
                t_prev + (t_now - t_prev) * k as f64 / SAMPLES as f64
            };
        }
        let (z0, dz0) = self.samples.at_mut(0);
        z0.copy_from_slice(&self.z_prev);
        // the last sample's rates (analytic only after events)
        dz0.copy_from_slice(&self.dz);
        // the end first, while the workspace may still hold the integrator's evaluation there
        self.x.copy_from_slice(solver.state().y.inner().as_slice());
        self.evaluate_end(t_now);
        {
            let phase = self.phase.borrow();
            self.guard.watch(&self.sys, &phase.disc, &phase.ws);
        }
        self.keep_sample(SAMPLES);
        self.take_sample(solver, MIDDLE)?;
        self.probed = false;
        let quiet = self.quiet(t_now - t_prev);
        if !quiet {
            for k in (1..SAMPLES).filter(|&k| k != MIDDLE) {
                self.take_sample(solver, k)?;
            }
        }
        Ok(quiet)
    }

    /// The indicators at the step's end (t, `x`): from the integrator's own evaluation there
    /// when the workspace still holds it (`Phase::holds`: an explicit step's last stage), else
    /// evaluated. Bit for bit the same either way.
    fn evaluate_end(&mut self, t: f64) {
        if !self.phase.borrow().holds(t, &self.x) {
            self.evaluate_here(t, true);
            return;
        }
        let guard = self.phase.borrow();
        indicators(&self.sys, &guard.disc, &guard.ws, &mut self.z);
    }

    /// Loads and evaluates interior sample `k` and keeps it.
    fn take_sample<'a, S>(&mut self, solver: &S, k: usize) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let t = self.samples.t[k];
        self.load(solver, t)?;
        self.probe_here(t);
        self.keep_sample(k);
        Ok(())
    }

    /// Keeps the indicators in `z` and the analytic rates of the workspace as sample `k`.
    fn keep_sample(&mut self, k: usize) {
        let (z, dz) = self.samples.at_mut(k);
        z.copy_from_slice(&self.z);
        let guard = self.phase.borrow();
        speed_rates(&self.sys, &guard.disc, &guard.ws, dz);
    }

    /// Whether every indicator stays clearly below zero over the step (`stays_below`), judged
    /// from the start, the midpoint and the end: such a step cannot hold a crossing, a hump or
    /// a rate-less indicator near its limit, so the quarter points are not needed.
    fn quiet(&self, h: f64) -> bool {
        let at = [0, MIDDLE, SAMPLES].map(|k| self.samples.at(k));
        (0..self.z.len()).all(|i| stays_below(at.map(|s| s.0[i]), at.map(|s| s.1[i]), h))
    }

    /// Whether an armed indicator without an analytic rate comes near zero in this step.
    fn needs_differences(&self) -> bool {
        let (_, dz_end) = self.samples.at(SAMPLES);
        (0..self.z.len()).any(|i| {
            let z0 = self.z_prev[i];
            let armed = dz_end[i].is_nan() && z0 <= 0.0 && z0 != NEVER && z0.is_finite();
            armed && {
                let (mut hi, mut lo) = (f64::NEG_INFINITY, f64::INFINITY);
                for k in 0..=SAMPLES {
                    let z = self.samples.at(k).0[i];
                    (hi, lo) = (hi.max(z), lo.min(z));
                }
                hi + NEAR * (hi - lo) > 0.0
            }
        })
    }

    /// The backward-difference rates at sample `k` (forward at the step's start, which the
    /// dense output does not reach behind) for the indicators without an analytic one. Taken
    /// when the search first reads the sample (`search_samples`): the samples after an
    /// interval holding a crossing are never read, and each difference is an evaluation.
    // Alike in shape only (the signature of every method over the solver), not in logic.
    fn difference_rate<'a, S>(&mut self, solver: &S, k: usize) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        if !self.samples.at(k).1.iter().any(|r| r.is_nan()) {
            return Ok(());
        }
        let (t_prev, t_now) = (self.samples.t[0], self.samples.t[SAMPLES]);
        let h = FD_STEP * (t_now - t_prev);
        let probe = if k == 0 {
            t_prev + h
        } else {
            self.samples.t[k] - h
        };
        self.load(solver, probe)?;
        self.probe_here(probe);
        let (z, dz) = self.samples.at_mut(k);
        for ((rate, &at), &other) in dz.iter_mut().zip(z.iter()).zip(&self.z) {
            if rate.is_nan() {
                *rate = if k == 0 { other - at } else { at - other } / h;
            }
        }
        Ok(())
    }

    /// The intervals between the samples in order: the first crossing, or the top of a hump
    /// that rises above zero between samples. With `differences`, each sample gets its
    /// difference rates before its first interval is searched (`difference_rate`).
    fn search_samples<'a, S>(
        &mut self,
        solver: &S,
        candidates: &mut Vec<(usize, f64, f64)>,
        differences: bool,
    ) -> Result<Option<(f64, usize)>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        if differences {
            self.difference_rate(solver, 0)?;
        }
        for k in 1..=SAMPLES {
            let (a, b) = (self.samples.t[k - 1], self.samples.t[k]);
            if differences {
                self.difference_rate(solver, k)?;
            }
            self.take_interval(k);
            // A speed indicator that rises above zero and falls back between the two samples
            // ends the bracket at its peak, so it competes with every crossing before it (a
            // later crossing of another indicator must not hide it).
            let end = match self.peak_between(solver, a, b)? {
                Some((t_peak, _)) => {
                    self.indicators_at(solver, t_peak)?;
                    t_peak
                }
                None => {
                    self.z.copy_from_slice(self.samples.at(k).0);
                    b
                }
            };
            candidates.clear();
            for (i, (&za, &zb)) in self.z_scan.iter().zip(&self.z).enumerate() {
                if za <= 0.0 && zb > 0.0 {
                    candidates.push((i, za, zb));
                }
            }
            if !candidates.is_empty() {
                let found = self.locate(solver, a, end, candidates)?;
                return self.earliest_before(solver, a, found, candidates).map(Some);
            }
            if let Some(found) = self.hump_before(solver, k)? {
                candidates.clear();
                candidates.push(found.1);
                return self.locate(solver, found.0, found.2, candidates).map(Some);
            }
        }
        self.hump_back = Some(self.samples.t[SAMPLES - 1]);
        self.z_back.copy_from_slice(self.samples.at(SAMPLES - 1).0);
        Ok(None)
    }

    /// Loads the samples bounding interval k into `z_scan`/`dz_scan` (its start) and
    /// `z`/`dz` (its end).
    fn take_interval(&mut self, k: usize) {
        let (za, dza) = self.samples.at(k - 1);
        self.z_scan.copy_from_slice(za);
        self.dz_scan.copy_from_slice(dza);
        let (zb, dzb) = self.samples.at(k);
        self.z.copy_from_slice(zb);
        self.dz.copy_from_slice(dzb);
    }

    /// A hump over the samples k − 2, k − 1 and k (the first uses the previous step's last
    /// interior sample) that may reach above zero.
    fn hump_before<'a, S>(&mut self, solver: &S, k: usize) -> Result<Option<Hump>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let t_back = if k >= 2 {
            self.z_back.copy_from_slice(self.samples.at(k - 2).0);
            self.samples.t[k - 2]
        } else {
            match self.hump_back {
                Some(t) => t,
                None => return Ok(None),
            }
        };
        let found = self.hump(solver, t_back, self.samples.t[0], self.samples.t[k])?;
        self.z.copy_from_slice(self.samples.at(k).0);
        Ok(found)
    }
}

/// Whether an indicator sampled at a step's start, midpoint and end (`z`, with its analytic
/// rates `dz` there, NaN where it has none) stays clearly below zero over the step of length
/// `h`: its largest sample lies more than `QUIET` times its spread below zero, the spread
/// taken over the samples and, where a rate is known, as far as that rate reaches over the
/// whole step. An indicator held exactly (a frozen signal's engagement at 0) cannot rise:
/// steps are kept below a quarter of the signals' time scale.
fn stays_below(z: [f64; 3], dz: [f64; 3], h: f64) -> bool {
    if z.iter().any(|v| !v.is_finite()) {
        return false;
    }
    let hi = z.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v));
    let lo = z.iter().fold(f64::INFINITY, |m, &v| m.min(v));
    let reach = (dz.iter().filter(|r| !r.is_nan())).fold(0.0f64, |m, r| m.max(r.abs() * h));
    // an infinite rate makes the reach infinite: not quiet
    (hi == lo && hi <= 0.0 && reach == 0.0) || hi + QUIET * (hi - lo).max(reach) < 0.0
}

/// A friction characteristic gone negative inside a step (`guard.rs`).
impl Stepper {
    /// The error of element `k`'s characteristic turning negative inside the step
    /// `(t_prev, t_now]`: its instant located by bisection on the step's dense output.
    pub(super) fn negative_characteristic<'a, S>(
        &mut self,
        solver: &S,
        t_prev: f64,
        t_now: f64,
        k: usize,
    ) -> SimError
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let (mut lo, mut hi) = (t_prev, t_now);
        loop {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi || hi - lo <= 4.0 * f64::EPSILON * hi.abs().max(1.0) {
                break;
            }
            if self.message_at(solver, mid, k).is_some() {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let name = self.sys.switching[k].name().to_string();
        let message = (self.message_at(solver, hi, k))
            .unwrap_or_else(|| format!("'{name}': its friction characteristic turned negative"));
        SimError::NegativeFriction {
            time: hi,
            element: name,
            message,
        }
    }

    fn message_at<'a, S>(&mut self, solver: &S, t: f64, k: usize) -> Option<String>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.load(solver, t).ok()?;
        self.evaluate_here(t, false);
        let phase = self.phase.borrow();
        let (st, v) = (&phase.disc.switching[k], &phase.ws.elements[k]);
        self.sys.switching[k].negative_characteristic(st, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NO_RATE: [f64; 3] = [f64::NAN; 3];

    #[test]
    fn far_or_held_indicators_are_quiet() {
        // NEVER, a disengaged clutch's frozen 0, a limit far below that barely moves
        assert!(stays_below([NEVER; 3], NO_RATE, 0.02));
        assert!(stays_below([0.0; 3], NO_RATE, 0.02));
        assert!(stays_below([-4.0, -3.8, -3.5], NO_RATE, 0.02));
        // a slip speed far from zero whose acceleration cannot bring it there in the step
        assert!(stays_below([-4.0, -3.8, -3.5], [10.0, 12.0, 15.0], 0.02));
    }

    #[test]
    fn indicators_that_may_reach_zero_are_not_quiet() {
        // the same values, but a rate that could carry the indicator to zero within the step
        assert!(!stays_below([-4.0, -3.8, -3.5], [50.0, 60.0, 55.0], 0.024));
        // a limit whose hump over three samples comes within three spreads of zero
        assert!(!stays_below([-0.5, -0.3, -0.5], NO_RATE, 0.02));
        // a crossing, a value touching zero with a rate, a held value above zero
        assert!(!stays_below([-0.1, 0.2, 0.4], NO_RATE, 0.02));
        assert!(!stays_below([0.0; 3], [1.0, 0.0, 0.0], 0.02));
        assert!(!stays_below([1e-3; 3], NO_RATE, 0.02));
        // anything not finite
        assert!(!stays_below([-1.0, f64::NAN, -1.0], NO_RATE, 0.02));
        assert!(!stays_below([-1.0; 3], [f64::INFINITY, 0.0, 0.0], 0.02));
    }
}
