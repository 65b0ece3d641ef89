//! Results: every output variable by its MSL name on the output grid plus both sides of every
//! event (as MSL reference files have them), the event log and solver statistics.

mod audit;
mod block;
pub mod csv;
mod flanges;
mod frame;
mod live;
pub mod mat;
pub mod metric;
mod ops;
mod probe;
mod rows;
mod shape;
mod stretch;
mod table;

pub(crate) use live::recorded_while;
#[cfg(test)]
pub use live::ROWS_BY_POOL;
use rows::RowEvaluator;
pub use stretch::recycle_table;
pub use table::MAX_TABLE_VALUES;

use std::sync::{Arc, Mutex, OnceLock};

pub use audit::ElementAudit;
pub use metric::{Accumulator, Metric};
pub use probe::{Probe, RowView};

use crate::engine::eval::{DiscreteState, Workspace};
use crate::switching::element::is_discrete;
use crate::switching::element::ElementValues;
use crate::system::outputs::{EnergyVar, SwitchVar};
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
    /// writes in place (times, then the states row after row), so that a block of grid rows
    /// costs one resize per column.
    pub fn push_block(
        &mut self,
        count: usize,
        (horizon, disc): (f64, u32),
        fill: impl FnOnce(&mut [f64], &mut [f64]),
    ) {
        let rows = self.t.len();
        self.t.resize(rows + count, 0.0);
        self.horizon.resize(rows + count, horizon);
        self.disc.resize(rows + count, disc);
        self.x.resize((rows + count) * self.width, 0.0);
        fill(&mut self.t[rows..], &mut self.x[rows * self.width..]);
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

/// Every output variable (time first, as in `SimResult::names`) at one evaluated instant.
pub fn row_values(sys: &System, ws: &Workspace, disc: &DiscreteState) -> Vec<f64> {
    let mut recorder = Recorder::new(sys, 1);
    recorder.record(sys, ws, disc);
    recorder.data
}

/// An output expression compiled for the hot loop: the common cases (a node's angle, speed or
/// acceleration, a friction quantity, a signal …) become direct lookups with a scale factor.
#[derive(Debug, Clone, Copy)]
enum Flat {
    Phi(usize, f64, f64),
    W(usize, f64),
    A(usize, f64),
    Switch(usize, SwitchVar, f64),
    Signal(usize, f64),
    LawTau(usize, f64),
    Flange(usize, f64),
    General(usize, f64),
}

impl Flat {
    /// Read from the state alone: an angle, a speed, a mode or flag.
    fn is_direct(&self) -> bool {
        match *self {
            Flat::Phi(..) | Flat::W(..) => true,
            Flat::Switch(_, var, _) => is_discrete(var),
            _ => false,
        }
    }

    /// Its value from the state alone (for `is_direct` ones).
    fn direct(&self, sys: &System, x: &[f64], disc: &DiscreteState) -> f64 {
        match *self {
            Flat::Phi(node, s, offset) => s * x[node] + offset,
            Flat::W(node, s) => s * x[sys.nodes + node],
            Flat::Switch(k, var, s) => {
                let none = ElementValues::default();
                s * sys.switching[k].variable(&disc.switching[k], &none, var)
            }
            _ => f64::NAN,
        }
    }
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
        Out::Switch(k, var) => Flat::Switch(*k, *var, scale),
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
    needs_flanges: bool,
}

impl Recorder {
    fn new(sys: &System, rows: usize) -> Self {
        let all: Vec<usize> = (0..sys.outputs.len()).collect();
        Self::select(sys, &all, rows)
    }

    /// A recorder of some outputs only (indices into `sys.outputs`).
    fn select(sys: &System, outputs: &[usize], rows: usize) -> Self {
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
    fn needs_evaluation(&self) -> bool {
        self.flat.iter().any(|f| !f.is_direct())
    }

    /// Appends one row from an evaluated workspace.
    fn record(&mut self, sys: &System, ws: &Workspace, disc: &DiscreteState) {
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

fn switch_value(
    sys: &System,
    ws: &Workspace,
    disc: &DiscreteState,
    k: usize,
    var: SwitchVar,
) -> f64 {
    sys.switching[k].variable(&disc.switching[k], &ws.elements[k], var)
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
        Out::Switch(k, var) => switch_value(sys, ws, disc, *k, *var),
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
