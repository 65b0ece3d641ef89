//! Every variable of every row, computed column by column. Row by row, each of the ~100 columns
//! of a row went through a `match` on its kind, bounds checks and a call per switching-element
//! variable, which cost more than the row's evaluation itself. Here the rows are evaluated in
//! blocks: each evaluation only copies the workspace arrays the columns read (angles, speeds,
//! accelerations, signals, law torques, element values); then the flange cut torques are solved
//! for the whole block (`flanges.rs`) and each column is filled for the block in one tight loop
//! (an element's continuous variable read as a field of its values, a mode or flag once per run
//! of rows in one discrete state). The arithmetic of each value is the row recorder's
//! (`s * x + offset`, the same calls), so the values are bit for bit those of `Recorder::record`.

use super::flanges::{BlockFlanges, Planes};
use super::source::Source;
use super::{compile, Flat, SimResult};
use crate::engine::eval::{DiscreteState, Workspace};
use crate::error::SimError;
use crate::switching::element::{is_discrete, value_field, ElementValues, SwitchVar};
use crate::system::System;

/// Rows evaluated before their columns are filled: enough to amortize a column's dispatch,
/// few enough that the copied workspaces stay in cache and memory stays bounded.
const BLOCK: usize = 64;

/// The most values the table of every variable may hold (2.4 GB), as for a run's states.
pub const MAX_TABLE_VALUES: f64 = 3.0e8;

impl SimResult {
    /// All variables, row-major (`rows × names.len()`), computed on first use; a usage error
    /// when they would not fit in memory (a run records only its states, see `check_table`).
    pub fn table(&self) -> Result<&[f64], SimError> {
        self.check_table()?;
        Ok(self.table.get_or_init(|| self.compute_table()))
    }

    /// All variables as a vector of its own: the one `table()` keeps, or computed without
    /// keeping it, for a caller that keeps it (Python hands it to NumPy without a copy).
    pub fn table_vec(&self) -> Result<Vec<f64>, SimError> {
        self.check_table()?;
        Ok(match self.table.get() {
            Some(table) => table.clone(),
            None => self.compute_table(),
        })
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

    /// All variables, row-major (`rows × names.len()`), filled column by column.
    pub(super) fn compute_table(&self) -> Vec<f64> {
        self.compute_columns(None)
    }

    /// Time and the outputs (all, or only output `only`), row-major, filled column by column.
    pub(super) fn compute_columns(&self, only: Option<usize>) -> Vec<f64> {
        let tr = &self.trajectory;
        let width = only.map_or(self.system.outputs.len(), |_| 1) + 1;
        let mut data = vec![0.0; tr.rows() * width];
        // Each stretch of rows between parameter changes is filled from its own system: the
        // values (an inertia's J, a law's constants) enter the compiled columns and the flange
        // torques' terms, the shapes are the same throughout.
        for (first, end, sys) in self.segments() {
            let mut general = Vec::new();
            let flat: Vec<Flat> = (sys.outputs.iter().enumerate())
                .filter(|&(i, _)| only.is_none_or(|o| o == i))
                .map(|(_, (_, out))| compile(out, 1.0, &mut general))
                .collect();
            let mut block = Block::new(sys, &flat, &general);
            self.visit_segment(first..end, sys, &mut |r, sys, row| {
                block.push(sys, r, row);
                if block.rows.len() == BLOCK {
                    block.flush(sys, self, &flat, &mut data, width);
                }
            });
            block.flush(sys, self, &flat, &mut data, width);
        }
        data
    }
}

/// Copies of the workspace arrays of up to `BLOCK` evaluated rows (each array row after row).
struct Block {
    /// The result rows held (consecutive), and whether each could be evaluated (a mode that cannot be
    /// factored leaves every variable but time NaN, as the row recorder does).
    rows: Vec<(usize, bool)>,
    phi: Vec<f64>,
    w: Vec<f64>,
    a: Vec<f64>,
    signals: Vec<f64>,
    law_tau: Vec<f64>,
    elements: Vec<ElementValues>,
    general_values: Vec<f64>,
    general: Vec<Source>,
    /// The flange cut torques, if a column reads them.
    flanges: Option<BlockFlanges>,
    needs_elements: bool,
}

impl Block {
    fn new(sys: &System, flat: &[Flat], general: &[crate::system::Out]) -> Self {
        let flanges = (sys.flange_torques.ports() > 0
            && (flat.iter()).any(|f| matches!(f, Flat::Flange(..))))
        .then(|| BlockFlanges::new(sys));
        let needs_elements = flanges.as_ref().is_some_and(|f| f.reads_elements())
            || (flat.iter()).any(|f| matches!(f, Flat::Switch(_, var, _) if !is_discrete(*var)));
        Self {
            rows: Vec::with_capacity(BLOCK),
            phi: Vec::new(),
            w: Vec::new(),
            a: Vec::new(),
            signals: Vec::new(),
            law_tau: Vec::new(),
            elements: Vec::new(),
            general_values: Vec::new(),
            general: general.iter().map(Source::of).collect(),
            flanges,
            needs_elements,
        }
    }

    /// Copies what the columns read from row `r`'s evaluation (or zeros, for a row that has none).
    fn push(&mut self, sys: &System, r: usize, row: Option<(&Workspace, &DiscreteState)>) {
        let Some((ws, disc)) = row else {
            self.rows.push((r, false));
            self.pad(sys);
            return;
        };
        self.rows.push((r, true));
        self.phi.extend_from_slice(&ws.phi);
        self.w.extend_from_slice(&ws.w);
        self.a.extend_from_slice(&ws.a);
        self.signals.extend_from_slice(&ws.signals);
        self.law_tau.extend_from_slice(&ws.law_tau);
        if self.needs_elements {
            self.elements.extend_from_slice(&ws.elements);
        }
        if let Some(f) = &mut self.flanges {
            f.push(sys, ws, disc);
        }
        // outputs are `Scaled` trees that `compile` unwraps: none left here reads a flange torque
        (self.general_values).extend(self.general.iter().map(|g| g.eval(sys, ws, disc, &[])));
    }

    /// Keeps the arrays aligned for a row without an evaluation (its values are not read).
    fn pad(&mut self, sys: &System) {
        let n = sys.nodes;
        self.phi.resize(self.phi.len() + n, 0.0);
        self.w.resize(self.w.len() + n, 0.0);
        self.a.resize(self.a.len() + n, 0.0);
        self.signals
            .resize(self.signals.len() + sys.signals.slots, 0.0);
        self.law_tau
            .resize(self.law_tau.len() + sys.laws.len(), 0.0);
        if self.needs_elements {
            let e = self.elements.len() + sys.switching.len();
            self.elements.resize(e, ElementValues::default());
        }
        if let Some(f) = &mut self.flanges {
            f.pad();
        }
        let g = self.general_values.len() + self.general.len();
        self.general_values.resize(g, 0.0);
    }

    /// Fills every column of the held rows into `data` and empties the block.
    fn flush(
        &mut self,
        sys: &System,
        result: &SimResult,
        flat: &[Flat],
        data: &mut [f64],
        width: usize,
    ) {
        // the shapes, the same for every system of the run
        let tr = &result.trajectory;
        let Some(&(first, _)) = self.rows.first() else {
            return;
        };
        let n = self.rows.len();
        for &(r, _) in &self.rows {
            data[r * width] = tr.t[r];
        }
        if let Some(f) = &mut self.flanges {
            let planes = Planes {
                a: &self.a,
                law_tau: &self.law_tau,
                elements: &self.elements,
            };
            f.solve(sys, n, &planes);
        }
        let tau = self.flanges.as_ref().map_or(&[][..], |f| &f.tau);
        for (c, f) in flat.iter().enumerate() {
            let fill = match *f {
                Flat::Phi(node, s, offset) => column(&self.phi, sys.nodes, node, s, Some(offset)),
                Flat::W(node, s) => column(&self.w, sys.nodes, node, s, None),
                Flat::A(node, s) => column(&self.a, sys.nodes, node, s, None),
                Flat::Signal(slot, s) => column(&self.signals, sys.signals.slots, slot, s, None),
                Flat::LawTau(k, s) => column(&self.law_tau, sys.laws.len(), k, s, None),
                // the torques are port after port: a port's rows are consecutive
                Flat::Flange(p, s) => ColumnFill {
                    plane: &tau[p * n..],
                    stride: 1,
                    s,
                    offset: None,
                },
                Flat::General(i, s) => column(&self.general_values, self.general.len(), i, s, None),
                Flat::Switch(k, var, s) => {
                    let col = c + 1;
                    self.fill_switch(sys, result, SwitchColumn { k, var, s, col }, data, width);
                    continue;
                }
            };
            fill.write(first, n, c + 1, data, width);
        }
        for &(r, ok) in &self.rows {
            if !ok {
                data[r * width + 1..(r + 1) * width].fill(f64::NAN);
            }
        }
        self.clear();
    }

    /// A switching element's variable: from its values row by row, or, for a mode or flag
    /// (a function of the discrete state alone), once per run of rows in one discrete state.
    fn fill_switch(
        &self,
        sys: &System,
        result: &SimResult,
        column: SwitchColumn,
        data: &mut [f64],
        width: usize,
    ) {
        let SwitchColumn { k, var, s, col } = column;
        let element = &*sys.switching[k];
        let (tr, discs) = (&result.trajectory, &result.discs);
        let ne = sys.switching.len();
        let first = self.rows[0].0;
        let ids = &tr.disc[first..first + self.rows.len()];
        let rows = data[first * width..(first + ids.len()) * width].chunks_exact_mut(width);
        let state = |id: u32| &discs[id as usize].switching[k];
        let mut last = (ids[0], state(ids[0]));
        if is_discrete(var) {
            let none = ElementValues::default();
            let mut v = s * element.variable(last.1, &none, var);
            for (row, &id) in rows.zip(ids) {
                if id != last.0 {
                    last = (id, state(id));
                    v = s * element.variable(last.1, &none, var);
                }
                row[col] = v;
            }
        } else if let Some(field) = value_field(var) {
            // a continuous variable is a field of the values (`variable` would return it)
            let values = self.elements.iter().skip(k).step_by(ne);
            for (row, v) in rows.zip(values) {
                row[col] = s * field(v);
            }
        } else {
            let values = self.elements.iter().skip(k).step_by(ne);
            for ((row, &id), v) in rows.zip(ids).zip(values) {
                if id != last.0 {
                    last = (id, state(id));
                }
                row[col] = s * element.variable(last.1, v, var);
            }
        }
    }

    fn clear(&mut self) {
        self.rows.clear();
        for plane in [
            &mut self.phi,
            &mut self.w,
            &mut self.a,
            &mut self.signals,
            &mut self.law_tau,
            &mut self.general_values,
        ] {
            plane.clear();
        }
        self.elements.clear();
    }
}

/// Variable `var` of switching element `k`, times `s`, into column `col`.
struct SwitchColumn {
    k: usize,
    var: SwitchVar,
    s: f64,
    col: usize,
}

/// One column read from a copied array: every `stride`-th value of `plane`, times `s`, plus an
/// angle's `offset` (added even when 0, as the row recorder does: −0 + 0 is +0).
struct ColumnFill<'a> {
    plane: &'a [f64],
    stride: usize,
    s: f64,
    offset: Option<f64>,
}

/// The column of entry `i` of `plane`'s rows of `len` values.
fn column(plane: &[f64], len: usize, i: usize, s: f64, offset: Option<f64>) -> ColumnFill<'_> {
    ColumnFill {
        plane: &plane[i..],
        stride: len.max(1),
        s,
        offset,
    }
}

impl ColumnFill<'_> {
    /// Writes column `col` of the consecutive rows from `first` (`data` is row-major).
    fn write(&self, first: usize, rows: usize, col: usize, data: &mut [f64], width: usize) {
        // strided iterators rather than row slices: no bounds check per cell
        let out = data[first * width + col..]
            .iter_mut()
            .step_by(width)
            .take(rows);
        let cells = out.zip(self.plane.iter().step_by(self.stride));
        let s = self.s;
        match self.offset {
            Some(offset) => cells.for_each(|(y, x)| *y = s * x + offset),
            None => cells.for_each(|(y, x)| *y = s * x),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::Recorder;
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

    /// Every element's continuous variables are the fields `value_field` reads (the table's
    /// shortcut past the virtual `variable`), on values that differ in every field.
    #[test]
    fn continuous_variables_are_fields() {
        use crate::switching::element::SwitchVar as V;
        use crate::switching::element::{is_discrete, value_field, ElementValues, Losses};
        let all = [
            V::Phi,
            V::W,
            V::A,
            V::Tau,
            V::Sa,
            V::LossPower,
            V::Tau0,
            V::Tau0Max,
            V::Fn,
            V::Mu,
            V::TauB,
            V::TauSupport,
            V::TauLoss,
            V::TauEta,
            V::Eta1,
            V::Eta2,
            V::Tbf1,
            V::Tbf2,
            V::TbfA,
            V::Mode,
            V::Locked,
            V::StartForward,
            V::StartBackward,
            V::Free,
            V::Stuck,
            V::TauEtaPos,
        ];
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
            for var in all {
                let field = value_field(var);
                assert_eq!(field.is_none(), is_discrete(var), "{var:?}");
                if let Some(field) = field {
                    let (a, b) = (e.variable(&st, &v, var), field(&v));
                    assert_eq!(a.to_bits(), b.to_bits(), "{} {var:?}", e.name());
                }
            }
        }
    }

    /// Column by column gives the row recorder's values bit for bit (more rows than a block,
    /// events, every kind of column: heat, a lossy gear, flange torques).
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
            let (columns, rows) = (r.table().expect("fits"), by_rows(&r));
            assert_eq!(columns.len(), rows.len(), "{name}");
            let same = columns
                .iter()
                .zip(&rows)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "{name}: the columns differ from the rows");
        }
    }
}
