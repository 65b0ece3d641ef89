//! A variable computed alone from the part of each row it reads (issue 34): a friction
//! element's torque, loss, normal force or `mu`, a law's torque, a signal, or a formula over
//! them. In a row whose discrete state leaves the variable outside the linear solve (a clutch
//! sliding or free: its torque is its own law) only the states, the blocks feeding the
//! element's inputs and that element's `forces` are computed; only the rows that need the
//! solve (the clutch locked: its torque is the lock row's multiplier) are evaluated as the
//! table evaluates them. The arithmetic is the table's, so the values are its own bit for bit.

use super::output_expr::{compile, value, Flat};
use super::SimResult;
use crate::engine::eval::{evaluate, kinematics, DiscreteState, Layout, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::engine::ModeCache;
use crate::signals::Stage;
use crate::switching::element::{common_variable, is_discrete, BeforeSolve, Kinematics, Solved};
use crate::system::outputs::EnergyVar;
use crate::system::{Out, System};
use std::rc::Rc;

/// The rows that need the solve, at most this fraction of the table's cost counted in
/// evaluations. Such a row is a whole evaluation (CoupledClutches: ~2 000 instructions, against
/// ~400 for a sliding clutch's torque); a row of the table is one plus about
/// `1 / VARIABLES_PER_EVALUATION` of one per variable (CoupledClutches, 106 variables: ~3 600
/// instructions a row; the 100-ladder, 2 800: 25 µs against 1.5 µs). A column that needs the
/// solve in most rows of a small model costs half its table, which once computed serves every
/// other variable too; in a large one a twentieth (the 100-ladder's brake torque: 1.8 against
/// 30-58 ms).
const SOLVED_SHARE: f64 = 0.25;

/// Variables of a table row that cost about one evaluation (see `SOLVED_SHARE`).
const VARIABLES_PER_EVALUATION: f64 = 150.0;

/// What an output reads before the solve (in the rows that do not need it).
#[derive(Default)]
struct Reads {
    laws: Vec<usize>,
    elements: Vec<usize>,
    /// Signal slots, or None: every signal and the whole of `kinematics`.
    slots: Option<Vec<usize>>,
}

/// Collects what `out` reads; false for what only the table computes (a flange's cut torque,
/// heat, the energies other than the kinetic, wear).
fn reads(out: &Out, sys: &System, r: &mut Reads) -> bool {
    let all_signals = |r: &mut Reads| r.slots = None;
    match out {
        Out::Angle(_) | Out::Speed(_) | Out::Accel(_) | Out::ConstraintTau(..) => true,
        Out::Time | Out::Const(_) | Out::Energy(EnergyVar::Kinetic) => true,
        Out::LawTau(k, _) | Out::LawLoss(k) => {
            r.laws.push(*k);
            all_signals(r); // what a law reads is not declared
            true
        }
        Out::Switch(k, _) => {
            r.elements.push(*k);
            match (sys.switching[*k].signal_slots(), &mut r.slots) {
                (Some(own), Some(slots)) => slots.extend(own),
                _ => all_signals(r),
            }
            true
        }
        Out::Signal(slot) => {
            if let Some(slots) = &mut r.slots {
                slots.push(*slot);
            }
            true
        }
        Out::Scaled(inner, _) => reads(inner, sys, r),
        Out::Formula(f) => f.leaves.iter().all(|leaf| reads(leaf, sys, r)),
        _ => false,
    }
}

/// Whether the rows of discrete state `disc` need the solve for `out` (`reads` took it).
/// `no_massless`: every shaft has inertia (taken once per output, not per discrete state: the
/// 1000-ladder has a thousand of each).
fn needs_solve(out: &Out, sys: &System, disc: &DiscreteState, no_massless: bool) -> bool {
    // a shaft without inertia moves with the solve (`massless_speeds`), and with it whatever
    // reads its speed: laws, elements, sensors
    let massive = |terms: &[(usize, f64)]| terms.iter().all(|&(n, _)| sys.mass[n] > 0.0);
    match out {
        Out::Angle(rel) | Out::Speed(rel) => !massive(&rel.terms),
        Out::Accel(_) | Out::ConstraintTau(..) => true,
        Out::LawTau(k, _) | Out::LawLoss(k) => !no_massless || !massive(&sys.laws[*k].rel.terms),
        Out::Switch(k, var) => {
            let (e, st) = (&sys.switching[*k], &disc.switching[*k]);
            let before = no_massless && e.before_solve(st, *var) != BeforeSolve::Never;
            !(is_discrete(*var) || before)
        }
        Out::Signal(slot) => match stage(sys, *slot) {
            Stage::Time => false,
            Stage::State => !no_massless,
            Stage::Solved => true,
        },
        Out::Scaled(inner, _) => needs_solve(inner, sys, disc, no_massless),
        Out::Formula(f) => (f.leaves.iter()).any(|leaf| needs_solve(leaf, sys, disc, no_massless)),
        _ => false,
    }
}

/// How the rows of one discrete state compute an output.
#[derive(Debug, Clone, Copy)]
enum Kind {
    /// This value in every row: one element's variable that its state fixes.
    Fixed(f64),
    /// Before the solve; `solved`: with the elements' `solved` after their `forces`.
    Before { solved: bool },
    /// The row evaluated as the table evaluates it.
    Solve,
}

/// How the rows of `disc` compute `out`, compiled to `flat`.
fn kind(out: &Out, flat: Flat, sys: &System, disc: &DiscreteState, no_massless: bool) -> Kind {
    if needs_solve(out, sys, disc, no_massless) {
        return Kind::Solve;
    }
    let Flat::Switch(k, var, s) = flat else {
        return Kind::Before { solved: true };
    };
    let (e, st) = (&sys.switching[k], &disc.switching[k]);
    match e.before_solve(st, var) {
        // the recorder's `s * variable`, whose value the state fixes
        BeforeSolve::Constant(c) => Kind::Fixed(s * c),
        _ if is_discrete(var) => Kind::Fixed(s * e.variable(st, &Default::default(), var)),
        BeforeSolve::Forces => Kind::Before { solved: false },
        _ => Kind::Before { solved: true },
    }
}

/// When signal `slot` is known within an evaluation.
fn stage(sys: &System, slot: usize) -> Stage {
    let g = &sys.signals;
    let writes = |part: &crate::signals::StagePart| {
        part.sensors.iter().any(|s| s.slot == slot) || part.blocks.iter().any(|b| b.output == slot)
    };
    if writes(&g.solved) {
        Stage::Solved
    } else if writes(&g.state) {
        Stage::State
    } else {
        Stage::Time
    }
}

/// The blocks of `Stage::Time` that `slots` need, in evaluation order, and whether they read
/// a temperature tap; None when some slot comes from elsewhere (a sensor, a derivative, a tap
/// that a block reads: `kinematics` then, in its order).
fn slice(sys: &System, slots: &[usize]) -> Option<(Vec<usize>, bool)> {
    let g = &sys.signals;
    let writer = |slot: usize| g.blocks.iter().position(|b| b.output == slot);
    let input = |slot: usize| sys.inputs.iter().any(|i| i.slot == slot);
    let tap = |slot: usize| sys.thermal.taps.iter().any(|t| t.slot == slot);
    let (mut blocks, mut taps) = (vec![false; g.blocks.len()], false);
    let mut todo: Vec<(usize, bool)> = slots.iter().map(|&s| (s, false)).collect();
    while let Some((slot, of_block)) = todo.pop() {
        match writer(slot) {
            Some(i) if !blocks[i] => {
                blocks[i] = true;
                todo.extend(g.blocks[i].inputs.iter().map(|&s| (s, true)));
            }
            Some(_) => {}
            None if input(slot) => {}
            None if tap(slot) && !of_block => taps = true,
            None => return None,
        }
    }
    let order = (0..blocks.len()).filter(|&i| blocks[i]).collect();
    Some((order, taps))
}

/// `value`, the kinetic energy summed from the speeds as `heat_and_energy` sums it (rows
/// that skipped it).
fn row_value(out: &Out, sys: &System, ws: &Workspace, disc: &DiscreteState) -> f64 {
    match out {
        Out::Energy(EnergyVar::Kinetic) => (sys.mass.iter().zip(&ws.w))
            .map(|(m, w)| 0.5 * m * w * w)
            .sum(),
        Out::Scaled(inner, s) => s * row_value(inner, sys, ws, disc),
        Out::Formula(f) => f.eval(|i| row_value(&f.leaves[i], sys, ws, disc)),
        other => value(other, sys, ws, disc, &[]),
    }
}

/// Output `c` of one system's rows, compiled as the recorder compiles it, and what it reads.
struct Plan<'a> {
    sys: &'a System,
    flat: Flat,
    general: Vec<Out>,
    reads: Reads,
    /// How the rows of each discrete state compute it.
    kinds: Vec<Kind>,
}

impl<'a> Plan<'a> {
    fn new(sys: &'a System, c: usize, discs: &[DiscreteState]) -> Option<Self> {
        let out = &sys.outputs[c].1;
        let mut r = Reads {
            slots: Some(Vec::new()),
            ..Reads::default()
        };
        if !reads(out, sys, &mut r) {
            return None;
        }
        let mut general = Vec::new();
        let flat = compile(out, 1.0, &mut general);
        let no_massless = sys.mass.iter().all(|&m| m > 0.0);
        let kinds = (discs.iter())
            .map(|d| kind(out, flat, sys, d, no_massless))
            .collect();
        Some(Self {
            sys,
            flat,
            general,
            reads: r,
            kinds,
        })
    }

    /// The value of a row from its evaluated workspace, as the recorder writes it.
    fn value(&self, ws: &Workspace, disc: &DiscreteState) -> f64 {
        let sys = self.sys;
        match self.flat {
            Flat::Phi(node, s, offset) => s * ws.phi[node] + offset,
            Flat::W(node, s) => s * ws.w[node],
            Flat::A(node, s) => s * ws.a[node],
            // a continuous variable is `common_variable`'s (the trait's rule), as the table
            // reads it, without a virtual call; `kind` fixed the discrete ones
            Flat::Switch(k, var, s) => {
                s * common_variable(&disc.switching[k], &ws.elements[k], var)
            }
            Flat::Signal(slot, s) => s * ws.signals[slot],
            Flat::LawTau(k, s) => s * ws.law_tau[k],
            Flat::Flange(..) => f64::NAN, // not alone (`reads`)
            Flat::General(i, s) => s * row_value(&self.general[i], sys, ws, disc),
        }
    }
}

/// What computing the rows of a plan keeps from one row to the next.
struct Rows {
    /// The rows before the solve have their own workspace: `kinematics` keeps the signals of
    /// the last instant it evaluated, and the slices write only some of them.
    before: Workspace,
    solved: Workspace,
    cache: ModeCache,
    modes: Vec<Option<Rc<ModeMatrix>>>,
    /// The blocks the rows before the solve evaluate, and whether they read a temperature tap
    /// (None: `kinematics`, every signal).
    sliced: Option<(Vec<usize>, bool)>,
    /// A general output reads the workspace's angles and speeds; one element's variable reads
    /// the states in place.
    general: bool,
    zeros: Vec<f64>,
    /// The elements' forces, never read.
    f: Vec<f64>,
}

impl Rows {
    fn new(sys: &System, plan: &Plan) -> Self {
        let states_only = !sys.prescribes() && sys.followers.is_empty();
        Self {
            before: Workspace::new(sys),
            solved: Workspace::new(sys),
            cache: ModeCache::default(),
            modes: Vec::new(),
            sliced: (plan.reads.slots.as_deref())
                .filter(|_| states_only)
                .and_then(|slots| slice(sys, slots)),
            general: matches!(plan.flat, Flat::General(..)),
            zeros: vec![0.0; sys.nodes],
            f: vec![0.0; sys.nodes],
        }
    }
}

impl SimResult {
    /// Whether output `c` is computed alone from part of each row (`sliced_column`).
    pub(super) fn sliced(&self, c: usize) -> bool {
        self.sliced_plans(c).is_some()
    }

    /// How output `c` is computed alone in each system's rows (first row, end, plan), when
    /// every row's system can and the rows that need their mode solve cost at most
    /// `SOLVED_SHARE` of the table.
    fn sliced_plans(&self, c: usize) -> Option<Vec<(usize, usize, Plan<'_>)>> {
        let tr = &self.trajectory;
        let mut solved = 0usize;
        let mut plans = Vec::new();
        for (first, end, sys) in self.segments() {
            let plan = Plan::new(sys, c, &self.discs)?;
            let solve = |d: &&u32| matches!(plan.kinds[**d as usize], Kind::Solve);
            solved += tr.disc[first..end].iter().filter(solve).count();
            plans.push((first, end, plan));
        }
        let table_row = 1.0 + self.names.len() as f64 / VARIABLES_PER_EVALUATION;
        (solved as f64 <= SOLVED_SHARE * table_row * tr.rows() as f64).then_some(plans)
    }

    /// Output `c` over every row when it is `sliced` (None otherwise): the rows that need the
    /// solve evaluated as the table evaluates them, the others from their states, the signals
    /// they read and the laws and elements they read computed before the solve. On this
    /// thread: shared out over the pool as the table's stretches are, CoupledClutches' clutch
    /// torque took longer (97 against 88-90 µs idle, 118 against 111 under load), a pool
    /// thread waking too late to take a share.
    pub(super) fn sliced_column(&self, c: usize) -> Option<Vec<f64>> {
        let plans = self.sliced_plans(c)?;
        let mut values = vec![f64::NAN; self.rows()];
        for (first, end, plan) in &plans {
            let mut rows = Rows::new(plan.sys, plan);
            self.sliced_rows(plan, &mut rows, *first, &mut values[*first..*end]);
        }
        Some(values)
    }

    /// Writes `out`, the values of rows `from..`.
    fn sliced_rows(&self, plan: &Plan, rows: &mut Rows, from: usize, out: &mut [f64]) {
        let (tr, sys) = (&self.trajectory, plan.sys);
        let n = sys.nodes;
        let none = Solved {
            a: &rows.zeros,
            permanent: None,
            lock: None,
            held: false,
        };
        for (r, value) in (from..).zip(out.iter_mut()) {
            let (id, t, x, h) = (tr.disc[r] as usize, tr.t[r], tr.x(r), tr.horizon[r]);
            let disc = &self.discs[id];
            let with_solved = match plan.kinds[id] {
                Kind::Fixed(v) => {
                    *value = v;
                    continue;
                }
                Kind::Solve => {
                    let modes = (&mut rows.cache, &mut rows.modes);
                    *value = self.solved_row(plan, modes, r, &mut rows.solved);
                    continue;
                }
                Kind::Before { solved } => solved,
            };
            let ws = &mut rows.before;
            let in_place = match &rows.sliced {
                Some((blocks, taps)) => {
                    (ws.t, ws.horizon) = (t, h);
                    for (input, value) in sys.inputs.iter().zip(&disc.inputs) {
                        ws.signals[input.slot] = *value;
                    }
                    sys.signals.eval_some(blocks, t, h, &mut ws.signals);
                    if *taps {
                        let lay = Layout::of(sys);
                        (sys.thermal).tap(&x[lay.temps()..lay.loss()], &mut ws.signals);
                    }
                    if rows.general {
                        ws.phi.copy_from_slice(&x[..n]);
                        ws.w.copy_from_slice(&x[n..2 * n]);
                    }
                    true
                }
                None => {
                    kinematics(sys, disc, t, x, h, ws);
                    false
                }
            };
            for &k in &plan.reads.laws {
                ws.law_tau[k] = sys.laws[k].law.tau(&ws.law_ctx(sys, disc, k));
            }
            let (phi, w) = match in_place {
                true => (&x[..n], &x[n..2 * n]),
                false => (&ws.phi[..], &ws.w[..]),
            };
            let kin = Kinematics {
                phi,
                w,
                signals: &ws.signals,
            };
            for &k in &plan.reads.elements {
                let (e, st, v) = (&sys.switching[k], &disc.switching[k], &mut ws.elements[k]);
                e.forces(st, &kin, v, &mut rows.f);
                if with_solved {
                    e.solved(st, &none, v);
                }
            }
            *value = plan.value(ws, disc);
        }
    }

    /// Row `r` evaluated as the table evaluates it (its mode factored once), and the plan's
    /// value there; NaN where the mode cannot be factored, as in the table.
    fn solved_row(
        &self,
        plan: &Plan,
        (cache, modes): (&mut ModeCache, &mut Vec<Option<Rc<ModeMatrix>>>),
        r: usize,
        ws: &mut Workspace,
    ) -> f64 {
        let tr = &self.trajectory;
        let (id, t) = (tr.disc[r] as usize, tr.t[r]);
        let disc = &self.discs[id];
        if id >= modes.len() {
            modes.resize(id + 1, None);
        }
        if modes[id].is_none() {
            modes[id] = cache.get(plan.sys, disc, t).ok();
        }
        let Some(mm) = &modes[id] else {
            return f64::NAN;
        };
        evaluate(plan.sys, mm, disc, t, tr.x(r), tr.horizon[r], ws);
        plan.value(ws, disc)
    }
}
