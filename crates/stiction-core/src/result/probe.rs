//! Some output variables at single rows, computed exactly as the result computes them (bit for
//! bit): what metrics and trajectory writers read while a run goes, without keeping its rows.

use std::rc::Rc;
use std::sync::Arc;

use super::recorder::Recorder;
use crate::engine::eval::{evaluate, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::engine::ModeCache;
use crate::error::SimError;
use crate::system::System;

/// One row of a run as it is produced.
#[derive(Debug, Clone, Copy)]
pub struct RowView<'a> {
    pub t: f64,
    pub x: &'a [f64],
    pub disc: &'a DiscreteState,
    /// The horizon of unhandled time events (the left row of an event has it at `t`).
    pub horizon: f64,
}

pub struct Probe {
    sys: Arc<System>,
    recorder: Recorder,
    ws: Workspace,
    cache: ModeCache,
    /// The mode last evaluated, to skip the cache's lookup while the mode stays.
    mode: Option<Rc<ModeMatrix>>,
    /// Every variable read from the state alone (`Flat::is_direct`): known once, not per row.
    direct: bool,
    /// The values of the last row read from the state alone, one per variable.
    read: Vec<f64>,
}

impl Probe {
    /// A probe of the named output variables; an unknown name is a usage error.
    pub fn new(sys: Arc<System>, names: &[String]) -> Result<Self, SimError> {
        let columns = names
            .iter()
            .map(|name| {
                sys.outputs
                    .iter()
                    .position(|(n, _)| n == name)
                    .ok_or_else(|| SimError::Usage(format!("unknown variable '{name}'")))
            })
            .collect::<Result<Vec<usize>, _>>()?;
        let recorder = Recorder::select(&sys, &columns, 1);
        Ok(Self {
            direct: !recorder.needs_evaluation(),
            read: vec![0.0; columns.len()],
            recorder,
            ws: Workspace::new(&sys),
            cache: ModeCache::default(),
            mode: None,
            sys,
        })
    }

    /// The states the variables are read from, when they are all read from the state alone
    /// (angles, speeds, modes): a row needs no others. None when one needs an evaluation.
    pub fn states_read(&self) -> Option<Vec<usize>> {
        if !self.direct {
            return None;
        }
        let mut states: Vec<usize> = Vec::new();
        for j in self
            .recorder
            .flat
            .iter()
            .filter_map(|f| f.state_read(&self.sys))
        {
            if !states.contains(&j) {
                states.push(j);
            }
        }
        Some(states)
    }

    /// Whether every variable is read from the state alone (`states_read`, `direct_value`).
    pub fn is_direct(&self) -> bool {
        self.direct
    }

    /// Variable `column` (in the order named) at `rows` rows of states `xs` (`n` a row) in
    /// the discrete state `disc`, appended to `out`, when `is_direct`: what `values` gives
    /// for it, row by row, without the others.
    pub fn direct_column(
        &self,
        column: usize,
        (xs, n, rows): (&[f64], usize, usize),
        disc: &DiscreteState,
        out: &mut Vec<f64>,
    ) {
        self.recorder.flat[column].direct_rows(&self.sys, (xs, n, rows), disc, out);
    }

    /// The variables at `row`, in the order they were named.
    pub fn values(&mut self, row: &RowView) -> Result<&[f64], SimError> {
        let sys = &*self.sys;
        if self.direct {
            // a sweep's metrics over speeds read thousands of rows a run: no row kept
            for (v, f) in self.read.iter_mut().zip(&self.recorder.flat) {
                *v = f.direct(sys, row.x, row.disc);
            }
            return Ok(&self.read);
        }
        self.recorder.data.clear();
        let mm = match &self.mode {
            Some(mm) if same_mode(sys, mm, row.disc) => mm.clone(),
            _ => {
                let mm = self.cache.get(sys, row.disc, row.t)?;
                self.mode = Some(mm.clone());
                mm
            }
        };
        evaluate(sys, &mm, row.disc, row.t, row.x, row.horizon, &mut self.ws);
        self.recorder.record(sys, &self.ws, row.disc);
        Ok(&self.recorder.data[1..])
    }
}

/// Whether `disc`'s mode is the one `mm` was factored for: the elements' mode keys, compared
/// as the mode cache keys them (locks, and slopes bit for bit). A sweep probes every row; the
/// whole discrete state compared per row (relations and inputs included) was a tenth of a
/// CoupledClutches variant.
fn same_mode(sys: &System, mm: &ModeMatrix, disc: &DiscreteState) -> bool {
    let states = sys.switching.iter().zip(&disc.switching);
    mm.keys.len() == disc.switching.len()
        && (states.zip(&mm.keys)).all(|((e, st), key)| {
            let now = e.mode_key(st);
            now.locked == key.locked && now.slope.to_bits() == key.slope.to_bits()
        })
}
