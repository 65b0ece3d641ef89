//! Results: every output variable by its MSL name on the output grid plus both sides of every
//! event (as MSL reference files have them), the event log and solver statistics.
//!
//! Here the recorded run (`SimResult`: trajectory, discrete states, events) and what reads it:
//! the output expressions (`output_expr`), the row recorder (`recorder`), metrics, probes and
//! the energy audit. `table/` is the parallel engine that computes every variable of every row
//! (the row recorder's values, bit for bit); `io/` writes result files (CSV, .mat).

mod audit;
pub mod io;
pub mod metric;
mod output_expr;
mod probe;
mod recorder;
mod sliced;
mod table;

use std::mem::MaybeUninit;
use std::sync::{Arc, Mutex, OnceLock};

pub use audit::ElementAudit;
pub use metric::{Accumulator, Metric};
pub use probe::{Probe, RowView};
pub use recorder::row_values;
pub(crate) use table::recorded_while;
#[cfg(test)]
pub use table::ROWS_BY_POOL;
pub use table::{recycle_table, MAX_TABLE_VALUES};

use crate::engine::eval::{DiscreteState, Workspace};
use crate::system::System;
use output_expr::{compile, Flat};
use table::RowEvaluator;

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
    /// Factorizations of the implicit methods' Newton matrix (each after a Jacobian update
    /// or a step-size change; 0 for the explicit method).
    pub lu_setups: usize,
    /// Jacobians of the right-hand side the implicit methods built (by forward differences).
    pub jacobian_evals: usize,
    /// Solver = "auto": 1 if the run changed to the implicit method.
    pub solver_switches: usize,
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

    /// Pushes `count` rows of one horizon and discrete state whose times and states `fill`
    /// writes in place (times, then the states row after row, into room not yet written),
    /// returning how many state values it wrote: a block of grid rows costs one resize per
    /// column, and the states (most of a run's memory) are written once, not zeroed first
    /// (zeroing them was a twentieth of HeatLosses' run).
    ///
    /// # Panics
    /// If `fill` did not write all `count` rows of states.
    pub fn push_block(
        &mut self,
        count: usize,
        (horizon, disc): (f64, u32),
        fill: impl FnOnce(&mut [f64], &mut [MaybeUninit<f64>]) -> usize,
    ) {
        let rows = self.t.len();
        self.t.resize(rows + count, 0.0);
        self.horizon.resize(rows + count, horizon);
        self.disc.resize(rows + count, disc);
        let values = count * self.width;
        self.x.reserve(values);
        let written = fill(
            &mut self.t[rows..],
            &mut self.x.spare_capacity_mut()[..values],
        );
        assert_eq!(written, values, "a block of rows left states unwritten");
        let len = self.x.len() + values;
        // SAFETY: `fill` wrote the `values` values after the length (checked above).
        unsafe { self.x.set_len(len) };
    }

    pub fn rows(&self) -> usize {
        self.t.len()
    }

    /// Room for `rows` more rows (a run knows its grid: no regrowth while recording).
    pub fn reserve(&mut self, rows: usize) {
        self.t.reserve(rows);
        self.horizon.reserve(rows);
        self.disc.reserve(rows);
        self.x.reserve(rows * self.width);
    }

    /// Rows `rows` into `out`, in place of its own (its row 0 is row `rows.start`).
    fn copy_rows_into(&self, rows: std::ops::Range<usize>, out: &mut Trajectory) {
        let w = self.width;
        out.width = w;
        out.t.clear();
        out.t.extend_from_slice(&self.t[rows.clone()]);
        out.horizon.clear();
        out.horizon.extend_from_slice(&self.horizon[rows.clone()]);
        out.disc.clear();
        out.disc.extend_from_slice(&self.disc[rows.clone()]);
        out.x.clear();
        out.x
            .extend_from_slice(&self.x[rows.start * w..rows.end * w]);
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
    /// The systems of the rows before parameter changes (`Simulation::set_parameters`): rows
    /// below each index were evaluated with its system; the rest with `system`.
    earlier: Vec<(usize, Arc<System>)>,
    trajectory: Trajectory,
    discs: Vec<DiscreteState>,
    table: OnceLock<Vec<f64>>,
    /// Every variable, computed while the run went on (`recorded_while`) and not yet handed
    /// out: `table` keeps it, `table_vec` takes it.
    ready: Mutex<Option<Vec<f64>>>,
    /// The most values `table` may hold (`MAX_TABLE_VALUES` unless a test lowers it).
    table_limit: f64,
    /// Switching elements whose loss power went below `−|tau|·slip_bound` (the audit's bound
    /// on a relative speed: event band plus integrator error) at the end of some step: a run to
    /// audit (Python warns when the audit finds a passive one delivering energy). Empty for a
    /// run that never saw it.
    pub delivering: Vec<String>,
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
            earlier: Vec::new(),
            trajectory,
            discs,
            table: OnceLock::new(),
            ready: Mutex::new(None),
            table_limit: MAX_TABLE_VALUES,
            delivering: Vec::new(),
        }
    }

    /// The result of a run whose parameters changed: rows below each index were computed with
    /// the system given with it (in increasing order), so they are evaluated with it.
    pub fn with_earlier_systems(mut self, earlier: Vec<(usize, Arc<System>)>) -> Self {
        self.earlier = earlier;
        self
    }

    /// The rows of each system, in order: (first row, end, system).
    fn segments(&self) -> Vec<(usize, usize, &System)> {
        let mut out = Vec::with_capacity(self.earlier.len() + 1);
        let mut start = 0;
        for (end, sys) in &self.earlier {
            out.push((start, *end, &**sys));
            start = *end;
        }
        out.push((start, self.trajectory.rows(), &*self.system));
        out
    }

    pub fn rows(&self) -> usize {
        self.trajectory.rows()
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
            // the part of each row it reads (an angle, a speed or the kinetic energy: the
            // states alone); the mode solve only where it needs it
            if let Some(values) = self.sliced_column(c - 1) {
                return Some(values);
            }
        }
        let Ok(table) = self.table() else {
            // too large for every variable at once: this one alone
            let single = self.compute_columns(Some(c - 1));
            return Some(single.iter().skip(1).step_by(2).copied().collect());
        };
        Some(
            table
                .iter()
                .skip(c)
                .step_by(self.names.len())
                .copied()
                .collect(),
        )
    }

    /// Whether variable `name` is read from the recorded states without evaluating the system
    /// (an angle, a speed, a mode, a flag, time); None for an unknown name. Any other variable
    /// is a column of the table, which computes every variable at once.
    pub fn is_direct(&self, name: &str) -> Option<bool> {
        let c = self.names.iter().position(|n| n == name)?;
        if c == 0 {
            return Some(true);
        }
        let mut general = Vec::new();
        Some(compile(&self.system.outputs[c - 1].1, 1.0, &mut general).is_direct())
    }

    /// Whether `column(name)` computes variable `name` alone, not as a column of the table
    /// of every variable: a direct one, one of the kinematics (the kinetic energy, an angle or
    /// speed between shafts), or one that needs the mode solve in few rows (a clutch's torque:
    /// only while locked, `sliced`); None for an unknown name.
    pub fn is_alone(&self, name: &str) -> Option<bool> {
        let c = self.names.iter().position(|n| n == name)?;
        Some(c == 0 || self.is_direct(name) == Some(true) || self.sliced(c - 1))
    }

    /// Variables that need no evaluation of the system: node angles and speeds, modes, flags.
    fn direct_column(&self, flat: Flat) -> Option<Vec<f64>> {
        let tr = &self.trajectory;
        let sys = &*self.system;
        flat.is_direct().then(|| {
            (0..tr.rows())
                .map(|r| flat.direct(sys, tr.x(r), &self.discs[tr.disc[r] as usize]))
                .collect()
        })
    }

    /// Evaluates every recorded row with the system it was computed with (`earlier`; each mode
    /// factored once per system) and hands `visit` row `r`, that system and the row's
    /// workspace and discrete state, or None where the mode cannot be factored.
    fn visit_rows(
        &self,
        mut visit: impl FnMut(usize, &System, Option<(&Workspace, &DiscreteState)>),
    ) {
        for (first, end, sys) in self.segments() {
            self.visit_segment(first..end, sys, &mut visit);
        }
    }

    fn visit_segment(
        &self,
        rows: std::ops::Range<usize>,
        sys: &System,
        visit: &mut impl FnMut(usize, &System, Option<(&Workspace, &DiscreteState)>),
    ) {
        let rows_of = (&self.trajectory, &self.discs[..]);
        RowEvaluator::new(sys).visit(rows_of, rows, sys, visit);
    }
}
