//! The row recorder: every output variable (or a chosen few) of evaluated instants, row by
//! row. The reference the table engine (`table/`) reproduces bit for bit, and what the probes
//! of metrics and sweeps read through.

use super::output_expr::{compile, switch_value, value, Flat};
use crate::engine::eval::{DiscreteState, Workspace};
use crate::system::{Out, System};

/// Every output variable (time first, as in `SimResult::names`) at one evaluated instant.
pub fn row_values(sys: &System, ws: &Workspace, disc: &DiscreteState) -> Vec<f64> {
    let mut recorder = Recorder::new(sys, 1);
    recorder.record(sys, ws, disc);
    recorder.data
}

/// Computes result rows from evaluated workspaces.
pub(super) struct Recorder {
    pub(super) data: Vec<f64>,
    pub(super) flat: Vec<Flat>,
    general: Vec<Out>,
    flange_tau: Vec<f64>,
    scratch: Vec<f64>,
    needs_flanges: bool,
}

impl Recorder {
    pub(super) fn new(sys: &System, rows: usize) -> Self {
        let all: Vec<usize> = (0..sys.outputs.len()).collect();
        Self::select(sys, &all, rows)
    }

    /// A recorder of some outputs only (indices into `sys.outputs`).
    pub(super) fn select(sys: &System, outputs: &[usize], rows: usize) -> Self {
        let mut general = Vec::new();
        let flat: Vec<Flat> = outputs
            .iter()
            .map(|&i| compile(&sys.outputs[i].1, 1.0, &mut general))
            .collect();
        let needs_flanges = flat
            .iter()
            .any(|f| matches!(f, Flat::Flange(..) | Flat::General(..)));
        Self {
            data: Vec::with_capacity(rows * (flat.len() + 1)),
            flat,
            general,
            flange_tau: vec![0.0; sys.flange_torques.ports()],
            scratch: Vec::new(),
            needs_flanges,
        }
    }

    /// Whether a row needs an evaluation of the system (an output is not a state or a mode).
    pub(super) fn needs_evaluation(&self) -> bool {
        self.flat.iter().any(|f| !f.is_direct())
    }

    /// Appends one row from an evaluated workspace.
    pub(super) fn record(&mut self, sys: &System, ws: &Workspace, disc: &DiscreteState) {
        if self.needs_flanges && sys.flange_torques.ports() > 0 {
            sys.flange_torques.solve(
                |out: &Out| value(out, sys, ws, disc, &[]),
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
            Flat::Switch(k, var, s) => s * switch_value(sys, ws, disc, k, var),
            Flat::Signal(slot, s) => s * ws.signals[slot],
            Flat::LawTau(k, s) => s * ws.law_tau[k],
            Flat::Flange(p, s) => s * tau[p],
            Flat::General(i, s) => s * value(&general[i], sys, ws, disc, tau),
        }));
    }
}
