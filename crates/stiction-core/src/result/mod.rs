//! Results: every output variable by its MSL name on the output grid plus both sides of every
//! event (as MSL reference files have them), the event log and solver statistics.

use crate::components::friction::logic::{FORWARD, STUCK};
use crate::system::eval::{DiscreteState, Workspace};
use crate::system::outputs::{EnergyVar, FrictionVar};
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
    pub factorizations: usize,
    pub wall_ms: f64,
}

#[derive(Debug, Clone)]
pub struct SimResult {
    pub names: Vec<String>,
    /// Row-major, `rows × names.len()`.
    pub data: Vec<f64>,
    pub events: Vec<EventRecord>,
    pub stats: Stats,
}

impl SimResult {
    pub fn rows(&self) -> usize {
        self.data.len() / self.names.len().max(1)
    }

    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let c = self.names.iter().position(|n| n == name)?;
        let w = self.names.len();
        Some(self.data.iter().skip(c).step_by(w).copied().collect())
    }
}

/// Collects rows while the solver runs.
pub struct Recorder {
    pub names: Vec<String>,
    pub data: Vec<f64>,
    flange_tau: Vec<f64>,
}

impl Recorder {
    pub fn new(sys: &System) -> Self {
        let mut names = vec!["time".to_string()];
        names.extend(sys.outputs.iter().map(|(n, _)| n.clone()));
        Self {
            names,
            data: Vec::new(),
            flange_tau: vec![0.0; sys.flange_torques.ports()],
        }
    }

    /// Appends one row from an evaluated workspace.
    pub fn record(&mut self, sys: &System, ws: &Workspace, disc: &DiscreteState) {
        let mut tau = std::mem::take(&mut self.flange_tau);
        sys.flange_torques
            .solve(&|out: &Out| value(out, sys, ws, disc, &[]), &mut tau);
        self.data.push(ws.t);
        for (_, out) in &sys.outputs {
            self.data.push(value(out, sys, ws, disc, &tau));
        }
        self.flange_tau = tau;
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
        Out::Friction(k, var) => {
            let v = &ws.friction[*k];
            let st = &disc.friction[*k];
            match var {
                FrictionVar::Tau => v.tau,
                FrictionVar::Mu => v.mu,
                FrictionVar::Fn => v.fn_,
                FrictionVar::Sa => v.sa,
                FrictionVar::Tau0 => v.tau0,
                FrictionVar::Tau0Max => v.tau0_max,
                FrictionVar::LossPower => v.loss,
                FrictionVar::Mode => st.pre.mode as f64,
                FrictionVar::Locked => flag(st.locked),
                FrictionVar::StartForward => flag(st.pre.start_forward),
                FrictionVar::StartBackward => flag(st.pre.start_backward),
                FrictionVar::Free => flag(st.free),
                FrictionVar::W => v.w,
                FrictionVar::A => v.a,
                FrictionVar::Phi => v.phi,
            }
        }
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
