//! Every variable of every row, in stretches of rows shared out over threads (`stretch.rs`).
//! Each evaluated row fills its frame (`frame.rs`: every value a column reads, each once, in one
//! flat array); the flange cut torques are solved for a block of rows at once (`block.rs`,
//! `flanges.rs`); then each row of the row-major table is written in one pass as plain reads of
//! its frame. The frame is read in pages of 256 values through `u8` indices,
//! so that a cell costs a load and a store, without a bounds check: a page is a fixed-size array
//! and no `u8` falls outside it. The values are the row recorder's, bit for bit.

use std::mem::MaybeUninit;
use std::ops::Range;
use std::sync::PoisonError;

mod block;
mod flanges;
mod frame;
mod live;
mod ops;
mod rows;
mod shape;
mod stretch;

pub(crate) use live::recorded_while;
#[cfg(test)]
pub use live::ROWS_BY_POOL;
pub(super) use rows::RowEvaluator;
pub use stretch::recycle_table;

use super::{SimResult, Trajectory};
use crate::engine::eval::DiscreteState;
use crate::error::SimError;
use crate::system::System;
use block::{Block, BLOCK};
use shape::Shape;
use stretch::{settle, share, streams, stretch_rows, table_memory, Stretch};

/// The fewest rows a stretch of the table is computed in: a table of fewer rows is not worth a
/// pool thread's wake-up (20–40 µs on this 2-core VM; the calling thread starts at once,
/// `share`). 1 024 was the floor when the calling thread slept through the table and was woken
/// at its end; now SimpleGearShift's 1 012 rows take 0.145 ms in stretches of 256, 0.18 on one
/// thread, and Modelica's `First` (2 001 rows) 0.21 ms, 0.31 on one.
const FEWEST_ROWS: usize = 4 * BLOCK;

/// The most values the table of every variable may hold (2.4 GB), as for a run's states.
pub const MAX_TABLE_VALUES: f64 = 3.0e8;

impl SimResult {
    /// All variables, row-major (`rows × names.len()`), computed on first use; a usage error
    /// when they would not fit in memory (a run records only its states, see `check_table`).
    pub fn table(&self) -> Result<&[f64], SimError> {
        self.check_table()?;
        Ok(self
            .table
            .get_or_init(|| (self.take_ready()).unwrap_or_else(|| self.compute_table())))
    }

    /// All variables as a vector of its own: the one `table()` keeps, or computed without
    /// keeping it, for a caller that keeps it (Python hands it to NumPy without a copy).
    pub fn table_vec(&self) -> Result<Vec<f64>, SimError> {
        self.check_table()?;
        Ok(match self.table.get() {
            Some(table) => table.clone(),
            None => (self.take_ready()).unwrap_or_else(|| self.compute_table()),
        })
    }

    /// The table computed while the run went on, if it was and nobody took it yet.
    fn take_ready(&self) -> Option<Vec<f64>> {
        self.ready
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take()
    }

    /// Whether every variable was computed while the run went on and is not taken yet.
    #[cfg(test)]
    pub(crate) fn has_ready_table(&self) -> bool {
        (self.ready.lock().unwrap_or_else(PoisonError::into_inner)).is_some()
    }

    /// This result with every variable computed already (`recorded_while`).
    pub(super) fn with_table(self, table: Vec<f64>) -> Self {
        *self.ready.lock().unwrap_or_else(PoisonError::into_inner) = Some(table);
        self
    }

    /// Whether every variable of every row fits in memory. A run keeps only its states, so
    /// a drivetrain of 10 000 elements runs; asking it for every variable at once is refused
    /// (one variable at a time still works: `column`).
    pub fn check_table(&self) -> Result<(), SimError> {
        let values = self.rows() as f64 * self.names.len() as f64;
        if values > self.table_limit {
            return Err(SimError::Usage(format!(
                "every variable of this result is {} rows × {} values, more than fits in memory: \
                 read variables one at a time (result[name]), or run with a larger Interval",
                self.rows(),
                self.names.len()
            )));
        }
        Ok(())
    }

    /// Lowers the most values the table may hold (tests of the refusal).
    pub fn set_table_limit(&mut self, values: f64) {
        self.table_limit = values;
    }

    /// All variables, row-major (`rows × names.len()`).
    pub(super) fn compute_table(&self) -> Vec<f64> {
        self.compute_columns(None)
    }

    /// Time and the outputs (all, or only output `only`), row-major. Rows are independent once
    /// the run has recorded their states and modes, so stretches of them are computed on all
    /// of the pool's threads, each thread with its own workspace and mode factors.
    pub(super) fn compute_columns(&self, only: Option<usize>) -> Vec<f64> {
        self.columns_in(only, |rows| stretch_rows(rows, FEWEST_ROWS))
    }

    /// `compute_columns` in stretches of `stretch(rows)` rows for a segment of `rows` rows.
    fn columns_in(&self, only: Option<usize>, stretch: impl Fn(usize) -> usize) -> Vec<f64> {
        let width = only.map_or(self.system.outputs.len(), |_| 1) + 1;
        let cells = self.rows() * width;
        // Not zeroed first: every cell is written below, and zeroing a table of megabytes cost
        // a tenth of CoupledClutches' table, on one thread before the others start.
        let mut data = table_memory(cells);
        let spare = &mut data.spare_capacity_mut()[..cells];
        self.fill_rows(0..self.rows(), only, spare, stretch);
        // SAFETY: `fill_rows` wrote every one of the `cells` values.
        unsafe { data.set_len(cells) };
        data
    }

    /// Writes rows `range` of the table (all outputs, or only output `only`) into `rows`, in
    /// stretches of `stretch(rows)` rows for a segment of `rows` rows; every cell is written.
    pub(super) fn fill_rows(
        &self,
        range: Range<usize>,
        only: Option<usize>,
        rows: &mut [MaybeUninit<f64>],
        stretch: impl Fn(usize) -> usize,
    ) {
        let width = only.map_or(self.system.outputs.len(), |_| 1) + 1;
        assert_eq!(rows.len(), range.len() * width, "a cell per value");
        let from = range.start;
        let stream = streams(self.rows() * width);
        let trajectory = (&self.trajectory, &self.discs[..]);
        // Each segment of rows between parameter changes is filled from its own system: the
        // values (an inertia's J, a law's constants) enter the compiled columns and the flange
        // torques' terms, the shapes are the same throughout.
        for (first, end, sys) in self.segments() {
            let (first, end) = (first.max(from), end.min(range.end));
            if first >= end {
                continue;
            }
            let own;
            // every variable's shape is kept with its system, for the next run's table
            let shape = match only.is_none().then(|| kept_shape(sys)).flatten() {
                Some(shape) => shape,
                None => {
                    own = Shape::new(sys, only);
                    &own
                }
            };
            let chunk = stretch(end - first).max(1);
            let context = || (Block::new(shape), RowEvaluator::new(sys));
            let fill = |context: &mut Context, (i, out): (usize, &mut [MaybeUninit<f64>])| {
                let mut out = Stretch::new(out, first + i * chunk, width, stream);
                fill_stretch(trajectory, sys, context, &mut out);
            };
            let rows = &mut rows[(first - from) * width..(end - from) * width];
            if chunk >= end - first {
                // one stretch: on this thread, without handing it to the pool and waiting
                fill(&mut context(), (0, rows));
            } else {
                let stretches = rows.chunks_mut(chunk * width).enumerate().collect();
                share(stretches, context, fill);
            }
        }
    }
}

/// The shape of the table of every variable of `sys`, built at its first table and kept with
/// it (None if the system keeps something else).
fn kept_shape(sys: &System) -> Option<&Shape> {
    sys.derived.get_or_init(|| Shape::new(sys, None))
}

/// Evaluates the rows of one stretch of `trajectory` and writes every one of its cells.
fn fill_stretch(
    trajectory: (&Trajectory, &[DiscreteState]),
    sys: &System,
    (block, rows_of): &mut Context,
    out: &mut Stretch,
) {
    let tr = trajectory.0;
    let rows = out.first..out.first + out.data.len() / out.width;
    rows_of.visit(trajectory, rows, sys, &mut |r, sys, row| {
        block.push(sys, r, (tr.disc[r], tr.t[r]), row);
        if block.rows.len() == BLOCK {
            block.flush(sys, &tr.t, out);
        }
    });
    block.flush(sys, &tr.t, out);
    settle(out);
    assert_eq!(
        out.written,
        out.data.len(),
        "every cell of the stretch written"
    );
}

/// What a thread keeps from one stretch of rows to the next: its frames and its evaluator.
type Context<'a> = (Block<'a>, RowEvaluator);

#[cfg(test)]
mod tests {
    use super::frame::Layout;
    use super::ops::PAGE;
    use crate::result::output_expr::compile;
    use crate::result::recorder::Recorder;
    use crate::ModelSpec;

    /// The row-by-row recorder's table, as it was computed before the columns.
    fn by_rows(r: &super::SimResult) -> Vec<f64> {
        let sys = &*r.system;
        let width = r.names.len();
        let mut recorder = Recorder::new(sys, r.rows());
        r.visit_rows(|row, sys, evaluated| match evaluated {
            Some((ws, disc)) => recorder.record(sys, ws, disc),
            None => {
                recorder.data.push(r.trajectory.t[row]);
                (recorder.data).extend(std::iter::repeat_n(f64::NAN, width - 1));
            }
        });
        recorder.data
    }

    /// A drivetrain of `n` clutches between `n + 1` inertias, each clutch closing at its own
    /// time (CoupledClutches, longer).
    fn clutch_chain(n: usize) -> String {
        let mut connect = vec![
            r#"["sin1.y", "torque.tau"]"#.to_string(),
            r#"["fixed.flange", "torque.support"]"#.to_string(),
            r#"["torque.flange", "J0.flange_a"]"#.to_string(),
        ];
        let mut components = String::from(
            "J0 = { type = \"Inertia\", J = 1.0, phi = 0.0, w = 10.0 }\n\
             torque = { type = \"Torque\", useSupport = true }\n\
             sin1 = { type = \"Sine\", amplitude = 10.0, f = 5.0 }\n\
             fixed = { type = \"Fixed\" }\n",
        );
        for k in 1..=n {
            connect.push(format!(r#"["J{}.flange_b", "clutch{k}.flange_a"]"#, k - 1));
            connect.push(format!(r#"["clutch{k}.flange_b", "J{k}.flange_a"]"#));
            connect.push(format!(r#"["step{k}.y", "clutch{k}.f_normalized"]"#));
            components += &format!(
                "J{k} = {{ type = \"Inertia\", J = 1.0, phi = 0.0, w = 0.0 }}\n\
                 clutch{k} = {{ type = \"Clutch\", peak = 1.1, fn_max = 20.0 }}\n\
                 step{k} = {{ type = \"Step\", startTime = {} }}\n",
                0.02 * k as f64
            );
        }
        format!(
            "name = \"Chain\"\nconnect = [{}]\n[experiment]\nStartTime = 0.0\nStopTime = 0.5\n\
             Interval = 0.001\nTolerance = 1e-6\n[components]\n{components}",
            connect.join(", ")
        )
    }

    /// A frame of several pages (16 clutches: 304 element fields alone) gives the row
    /// recorder's values bit for bit too.
    #[test]
    fn frames_of_several_pages_equal_rows() {
        let spec = ModelSpec::from_toml(&clutch_chain(16), ".").expect("valid model");
        let r = crate::simulate(&spec).expect("runs");
        let (columns, rows) = (r.table().expect("fits"), by_rows(&r));
        assert_eq!(columns.len(), rows.len());
        let mut general = Vec::new();
        let outs = r.system.outputs.iter();
        let flat: Vec<_> = outs.map(|(_, o)| compile(o, 1.0, &mut general)).collect();
        let frame = Layout::new(&r.system, &flat, &general).len;
        assert!(frame > 2 * PAGE, "{frame} values: more than two pages");
        let same = (columns.iter().zip(&rows)).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "the columns differ from the rows");
    }

    /// Every element's continuous variables are the fields `value_field` reads (the table's
    /// shortcut past the virtual `variable`), on values that differ in every field.
    #[test]
    fn continuous_variables_are_fields() {
        use super::ops::FIELDS;
        use crate::switching::element::SwitchVar as V;
        use crate::switching::element::{is_discrete, value_field, ElementValues, Losses};
        // the continuous ones, then the modes and flags
        let discrete = [
            V::Mode,
            V::Locked,
            V::StartForward,
            V::StartBackward,
            V::Free,
            V::Stuck,
            V::TauEtaPos,
        ];
        let all = FIELDS.iter().chain(&discrete).copied();
        let v = ElementValues {
            phi: 1.5,
            w: 2.5,
            a: 3.5,
            tau: 4.5,
            sa: 5.5,
            loss: 6.5,
            withheld: 0.0,
            held: true,
            tau0: 7.5,
            tau0_max: 8.5,
            fn_: 9.5,
            mu: 10.5,
            tau_b: 11.5,
            tau_support: 12.5,
            tau_loss: 13.5,
            tau_eta: 14.5,
            slope: 15.5,
            losses: Losses {
                eta1: 16.5,
                eta2: 17.5,
                tbf1: 18.5,
                tbf2: 19.5,
                tbf_a: 20.5,
            },
        };
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
        let text = std::fs::read_to_string(format!("{dir}/HeatLosses.toml")).expect("example");
        let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
        let sys = crate::assembly::CompiledModel::new(spec)
            .expect("builds")
            .system();
        assert!(
            sys.switching.len() >= 5,
            "friction, brake, one-way clutch, lossy gear"
        );
        for e in &sys.switching {
            let st = e.initial_state();
            for var in all.clone() {
                let field = value_field(var);
                assert_eq!(field.is_none(), is_discrete(var), "{var:?}");
                // the frame holds exactly the continuous ones
                assert_eq!(FIELDS.contains(&var), field.is_some(), "{var:?}");
                if let Some(field) = field {
                    let (a, b) = (e.variable(&st, &v, var), field(&v));
                    assert_eq!(a.to_bits(), b.to_bits(), "{} {var:?}", e.name());
                }
            }
        }
    }

    /// The table computed on `threads` threads (as many stretches of rows, and more, as the
    /// pool asks for).
    fn table_on(r: &super::SimResult, threads: usize) -> Vec<f64> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
        pool.expect("a thread pool").install(|| r.compute_table())
    }

    /// Column by column gives the row recorder's values bit for bit (more rows than a block,
    /// events, every kind of column: heat, a lossy gear, flange torques), however many
    /// stretches the rows are computed in: one thread, or five (stretches that start inside a
    /// mode, each thread factoring the modes it meets), or seven stretches one after the other
    /// on one thread with the same workspace, modes and frames (nothing of one stretch leaks
    /// into the next).
    #[test]
    fn columns_equal_rows_bit_for_bit() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
        for name in [
            "CoupledClutches",
            "HeatLosses",
            "SimpleGearShift",
            "Friction",
        ] {
            let text = std::fs::read_to_string(format!("{dir}/{name}.toml")).expect("example");
            let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
            let r = crate::simulate(&spec).expect("runs");
            let rows = by_rows(&r);
            let one = rayon::ThreadPoolBuilder::new().num_threads(1).build();
            let seven = one
                .expect("a thread pool")
                .install(|| r.columns_in(None, |rows| rows.div_ceil(7)));
            let tables = [
                ("one thread", table_on(&r, 1)),
                ("five threads", table_on(&r, 5)),
                ("seven stretches on one thread", seven),
            ];
            for (how, columns) in tables {
                assert_eq!(columns.len(), rows.len(), "{name}");
                let same = columns
                    .iter()
                    .zip(&rows)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "{name}, {how}: the columns differ from the rows");
            }
        }
    }

    /// The table's shape is kept with its system: the second run of a compiled model reuses
    /// the first's and gives its table bit for bit; a variant (another system, other values)
    /// builds its own and gives the row recorder's values.
    #[test]
    fn shape_kept_with_its_system() {
        use crate::assembly::CompiledModel;
        use crate::simulation::run;
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
        let text = std::fs::read_to_string(format!("{dir}/CoupledClutches.toml")).expect("example");
        let model = CompiledModel::new(ModelSpec::from_toml(&text, dir).expect("valid model"));
        let model = model.expect("builds");
        let first = run(model.system()).expect("runs");
        let kept = |r: &super::SimResult| {
            r.system
                .derived
                .get::<super::Shape>()
                .map(|s| s as *const _)
        };
        assert!(kept(&first).is_none(), "nothing kept before a table");
        let table = first.table().expect("fits").to_vec();
        let second = run(model.system()).expect("runs");
        assert!(kept(&second).is_some(), "the first table's shape kept");
        let before = kept(&second);
        let again = second.table().expect("fits");
        let same = table
            .iter()
            .zip(again)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(
            same && table.len() == again.len(),
            "the second run's table differs"
        );
        assert_eq!(
            kept(&second),
            before,
            "the kept shape reused, not built again"
        );
        let float = toml::Value::Float(2.5);
        let variant = model.with(&[("J1.J", float)]).expect("a variant");
        let r = run(variant.system()).expect("runs");
        let (columns, rows) = (r.table().expect("fits"), by_rows(&r));
        assert!(
            columns.iter().zip(&table).any(|(a, b)| a != b),
            "J1.J changed nothing"
        );
        let same = columns
            .iter()
            .zip(&rows)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "the variant's table differs from its rows");
    }
}
