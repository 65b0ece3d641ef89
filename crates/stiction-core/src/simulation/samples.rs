//! What the crossing scan keeps of one integrator step (`scan.rs`) and what its searches
//! (`locate.rs`) share: the samples' indicators and rates, the finite-difference step, and the
//! shape of a hump found between samples.

/// Interior samples plus the step's end.
pub(super) const SAMPLES: usize = 4;

/// The step of the backward differences that give rates to indicators with no analytic one,
/// as a fraction of the integrator step.
pub(super) const FD_STEP: f64 = 1e-6;

/// A hump that reaches above zero: bracket start, (indicator, value there, value at the top),
/// and the top's time.
pub(super) type Hump = (f64, (usize, f64, f64), f64);

/// The indicators and their rates at the start of a step and at its samples, each sample
/// evaluated once and kept while the step is searched.
#[derive(Default)]
pub(super) struct StepSamples {
    pub(super) t: [f64; SAMPLES + 1],
    pub(super) z: Vec<f64>,
    pub(super) dz: Vec<f64>,
}

impl StepSamples {
    pub(super) fn at(&self, k: usize) -> (&[f64], &[f64]) {
        let nz = self.z.len() / (SAMPLES + 1);
        (
            &self.z[k * nz..(k + 1) * nz],
            &self.dz[k * nz..(k + 1) * nz],
        )
    }

    pub(super) fn at_mut(&mut self, k: usize) -> (&mut [f64], &mut [f64]) {
        let nz = self.z.len() / (SAMPLES + 1);
        (
            &mut self.z[k * nz..(k + 1) * nz],
            &mut self.dz[k * nz..(k + 1) * nz],
        )
    }
}

/// The highest value on [0, h] of the cubic with values `za`, `zb` and rates `dza`, `dzb` at
/// its ends (Hermite). A slip speed whose rate is tiny at the start of an interval and whose
/// acceleration then grows (a brake re-engaging from a vanishing normal force while its drive
/// ramps) makes a hump that no tangent at either end bounds; the cubic through both ends'
/// values and rates follows it.
pub(super) fn hermite_top(za: f64, zb: f64, dza: f64, dzb: f64, h: f64) -> f64 {
    // p(s) = za + a1·s + a2·s² + a3·s³ on s ∈ [0, 1]
    let a1 = h * dza;
    let rise = zb - za - a1;
    let a3 = h * dzb - a1 - 2.0 * rise;
    let a2 = rise - a3;
    let p = |s: f64| za + s * (a1 + s * (a2 + s * a3));
    let mut top = za.max(zb);
    // p'(s) = a1 + 2·a2·s + 3·a3·s²
    let (qa, qb, qc) = (3.0 * a3, 2.0 * a2, a1);
    let roots = if qa == 0.0 {
        [-qc / qb, f64::NAN]
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        let root = disc.max(0.0).sqrt();
        [(-qb + root) / (2.0 * qa), (-qb - root) / (2.0 * qa)]
    };
    for s in roots {
        if s > 0.0 && s < 1.0 {
            top = top.max(p(s));
        }
    }
    top
}

#[cfg(test)]
mod tests {
    use super::hermite_top;

    #[test]
    fn the_cubic_through_ends_and_rates_finds_a_hump_the_start_tangent_misses() {
        // z(t) = -1e-10 + 6.7e-11·t + 0.017·t² - 2.8·t³: a rate of 6.7e-11 at t = 0 and a top of
        // about 5e-8 near t = 4 ms, on an interval of 31 ms
        let z = |t: f64| -1e-10 + 6.7e-11 * t + 0.017 * t * t - 2.8 * t * t * t;
        let dz = |t: f64| 6.7e-11 + 0.034 * t - 8.4 * t * t;
        let h = 0.031;
        let top = hermite_top(z(0.0), z(h), dz(0.0), dz(h), h);
        let exact = (0..=10_000)
            .map(|k| z(h * k as f64 / 1e4))
            .fold(f64::MIN, f64::max);
        assert!(
            (top - exact).abs() < 1e-12 * exact.abs().max(1.0),
            "{top} {exact}"
        );
        assert!(top > 0.0);
        // the tangent at the start says it stays below zero over twice the interval
        assert!(z(0.0) + dz(0.0) * 2.0 * h < 0.0);
    }

    #[test]
    fn a_monotone_interval_tops_at_its_larger_end() {
        assert_eq!(hermite_top(-2.0, -1.0, 1.0, 1.0, 1.0), -1.0);
        assert_eq!(hermite_top(-1.0, -3.0, -2.0, -2.0, 1.0), -1.0);
    }
}
