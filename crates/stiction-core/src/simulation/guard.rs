//! What the run watches at the end of every step besides the crossings, from the evaluation
//! the crossing scan makes there anyway (`scan::sample_step`): a friction characteristic that
//! its table's extrapolation takes below 0 (the run stops there with an error naming the
//! element, the slip speed and the table), and switching elements whose loss power went
//! negative beyond the event band (the result lists them, and Python audits those runs).
//! The scan (`scan.rs`) locates the instant a characteristic turned negative.

use crate::engine::eval::{DiscreteState, Workspace};
use crate::switching::relation::EVENT_EPSILON;
use crate::system::System;

/// The run's guards over its switching elements.
pub(super) struct Guard {
    /// Elements whose characteristic may turn negative (`may_turn_negative`): none in most
    /// models, so the check costs nothing there.
    limited: Vec<usize>,
    /// The first of them found negative at the last step's end.
    pub(super) negative: Option<usize>,
    /// Per switching element: its loss power went below `−|torque|·slip_bound` at some step's
    /// end, the slip bound being the energy audit's: the event band plus the integrator's
    /// error bound on a relative speed, `2·EVENT_EPSILON + 2·Tolerance·(1 + |w|)` (a stuck
    /// element's slip stays inside the band; a start drifts by the integrator's error).
    pub(super) delivered: Vec<bool>,
    /// Those the last step's end saw, kept only if no crossing lies inside the step (past a
    /// crossing the step's end is in the old mode: a slip reversed under a sliding torque).
    seen: Vec<usize>,
    tolerance: f64,
}

impl Guard {
    pub(super) fn new(sys: &System) -> Self {
        Guard {
            limited: (sys.switching.iter().enumerate())
                .filter(|(_, e)| e.may_turn_negative())
                .map(|(k, _)| k)
                .collect(),
            negative: None,
            delivered: vec![false; sys.switching.len()],
            seen: Vec::new(),
            tolerance: sys.experiment.tolerance,
        }
    }

    /// The guards of a new system (a parameter change) keep what the run has seen.
    pub(super) fn renew(&mut self, sys: &System) {
        let delivered = std::mem::take(&mut self.delivered);
        *self = Guard::new(sys);
        if delivered.len() == self.delivered.len() {
            self.delivered = delivered;
        }
    }

    /// At a step's end, the workspace evaluated there.
    #[inline]
    pub(super) fn watch(&mut self, sys: &System, disc: &DiscreteState, ws: &Workspace) {
        self.seen.clear();
        for (k, v) in ws.elements.iter().enumerate() {
            if v.loss < 0.0 {
                let slip_bound = 2.0 * EVENT_EPSILON + 2.0 * self.tolerance * (1.0 + v.w.abs());
                // a friction element's loss is tau·w, a LossyGear's tauLoss·w_a
                if v.loss < -slip_bound * v.tau.abs().max(v.tau_loss.abs()) {
                    self.seen.push(k);
                }
            }
        }
        self.negative = None;
        for &k in &self.limited {
            let (e, st, v) = (&sys.switching[k], &disc.switching[k], &ws.elements[k]);
            if e.negative_characteristic(st, v).is_some() {
                self.negative = Some(k);
                return;
            }
        }
    }

    /// The step's end holds no crossing: what it saw stands.
    #[inline]
    pub(super) fn keep(&mut self) {
        for &k in &self.seen {
            self.delivered[k] = true;
        }
    }

    /// The names of the elements whose loss power went negative.
    pub(super) fn delivering(&self, sys: &System) -> Vec<String> {
        (sys.switching.iter().zip(&self.delivered))
            .filter(|(_, seen)| **seen)
            .map(|(e, _)| e.name().to_string())
            .collect()
    }
}
