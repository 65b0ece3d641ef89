//! Evaluating recorded rows: a workspace and the factored modes of one system, kept from one
//! stretch of rows to the next that a thread computes (a calling thread that also takes the
//! stretch of a pool thread that woke late neither factors its modes again nor allocates).

use std::ops::Range;
use std::rc::Rc;

use crate::engine::eval::{evaluate, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::engine::ModeCache;
use crate::result::Trajectory;
use crate::system::System;

/// What evaluating rows of one system needs, kept between stretches of rows.
pub(in crate::result) struct RowEvaluator {
    ws: Workspace,
    cache: ModeCache,
    /// Each discrete state's factored mode, once met (None: not yet, or not factorable); as
    /// long as the highest state met (a run still going on meets more).
    modes: Vec<Option<Rc<ModeMatrix>>>,
}

impl RowEvaluator {
    /// An evaluator of rows of `sys`.
    pub(in crate::result) fn new(sys: &System) -> Self {
        Self {
            ws: Workspace::new(sys),
            cache: ModeCache::default(),
            modes: Vec::new(),
        }
    }

    /// Evaluates rows `rows` of `tr` (all of them computed with `sys`, their discrete states
    /// in `discs`) and hands `visit` each row, the system and the row's workspace and discrete
    /// state, or None where the mode cannot be factored.
    pub(in crate::result) fn visit(
        &mut self,
        (tr, discs): (&Trajectory, &[DiscreteState]),
        rows: Range<usize>,
        sys: &System,
        visit: &mut impl FnMut(usize, &System, Option<(&Workspace, &DiscreteState)>),
    ) {
        for r in rows {
            let id = tr.disc[r] as usize;
            let disc = &discs[id];
            if id >= self.modes.len() {
                self.modes.resize(id + 1, None);
            }
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
