//! One evaluation of the hybrid system at (t, x) for a given discrete state: signals, torques of
//! the force laws and of sliding friction, the per-mode linear solve, friction quantities (`sa`,
//! `tau0_max`, …), heat flows and the state derivatives. The integrator, the zero-crossing
//! functions, the event iteration and the result rows all read this one workspace.

use nalgebra::{DMatrix, DVector};

use super::kkt::ModeMatrix;
use super::massless::Massless;
use crate::signals::{Mechanics, StagePart};
use crate::switching::element::{
    angle_and_speed, ElementValues, Kinematics, ModeKey, Solved, SwitchState,
};
use crate::switching::logic::STUCK;
use crate::system::{EnergyRole, LawCtx, System};
use crate::thermal::HeatCache;

/// Discrete state between events: the switching elements' states, the frozen relations of
/// laws, and the values of the model inputs (they change only at events, through `set_input`).
#[derive(Debug, Clone, PartialEq)]
pub struct DiscreteState {
    pub switching: Vec<SwitchState>,
    pub relations: Vec<bool>,
    pub inputs: Vec<f64>,
}

impl DiscreteState {
    /// The `pre()` start values of every element and the inputs' start values.
    pub fn initial(sys: &System) -> Self {
        DiscreteState {
            switching: sys.switching.iter().map(|e| e.initial_state()).collect(),
            relations: vec![false; sys.relation_count],
            inputs: sys.inputs.iter().map(|i| i.start).collect(),
        }
    }

    /// Whether this state has the shape of `sys`'s.
    pub fn fits(&self, sys: &System) -> bool {
        self.switching.len() == sys.switching.len()
            && self.relations.len() == sys.relation_count
            && self.inputs.len() == sys.inputs.len()
    }

    /// How each switching element enters the linear system (the key of the factored mode),
    /// into `keys`.
    pub fn mode_keys(&self, sys: &System, keys: &mut Vec<ModeKey>) {
        keys.clear();
        keys.extend((sys.switching.iter().zip(&self.switching)).map(|(e, st)| e.mode_key(st)));
    }
}

/// Everything known at one instant. Allocated once per run and reused.
pub struct Workspace {
    pub t: f64,
    pub horizon: f64,
    pub phi: Vec<f64>,
    pub w: Vec<f64>,
    pub a: Vec<f64>,
    pub signals: Vec<f64>,
    /// The (t, horizon) bits `signals` were evaluated at (`update_signals`).
    signals_at: Option<(u64, u64)>,
    pub law_phi: Vec<f64>,
    pub law_w: Vec<f64>,
    pub law_tau: Vec<f64>,
    /// The loss power of each law with a heat port (what it puts into its heat node), as
    /// `heat_and_energy` computed it; 0 for the other laws, whose loss nothing here needs.
    pub law_loss: Vec<f64>,
    pub constraint_tau: Vec<f64>,
    /// The values of each switching element.
    pub elements: Vec<ElementValues>,
    pub heat_in: Vec<f64>,
    /// Each switching element's heat node (None for all without a heat network), asked once
    /// here instead of by a virtual call per element and evaluation.
    element_heat: Vec<Option<usize>>,
    pub temps: Vec<f64>,
    pub heat_net: Vec<f64>,
    heat_cache: HeatCache,
    /// Kinetic, potential, dissipated energy and work of the sources.
    pub energy: [f64; 4],
    /// Rates of the last two: dissipated power and source power.
    pub rates: (f64, f64),
    /// The worn volumes (`System::wear`), from the state, and their rates: 0 while the
    /// element is locked (its slip then only the event band's round-off).
    pub wear: Vec<f64>,
    wear_rates: Vec<f64>,
    rhs: Vec<f64>,
    pub rhs_evals: usize,
    /// The count of evaluations (`rhs_evals`) at which the event iteration left the
    /// workspace holding `evaluate_switching` of the discrete state it settled on, at the
    /// event's state (`iterate`): the right row's evaluation then needs only the rest.
    pub settled_at: Option<usize>,
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
            signals_at: None,
            law_phi: vec![0.0; sys.laws.len()],
            law_w: vec![0.0; sys.laws.len()],
            law_tau: vec![0.0; sys.laws.len()],
            law_loss: vec![0.0; sys.laws.len()],
            constraint_tau: vec![0.0; sys.constraints.len()],
            elements: vec![ElementValues::default(); sys.switching.len()],
            heat_in: vec![0.0; sys.thermal.nodes],
            element_heat: (sys.switching.iter())
                .map(|e| (sys.thermal.nodes > 0).then(|| e.heat_node()).flatten())
                .collect(),
            temps: vec![0.0; sys.thermal.nodes],
            heat_net: vec![0.0; sys.thermal.nodes],
            heat_cache: HeatCache::default(),
            energy: [0.0; 4],
            rates: (0.0, 0.0),
            wear: vec![0.0; sys.wear.len()],
            wear_rates: vec![0.0; sys.wear.len()],
            rhs: Vec::new(),
            rhs_evals: 0,
            settled_at: None,
        }
    }

    #[inline]
    pub fn law_ctx<'a>(&'a self, sys: &System, disc: &'a DiscreteState, k: usize) -> LawCtx<'a> {
        let (law, phi_rel, w_rel) = (&sys.laws[k], self.law_phi[k], self.law_w[k]);
        law.view(
            (self.t, self.horizon),
            (phi_rel, w_rel),
            &self.signals,
            &disc.relations,
        )
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
    pub fn temps(&self) -> usize {
        2 * self.nodes
    }
    pub fn loss(&self) -> usize {
        2 * self.nodes + self.caps
    }
    pub fn work(&self) -> usize {
        self.loss() + 1
    }
    /// The first worn volume.
    pub fn wear(&self) -> usize {
        self.work() + 1
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
    update_signals(sys, disc, t, horizon, ws);
    if !sys.thermal.taps.is_empty() {
        // a temperature some law reads (an eddy current brake's), before the laws read it
        let lay = Layout::of(sys);
        (sys.thermal).tap(&x[lay.temps()..lay.loss()], &mut ws.signals);
    }
    for c in &sys.constraints {
        c.prescribe(&ws.signals, &mut ws.phi, &mut ws.w);
    }
    sys.follow(&mut ws.phi, &mut ws.w);
    measure(&sys.signals.state, ws);
    for (k, law) in sys.laws.iter().enumerate() {
        (ws.law_phi[k], ws.law_w[k]) = angle_and_speed(&law.rel, &ws.phi, &ws.w);
    }
}

/// The signals at (t, horizon) with the discrete state's input values. The blocks are pure
/// functions of these, so an evaluation at the instant of the last one keeps its signals: the
/// event iteration and the searches evaluate one instant many times (a sixth of
/// CoupledClutches' evaluations), and a Sine's `sin` is a tenth of an evaluation's time.
/// Compared bit for bit, so the signals are exactly those evaluated anew.
fn update_signals(sys: &System, disc: &DiscreteState, t: f64, horizon: f64, ws: &mut Workspace) {
    let at = (t.to_bits(), horizon.to_bits());
    let same_inputs = (sys.inputs.iter().zip(&disc.inputs))
        .all(|(input, value)| ws.signals[input.slot].to_bits() == value.to_bits());
    if ws.signals_at == Some(at) && same_inputs {
        return;
    }
    for (input, value) in sys.inputs.iter().zip(&disc.inputs) {
        ws.signals[input.slot] = *value;
    }
    sys.signals.eval(t, horizon, &mut ws.signals);
    ws.signals_at = Some(at);
}

/// The sensors of one stage (`signals::Stage`) and the blocks after them, at the values in
/// `ws`: angles and speeds after `kinematics` has set them, accelerations and cut torques after
/// the solve. Nothing for an empty stage (every model without sensors).
#[inline]
fn measure(part: &StagePart, ws: &mut Workspace) {
    if part.is_empty() {
        return;
    }
    let m = Mechanics {
        phi: &ws.phi,
        w: &ws.w,
        a: &ws.a,
        constraint_tau: &ws.constraint_tau,
    };
    part.eval(ws.t, ws.horizon, &m, &mut ws.signals);
}

/// Writes the algebraic speeds of the shafts without inertia in mode `mm`, and the angles and
/// speeds of prescribed motions, into `x` (its other entries unchanged), so that recorded rows
/// and event states hold the values the system has — and the integrator, restarted from an
/// event's state, continues from the prescribed motion (the reset at an input event).
pub fn consistent_speeds(
    sys: &System,
    mm: &ModeMatrix,
    disc: &DiscreteState,
    t: f64,
    x: &mut [f64],
    horizon: f64,
    ws: &mut Workspace,
) {
    if mm.massless.is_some() || sys.prescribes() {
        evaluate(sys, mm, disc, t, x, horizon, ws);
        x[..sys.nodes].copy_from_slice(&ws.phi);
        x[sys.nodes..2 * sys.nodes].copy_from_slice(&ws.w);
    }
}

/// Evaluates everything at (t, x) in discrete state `disc`, whose mode `mm` was factored for.
/// (A LossyGear whose losses depend on its speed changes the factored matrix by a rank-one term.)
pub fn evaluate(
    sys: &System,
    mm: &ModeMatrix,
    disc: &DiscreteState,
    t: f64,
    x: &[f64],
    horizon: f64,
    ws: &mut Workspace,
) {
    evaluate_switching(sys, mm, disc, t, x, horizon, ws);
    heat_and_energy(sys, disc, x, ws);
}

/// What `evaluate` computes short of the heat flows, the energies and the wear rates: all
/// that the crossing indicators, their speed rates and the event iteration's relations read
/// (angles, speeds, signals, torques, the mode's solve, the elements' values, the worn
/// volumes). The crossing scan, the searches that locate a crossing and the event iteration
/// evaluate more often than the integrator and read nothing else; the heat network's solve
/// and the energy audit were a tenth of each of their evaluations. The same arithmetic as
/// `evaluate` on what it computes, so everything read is the same bits.
pub fn evaluate_switching(
    sys: &System,
    mm: &ModeMatrix,
    disc: &DiscreteState,
    t: f64,
    x: &[f64],
    horizon: f64,
    ws: &mut Workspace,
) {
    ws.rhs_evals += 1;
    kinematics(sys, disc, t, x, horizon, ws);
    accelerations(sys, mm, disc, ws);
    // the assembly checks that no force law, switching element or prescribed motion reads these
    measure(&sys.signals.solved, ws);
    if !sys.wear.is_empty() {
        // the pads' limit indicators read the worn volumes
        ws.wear.copy_from_slice(&x[Layout::of(sys).wear()..]);
    }
}

/// The torques of laws and switching elements, the mode's linear solve, and what the switching
/// elements read from its solution.
fn accelerations(sys: &System, mm: &ModeMatrix, disc: &DiscreteState, ws: &mut Workspace) {
    let n = sys.nodes;
    let mut rhs = std::mem::take(&mut ws.rhs);
    rhs.resize(mm.size, 0.0);
    // `forces` adds into the node rows; every row starts at zero (one memset call)
    rhs.fill(0.0);
    forces(sys, disc, ws, &mut rhs[..n]);
    // the permanent constraints are G's first rows; a prescribed motion's holds its acceleration
    for (k, c) in sys.constraints.iter().enumerate() {
        rhs[n + k] = c.accel(&ws.signals, &ws.phi, &ws.w);
    }
    if let Some(ml) = &mm.massless {
        massless_speeds(sys, ml, disc, ws, &mut rhs[..n]);
    }
    let elements = &ws.elements;
    mm.solve_with_slopes(sys, |k| elements[k].slope, &mut rhs);
    let m = sys.constraints.len();
    ws.a.copy_from_slice(&rhs[..n]);
    if let Some(ml) = &mm.massless {
        ml.accelerate(&ws.w, &mut ws.a);
    }
    if m > 0 {
        // (a call to memcpy even when empty, in every evaluation)
        ws.constraint_tau.copy_from_slice(&rhs[n..n + m]);
    }
    let multiplier = |row: Option<usize>| row.map(|r| rhs[n + r]);
    let elements = (sys.switching.iter().zip(&disc.switching))
        .zip(mm.element_rows.iter().zip(&mut ws.elements));
    for ((e, st), (rows, v)) in elements {
        let solved = Solved {
            a: &ws.a,
            permanent: multiplier(rows.permanent),
            lock: multiplier(rows.lock),
            held: rows.held,
        };
        e.solved(st, &solved, v);
        if rows.forced && !st.free && st.pre.mode == STUCK {
            let beyond = forced_breakaway(e.motion().dot(&ws.w), e.motion().dot(&ws.a));
            if beyond != 0.0 {
                v.sa = beyond;
            }
        }
    }
    ws.rhs = rhs;
}

/// `sa` of a stuck (locked or starting) element whose motion a prescribed motion moves (an
/// AngleToTorqueAdaptor's shaft braked): no torque holds it — its lock row is dependent — so
/// `sa` is beyond any breakaway torque in the direction of the prescribed relative speed (at
/// zero speed, of its acceleration) and the element starts sliding that way at once, in every
/// pass of the event iteration (without this, starting at a = 0 puts `sa` exactly on the
/// threshold and the mixed system cycles back to stuck). 0 when the motion rests: it holds,
/// carrying nothing. Finite, so that the event iteration's sums stay finite.
pub fn forced_breakaway(w: f64, a: f64) -> f64 {
    const BEYOND_ANY_BREAKAWAY: f64 = 1e100;
    const BAND: f64 = 1e-10; // the event hysteresis (`switching::relation`)
    if w.abs() > BAND {
        BEYOND_ANY_BREAKAWAY.copysign(w)
    } else if a != 0.0 {
        BEYOND_ANY_BREAKAWAY.copysign(a)
    } else {
        0.0
    }
}

/// The generalized forces of the laws and switching elements at the speeds in `ws`, added into
/// `f` (zero on entry).
fn forces(sys: &System, disc: &DiscreteState, ws: &mut Workspace, f: &mut [f64]) {
    // zipped, not indexed: no bounds checks per law in every evaluation
    let laws = (sys.laws.iter())
        .zip(ws.law_phi.iter().zip(&ws.law_w))
        .zip(&mut ws.law_tau);
    for ((law, (&phi_rel, &w_rel)), law_tau) in laws {
        let ctx = law.view(
            (ws.t, ws.horizon),
            (phi_rel, w_rel),
            &ws.signals,
            &disc.relations,
        );
        let tau = law.law.tau(&ctx);
        *law_tau = tau;
        law.rel.apply(tau, f);
    }
    let kin = Kinematics {
        phi: &ws.phi,
        w: &ws.w,
        signals: &ws.signals,
    };
    for ((e, st), v) in sys
        .switching
        .iter()
        .zip(&disc.switching)
        .zip(&mut ws.elements)
    {
        e.forces(st, &kin, v, f);
    }
}

/// Solves the algebraic speeds of the shafts without inertia (`Nᵀf = 0`), leaving the forces at
/// them in `f`. Affine laws need one step (the next residual confirms it); when other speed-dependent
/// torques act along `N` (a friction table), Newton steps follow, each with the slope measured
/// by finite differences.
fn massless_speeds(
    sys: &System,
    ml: &Massless,
    disc: &DiscreteState,
    ws: &mut Workspace,
    f: &mut [f64],
) {
    let mut slope: Option<DMatrix<f64>> = None;
    let (mut first, mut last) = (f64::INFINITY, f64::INFINITY);
    for iteration in 0..MASSLESS_ITERATIONS {
        let scale = ws.w.iter().fold(1.0f64, |m, w| m.max(w.abs()));
        let r = ml.residual(f);
        let step = match &slope {
            Some(m) => m
                .clone()
                .lu()
                .solve(&r)
                .unwrap_or_else(|| ml.affine_step(&r)),
            None => ml.affine_step(&r),
        };
        let size = step.amax();
        // solved, or Newton at its round-off floor (tiny steps that no longer shrink): `f` is
        // at these speeds already
        if size <= 1e-14 * scale || (size >= 0.5 * last && size <= 1e-9 * first) {
            break;
        }
        ml.add(&step, &mut ws.w);
        refresh(sys, disc, ws, f);
        // affine (the second step is round-off of the first): done
        if iteration == 1 && size <= 1e-9 * first {
            break;
        }
        if iteration >= 1 {
            // not affine: Newton, the slope measured anew (a table's kink changes it)
            slope = Some(measured_slope(sys, ml, disc, ws, f, scale));
        }
        if iteration == 0 {
            first = size;
        }
        last = size;
    }
}

/// `−∂(Nᵀf)/∂s` at the speeds in `ws`, by forward differences along each direction.
fn measured_slope(
    sys: &System,
    ml: &Massless,
    disc: &DiscreteState,
    ws: &mut Workspace,
    f: &mut [f64],
    scale: f64,
) -> DMatrix<f64> {
    let k = ml.dim();
    let r0 = ml.residual(f);
    let h = 1e-7 * scale;
    let mut m = DMatrix::zeros(k, k);
    for j in 0..k {
        let e = DVector::from_fn(k, |i, _| if i == j { h } else { 0.0 });
        ml.add(&e, &mut ws.w);
        refresh(sys, disc, ws, f);
        m.set_column(j, &((&r0 - ml.residual(f)) / h));
        ml.add(&-e, &mut ws.w);
    }
    refresh(sys, disc, ws, f);
    m
}

/// The laws' relative speeds, the signals measured from speeds and the forces after the speeds
/// in `ws` changed (a SpeedSensor on a shaft without inertia driving a brake: the solve for the
/// speed sees the brake's torque at each trial speed).
fn refresh(sys: &System, disc: &DiscreteState, ws: &mut Workspace, f: &mut [f64]) {
    measure(&sys.signals.state, ws);
    for (k, law) in sys.laws.iter().enumerate() {
        ws.law_w[k] = law.rel.dot(&ws.w);
    }
    f.fill(0.0);
    forces(sys, disc, ws, f);
}

/// Bound on the steps of `massless_speeds`.
const MASSLESS_ITERATIONS: usize = 16;

/// What `evaluate` computes beyond `evaluate_switching` (the heat flows into the heat network,
/// the energy audit and the rates), when the workspace holds `evaluate_switching` at (t, x) in
/// `disc` already: together, `evaluate`'s workspace bit for bit (the event iteration's last
/// evaluation is the settled state's, at the event's state).
pub fn heat_and_energy(sys: &System, disc: &DiscreteState, x: &[f64], ws: &mut Workspace) {
    let lay = Layout::of(sys);
    ws.heat_in.iter_mut().for_each(|q| *q = 0.0);
    let (mut loss, mut work, mut potential) = (0.0, 0.0, 0.0);
    let laws = (sys.laws.iter())
        .zip(ws.law_phi.iter().zip(&ws.law_w))
        .zip(ws.law_tau.iter().zip(&mut ws.law_loss));
    for ((law, (&phi_rel, &w_rel)), (&tau, law_loss)) in laws {
        let ctx = law.view(
            (ws.t, ws.horizon),
            (phi_rel, w_rel),
            &ws.signals,
            &disc.relations,
        );
        match law.role {
            EnergyRole::Source => work -= tau * w_rel,
            _ => {
                loss += law.law.dissipation(&ctx, tau);
                potential += law.law.potential(&ctx);
            }
        }
        if let Some(node) = law.heat_node {
            let q = law.law.loss_power(&ctx, tau);
            *law_loss = q;
            ws.heat_in[node] += q;
        }
    }
    for (v, heat) in ws.elements.iter().zip(&ws.element_heat) {
        loss += v.loss;
        if let Some(node) = *heat {
            ws.heat_in[node] += v.loss;
        }
    }
    for (c, tau) in sys.constraints.iter().zip(&ws.constraint_tau) {
        if c.does_work {
            work -= tau * c.rel.dot(&ws.w);
        }
    }
    let kinetic: f64 = (sys.mass.iter().zip(&ws.w))
        .map(|(m, w)| 0.5 * m * w * w)
        .sum();
    ws.energy = [kinetic, potential, x[lay.loss()], x[lay.work()]];
    if !sys.wear.is_empty() {
        // the worn volumes are `evaluate_switching`'s copy of the state's
        let (states, rates) = (&disc.switching, &mut ws.wear_rates);
        crate::wear::rates(&sys.wear, states, &ws.elements, &ws.signals, rates);
    }
    if sys.thermal.nodes > 0 {
        sys.thermal.temperatures(
            &x[lay.temps()..lay.loss()],
            &ws.signals,
            &ws.heat_in,
            &mut ws.temps,
            &mut ws.heat_cache,
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
    if !sys.wear.is_empty() {
        dx[lay.wear()..].copy_from_slice(&ws.wear_rates);
    }
}
