//! Results: every output variable by its MSL name on the output grid plus both sides of every
//! event (as MSL reference files have them), the event log and solver statistics.

pub mod csv;
pub mod mat;

use std::sync::{Arc, OnceLock};

use crate::engine::eval::{evaluate, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::switching::logic::{FORWARD, STUCK};
use crate::system::outputs::{EnergyVar, FrictionVar, GearVar};
use crate::system::{Out, System};

#[derive(Debug, Clone, PartialEq)]
pub struct EventRecord {
    pub time: f64,
    pub component: String,
    pub old_mode: i8,
    pub new_mode: i8,
    pub cause: String,
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stats {
    pub steps: usize,
    pub rejected_steps: usize,
    pub rhs_evals: usize,
    pub state_events: usize,
    pub time_events: usize,
    /// Events caused by setting a model input to a new value.
    pub input_events: usize,
    pub factorizations: usize,
    pub wall_ms: f64,
}

/// The continuous state on the output grid and on both sides of every event, with the discrete
/// state in force at each row. Every output variable is a function of a row, so the result
/// stores rows and computes variables when they are asked for: a state variable (an angle, a
/// speed, a mode) is read directly, anything algebraic (torques, accelerations, …) comes from
/// one evaluation pass over all rows, done once and kept.
#[derive(Debug, Clone, Default)]
pub struct Trajectory {
    pub t: Vec<f64>,
    /// The horizon of unhandled time events at each row (the left row of an event has it at t).
    pub horizon: Vec<f64>,
    pub disc: Vec<u32>,
    pub x: Vec<f64>,
    pub width: usize,
}

impl Trajectory {
    pub fn push(&mut self, t: f64, horizon: f64, disc: u32, x: &[f64]) {
        self.t.push(t);
        self.horizon.push(horizon);
        self.disc.push(disc);
        self.x.extend_from_slice(x);
    }

    pub fn rows(&self) -> usize {
        self.t.len()
    }

    fn x(&self, row: usize) -> &[f64] {
        &self.x[row * self.width..(row + 1) * self.width]
    }
}

pub struct SimResult {
    pub names: Vec<String>,
    pub events: Vec<EventRecord>,
    pub stats: Stats,
    system: Arc<System>,
    trajectory: Trajectory,
    discs: Vec<DiscreteState>,
    table: OnceLock<Vec<f64>>,
}

impl SimResult {
    pub fn new(
        system: Arc<System>,
        trajectory: Trajectory,
        discs: Vec<DiscreteState>,
        events: Vec<EventRecord>,
        stats: Stats,
    ) -> Self {
        let mut names = vec!["time".to_string()];
        names.extend(system.outputs.iter().map(|(n, _)| n.clone()));
        Self {
            names,
            events,
            stats,
            system,
            trajectory,
            discs,
            table: OnceLock::new(),
        }
    }

    pub fn rows(&self) -> usize {
        self.trajectory.rows()
    }

    /// All variables, row-major (`rows × names.len()`), computed on first use.
    pub fn table(&self) -> &[f64] {
        self.table.get_or_init(|| self.compute_table())
    }

    /// One variable over all rows.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let c = self.names.iter().position(|n| n == name)?;
        if c == 0 {
            return Some(self.trajectory.t.clone());
        }
        if self.table.get().is_none() {
            let mut general = Vec::new();
            let flat = compile(&self.system.outputs[c - 1].1, 1.0, &mut general);
            if let Some(values) = self.direct_column(flat) {
                return Some(values);
            }
        }
        let w = self.names.len();
        Some(self.table().iter().skip(c).step_by(w).copied().collect())
    }

    /// Variables that need no evaluation of the system: node angles and speeds, modes, flags.
    fn direct_column(&self, flat: Flat) -> Option<Vec<f64>> {
        let tr = &self.trajectory;
        let n = self.system.nodes;
        let rows = 0..tr.rows();
        match flat {
            Flat::Phi(node, s, offset) => Some(rows.map(|r| s * tr.x(r)[node] + offset).collect()),
            Flat::W(node, s) => Some(rows.map(|r| s * tr.x(r)[n + node]).collect()),
            Flat::Friction(k, var, s) if is_discrete(var) => Some(
                rows.map(|r| s * discrete_value(&self.discs[tr.disc[r] as usize], k, var))
                    .collect(),
            ),
            _ => None,
        }
    }

    fn compute_table(&self) -> Vec<f64> {
        let sys = &*self.system;
        let tr = &self.trajectory;
        let mut recorder = Recorder::new(sys, tr.rows());
        let mut ws = Workspace::new(sys);
        let mut modes: Vec<Option<ModeMatrix>> = (0..self.discs.len()).map(|_| None).collect();
        for r in 0..tr.rows() {
            let id = tr.disc[r] as usize;
            let disc = &self.discs[id];
            if modes[id].is_none() {
                // The run factored this mode already; it cannot be singular here.
                modes[id] =
                    ModeMatrix::factor(sys, &disc.locked_set(), &disc.gear_modes(sys), tr.t[r])
                        .ok();
            }
            let Some(mm) = modes[id].as_ref() else {
                recorder.data.push(tr.t[r]);
                recorder
                    .data
                    .extend(std::iter::repeat_n(f64::NAN, self.names.len() - 1));
                continue;
            };
            evaluate(sys, mm, disc, tr.t[r], tr.x(r), tr.horizon[r], &mut ws);
            recorder.record(sys, &ws, disc);
        }
        recorder.data
    }
}

/// Every output variable (time first, as in `SimResult::names`) at one evaluated instant.
pub fn row_values(sys: &System, ws: &Workspace, disc: &DiscreteState) -> Vec<f64> {
    let mut recorder = Recorder::new(sys, 1);
    recorder.record(sys, ws, disc);
    recorder.data
}

fn is_discrete(var: FrictionVar) -> bool {
    matches!(
        var,
        FrictionVar::Mode
            | FrictionVar::Locked
            | FrictionVar::StartForward
            | FrictionVar::StartBackward
            | FrictionVar::Free
            | FrictionVar::Stuck
    )
}

fn discrete_value(disc: &DiscreteState, k: usize, var: FrictionVar) -> f64 {
    let st = &disc.friction[k];
    match var {
        FrictionVar::Mode => st.pre.mode as f64,
        FrictionVar::Locked => flag(st.locked),
        FrictionVar::StartForward => flag(st.pre.start_forward),
        FrictionVar::StartBackward => flag(st.pre.start_backward),
        FrictionVar::Free => flag(st.free),
        FrictionVar::Stuck => flag(st.pre.mode == crate::switching::logic::STUCK),
        _ => f64::NAN,
    }
}

/// An output expression compiled for the hot loop: the common cases (a node's angle, speed or
/// acceleration, a friction quantity, a signal …) become direct lookups with a scale factor.
#[derive(Debug, Clone, Copy)]
enum Flat {
    Phi(usize, f64, f64),
    W(usize, f64),
    A(usize, f64),
    Friction(usize, FrictionVar, f64),
    Signal(usize, f64),
    LawTau(usize, f64),
    Flange(usize, f64),
    General(usize, f64),
}

fn compile(out: &Out, scale: f64, general: &mut Vec<Out>) -> Flat {
    let single = |rel: &crate::system::Rel| match rel.terms.as_slice() {
        [(node, c)] => Some((*node, *c)),
        _ => None,
    };
    match out {
        Out::Scaled(inner, s) => compile(inner, scale * s, general),
        Out::Angle(rel) if single(rel).is_some() => {
            let (node, c) = single(rel).expect("checked");
            Flat::Phi(node, scale * c, scale * rel.offset)
        }
        Out::Speed(rel) if single(rel).is_some() => {
            let (node, c) = single(rel).expect("checked");
            Flat::W(node, scale * c)
        }
        Out::Accel(rel) if single(rel).is_some() => {
            let (node, c) = single(rel).expect("checked");
            Flat::A(node, scale * c)
        }
        Out::Friction(k, var) => Flat::Friction(*k, *var, scale),
        Out::Signal(slot) => Flat::Signal(*slot, scale),
        Out::LawTau(k, s) => Flat::LawTau(*k, scale * s),
        Out::FlangeTau(p) => Flat::Flange(*p, scale),
        other => {
            general.push(other.clone());
            Flat::General(general.len() - 1, scale)
        }
    }
}

/// Computes result rows from evaluated workspaces.
struct Recorder {
    data: Vec<f64>,
    flat: Vec<Flat>,
    general: Vec<Out>,
    flange_tau: Vec<f64>,
    scratch: Vec<f64>,
}

impl Recorder {
    fn new(sys: &System, rows: usize) -> Self {
        let mut general = Vec::new();
        let flat = sys
            .outputs
            .iter()
            .map(|(_, out)| compile(out, 1.0, &mut general))
            .collect();
        Self {
            data: Vec::with_capacity(rows * (sys.outputs.len() + 1)),
            flat,
            general,
            flange_tau: vec![0.0; sys.flange_torques.ports()],
            scratch: Vec::new(),
        }
    }

    /// Appends one row from an evaluated workspace.
    fn record(&mut self, sys: &System, ws: &Workspace, disc: &DiscreteState) {
        if sys.flange_torques.ports() > 0 {
            sys.flange_torques.solve(
                &|out: &Out| value(out, sys, ws, disc, &[]),
                &mut self.flange_tau,
                &mut self.scratch,
            );
        }
        let tau = &self.flange_tau;
        let general = &self.general;
        self.data.push(ws.t);
        self.data.extend(self.flat.iter().map(|f| match *f {
            Flat::Phi(node, s, offset) => s * ws.phi[node] + offset,
            Flat::W(node, s) => s * ws.w[node],
            Flat::A(node, s) => s * ws.a[node],
            Flat::Friction(k, var, s) => s * friction_value(ws, disc, k, var),
            Flat::Signal(slot, s) => s * ws.signals[slot],
            Flat::LawTau(k, s) => s * ws.law_tau[k],
            Flat::Flange(p, s) => s * tau[p],
            Flat::General(i, s) => s * value(&general[i], sys, ws, disc, tau),
        }));
    }
}

fn friction_value(ws: &Workspace, disc: &DiscreteState, k: usize, var: FrictionVar) -> f64 {
    let v = &ws.friction[k];
    match var {
        FrictionVar::Tau => v.tau,
        FrictionVar::Mu => v.mu,
        FrictionVar::Fn => v.fn_,
        FrictionVar::Sa => v.sa,
        FrictionVar::Tau0 => v.tau0,
        FrictionVar::Tau0Max => v.tau0_max,
        FrictionVar::LossPower => v.loss,
        FrictionVar::Mode
        | FrictionVar::Locked
        | FrictionVar::StartForward
        | FrictionVar::StartBackward
        | FrictionVar::Free
        | FrictionVar::Stuck => discrete_value(disc, k, var),
        FrictionVar::W => v.w,
        FrictionVar::A => v.a,
        FrictionVar::Phi => v.phi,
    }
}

fn flag(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// The value of one output expression at an evaluated instant.
pub fn value(
    out: &Out,
    sys: &System,
    ws: &Workspace,
    disc: &DiscreteState,
    flange_tau: &[f64],
) -> f64 {
    match out {
        Out::Angle(rel) => rel.angle(&ws.phi),
        Out::Speed(rel) => rel.dot(&ws.w),
        Out::Accel(rel) => rel.dot(&ws.a),
        Out::LawTau(k, s) => s * ws.law_tau[*k],
        Out::LawLoss(k) => sys.laws[*k]
            .law
            .loss_power(&ws.law_ctx(sys, disc, *k), ws.law_tau[*k]),
        Out::ConstraintTau(k, s) => s * ws.constraint_tau[*k],
        Out::Friction(k, var) => friction_value(ws, disc, *k, *var),
        Out::Gear(k, var) => gear_value(sys, ws, disc, *k, *var),
        Out::Scaled(inner, s) => s * value(inner, sys, ws, disc, flange_tau),
        Out::Signal(slot) => ws.signals[*slot],
        Out::FlangeTau(p) => flange_tau.get(*p).copied().unwrap_or(f64::NAN),
        Out::HeatT(node) => ws.temps[*node],
        Out::HeatDerT(node) => sys
            .thermal
            .capacities
            .iter()
            .find(|c| c.node == *node)
            .map_or(0.0, |c| ws.heat_net[*node] / c.c),
        Out::HeatDiff(a, b) => ws.temps[*a] - ws.temps[*b],
        Out::HeatLinkFlow(k, s) => {
            let l = &sys.thermal.links[*k];
            s * l.conductance(&ws.signals) * (ws.temps[l.a] - ws.temps[l.b])
        }
        Out::HeatNodeInflow(node, s) => s * ws.heat_net[*node],
        Out::HeatCapacitorFlow(node, c) => {
            let total: f64 = sys
                .thermal
                .capacities
                .iter()
                .filter(|cap| cap.node == *node)
                .map(|cap| cap.c)
                .sum();
            if total > 0.0 {
                ws.heat_net[*node] * c / total
            } else {
                0.0
            }
        }
        Out::Energy(var) => match var {
            EnergyVar::Kinetic => ws.energy[0],
            EnergyVar::Potential => ws.energy[1],
            EnergyVar::Dissipated => ws.energy[2],
            EnergyVar::Work => ws.energy[3],
        },
        Out::Const(c) => *c,
    }
}

fn gear_value(sys: &System, ws: &Workspace, disc: &DiscreteState, k: usize, var: GearVar) -> f64 {
    let v = &ws.gears[k];
    let st = &disc.gears[k];
    match var {
        GearVar::TauA => v.tau_a,
        GearVar::TauB => v.tau_b,
        GearVar::TauSupport => v.tau_support,
        GearVar::W => v.w,
        GearVar::A => v.a,
        GearVar::Sa => v.sa,
        GearVar::TauLoss => v.tau_loss,
        GearVar::TauEta => v.tau_eta,
        GearVar::Eta1 => v.losses.eta1,
        GearVar::Eta2 => v.losses.eta2,
        GearVar::Tbf1 => v.losses.tbf1,
        GearVar::Tbf2 => v.losses.tbf2,
        GearVar::TbfA => v.losses.tbf_a,
        GearVar::LossMaxP => v.loss_max_p,
        GearVar::LossMinM => v.loss_min_m,
        GearVar::LossPower => v.loss,
        GearVar::Mode => st.pre.mode as f64,
        GearVar::Locked => flag(st.locked),
        GearVar::StartForward => flag(st.pre.start_forward),
        GearVar::StartBackward => flag(st.pre.start_backward),
        GearVar::TauEtaPos => flag(st.tau_eta_pos()),
        GearVar::Ideal => flag(sys.lossy_gears[k].ideal),
    }
}

/// Human-readable mode name (−1 Backward, 0 Stuck, 1 Forward, 2 Free, 3 Unknown).
pub fn mode_name(mode: i8) -> &'static str {
    match mode {
        m if m == FORWARD => "Forward",
        m if m == STUCK => "Stuck",
        -1 => "Backward",
        2 => "Free",
        _ => "Unknown",
    }
}
