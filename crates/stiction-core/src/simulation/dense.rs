//! The output grid's reading of one step's dense output. Tsit45's continuous extension is a
//! polynomial of degree 4 in the step fraction θ; diffsol evaluates it through its generic
//! matrix kernels (about a thousand instructions per call for eight states), and a long step
//! holds tens of grid rows. So a step with many rows is sampled on diffsol's dense output at
//! five equally spaced instants and the polynomial through them (Newton form, Lebesgue
//! constant about 2 on the step) answers every row: the same polynomial, to round-off, at a
//! few multiply-adds per state.

use crate::error::SimError;

/// Samples per fitted step: degree 4 needs five.
const NODES: usize = 5;

/// The fitted polynomial of the step pending, if one was fitted.
#[derive(Default)]
pub(super) struct StepPoly {
    /// The step's start and length, so θ = (t − t0) / dt.
    t0: f64,
    dt: f64,
    theta: [f64; NODES],
    /// Newton coefficients, `NODES` per state, state after state.
    coef: Vec<f64>,
    fitted: bool,
}

impl StepPoly {
    /// Forgets the fit: a new step was taken.
    pub fn clear(&mut self) {
        self.fitted = false;
    }

    pub fn fitted(&self) -> bool {
        self.fitted
    }

    /// Fits the step [t0, t1] from `sample(t, out)`, the integrator's dense output.
    pub fn fit(
        &mut self,
        t0: f64,
        t1: f64,
        n: usize,
        mut sample: impl FnMut(f64, &mut [f64]) -> Result<(), SimError>,
    ) -> Result<(), SimError> {
        let dt = t1 - t0;
        self.coef.resize(n * NODES, 0.0);
        let mut y = vec![0.0; n];
        for j in 0..NODES {
            let t = if j + 1 == NODES {
                t1
            } else {
                t0 + dt * j as f64 / (NODES - 1) as f64
            };
            self.theta[j] = (t - t0) / dt;
            sample(t, &mut y)?;
            for (i, v) in y.iter().enumerate() {
                self.coef[i * NODES + j] = *v;
            }
        }
        // divided differences in place, per state
        for c in self.coef.chunks_exact_mut(NODES) {
            for level in 1..NODES {
                for j in (level..NODES).rev() {
                    c[j] = (c[j] - c[j - 1]) / (self.theta[j] - self.theta[j - level]);
                }
            }
        }
        (self.t0, self.dt, self.fitted) = (t0, dt, true);
        Ok(())
    }

    /// The polynomial at t (inside the fitted step), into `out`.
    pub fn eval(&self, t: f64, out: &mut [f64]) {
        let th = (t - self.t0) / self.dt;
        let d: [f64; NODES] = std::array::from_fn(|j| th - self.theta[j]);
        for (o, c) in out.iter_mut().zip(self.coef.chunks_exact(NODES)) {
            let mut acc = c[NODES - 1];
            for j in (0..NODES - 1).rev() {
                acc = c[j] + d[j] * acc;
            }
            *o = acc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A degree-4 polynomial is reproduced to round-off anywhere in the step, and exactly at
    /// the samples' ends.
    #[test]
    fn reproduces_a_quartic() {
        let f = |t: f64| {
            [
                1.5 + t * (2.0 - t * (3.0 + t * (0.5 - 4.0 * t))),
                -7.0 * t.powi(4),
            ]
        };
        let (t0, t1) = (0.3, 0.42);
        let mut p = StepPoly::default();
        p.fit(t0, t1, 2, |t, out| {
            out.copy_from_slice(&f(t));
            Ok(())
        })
        .unwrap();
        let mut out = [0.0; 2];
        for k in 0..=100 {
            let t = t0 + (t1 - t0) * k as f64 / 100.0;
            p.eval(t, &mut out);
            let want = f(t);
            for i in 0..2 {
                assert!(
                    (out[i] - want[i]).abs() <= 4.0 * f64::EPSILON * 3.0,
                    "{t}: {out:?} {want:?}"
                );
            }
        }
        p.eval(t0, &mut out);
        assert_eq!(out, f(t0));
    }
}
