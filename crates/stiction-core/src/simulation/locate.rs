//! Locating zero crossings inside one integrator step, on diffsol's dense output, once the scan
//! (`scan.rs`) has bracketed one: found by Illinois regula falsi that always returns the instant just *after* it (the event iteration then sees
//! the relation changed, as Modelica requires). diffsol's own root finder is not used: it reports
//! any sign change to a tolerance we do not control, while MSL semantics need the directional,
//! frozen-relation crossings of `events::crossings`.

use diffsol::OdeSolverMethod;

use super::integrator::Eqn;
use super::samples::{hermite_top, Hump, FD_STEP};
use super::stepper::Stepper;
use crate::engine::eval::evaluate_switching;
use crate::engine::speed_rates;
use crate::error::SimError;
use crate::switching::element::{INDICATORS, NEVER};

impl Stepper {
    /// The indicator `i` at time t on the dense output of the last step.
    // Alike in shape only (the signature of every method over the solver), not in logic.
    pub(super) fn indicator_at<'a, S>(
        &mut self,
        solver: &S,
        t: f64,
        i: usize,
    ) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.indicators_at(solver, t)?;
        Ok(self.z[i])
    }

    /// Indicator `i` at time t as `locate` reads it: a sliding element's slip speed straight
    /// from the interpolated state when nothing rewrites the speeds (no shafts without inertia,
    /// no prescribed motion: `w` is then the state's, bit for bit), else by evaluating the
    /// system. Regula falsi probes a bracket tens of times, and a whole evaluation per probe
    /// made locating cost the size of the model times the number of probes.
    fn locate_probe<'a, S>(&mut self, solver: &S, t: f64, i: usize) -> Result<f64, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let (k, slot) = (i / INDICATORS, i % INDICATORS);
        let direct = slot == 1 && k < self.sys.switching.len() && {
            let guard = self.phase.borrow();
            let st = &guard.disc.switching[k];
            guard.mm.massless.is_none()
                && !self.sys.prescribes()
                && self.sys.switching[k].slip_indicator(st, 0.0).is_some()
        };
        if !direct {
            return self.indicator_at(solver, t, i);
        }
        self.probed = true;
        self.load(solver, t)?;
        let n = self.sys.nodes;
        let e = &self.sys.switching[k];
        let w = e.motion().dot(&self.x[n..2 * n]);
        let guard = self.phase.borrow();
        let z = e.slip_indicator(&guard.disc.switching[k], w);
        Ok(z.unwrap_or(NEVER))
    }

    /// The indicators at (t, self.x) in the current discrete state, into `z`, from an
    /// evaluation short of the heat flows and energies (`evaluate_switching`): the crossing
    /// scan's samples and the searches' probes read nothing else. Not noted as evaluated there
    /// (`holds`): the workspace does not hold the derivative.
    pub fn probe_here(&mut self, t: f64) {
        self.evaluate_with(evaluate_switching, t, true);
    }

    /// Every indicator at time t on the dense output of the last step, in `z` (a probe away
    /// from the samples the scan keeps).
    pub(super) fn indicators_at<'a, S>(&mut self, solver: &S, t: f64) -> Result<(), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        self.probed = true;
        self.load(solver, t)?;
        self.probe_here(t);
        Ok(())
    }

    /// An indicator that rises and falls back between samples (`t_back` with its indicators in
    /// `z_back`, the last in `z_scan`, `b` in `z`) without showing a sign change at any of them — a locked clutch's torque passing its falling static limit
    /// for a few milliseconds inside one long step. Where three samples make a hump whose top
    /// may reach zero (a parabola through them says so), its maximum is found on the dense
    /// output (golden section); if it is above zero, the crossing lies before it:
    /// `(bracket start, (i, z there, z at the top), top)`, searched within this step (from
    /// `step_start` at the earliest). Probes overwrite `z`.
    pub(super) fn hump<'a, S>(
        &mut self,
        solver: &S,
        t_back: f64,
        step_start: f64,
        b: f64,
    ) -> Result<Option<Hump>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let z0 = &self.z_back;
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
        // most intervals have none: that is found without collecting (a few intervals a step)
        let hump_at = |i: &usize| may_cross(z0[*i], self.z_scan[*i], self.z[*i]);
        if !(0..self.z.len()).any(|i| hump_at(&i)) {
            return Ok(None);
        }
        let humps: Vec<usize> = (0..self.z.len()).filter(hump_at).collect();
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
        let z_t = self.indicator_at(solver, t, i)?;
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
    /// acceleration; others' rates are backward differences). A peak the tangents at both ends
    /// keep below zero is not searched: the tangents bound a concave hump from above, and
    /// `TANGENT_MARGIN` allows for a hump that is not quite concave. One that is far from
    /// concave (its rate grows before it falls) is searched where the cubic through both ends'
    /// values and rates rises above zero, less a tenth of its rise (`hermite_top`).
    pub(super) fn peak_between<'a, S>(
        &mut self,
        solver: &S,
        a: f64,
        b: f64,
    ) -> Result<Option<(f64, usize)>, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        const TANGENT_MARGIN: f64 = 2.0;
        let reach = TANGENT_MARGIN * (b - a);
        let turns = |i: &usize| {
            let i = *i;
            let (za, zb, dza, dzb) = (self.z_scan[i], self.z[i], self.dz_scan[i], self.dz[i]);
            let tangents = za + dza * reach > 0.0 && zb - dzb * reach > 0.0;
            dza > 0.0
                && dzb < 0.0
                && za <= 0.0
                && zb <= 0.0
                && (tangents || {
                    let top = hermite_top(za, zb, dza, dzb, b - a);
                    top + 0.1 * (top - za.min(zb)) > 0.0
                })
        };
        // most intervals have none: that is found without collecting
        if !(0..self.dz.len()).any(|i| turns(&i)) {
            return Ok(None);
        }
        let turning: Vec<usize> = (0..self.dz.len()).filter(turns).collect();
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

    /// The crossing `found` in (a, b], or an earlier one that the samples did not show: an
    /// indicator that is above zero at `found` though not at `a` (in `z_scan`) crossed in
    /// between, in a hump too narrow for the samples at both ends of the interval (a brake
    /// re-engaging with a vanishing normal force starts backward and its slip passes the
    /// relation band within 0.1 ms of a 31 ms interval, while the start's end is what changes
    /// sign at the samples: left there, the start ended and locked three bands away from zero).
    /// One evaluation at `found`; each round moves the crossing earlier.
    pub(super) fn earliest_before<'a, S>(
        &mut self,
        solver: &S,
        a: f64,
        mut found: (f64, usize),
        candidates: &mut Vec<(usize, f64, f64)>,
    ) -> Result<(f64, usize), SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        loop {
            self.indicators_at(solver, found.0)?;
            candidates.clear();
            for (i, (&za, &z)) in self.z_scan.iter().zip(&self.z).enumerate() {
                if i != found.1 && za <= 0.0 && z > 0.0 {
                    candidates.push((i, za, z));
                }
            }
            if candidates.is_empty() {
                return Ok(found);
            }
            let earlier = self.locate(solver, a, found.0, candidates)?;
            if earlier.0 >= found.0 {
                return Ok(found);
            }
            found = earlier;
        }
    }

    /// Earliest instant in (a, b] at which one of `candidates` becomes > 0: Illinois regula falsi
    /// on each, keeping the bracket so the returned time lies just after the crossing.
    pub(super) fn locate<'a, S>(
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
                zb = self.locate_probe(solver, tb, i)?;
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
                let zm = self.locate_probe(solver, tm, i)?;
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
