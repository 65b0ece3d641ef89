//! Scanning one integrator step for crossings. The step is sampled at three interior points of
//! its dense output and at its end, each sample evaluated once and kept; only then is it
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
use crate::engine::speed_rates;
use crate::error::SimError;
use crate::switching::element::NEVER;

/// An indicator without analytic rate is searched for humps between samples when its largest
/// sample in the step lies within `NEAR` times its spread over the step of zero. The quartic
/// through the five samples can rise at most 0.6 spreads above the largest sample (the
/// Lebesgue constant of five equidistant points is 2.2), so 3 leaves a wide margin for what
/// the quartic does not capture of a step the integrator resolved.
const NEAR: f64 = 3.0;

impl Stepper {
    /// Looks for a crossing in the last step (t_prev, t_now]; a relation that flips and flips
    /// back within one step (a freewheel touching lock for a millisecond) is still seen. Leaves
    /// the indicators and rates at the step end in `z` and `dz`, evaluated there.
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
        self.sample_step(solver, t_prev, t_now)?;
        let differences = self.needs_differences();
        if differences {
            self.difference_rates(solver, t_prev, t_now)?;
        }
        let found = self.search_samples(solver, candidates)?;
        if found.is_none() {
            let (z, dz) = self.samples.at(SAMPLES);
            self.z.copy_from_slice(z);
            self.dz.copy_from_slice(dz);
            if differences || self.probed {
                // probes moved the evaluation away from the step end
                self.x.copy_from_slice(solver.state().y.inner().as_slice());
                self.evaluate_here(t_now, false);
            }
        }
        Ok(found)
    }

    /// Evaluates the samples of the step (feeding the grid rows' fit) and keeps their
    /// indicators and analytic rates; sample 0 is the step's start.
    fn sample_step<'a, S>(&mut self, solver: &S, t_prev: f64, t_now: f64) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let nz = self.z.len();
        let mut samples = std::mem::take(&mut self.samples);
        samples.z.resize((SAMPLES + 1) * nz, 0.0);
        samples.dz.resize((SAMPLES + 1) * nz, f64::NAN);
        samples.t[0] = t_prev;
        let (z0, dz0) = samples.at_mut(0);
        z0.copy_from_slice(&self.z_prev);
        dz0.copy_from_slice(&self.dz); // the last sample's rates (analytic only after events)
        for k in 1..=SAMPLES {
            let t = if k == SAMPLES {
                self.x.copy_from_slice(solver.state().y.inner().as_slice());
                t_now
            } else {
                let t = t_prev + (t_now - t_prev) * k as f64 / SAMPLES as f64;
                self.load(solver, t)?;
                self.offer_sample(t);
                t
            };
            self.evaluate_here(t, true);
            samples.t[k] = t;
            let (z, dz) = samples.at_mut(k);
            z.copy_from_slice(&self.z);
            let guard = self.phase.borrow();
            speed_rates(&self.sys, &guard.disc, &guard.ws, dz);
        }
        self.samples = samples;
        self.probed = false;
        Ok(())
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

    /// Backward-difference rates at every sample (forward at the step's start, which the dense
    /// output does not reach behind) for the indicators without an analytic one.
    fn difference_rates<'a, S>(
        &mut self,
        solver: &S,
        t_prev: f64,
        t_now: f64,
    ) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let h = FD_STEP * (t_now - t_prev);
        let mut samples = std::mem::take(&mut self.samples);
        for k in 0..=SAMPLES {
            if !samples.at(k).1.iter().any(|r| r.is_nan()) {
                continue;
            }
            let probe = if k == 0 { t_prev + h } else { samples.t[k] - h };
            self.load(solver, probe)?;
            self.evaluate_here(probe, true);
            let (z, dz) = samples.at_mut(k);
            for ((rate, &at), &other) in dz.iter_mut().zip(z.iter()).zip(&self.z) {
                if rate.is_nan() {
                    *rate = if k == 0 { other - at } else { at - other } / h;
                }
            }
        }
        self.samples = samples;
        Ok(())
    }

    /// The intervals between the samples in order: the first crossing, or the top of a hump
    /// that rises above zero between samples.
    fn search_samples<'a, S>(
        &mut self,
        solver: &S,
        candidates: &mut Vec<(usize, f64, f64)>,
    ) -> Result<Option<(f64, usize)>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        for k in 1..=SAMPLES {
            let (a, b) = (self.samples.t[k - 1], self.samples.t[k]);
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
