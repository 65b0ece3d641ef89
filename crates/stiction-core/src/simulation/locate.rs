//! Locating zero crossings inside one integrator step, on diffsol's dense output: the step is
//! sampled at three interior points and its end; a crossing is bracketed and found by Illinois
//! regula falsi that always returns the instant just *after* it (the event iteration then sees
//! the relation changed, as Modelica requires). diffsol's own root finder is not used: it reports
//! any sign change to a tolerance we do not control, while MSL semantics need the directional,
//! frozen-relation crossings of `events::crossings`.

use diffsol::{OdeSolverMethod, VectorCommon};

use super::integrator::Eqn;
use super::stepper::Stepper;
use crate::engine::speed_rates;
use crate::error::SimError;
use crate::switching::element::NEVER;

/// The step of the backward differences that give rates to indicators with no analytic one,
/// as a fraction of the integrator step.
const FD_STEP: f64 = 1e-6;

/// A hump that reaches above zero: bracket start, (indicator, value there, value at the top),
/// and the top's time.
type Hump = (f64, (usize, f64, f64), f64);

impl Stepper {
    /// The indicator `i` at time t on the dense output of the last step.
    pub(super) fn indicator_at<'a, S>(
        &mut self,
        solver: &S,
        t: f64,
        i: usize,
    ) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.load(solver, t)?;
        self.evaluate_here(t, true);
        Ok(self.z[i])
    }

    /// Looks for a crossing in the last step at three interior points of the dense output and
    /// at its end — a relation that flips and flips back within one step (a freewheel touching
    /// lock for a millisecond) is still seen. Leaves the indicators at the step end in `z`.
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
        const SAMPLES: usize = 4;
        let h = FD_STEP * (t_now - t_prev);
        let finite_differences = self.wants_finite_differences();
        self.z_scan.copy_from_slice(&self.z_prev);
        // the rates at the step's start: those of the last sample (NaN right after an event)
        self.dz_scan.copy_from_slice(&self.dz);
        let mut a = t_prev;
        // the sample before `a` (the last interior one of the previous step, if no event since)
        let mut back = self.hump_back.take();
        for k in 1..=SAMPLES {
            let t_sample = t_prev + (t_now - t_prev) * k as f64 / SAMPLES as f64;
            if finite_differences {
                self.indicators_before(solver, t_sample.min(t_now), h)?;
            }
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
            {
                let guard = self.phase.borrow();
                speed_rates(&self.sys, &guard.disc, &guard.ws, &mut self.dz);
            }
            if finite_differences {
                self.fill_finite_difference_rates(h);
            }
            // A speed indicator that rises above zero and falls back between the two samples
            // ends the bracket at its peak, so it competes with every crossing before it (a
            // later crossing of another indicator must not hide it).
            let end = self.end_at_peak(solver, a, t, k == SAMPLES)?;
            candidates.clear();
            for (i, (&za, &zb)) in self.z_scan.iter().zip(&self.z).enumerate() {
                if za <= 0.0 && zb > 0.0 {
                    candidates.push((i, za, zb));
                }
            }
            if !candidates.is_empty() {
                return self.locate(solver, a, end, candidates).map(Some);
            }
            if let Some((t_back, z_back)) = &back {
                if let Some(found) = self.hump(solver, (*t_back, z_back.clone()), t_prev, t)? {
                    candidates.clear();
                    candidates.push(found.1);
                    return self.locate(solver, found.0, found.2, candidates).map(Some);
                }
            }
            back = Some((a, self.z_scan.clone()));
            self.z_scan.copy_from_slice(&self.z);
            self.dz_scan.copy_from_slice(&self.dz);
            a = t;
        }
        self.hump_back = back;
        Ok(None)
    }

    /// An indicator that rises and falls back between samples (`back`, the last, `b`) without showing a
    /// sign change at any of them — a locked clutch's torque passing its falling static limit
    /// for a few milliseconds inside one long step. Where three samples make a hump whose top
    /// may reach zero (a parabola through them says so), its maximum is found on the dense
    /// output (golden section); if it is above zero, the crossing lies before it:
    /// `(bracket start, (i, z there, z at the top), top)`, searched within this step (from
    /// `step_start` at the earliest). Leaves the sample at `b` loaded.
    fn hump<'a, S>(
        &mut self,
        solver: &S,
        back: (f64, Vec<f64>),
        step_start: f64,
        b: f64,
    ) -> Result<Option<Hump>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let (t_back, z0) = back;
        // the dense output covers this step only: a hump from the last step is searched from here
        let t0 = t_back.max(step_start);
        let may_cross = |zl: f64, zm: f64, zr: f64| {
            let curvature = 2.0 * zm - zl - zr;
            zl < zm && zm > zr && zm <= 0.0 && curvature > 0.0 && {
                // the top of the parabola through the three samples, with a margin for its error
                let top = zm + (zr - zl) * (zr - zl) / (8.0 * curvature);
                top > -0.5 * (zm - zl.min(zr))
            }
        };
        let humps: Vec<usize> = (0..self.z.len())
            .filter(|&i| may_cross(z0[i], self.z_scan[i], self.z[i]))
            .collect();
        if humps.is_empty() {
            return Ok(None);
        }
        let mut found: Option<Hump> = None;
        for i in humps {
            let Some((t_top, z_top)) = self.top_of(solver, i, t0, b)? else {
                continue;
            };
            let z_start = self.indicator_at(solver, t0, i)?;
            if z_start <= 0.0 && found.as_ref().is_none_or(|f| t_top < f.2) {
                found = Some((t0, (i, z_start, z_top), t_top));
            }
        }
        self.reload_sample(solver, b)?;
        Ok(found)
    }

    /// Where indicator `i` first shows above zero while its maximum between `lo` and `hi` is
    /// searched (golden section on the dense output): `(t, z)`, or None if it stays ≤ 0.
    fn top_of<'a, S>(
        &mut self,
        solver: &S,
        i: usize,
        lo: f64,
        hi: f64,
    ) -> Result<Option<(f64, f64)>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let (mut lo, mut hi, width) = (lo, hi, hi - lo);
        let golden = 0.5 * (5f64.sqrt() - 1.0);
        let (mut c, mut d) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
        let mut zc = self.indicator_at(solver, c, i)?;
        let mut zd = self.indicator_at(solver, d, i)?;
        for _ in 0..60 {
            if zc.max(zd) > 0.0 || hi - lo <= 1e-9 * width {
                break;
            }
            if zc > zd {
                (hi, d, zd) = (d, c, zc);
                c = hi - golden * (hi - lo);
                zc = self.indicator_at(solver, c, i)?;
            } else {
                (lo, c, zc) = (c, d, zd);
                d = lo + golden * (hi - lo);
                zd = self.indicator_at(solver, d, i)?;
            }
        }
        let top = if zc >= zd { (c, zc) } else { (d, zd) };
        Ok((top.1 > 0.0).then_some(top))
    }

    /// The sample at `t` again (after probing elsewhere on the step).
    fn reload_sample<'a, S>(&mut self, solver: &S, t: f64) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        if t == solver.state().t {
            self.x.copy_from_slice(solver.state().y.inner().as_slice());
        } else {
            self.load(solver, t)?;
        }
        self.evaluate_here(t, true);
        let guard = self.phase.borrow();
        speed_rates(&self.sys, &guard.disc, &guard.ws, &mut self.dz);
        Ok(())
    }

    /// `t`, or the peak of a speed indicator that rises above zero and falls back between the
    /// samples `a` and `t`; the indicators are left evaluated there (the sample at `t` is the
    /// step's end when `last`).
    fn end_at_peak<'a, S>(
        &mut self,
        solver: &S,
        a: f64,
        t: f64,
        last: bool,
    ) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let peak = self.peak_between(solver, a, t)?;
        let end = if let Some((t_peak, _)) = peak {
            self.load(solver, t_peak)?;
            t_peak
        } else if last {
            self.x.copy_from_slice(solver.state().y.inner().as_slice());
            t
        } else {
            self.load(solver, t)?;
            t
        };
        self.evaluate_here(end, true);
        Ok(end)
    }

    /// Whether this step's indicators need finite-difference rates: one without an analytic
    /// rate (a locked element's torque against its static limit, a law's relation) is armed.
    fn wants_finite_differences(&mut self) -> bool {
        let mut analytic = std::mem::take(&mut self.dz_probe);
        {
            let guard = self.phase.borrow();
            speed_rates(&self.sys, &guard.disc, &guard.ws, &mut analytic);
        }
        let armed = (self.z_prev.iter().zip(&analytic))
            .any(|(&z, &rate)| rate.is_nan() && z <= 0.0 && z != NEVER && z.is_finite());
        self.dz_probe = analytic;
        armed
    }

    /// The indicators at `t − h` (kept in `dz_probe`), for backward differences at `t`.
    fn indicators_before<'a, S>(&mut self, solver: &S, t: f64, h: f64) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.load(solver, t - h)?;
        self.evaluate_here(t - h, true);
        self.dz_probe.copy_from_slice(&self.z);
        Ok(())
    }

    /// Rates of the indicators without an analytic one, from the values at `t − h` and `t`.
    fn fill_finite_difference_rates(&mut self, h: f64) {
        for ((rate, &z), &before) in self.dz.iter_mut().zip(&self.z).zip(&self.dz_probe) {
            if rate.is_nan() {
                *rate = (z - before) / h;
            }
        }
    }

    /// The rate of indicator `i` at `t` inside the samples `span`: analytic for a speed, else a
    /// one-sided difference that stays inside the span (the dense output covers no more).
    fn rate_at<'a, S>(
        &mut self,
        solver: &S,
        t: f64,
        i: usize,
        span: (f64, f64),
    ) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.load(solver, t)?;
        self.evaluate_here(t, true);
        let z_t = self.z[i];
        let analytic = {
            let guard = self.phase.borrow();
            let mut dz = std::mem::take(&mut self.dz_probe);
            speed_rates(&self.sys, &guard.disc, &guard.ws, &mut dz);
            let r = dz[i];
            self.dz_probe = dz;
            r
        };
        if !analytic.is_nan() {
            return Ok(analytic);
        }
        let h = FD_STEP * (span.1 - span.0);
        if t - h >= span.0 {
            Ok((z_t - self.indicator_at(solver, t - h, i)?) / h)
        } else {
            Ok((self.indicator_at(solver, t + h, i)? - z_t) / h)
        }
    }

    /// The earliest peak above zero between samples `a` and `b` of an indicator whose rate goes
    /// from positive (at a, in `dz_scan`) to negative (at b, in `dz`) while it stays ≤ 0 at both
    /// ends: the rate's zero, by bisection on the dense output (a speed's rate is its relative
    /// acceleration; others' rates are backward differences).
    fn peak_between<'a, S>(
        &mut self,
        solver: &S,
        a: f64,
        b: f64,
    ) -> Result<Option<(f64, usize)>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let turning: Vec<usize> = (0..self.dz.len())
            .filter(|&i| {
                let (za, zb) = (self.z_scan[i], self.z[i]);
                self.dz_scan[i] > 0.0 && self.dz[i] < 0.0 && za <= 0.0 && zb <= 0.0
            })
            .collect();
        let mut earliest: Option<(f64, usize)> = None;
        for i in turning {
            let (mut lo, mut hi) = (a, b);
            for _ in 0..60 {
                if hi - lo <= 1e-9 * (b - a) {
                    break;
                }
                let mid = 0.5 * (lo + hi);
                if self.rate_at(solver, mid, i, (a, b))? > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let peak = 0.5 * (lo + hi);
            let above = self.indicator_at(solver, peak, i)? > 0.0;
            if above && earliest.is_none_or(|(t, _)| peak < t) {
                earliest = Some((peak, i));
            }
        }
        Ok(earliest)
    }

    /// Earliest instant in (a, b] at which one of `candidates` becomes > 0: Illinois regula falsi
    /// on each, keeping the bracket so the returned time lies just after the crossing.
    fn locate<'a, S>(
        &mut self,
        solver: &S,
        a: f64,
        b: f64,
        candidates: &[(usize, f64, f64)],
    ) -> Result<(f64, usize), SimError>
    where
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
}
