//! Tsit45's dense output, evaluated here rather than by diffsol. Its continuous extension is
//! `y(θ) = y0 + Σᵢ βᵢ(θ)·h·kᵢ`, a quartic in the step fraction θ without constant term, over
//! the seven stage derivatives `kᵢ`; diffsol evaluates it through its generic matrix kernels
//! (about a thousand instructions per call for ten states), and a step is read tens of times
//! (grid rows, the crossing scan's samples, the probes that locate a crossing). The right-hand
//! side records the stages as diffsol computes them (`Stages`), and the step's quartic is
//! formed once from them (`StepPoly`): the same polynomial to round-off, a few multiply-adds
//! per state and instant.

use diffsol::Tableau;

/// Tsit45's stages; the first is the previous step's last (first same as last).
const STAGES: usize = 7;
/// The coefficients of θ¹…θ⁴.
const DEGREE: usize = 4;

/// The stage derivatives of the explicit step being taken. Inside a Tsit45 step the
/// right-hand side is called only for its stages, 1 to 6 in order, once per attempt; so after
/// the step the last six calls are the accepted attempt's stages.
#[derive(Default)]
pub(crate) struct Stages {
    on: bool,
    calls: usize,
    n: usize,
    /// `STAGES` derivatives, stage after stage.
    k: Vec<f64>,
}

impl Stages {
    /// Starts recording a step whose first stage is the derivative `dy0` at its start.
    pub fn begin(&mut self, dy0: &[f64]) {
        self.n = dy0.len();
        self.k.resize(STAGES * self.n, 0.0);
        self.k[..self.n].copy_from_slice(dy0);
        (self.on, self.calls) = (true, 0);
    }

    /// Keeps a right-hand side computed while recording.
    pub fn record(&mut self, f: &[f64]) {
        if self.on && f.len() == self.n {
            let slot = 1 + self.calls % (STAGES - 1);
            self.k[slot * self.n..(slot + 1) * self.n].copy_from_slice(f);
            self.calls += 1;
        }
    }

    /// Stops recording; whether whole attempts were recorded.
    pub fn end(&mut self) -> bool {
        self.on = false;
        self.calls > 0 && self.calls.is_multiple_of(STAGES - 1)
    }
}

/// The quartic of the step pending, from its stages.
pub(super) struct StepPoly {
    /// The step's start, end and length, so θ = (t − t0) / dt; the state at its end.
    t0: f64,
    t1: f64,
    dt: f64,
    y1: Vec<f64>,
    /// `y0` and the coefficients of θ¹…θ⁴, each `n` values (one per state).
    coef: Vec<f64>,
    n: usize,
    valid: bool,
    /// `β` of Tsit45's continuous extension: `beta[r][i]` multiplies θ^(r+1)·h·kᵢ.
    beta: [[f64; STAGES]; DEGREE],
}

impl Default for StepPoly {
    fn default() -> Self {
        let tableau = Tableau::<f64>::tsit45();
        let beta_t = tableau.beta_t().expect("Tsit45 has a continuous extension");
        Self {
            t0: 0.0,
            t1: 0.0,
            dt: 0.0,
            y1: Vec::new(),
            coef: Vec::new(),
            n: 0,
            valid: false,
            beta: std::array::from_fn(|r| std::array::from_fn(|i| beta_t[(r, i)])),
        }
    }
}

impl StepPoly {
    /// The step [t0, t1] from `y0` to `y1` with the stage derivatives `stages`.
    pub fn set(&mut self, (t0, y0): (f64, &[f64]), (t1, y1): (f64, &[f64]), stages: &Stages) {
        let n = y0.len();
        let h = t1 - t0;
        (self.t0, self.t1, self.dt, self.n) = (t0, t1, h, n);
        self.y1.clear();
        self.y1.extend_from_slice(y1);
        self.coef.clear();
        self.coef.extend_from_slice(y0);
        self.coef.resize(n * (DEGREE + 1), 0.0);
        // per state, the stages' contributions to each power of θ (in the stages' order)
        for j in 0..n {
            let mut c = [0.0; DEGREE];
            for (i, k) in stages.k.chunks_exact(n).enumerate() {
                let hk = h * k[j];
                for (cr, beta) in c.iter_mut().zip(&self.beta) {
                    *cr += beta[i] * hk;
                }
            }
            for (r, cr) in c.into_iter().enumerate() {
                self.coef[(r + 1) * n + j] = cr;
            }
        }
        self.valid = true;
    }

    /// Forgets the step (the integrator's state changed).
    pub fn clear(&mut self) {
        self.valid = false;
    }

    /// Whether the quartic of the step holds at t.
    pub fn covers(&self, t: f64) -> bool {
        self.valid && t >= self.t0 && t <= self.t1
    }

    /// The quartic at t (inside the step), into `out`: Horner per state, over the states in
    /// one pass (the coefficients are stored degree after degree, so it vectorizes). At the
    /// step's end, the integrator's state itself (equal in exact arithmetic): a run that stops
    /// there reads that state, and a row there must be the same bits.
    pub fn eval(&self, t: f64, out: &mut [f64]) {
        let coef = self.coefficients();
        self.eval_with(&coef, t, out);
    }

    /// `eval` at each of `times` read no later than `end`, into `out` (`n` values a row):
    /// the grid rows of a step, with the coefficient slices (and their bounds checks) taken
    /// once for the block instead of once a row. Not inlined: its loop, inlined into
    /// `Trajectory::push_block` with the grid times, took 14 % more instructions.
    /// Into `out` as it is (`f64`) or not yet written (`MaybeUninit`, a trajectory's spare
    /// room: its rows need no zeroing first); returns how many values it wrote.
    ///
    /// On a CPU with AVX, the same loop compiled for it: four states per multiply and add
    /// instead of two (a run's grid is tens of thousands of rows: the largest single cost of
    /// HeatLosses' run). The same IEEE products and sums lane by lane (no fused multiply-add:
    /// Rust never contracts `a + th * b`), so the rows are the same bits.
    #[inline(never)]
    pub fn eval_rows<T: Slot>(&self, times: &[f64], end: f64, out: &mut [T]) -> usize {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX (detected just above)
            return unsafe { self.eval_rows_avx(times, end, out) };
        }
        self.eval_rows_plain(times, end, out)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    #[inline(never)]
    fn eval_rows_avx<T: Slot>(&self, times: &[f64], end: f64, out: &mut [T]) -> usize {
        self.eval_rows_plain(times, end, out)
    }

    #[inline(always)]
    fn eval_rows_plain<T: Slot>(&self, times: &[f64], end: f64, out: &mut [T]) -> usize {
        let coef = self.coefficients();
        let mut written = 0;
        for (&t, row) in times.iter().zip(out.chunks_exact_mut(self.n)) {
            self.eval_with(&coef, t.min(end), row);
            written += row.len();
        }
        written
    }

    /// `eval_rows` for the states `states` alone (the others in `out` left as they were):
    /// each the very expression `eval_with` computes for it, so the same bits.
    #[inline(never)]
    pub fn eval_rows_of(&self, times: &[f64], end: f64, out: &mut [f64], states: &[usize]) {
        let [a, b, c, d, e] = self.coefficients();
        for (&t, row) in times.iter().zip(out.chunks_exact_mut(self.n)) {
            let t = t.min(end);
            if t == self.t1 {
                for &j in states {
                    row[j] = self.y1[j];
                }
                continue;
            }
            let th = (t - self.t0) / self.dt;
            for &j in states {
                row[j] = a[j] + th * (b[j] + th * (c[j] + th * (d[j] + th * e[j])));
            }
        }
    }

    /// The coefficients of θ⁰…θ⁴, each `n` values.
    fn coefficients(&self) -> [&[f64]; DEGREE + 1] {
        let n = self.n;
        std::array::from_fn(|r| &self.coef[r * n..(r + 1) * n])
    }

    #[inline(always)]
    fn eval_with<T: Slot>(&self, [a, b, c, d, e]: &[&[f64]; DEGREE + 1], t: f64, out: &mut [T]) {
        if t == self.t1 {
            for (o, &y) in out.iter_mut().zip(&self.y1) {
                o.put(y);
            }
            return;
        }
        let th = (t - self.t0) / self.dt;
        let terms = (a.iter().zip(*b).zip(*c)).zip(d.iter().zip(*e));
        for (o, (((a, b), c), (d, e))) in out.iter_mut().zip(terms) {
            o.put(a + th * (b + th * (c + th * (d + th * e))));
        }
    }
}

/// Where `StepPoly` writes a state value: a written `f64`, or room not yet written.
pub(crate) trait Slot {
    fn put(&mut self, value: f64);
}

impl Slot for f64 {
    #[inline(always)]
    fn put(&mut self, value: f64) {
        *self = value;
    }
}

impl Slot for std::mem::MaybeUninit<f64> {
    #[inline(always)]
    fn put(&mut self, value: f64) {
        self.write(value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// For y' = 1 + 2t + 3t² + 4t³ (exact stages: Tsit45's `c`), the extension reproduces the
    /// cubic's integral to the round-off of its 14-digit coefficients, as a fourth-order dense
    /// output must (a lower order would be off by about 1e-4 here).
    #[test]
    fn reproduces_a_quartic_solution() {
        let tableau = Tableau::<f64>::tsit45();
        let f = |t: f64| 1.0 + t * (2.0 + t * (3.0 + 4.0 * t));
        let y = |t: f64| t * (1.0 + t * (1.0 + t * (1.0 + t)));
        let (t0, t1) = (0.3, 0.42);
        let mut stages = Stages::default();
        stages.begin(&[f(t0)]);
        for i in 1..STAGES {
            stages.record(&[f(t0 + tableau.c()[i] * (t1 - t0))]);
        }
        assert!(stages.end());
        let mut p = StepPoly::default();
        p.set((t0, &[y(t0)]), (t1, &[y(t1)]), &stages);
        let mut out = [0.0];
        for k in 0..=20 {
            let t = t0 + (t1 - t0) * k as f64 / 20.0;
            assert!(p.covers(t));
            p.eval(t, &mut out);
            assert!((out[0] - y(t)).abs() <= 1e-13, "{t}: {} {}", out[0], y(t));
        }
        assert!(!p.covers(t1 + 1e-9));
    }
}
