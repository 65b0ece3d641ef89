//! `Solver = "auto"`: the explicit method (Tsit45) while its steps are set by accuracy, the
//! implicit one (Esdirk34) once they are set by stability. A stiff shaft (c = 1e8 between two
//! 1e-3 kg·m² inertias) rings at 4.5e5 rad/s; the ringing dies out within milliseconds, and from
//! then on Tsit45 is held to h ≈ 3.5/ρ by its stability bound (ρ the spectral radius of the
//! mode's Jacobian) — hundreds of thousands of steps where the solution needs a few hundred.
//!
//! Detection: every `CHECK_EVERY` accepted explicit steps, ρ is estimated by power iteration
//! on Jacobian–vector products (forward differences of the right-hand side, as the implicit
//! methods use), and the mean step of that window times ρ is compared with `STIFF_HRHO`.
//! Steps set by accuracy resolve the fastest motion (h·ρ well below 1); steps at the stability
//! bound sit near 3.5 whatever the tolerance. The check only evaluates the right-hand side, so
//! a run that never switches has the explicit method's arithmetic exactly (every MSL example).
//! Once switched, the run stays implicit: its events restart the implicit method with the new
//! mode's Jacobian (`event.rs`), and it locates events on the implicit method's dense output.

use std::cell::RefCell;

use diffsol::ode_solver::OdeSolverStatistics;
use diffsol::OdeSolverMethod;
use nalgebra::Complex;

use super::integrator::{self, with_solver};
use super::{Phase, Simulation};
use crate::engine::eval::{derivative, evaluate};
use crate::error::SimError;
use crate::system::System;

/// Accepted explicit steps between two stiffness checks.
const CHECK_EVERY: usize = 100;
/// The fraction of Tsit45's stability bound (along the dominant eigenvalue) above which its
/// mean step is taken to be held by stability: such steps hover at the bound (≈ 1), steps set
/// by accuracy stay well inside it (≤ 0.5 on the MSL examples).
const STIFF_FRACTION: f64 = 0.75;
/// With fewer explicit steps than this left at the stability-bound step, the explicit method
/// finishes before the implicit one pays back its Jacobians and factorizations: HeatLosses,
/// its backlash contacts at the bound (h·ρ at 0.80 of it) with 236 steps left, ran in 8.2 ms
/// explicit and 14.5 ms switched; StiffHeatLosses switches with 5000 left, StiffShaft 6e5.
const MIN_STEPS_LEFT: f64 = 1000.0;
/// Power iterations per estimate (two right-hand sides each).
const POWER_ITERATIONS: usize = 12;

/// The counts of the solvers a run has retired (their statistics go with them).
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct Retired {
    pub(super) steps: usize,
    pub(super) rejected: usize,
    pub(super) lu_setups: usize,
}

impl Retired {
    pub(super) fn add(&mut self, s: &OdeSolverStatistics) {
        self.steps += s.number_of_steps;
        self.rejected += s.number_of_error_test_failures;
        self.lu_setups += s.number_of_linear_solver_setups;
    }
}

/// Watches the explicit steps of an "auto" run for stiffness.
pub(super) struct StiffnessWatch {
    /// Whether the run is "auto" and still explicit.
    pub(super) active: bool,
    /// Set once a check found the steps held by stability; the switch follows at the next
    /// step boundary.
    pub(super) switch_due: bool,
    pub(super) retired: Retired,
    pub(super) switches: usize,
    pub(super) steps: usize,
    pub(super) span: f64,
    x: Vec<f64>,
    v: Vec<f64>,
    w: Vec<f64>,
    u: Vec<f64>,
    f0: Vec<f64>,
}

impl StiffnessWatch {
    pub(super) fn new(auto: bool, n: usize) -> Self {
        StiffnessWatch {
            active: auto,
            switch_due: false,
            retired: Retired::default(),
            switches: 0,
            steps: 0,
            span: 0.0,
            x: vec![0.0; n],
            v: vec![0.0; n],
            w: vec![0.0; n],
            u: vec![0.0; n],
            f0: vec![0.0; n],
        }
    }

    /// The mean accepted step of the window, when a check is due.
    fn record(&mut self, h: f64) -> Option<f64> {
        if !self.active || self.switch_due {
            return None;
        }
        self.steps += 1;
        self.span += h;
        if self.steps < CHECK_EVERY {
            return None;
        }
        let mean = self.span / self.steps as f64;
        (self.steps, self.span) = (0, 0.0);
        Some(mean)
    }
}

impl StiffnessWatch {
    /// After an accepted step of length `h` ending at (t, x): count it and, when a check is
    /// due, decide whether the explicit method is held back by stability.
    pub(super) fn watch(
        &mut self,
        sys: &System,
        phase: &RefCell<Phase>,
        t: f64,
        x: &[f64],
        h: f64,
    ) {
        let Some(mean_h) = self.record(h) else {
            return;
        };
        self.x.copy_from_slice(x);
        let lambda = dominant_eigenvalue(sys, &mut phase.borrow_mut(), t, self);
        // a growing (or undamped) dominant mode is not what holds an explicit method back
        if lambda.re >= 0.0 || !lambda.norm().is_finite() {
            return;
        }
        let used = mean_h * lambda.norm() / stability_radius(lambda);
        let left = (sys.experiment.stop_time - t) / mean_h;
        self.switch_due = used > STIFF_FRACTION && left > MIN_STEPS_LEFT;
    }
}

/// The dominant eigenvalue of the current mode's Jacobian at (t, watch.x): power iteration on
/// forward-difference Jacobian–vector products, then the pair of eigenvalues of the last two
/// iterates' span (a dominant complex pair — a ringing shaft — never converges to one vector).
fn dominant_eigenvalue(
    sys: &System,
    phase: &mut Phase,
    t: f64,
    watch: &mut StiffnessWatch,
) -> Complex<f64> {
    let StiffnessWatch { x, v, w, u, f0, .. } = watch;
    let Phase {
        disc,
        mm,
        ws,
        rhs_calls,
        probe,
        horizon,
        ..
    } = phase;
    let n = x.len();
    let zero = Complex::new(0.0, 0.0);
    if n == 0 {
        return zero;
    }
    evaluate(sys, mm, disc, t, x, *horizon, ws);
    derivative(sys, ws, f0);
    *rhs_calls += 1;
    // a fixed start with no special structure, so that no eigenvector is missed by symmetry
    for (i, vi) in v.iter_mut().enumerate() {
        *vi = 1.0 + ((i as f64 + 1.0) * 0.618_033_988_75).fract();
    }
    let xnorm = norm(x);
    let eps = f64::EPSILON.sqrt() * (1.0 + xnorm);
    // w = J·v for a unit v (v is normalized in place)
    let mut jvp = |v: &mut [f64], w: &mut [f64]| -> bool {
        let vnorm = norm(v);
        if vnorm == 0.0 || !vnorm.is_finite() {
            return false;
        }
        v.iter_mut().for_each(|a| *a /= vnorm);
        for i in 0..n {
            probe[i] = x[i] + eps * v[i];
        }
        evaluate(sys, mm, disc, t, probe, *horizon, ws);
        derivative(sys, ws, w);
        *rhs_calls += 1;
        for i in 0..n {
            w[i] = (w[i] - f0[i]) / eps;
        }
        true
    };
    for _ in 0..POWER_ITERATIONS {
        if !jvp(v, w) {
            return zero;
        }
        v.copy_from_slice(w);
    }
    // u0 = v (unit), u1 = J·u0, u2 = J·u1 / |u1| scaled back: fit u2 ≈ a·u1 + b·u0
    if !jvp(v, w) {
        return zero;
    }
    u.copy_from_slice(w); // u1 = J·u0
    let scale = norm(u);
    if !jvp(u, w) {
        return zero;
    }
    // now u = u1/|u1| and w = J·u; bring both back to u1 and J·u1
    u.iter_mut().for_each(|a| *a *= scale);
    w.iter_mut().for_each(|a| *a *= scale);
    pair_from_span(v, u, w)
}

/// The larger-magnitude root of λ² = a·λ + b, with a, b the least-squares fit of
/// u2 ≈ a·u1 + b·u0 (u1 = J·u0, u2 = J·u1).
fn pair_from_span(u0: &[f64], u1: &[f64], u2: &[f64]) -> Complex<f64> {
    let dot = |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(a, b)| a * b).sum::<f64>();
    let (g11, g10, g00) = (dot(u1, u1), dot(u1, u0), dot(u0, u0));
    let (r1, r0) = (dot(u1, u2), dot(u0, u2));
    let det = g11 * g00 - g10 * g10;
    if det <= 1e-12 * g11 * g00 {
        // u1 ∥ u0: a real dominant eigenvalue, converged
        return Complex::new(g10 / g00, 0.0);
    }
    let a = (r1 * g00 - r0 * g10) / det;
    let b = (g11 * r0 - g10 * r1) / det;
    let disc = a * a + 4.0 * b;
    if disc >= 0.0 {
        let root = disc.sqrt();
        let (p, q) = ((a + root) / 2.0, (a - root) / 2.0);
        Complex::new(if p.abs() >= q.abs() { p } else { q }, 0.0)
    } else {
        Complex::new(a / 2.0, (-disc).sqrt() / 2.0)
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Tsit45's stability function: the Taylor polynomial of eᶻ to order 5 plus b·A⁵·1 z⁶ (from
/// diffsol's tableau).
fn tsit45_stability(z: Complex<f64>) -> Complex<f64> {
    const COEFFS: [f64; 7] = [
        1.0,
        1.0,
        0.5,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        0.001_432_211_324_807_347_1,
    ];
    COEFFS
        .iter()
        .rev()
        .fold(Complex::new(0.0, 0.0), |acc, &c| acc * z + c)
}

/// How far Tsit45 can step along the direction of `lambda` before it amplifies that mode:
/// the first r (in steps of 0.01) with |R(r·λ/|λ|)| > 1 + 1e-3 (the tolerance keeps the
/// negligible growth of a purely imaginary eigenvalue at small r from counting). About 3.5 on
/// the negative real axis, 1.45 for the lightly damped ringing of a stiff shaft.
fn stability_radius(lambda: Complex<f64>) -> f64 {
    let direction = lambda / lambda.norm();
    (1..=600)
        .map(|k| k as f64 * 0.01)
        .find(|&r| tsit45_stability(direction * r).norm() > 1.0 + 1e-3)
        .unwrap_or(6.0)
}

impl Simulation {
    /// Solver = "auto": the explicit method is held back by stability, so the run continues
    /// with Esdirk34 from where it stands (between two steps), starting from the explicit
    /// method's last step size.
    pub(super) fn switch_to_implicit(&mut self) -> Result<(), SimError> {
        const METHOD: &str = "esdirk34";
        let Simulation { cell, stepper, .. } = self;
        let h = cell.with_dependent_mut(|_, integ| {
            with_solver!(integ, s => {
                stepper.stiffness.retired.add(s.get_statistics());
                s.state().h
            })
        });
        // a problem of its own: diffsol keeps the step-size controller's gain there
        let (t, sys) = (stepper.t_prev, &stepper.sys);
        let tolerance = sys.experiment.tolerance;
        let problem =
            integrator::problem(sys, &stepper.phase, t, stepper.x.clone(), tolerance, METHOD)?;
        *cell = integrator::integrator(problem, METHOD)?;
        cell.with_dependent_mut(|_, integ| {
            stepper.stage_dense = integ.polynomial_dense_output(); // its own dense output
            let watch = &mut stepper.stiffness;
            (watch.active, watch.switch_due) = (false, false);
            watch.switches += 1;
            let order = integ.order();
            with_solver!(integ, s => {
                stepper.restart_at(s, t, order, true, false)?;
                *s.state_mut().h = h;
                Ok(())
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stability_radius_of_tsit45_matches_its_tableau() {
        // negative real axis: the known bound of Tsitouras 5(4), about 3.5
        let real = stability_radius(Complex::new(-1.0, 0.0));
        assert!((real - 3.5).abs() < 0.05, "{real}");
        // a lightly damped oscillation has a much shorter bound
        let ringing = stability_radius(Complex::new(-0.0022, 1.0));
        assert!(ringing > 1.0 && ringing < 2.0, "{ringing}");
        // |R(z)| equals |e^z| to order 5 near 0
        let z = Complex::new(-0.1, 0.05);
        assert!((tsit45_stability(z) - z.exp()).norm() < 1e-7);
    }

    #[test]
    fn a_complex_pair_is_recovered_from_the_span_of_two_iterates() {
        // J = [[-1, -100], [100, -1]]: eigenvalues -1 ± 100i
        let j = |u: &[f64]| vec![-u[0] - 100.0 * u[1], 100.0 * u[0] - u[1]];
        let u0 = vec![0.3, 0.9];
        let u1 = j(&u0);
        let u2 = j(&u1);
        let lambda = pair_from_span(&u0, &u1, &u2);
        assert!((lambda.re + 1.0).abs() < 1e-9 && (lambda.im.abs() - 100.0).abs() < 1e-9);
        // a real dominant eigenvalue converged: u1 ∥ u0
        let lambda = pair_from_span(&[1.0, 0.0], &[-5.0, 0.0], &[25.0, 0.0]);
        assert!((lambda.re + 5.0).abs() < 1e-12 && lambda.im == 0.0);
    }
}
