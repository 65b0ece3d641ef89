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
