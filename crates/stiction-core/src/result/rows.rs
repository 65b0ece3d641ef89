//! Evaluating recorded rows: a workspace and the factored modes of one system, kept from one
//! stretch of rows to the next that a thread computes (a calling thread that also takes the
//! stretch of a pool thread that woke late neither factors its modes again nor allocates).

use std::ops::Range;
use std::rc::Rc;

use super::SimResult;
use crate::engine::eval::{evaluate, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::engine::ModeCache;
use crate::system::System;

/// What evaluating rows of one system needs, kept between stretches of rows.
pub(super) struct RowEvaluator {
    ws: Workspace,
    cache: ModeCache,
    /// Each discrete state's factored mode, once met (None: not yet, or not factorable).
    modes: Vec<Option<Rc<ModeMatrix>>>,
}

impl RowEvaluator {
    /// An evaluator of rows of `sys` in a run with `states` discrete states.
    pub(super) fn new(sys: &System, states: usize) -> Self {
        Self {
            ws: Workspace::new(sys),
            cache: ModeCache::default(),
            modes: vec![None; states],
        }
    }

    /// Evaluates rows `rows` of `result` (all of them computed with `sys`) and hands `visit`
    /// each row, the system and the row's workspace and discrete state, or None where the mode
    /// cannot be factored.
    pub(super) fn visit(
        &mut self,
        result: &SimResult,
        rows: Range<usize>,
        sys: &System,
        visit: &mut impl FnMut(usize, &System, Option<(&Workspace, &DiscreteState)>),
    ) {
        let tr = &result.trajectory;
        for r in rows {
            let id = tr.disc[r] as usize;
            let disc = &result.discs[id];
            if self.modes[id].is_none() {
                // The run factored this mode already; it cannot be singular here.
                self.modes[id] = self.cache.get(sys, disc, tr.t[r]).ok();
            }
            match self.modes[id].as_ref() {
                Some(mm) => {
                    evaluate(sys, mm, disc, tr.t[r], tr.x(r), tr.horizon[r], &mut self.ws);
                    visit(r, sys, Some((&self.ws, disc)));
                }
                None => visit(r, sys, None),
            }
        }
    }
}
