//! The ODE integrator (diffsol) as one object a `Simulation` owns across calls: the problem
//! (right-hand side, Jacobian-vector product, initial state) and the solver that borrows it,
//! kept alive together so that a run advanced in pieces continues the very same steps.

use std::cell::RefCell;
use std::rc::Rc;

use diffsol::{
    Bdf, Closure, ConstantClosure, ExplicitRk, NalgebraLU, NalgebraMat, NalgebraVec, OdeBuilder,
    OdeSolverEquations, OdeSolverMethod, OdeSolverProblem, Sdirk, UnitCallable,
};
use self_cell::self_cell;

use super::Phase;
use crate::engine::eval::{derivative, evaluate, Layout};
use crate::error::SimError;
use crate::system::System;

pub type M = NalgebraMat<f64>;
pub type V = NalgebraVec<f64>;
pub type LS = NalgebraLU<f64>;

type RhsFn = Box<dyn Fn(&[f64], &[f64], f64, &mut [f64])>;
type JacFn = Box<dyn Fn(&[f64], &[f64], f64, &[f64], &mut [f64])>;
type InitFn = Box<dyn Fn(&[f64], f64, &mut [f64])>;

/// The equations as diffsol sees them: closures over the run's current `Phase`.
pub type Eqn = OdeSolverEquations<
    M,
    Closure<M, RhsFn, JacFn>,
    ConstantClosure<M, InitFn>,
    UnitCallable<M>,
    UnitCallable<M>,
    UnitCallable<M>,
>;
pub type Problem = OdeSolverProblem<Eqn>;

/// diffsol counts nonlinear-solver failures over the whole run against a limit it documents
/// as per solve (50), so a long stiff run fails on the 51st failure however far apart they
/// are. Before each step the limit is moved to the count so far plus this many.
const NEWTON_FAILS_PER_STEP: usize = 50;

/// The step-size controller's integral gain for Tsit45 (diffsol's default 0.5: the step chosen
/// so that the next error estimate equals the tolerance, dead-beat). After an event restart,
/// 0.5 and growth up to 2× overshot and were rejected on 18 of CoupledClutches' 96 attempts;
/// 0.3 and growth up to 5× reject 4 (528 right-hand sides instead of 600, SimpleGearShift 238
/// instead of 340).
const EXPLICIT_STEP_GAIN: f64 = 0.3;
/// The implicit methods keep diffsol's dead-beat gain: with 0.3, StiffHeatLosses under "auto"
/// took 2067 steps instead of 1608 (15.5 ms instead of 13.5) and StiffShaft 8582 instead of
/// 7713. diffsol keeps the gain in the problem, so a change of method builds a new problem.
const IMPLICIT_STEP_GAIN: f64 = 0.5;
/// The most Tsit45's step may grow from one step to the next (diffsol's default 2).
const TSIT45_MAX_GROWTH: f64 = 5.0;

/// What a method needs renewed before each step.
pub trait StepBudget {
    fn renew_budget(&mut self) {}
    /// Keeps the next step at most `h_max` long (`stepper::max_step`).
    fn limit_step(&mut self, h_max: f64);
}

/// The Runge–Kutta methods take a new step size as it is.
fn limit_rk_step<'a, S: OdeSolverMethod<'a, Eqn>>(solver: &mut S, h_max: f64) {
    if solver.state().h > h_max {
        *solver.state_mut().h = h_max;
    }
}

impl StepBudget for ExplicitRk<'_, Eqn> {
    fn limit_step(&mut self, h_max: f64) {
        limit_rk_step(self, h_max);
    }
}

impl StepBudget for Bdf<'_, Eqn, LS> {
    fn renew_budget(&mut self) {
        let failures = self.get_statistics().number_of_nonlinear_solver_fails;
        self.config_mut().maximum_newton_fails = failures + NEWTON_FAILS_PER_STEP;
    }
    /// Not limited: diffsol's BDF restarts at first order whenever its state is touched, which
    /// would hold it at tiny steps for ever.
    fn limit_step(&mut self, _h_max: f64) {}
}

impl StepBudget for Sdirk<'_, Eqn, LS> {
    fn renew_budget(&mut self) {
        let failures = self.get_statistics().number_of_nonlinear_solver_fails;
        self.config_mut().maximum_newton_fails = failures + NEWTON_FAILS_PER_STEP;
    }
    fn limit_step(&mut self, h_max: f64) {
        limit_rk_step(self, h_max);
    }
}

/// The integration methods offered through the experiment's `Solver` setting ("auto" starts
/// with Tsit45 and may change to Esdirk34 during the run, `simulation/auto.rs`).
pub enum Integrator<'a> {
    Tsit45(Box<ExplicitRk<'a, Eqn>>),
    Bdf(Box<Bdf<'a, Eqn, LS>>),
    Esdirk34(Box<Sdirk<'a, Eqn, LS>>),
}

impl Integrator<'_> {
    /// The order used to pick a restart step size.
    pub fn order(&self) -> usize {
        match self {
            Integrator::Tsit45(_) => 4,
            Integrator::Bdf(_) => 1,
            Integrator::Esdirk34(_) => 3,
        }
    }

    /// Whether the dense output is tsit45's quartic, formed from the stages (`dense.rs`).
    pub fn polynomial_dense_output(&self) -> bool {
        matches!(self, Integrator::Tsit45(_))
    }

    pub fn implicit(&self) -> bool {
        !matches!(self, Integrator::Tsit45(_))
    }
}

self_cell!(
    /// The problem and the solver that borrows it (diffsol's solvers hold `&Problem`).
    pub struct IntegratorCell {
        owner: Problem,
        #[not_covariant]
        dependent: Integrator,
    }
);

/// Runs `$body` with `$s` bound to the concrete solver inside an `Integrator`.
macro_rules! with_solver {
    ($integrator:expr, $s:ident => $body:expr) => {
        match $integrator {
            $crate::simulation::integrator::Integrator::Tsit45(boxed) => {
                let $s = &mut **boxed;
                $body
            }
            $crate::simulation::integrator::Integrator::Bdf(boxed) => {
                let $s = &mut **boxed;
                $body
            }
            $crate::simulation::integrator::Integrator::Esdirk34(boxed) => {
                let $s = &mut **boxed;
                $body
            }
        }
    };
}
pub(crate) use with_solver;

pub fn integrator_error(time: f64, e: impl std::fmt::Display) -> SimError {
    SimError::Integrator {
        time,
        message: e.to_string(),
    }
}

/// The problem of a run by `method` (its step-size controller's gain): `dx/dt` from one evaluation of the phase's system (a parameter change swaps it,
/// `tune.rs`), and a Jacobian-vector product by forward differences for the implicit methods.
pub fn problem(
    sys: &std::sync::Arc<System>,
    phase: &Rc<RefCell<Phase>>,
    t0: f64,
    x0: Vec<f64>,
    tolerance: f64,
    method: &str,
) -> Result<Problem, SimError> {
    let n = x0.len();
    debug_assert!(std::sync::Arc::ptr_eq(sys, &phase.borrow().sys));
    let ph = phase.clone();
    let rhs: RhsFn = Box::new(move |x, _p, t, y| {
        let mut guard = ph.borrow_mut();
        let Phase {
            sys: sy,
            disc,
            mm,
            ws,
            rhs_calls,
            horizon,
            stages,
            ..
        } = &mut *guard;
        *rhs_calls += 1;
        evaluate(sy, mm, disc, t, x, *horizon, ws);
        derivative(sy, ws, y);
        stages.record(y);
        guard.evaluated_at(t, x);
    });
    let ph = phase.clone();
    // Not merged with `rhs` above: each closure borrows the fields of the phase it uses (the
    // Jacobian product needs its probe and the f0 cache besides).
    let jac_vec: JacFn = Box::new(move |x, _p, t, v, y| {
        let mut guard = ph.borrow_mut();
        let Phase {
            sys: sy,
            disc,
            mm,
            ws,
            rhs_calls,
            probe,
            f0,
            f0_t,
            f0_x,
            jacobians,
            horizon,
            ..
        } = &mut *guard;
        let horizon = *horizon;
        let vnorm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        if vnorm == 0.0 {
            y.fill(0.0);
            return;
        }
        let xnorm = x.iter().map(|a| a * a).sum::<f64>().sqrt();
        let eps = f64::EPSILON.sqrt() * (1.0 + xnorm) / vnorm;
        if !(*f0_t == t && f0_x[..] == x[..]) {
            *jacobians += 1;
            *rhs_calls += 1;
            evaluate(sy, mm, disc, t, x, horizon, ws);
            derivative(sy, ws, f0);
            *f0_t = t;
            f0_x.copy_from_slice(x);
        }
        *rhs_calls += 1;
        for i in 0..x.len() {
            probe[i] = x[i] + eps * v[i];
        }
        evaluate(sy, mm, disc, t, probe, horizon, ws);
        derivative(sy, ws, y);
        for i in 0..y.len() {
            y[i] = (y[i] - f0[i]) / eps;
        }
    });
    let init: InitFn = Box::new(move |_p, _t, y| y.copy_from_slice(&x0));
    let mut p = OdeBuilder::<M>::new()
        .t0(t0)
        .rtol(tolerance)
        .atol(absolute_tolerance(sys, tolerance))
        .rhs_implicit(rhs, jac_vec)
        .init(init, n)
        .build()
        .map_err(|e| integrator_error(t0, e))?;
    p.ode_options.pi_control_integral = match method {
        "bdf" | "esdirk34" => IMPLICIT_STEP_GAIN,
        _ => EXPLICIT_STEP_GAIN,
    };
    Ok(p)
}

/// The absolute tolerance of each state, as Dymola's DASSL scales it: Tolerance·nominal, where
/// a start value's `nominal` tightens every state its variable is made of (the angles of a
/// `phi_rel`'s nodes, the speeds of a `w_rel`'s, a capacity's temperature). One value for all
/// states when no nominal is given, so such runs stay as they were bit for bit.
pub fn absolute_tolerance(sys: &System, tolerance: f64) -> Vec<f64> {
    let nodes = sys.nodes;
    let angles = sys.init_phi.iter().map(|eq| (0, eq));
    let speeds = sys.init_w.iter().map(|eq| (nodes, eq));
    let scaled = (angles.chain(speeds)).filter(|(_, eq)| eq.value.nominal != 1.0);
    let capacities = sys.thermal.capacities.iter().enumerate();
    let warm = capacities.filter(|(_, c)| c.init.nominal != 1.0);
    let mut atol = vec![tolerance];
    for (base, eq) in scaled {
        for &(node, _) in &eq.rel.terms {
            tighten(&mut atol, sys, base + node, tolerance * eq.value.nominal);
        }
    }
    for (k, capacity) in warm {
        tighten(
            &mut atol,
            sys,
            2 * nodes + k,
            tolerance * capacity.init.nominal,
        );
    }
    // a worn volume is on its own scale (cubic millimetres and less)
    let worn = Layout::of(sys).wear();
    for (k, wear) in sys.wear.iter().enumerate() {
        tighten(&mut atol, sys, worn + k, tolerance * wear.nominal);
    }
    atol
}

/// `atol[state] = min(atol[state], value)`, first spreading the single value over all states.
fn tighten(atol: &mut Vec<f64>, sys: &System, state: usize, value: f64) {
    if atol.len() == 1 {
        *atol = vec![atol[0]; sys.state_len()];
    }
    atol[state] = atol[state].min(value);
}

/// The problem with a fresh solver of the named method ("auto" starts explicit).
pub fn integrator(problem: Problem, method: &str) -> Result<IntegratorCell, SimError> {
    IntegratorCell::try_new(problem, |p| solver_for(p, method))
}

/// A fresh solver of the named method over `p`, at the problem's start.
pub fn solver_for<'a>(p: &'a Problem, method: &str) -> Result<Integrator<'a>, SimError> {
    let t0 = p.t0;
    Ok(match method {
        "bdf" => Integrator::Bdf(Box::new(
            p.bdf::<LS>().map_err(|e| integrator_error(t0, e))?,
        )),
        "esdirk34" => Integrator::Esdirk34(Box::new(
            p.esdirk34::<LS>().map_err(|e| integrator_error(t0, e))?,
        )),
        _ => {
            let mut tsit45 = p.tsit45().map_err(|e| integrator_error(t0, e))?;
            tsit45.config_mut().maximum_timestep_growth = TSIT45_MAX_GROWTH;
            Integrator::Tsit45(Box::new(tsit45))
        }
    })
}
