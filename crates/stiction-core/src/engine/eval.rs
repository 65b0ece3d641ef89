//! One evaluation of the hybrid system at (t, x) for a given discrete state: signals, torques of
//! the force laws and of sliding friction, the per-mode linear solve, friction quantities (`sa`,
//! `tau0_max`, …), heat flows and the state derivatives. The integrator, the zero-crossing
//! functions, the event iteration and the result rows all read this one workspace.

use nalgebra::DVector;

use super::kkt::ModeMatrix;
use crate::switching::friction::FrictionState;
use crate::switching::logic;
use crate::switching::lossy_gear::{GearMode, GearState, Losses};
use crate::system::{EnergyRole, LawCtx, System};

/// Discrete state between events: friction and gear states, the frozen relations of laws, and
/// the values of the model inputs (they change only at events, through `set_input`).
#[derive(Debug, Clone, PartialEq)]
pub struct DiscreteState {
    pub friction: Vec<FrictionState>,
    pub gears: Vec<GearState>,
    pub relations: Vec<bool>,
    pub inputs: Vec<f64>,
}

impl DiscreteState {
    /// The `pre()` start values of every element and the inputs' start values.
    pub fn initial(sys: &System) -> Self {
        DiscreteState {
            friction: sys.frictions.iter().map(FrictionState::initial).collect(),
            gears: vec![GearState::INITIAL; sys.lossy_gears.len()],
            relations: vec![false; sys.relation_count],
            inputs: sys.inputs.iter().map(|i| i.start).collect(),
        }
    }

    /// Whether this state has the shape of `sys`'s.
    pub fn fits(&self, sys: &System) -> bool {
        self.friction.len() == sys.frictions.len()
            && self.gears.len() == sys.lossy_gears.len()
            && self.relations.len() == sys.relation_count
            && self.inputs.len() == sys.inputs.len()
    }

    pub fn locked_set(&self) -> Vec<bool> {
        self.friction.iter().map(|f| f.locked).collect()
    }

    /// How each LossyGear enters the linear system, with its losses at rest: the key of the
    /// factored mode (exact unless the loss table depends on the speed).
    pub fn gear_modes(&self, sys: &System) -> Vec<GearMode> {
        sys.lossy_gears
            .iter()
            .zip(&self.gears)
            .map(|(g, st)| g.mode_in(st, &g.losses_at_rest()))
            .collect()
    }
}

/// Values of one LossyGear at an instant.
#[derive(Debug, Clone, Copy, Default)]
pub struct GearValues {
    pub tau_a: f64,
    pub tau_b: f64,
    pub tau_support: f64,
    pub w: f64,
    pub a: f64,
    pub sa: f64,
    pub tau_loss: f64,
    pub tau_eta: f64,
    pub losses: Losses,
    /// `c1` of the rolling loss line at this speed.
    pub slope: f64,
    pub loss_max_p: f64,
    pub loss_min_m: f64,
    pub loss: f64,
    /// The mode's rows hold this gear's speed fixed.
    pub held: bool,
}

#[derive(Debug, Clone, Copy, Default)]
pub struct FrictionValues {
    pub phi: f64,
    pub w: f64,
    pub a: f64,
    pub fn_: f64,
    pub tau0: f64,
    pub tau0_max: f64,
    pub tau: f64,
    pub mu: f64,
    pub sa: f64,
    pub loss: f64,
    /// The mode's rows hold this element's relative speed fixed.
    pub held: bool,
}

/// Everything known at one instant. Allocated once per run and reused.
pub struct Workspace {
    pub t: f64,
    pub horizon: f64,
    pub phi: Vec<f64>,
    pub w: Vec<f64>,
    pub a: Vec<f64>,
    pub signals: Vec<f64>,
    pub law_phi: Vec<f64>,
    pub law_w: Vec<f64>,
    pub law_tau: Vec<f64>,
    pub constraint_tau: Vec<f64>,
    pub friction: Vec<FrictionValues>,
    pub gears: Vec<GearValues>,
    pub heat_in: Vec<f64>,
    pub temps: Vec<f64>,
    pub heat_net: Vec<f64>,
    /// Kinetic, potential, dissipated energy and work of the sources.
    pub energy: [f64; 4],
    /// Rates of the last two: dissipated power and source power.
    pub rates: (f64, f64),
    rhs: DVector<f64>,
    pub rhs_evals: usize,
}

impl Workspace {
    pub fn new(sys: &System) -> Self {
        let n = sys.nodes;
        Self {
            t: 0.0,
            horizon: f64::INFINITY,
            phi: vec![0.0; n],
            w: vec![0.0; n],
            a: vec![0.0; n],
            signals: vec![0.0; sys.signals.slots],
            law_phi: vec![0.0; sys.laws.len()],
            law_w: vec![0.0; sys.laws.len()],
            law_tau: vec![0.0; sys.laws.len()],
            constraint_tau: vec![0.0; sys.constraints.len()],
            friction: vec![FrictionValues::default(); sys.frictions.len()],
            gears: vec![GearValues::default(); sys.lossy_gears.len()],
            heat_in: vec![0.0; sys.thermal.nodes],
            temps: vec![0.0; sys.thermal.nodes],
            heat_net: vec![0.0; sys.thermal.nodes],
            energy: [0.0; 4],
            rates: (0.0, 0.0),
            rhs: DVector::zeros(0),
            rhs_evals: 0,
        }
    }

    pub fn law_ctx<'a>(&'a self, sys: &System, disc: &'a DiscreteState, k: usize) -> LawCtx<'a> {
        let law = &sys.laws[k];
        let base = law.relation_base;
        LawCtx {
            t: self.t,
            horizon: self.horizon,
            phi_rel: self.law_phi[k],
            w_rel: self.law_w[k],
            signals: &self.signals,
            relations: &disc.relations[base..base + law.law.relation_count()],
        }
    }
}

/// Offsets of the parts of the continuous state vector.
pub struct Layout {
    pub nodes: usize,
    pub caps: usize,
}

impl Layout {
    pub fn of(sys: &System) -> Self {
        Self {
            nodes: sys.nodes,
            caps: sys.thermal.capacities.len(),
        }
    }
    pub fn w(&self) -> usize {
        self.nodes
    }
    pub fn temps(&self) -> usize {
        2 * self.nodes
    }
    pub fn loss(&self) -> usize {
        2 * self.nodes + self.caps
    }
    pub fn work(&self) -> usize {
        self.loss() + 1
    }
}

/// What needs no linear solve: node angles and speeds, signals (the model inputs' values from
/// the discrete state), the laws' relative coordinates (enough for the relations the event
/// iteration evaluates literally).
pub fn kinematics(
    sys: &System,
    disc: &DiscreteState,
    t: f64,
    x: &[f64],
    horizon: f64,
    ws: &mut Workspace,
) {
    let n = sys.nodes;
    ws.t = t;
    ws.horizon = horizon;
    ws.phi.copy_from_slice(&x[..n]);
    ws.w.copy_from_slice(&x[n..2 * n]);
    for (input, value) in sys.inputs.iter().zip(&disc.inputs) {
        ws.signals[input.slot] = *value;
    }
    sys.signals.eval(t, horizon, &mut ws.signals);
    for (k, law) in sys.laws.iter().enumerate() {
        ws.law_phi[k] = law.rel.angle(&ws.phi);
        ws.law_w[k] = law.rel.dot(&ws.w);
    }
}

/// Evaluates everything at (t, x) in discrete state `disc`, whose mode `mm` was factored for.
/// (A LossyGear whose losses depend on its speed gets a matrix factored for this instant.)
pub fn evaluate(
    sys: &System,
    mm: &ModeMatrix,
    disc: &DiscreteState,
    t: f64,
    x: &[f64],
    horizon: f64,
    ws: &mut Workspace,
) {
    let lay = Layout::of(sys);
    let n = sys.nodes;
    ws.rhs_evals += 1;
    kinematics(sys, disc, t, x, horizon, ws);

    // LossyGears: losses at the current speed (their slopes enter the solve below).
    for (k, g) in sys.lossy_gears.iter().enumerate() {
        let v = &mut ws.gears[k];
        v.w = g.lock_row.dot(&ws.w);
        v.losses = g.losses(v.w);
        v.slope = g.mode_in(&disc.gears[k], &v.losses).c1;
    }

    // Generalized forces of laws and sliding friction.
    let m = sys.constraints.len();
    let size = mm.size;
    let mut rhs = std::mem::replace(&mut ws.rhs, DVector::zeros(0));
    if rhs.len() != size {
        rhs = DVector::zeros(size);
    }
    rhs.fill(0.0);
    let f = rhs.as_mut_slice();
    for (k, law) in sys.laws.iter().enumerate() {
        ws.law_phi[k] = law.rel.angle(&ws.phi);
        ws.law_w[k] = law.rel.dot(&ws.w);
        let tau = law.law.tau(&ws.law_ctx(sys, disc, k));
        ws.law_tau[k] = tau;
        law.rel.apply(tau, &mut f[..n]);
    }
    for (k, fe) in sys.frictions.iter().enumerate() {
        let st = &disc.friction[k];
        let v = &mut ws.friction[k];
        v.phi = fe.rel.angle(&ws.phi);
        v.w = fe.rel.dot(&ws.w);
        v.fn_ = fe.reported_normal_force(&ws.signals, st.free);
        (v.tau0, v.tau0_max) = fe.limits(v.fn_, st.free);
        let (mu, tau) = fe.sliding(
            v.w,
            v.fn_,
            st.pre.mode,
            st.pre.start_forward,
            st.pre.start_backward,
        );
        v.mu = mu;
        v.tau = if st.free { 0.0 } else { tau };
        if !st.locked {
            fe.rel.apply(v.tau, &mut f[..n]);
        }
    }
    // A rolling gear's constant loss part c0 acts through ℓ.
    for (k, g) in sys.lossy_gears.iter().enumerate() {
        let st = &disc.gears[k];
        if !g.ideal && !st.locked {
            let (_, c0) = g.rolling_line(st, &ws.gears[k].losses);
            g.loss_col.apply(c0, &mut f[..n]);
        }
    }
    if sys.lossy_gears.is_empty() {
        mm.solve(&mut rhs);
    } else {
        let gears = &ws.gears;
        mm.solve_with_gear_slopes(sys, |k| gears[k].slope, &mut rhs);
    }
    ws.a.copy_from_slice(&rhs.as_slice()[..n]);
    ws.constraint_tau.copy_from_slice(&rhs.as_slice()[n..n + m]);
    for (k, row) in mm.friction_row.iter().enumerate() {
        if disc.friction[k].locked {
            // a locked element whose row depends on others carries no torque
            ws.friction[k].tau = row.map_or(0.0, |r| rhs[n + r]);
        }
    }
    for (k, g) in sys.lossy_gears.iter().enumerate() {
        let st = &disc.gears[k];
        let v = &mut ws.gears[k];
        v.tau_a = rhs[n + mm.gear_row[k]];
        v.held = mm.gear_held[k];
        v.a = g.lock_row.dot(&ws.a);
        v.tau_loss = if g.ideal {
            0.0
        } else if st.locked {
            mm.gear_lock_row[k].map_or(0.0, |r| rhs[n + r])
        } else {
            let (c1, c0) = g.rolling_line(st, &v.losses);
            c1 * v.tau_a + c0
        };
        v.sa = if st.locked {
            v.tau_loss
        } else {
            v.a + v.tau_loss
        };
        v.tau_b = -g.ratio * (v.tau_a - v.tau_loss);
        v.tau_support = -v.tau_a - v.tau_b;
        v.tau_eta = g.tau_eta(st, v.tau_a, v.losses.tbf_a);
        (v.loss_max_p, v.loss_min_m) = g.rest_limits(v.tau_a);
        v.loss = v.tau_loss * v.w;
    }
    ws.rhs = rhs;

    for (k, fe) in sys.frictions.iter().enumerate() {
        let st = &disc.friction[k];
        let v = &mut ws.friction[k];
        v.a = fe.rel.dot(&ws.a);
        v.held = mm.friction_held[k];
        v.sa = if st.locked {
            v.tau
        } else {
            fe.sa_from_accel(st.free, st.pre, v.a, v.tau0, v.tau0_max)
        };
        // A OneWayClutch dissipates nothing while stuck (spec §10.8).
        let stuck_one_way = fe.one_way.is_some() && st.pre.mode == logic::STUCK;
        v.loss = if stuck_one_way { 0.0 } else { v.tau * v.w };
    }

    // Heat and energy.
    ws.heat_in.iter_mut().for_each(|q| *q = 0.0);
    let (mut loss, mut work, mut potential) = (0.0, 0.0, 0.0);
    for (k, law) in sys.laws.iter().enumerate() {
        let ctx = ws.law_ctx(sys, disc, k);
        match law.law.role() {
            EnergyRole::Source => work -= ws.law_tau[k] * ws.law_w[k],
            _ => {
                loss += law.law.dissipation(&ctx, ws.law_tau[k]);
                potential += law.law.potential(&ctx);
            }
        }
        if let Some(node) = law.heat_node {
            ws.heat_in[node] += law.law.loss_power(&ctx, ws.law_tau[k]);
        }
    }
    for (k, fe) in sys.frictions.iter().enumerate() {
        loss += ws.friction[k].loss;
        if let Some(node) = fe.heat_node {
            ws.heat_in[node] += ws.friction[k].loss;
        }
    }
    for (g, v) in sys.lossy_gears.iter().zip(&ws.gears) {
        loss += v.loss;
        if let Some(node) = g.heat_node {
            ws.heat_in[node] += v.loss;
        }
    }
    for (c, tau) in sys.constraints.iter().zip(&ws.constraint_tau) {
        if c.does_work {
            work -= tau * c.rel.dot(&ws.w);
        }
    }
    let kinetic: f64 = (0..n).map(|i| 0.5 * sys.mass[i] * ws.w[i] * ws.w[i]).sum();
    ws.energy = [kinetic, potential, x[lay.loss()], x[lay.work()]];
    if sys.thermal.nodes > 0 {
        sys.thermal.temperatures(
            &x[lay.temps()..lay.loss()],
            &ws.signals,
            &ws.heat_in,
            &mut ws.temps,
        );
        sys.thermal
            .net_inflow(&ws.temps, &ws.signals, &ws.heat_in, &mut ws.heat_net);
    }
    ws.rates = (loss, work);
}

/// The state derivative after `evaluate`.
pub fn derivative(sys: &System, ws: &Workspace, dx: &mut [f64]) {
    let lay = Layout::of(sys);
    let n = sys.nodes;
    dx[..n].copy_from_slice(&ws.w);
    dx[n..2 * n].copy_from_slice(&ws.a);
    for (k, cap) in sys.thermal.capacities.iter().enumerate() {
        dx[lay.temps() + k] = ws.heat_net[cap.node] / cap.c;
    }
    dx[lay.loss()] = ws.rates.0;
    dx[lay.work()] = ws.rates.1;
}
