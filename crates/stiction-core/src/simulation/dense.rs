//! The output grid's reading of one step's dense output. Tsit45's continuous extension is a
//! polynomial of degree 4 in the step fraction θ; diffsol evaluates it through its generic
//! matrix kernels (about a thousand instructions per call for eight states), and a long step
//! holds tens of grid rows. So a step with many rows is sampled at five equally spaced
//! instants — its start and end states, and the three interior points the crossing scan reads
//! on diffsol's dense output anyway — and the polynomial through them (Newton form, Lebesgue
//! constant about 2 on the step) answers every row: the same polynomial, to round-off, at a
//! few multiply-adds per state.

use crate::error::SimError;

/// Samples per fitted step: degree 4 needs five.
const NODES: usize = 5;

/// The polynomial of the step pending, from its samples.
#[derive(Default)]
pub(super) struct StepPoly {
    /// The step's start and length, so θ = (t − t0) / dt.
    t0: f64,
    dt: f64,
    theta: [f64; NODES],
    n: usize,
    /// Samples, node after node (`n` values each).
    samples: Vec<f64>,
    /// Newton coefficients, `NODES` per state, state after state (Horner per state).
    coef: Vec<f64>,
    have: [bool; NODES],
    fitted: bool,
}

impl StepPoly {
    /// Starts a new step [t0, t1] whose start state is `x0`; nothing is fitted yet.
    pub fn begin(&mut self, t0: f64, t1: f64, x0: &[f64]) {
        let n = x0.len();
        (self.t0, self.dt, self.n, self.fitted) = (t0, t1 - t0, n, false);
        self.samples.resize(n * NODES, 0.0);
        self.coef.resize(n * NODES, 0.0);
        for j in 0..NODES {
            self.theta[j] = (self.node_time(j) - t0) / self.dt;
        }
        self.have = [false; NODES];
        self.put(t0, x0);
    }

    /// The instant of sample `j`: the step's end, or `j` quarters into it (the instants at
    /// which the crossing scan samples the step, so its samples serve here too).
    fn node_time(&self, j: usize) -> f64 {
        if j + 1 == NODES {
            self.t0 + self.dt
        } else {
            self.t0 + self.dt * j as f64 / (NODES - 1) as f64
        }
    }

    /// Keeps the state `x` at `t` if `t` is one of the sample instants.
    pub fn put(&mut self, t: f64, x: &[f64]) {
        if self.fitted || x.len() != self.n {
            return;
        }
        if let Some(j) = (0..NODES).find(|&j| self.node_time(j) == t) {
            self.samples[j * self.n..(j + 1) * self.n].copy_from_slice(x);
            self.have[j] = true;
        }
    }

    pub fn fitted(&self) -> bool {
        self.fitted
    }

    /// Fits the step: the missing samples from `sample(t, out)` (the integrator's dense output;
    /// `end` is the state at the step's end), then divided differences.
    pub fn fit(
        &mut self,
        end: &[f64],
        mut sample: impl FnMut(f64, &mut [f64]) -> Result<(), SimError>,
    ) -> Result<(), SimError> {
        let n = self.n;
        self.put(self.t0 + self.dt, end);
        for j in 0..NODES {
            if !self.have[j] {
                let t = self.node_time(j);
                sample(t, &mut self.samples[j * n..(j + 1) * n])?;
            }
        }
        for (i, c) in self.coef.chunks_exact_mut(NODES).enumerate() {
            for (j, cj) in c.iter_mut().enumerate() {
                *cj = self.samples[j * n + i];
            }
            for level in 1..NODES {
                for j in (level..NODES).rev() {
                    c[j] = (c[j] - c[j - 1]) / (self.theta[j] - self.theta[j - level]);
                }
            }
        }
        self.fitted = true;
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
        p.begin(t0, t1, &f(t0));
        p.put(t0 + (t1 - t0) * 2.0 / 4.0, &f(t0 + (t1 - t0) * 2.0 / 4.0));
        let mut asked = Vec::new();
        p.fit(&f(t1), |t, out| {
            asked.push(t);
            out.copy_from_slice(&f(t));
            Ok(())
        })
        .unwrap();
        assert_eq!(asked.len(), 2, "only the samples not given are asked for");
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
        p.eval(t1, &mut out);
        assert_eq!(out, f(t1));
    }
}
