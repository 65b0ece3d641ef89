//! The per-mode linear solve (design §3): accelerations `a` and multipliers `λ` from
//!
//! ```text
//! [ M  C ] [ a ]   [ f ]
//! [ G  0 ] [ λ ] = [ 0 ]
//! ```
//!
//! G holds the permanent constraints (gears, speed sources), one row per LossyGear, and the
//! rows of the friction elements and gears that are locked; C holds the columns through which
//! each multiplier acts on the nodes (C = Gᵀ except a rolling LossyGear, whose loss torque
//! follows its torque). The matrix depends on the mode only — factor once per mode and reuse.
//! A locked row that depends on the others (two elements locking the same motion) is left out:
//! its torque is 0, one of the consistent splits MSL allows (spec §7.9). Locked friction
//! elements come before locked gears, as in the reference results: a bearing stuck together
//! with a gear carries the load first.

use std::cell::RefCell;

use nalgebra::{DMatrix, DVector};

use super::massless::Massless;
use super::mode_solver::{column_entries, ModeSolver};
use crate::error::SimError;
use crate::linalg::{Factorization, RowBasis, Triplets};
use crate::switching::element::{Column, ModeKey};
use crate::system::{Rel, System};

/// Where a switching element's multipliers sit in the solution of one mode.
#[derive(Debug, Clone, Copy, Default)]
pub struct ElementRows {
    /// Row of its permanent row's multiplier (a LossyGear's `τa`).
    pub permanent: Option<usize>,
    /// Row of its lock multiplier, when locked and independent of the rows before.
    pub lock: Option<usize>,
    /// The mode's rows hold its relative motion: its speed cannot change, so it is not watched
    /// for zero crossings (no events from round-off).
    pub held: bool,
    /// A prescribed motion (with the other rows) sets its relative motion, which may change:
    /// locked, its row is dependent and it could hold nothing (see `eval::forced_breakaway`).
    pub forced: bool,
}

pub struct ModeMatrix {
    factors: Box<dyn Factorization>,
    pub size: usize,
    /// Each switching element's rows.
    pub element_rows: Vec<ElementRows>,
    /// The mode this matrix was factored for.
    pub keys: Vec<ModeKey>,
    /// The elements whose loss slope may differ from the factored one (unlocked, with a
    /// permanent row and a slope column), found once per mode so an evaluation of a mode
    /// without them looks at no element.
    sloped: Vec<usize>,
    /// Scratch for the rank-one correction (`solve_with_slopes`), so an evaluation allocates
    /// nothing.
    scratch: RefCell<Vec<f64>>,
    /// Shafts without inertia whose speeds are algebraic in this mode (rows `Nᵀa = 0` last).
    pub massless: Option<Massless>,
}

impl ModeMatrix {
    /// Factors the system of the mode `keys` with `solver`; the locks that depend on others
    /// are left out (`RowBasis`, in row order).
    pub fn factor(
        sys: &System,
        keys: &[ModeKey],
        time: f64,
        solver: &mut ModeSolver,
    ) -> Result<Self, SimError> {
        let (mut rows, element_rows) = mode_rows(sys, keys);
        let g: Vec<&Rel> = rows.iter().map(|(rel, _)| *rel).collect();
        let massless = Massless::of(sys, &g).map_err(|nodes| SimError::SingularMode {
            time,
            detail: singular_detail(sys, keys, &nodes),
        })?;
        if let Some(ml) = &massless {
            rows.extend(ml.basis.iter().map(|v| (v, Column::Same)));
        }
        let m = kkt_matrix(sys, &rows);
        let owners = (massless.is_none()).then(|| row_owners(sys, &element_rows, rows.len()));
        let factors =
            (solver.factor(sys, &m, owners.as_deref())).map_err(|_| SimError::SingularMode {
                time,
                detail: singular_detail(sys, keys, &massless_nodes(sys)),
            })?;
        let sloped = (sys.switching.iter().zip(keys).enumerate())
            .filter(|(k, (e, key))| {
                !key.locked && element_rows[*k].permanent.is_some() && e.slope_column().is_some()
            })
            .map(|(k, _)| k)
            .collect();
        Ok(Self {
            factors,
            sloped,
            size: m.size,
            element_rows,
            keys: keys.to_vec(),
            scratch: RefCell::new(Vec::new()),
            massless,
        })
    }

    /// Memory held by the factors (bytes, about).
    pub fn bytes(&self) -> usize {
        self.factors.bytes()
    }

    /// Solves in place: on entry `[f; 0]`, on exit `[a; λ]`.
    pub fn solve(&self, rhs: &mut [f64]) {
        self.factors.solve_in_place(rhs);
    }

    /// Solves with elements whose loss slope differs from the factored one (a LossyGear whose
    /// losses depend on the speed): each such element's permanent column changes by `Δs·ℓ`, a
    /// rank-one change, so the factored matrix serves through the Woodbury identity instead of
    /// a new factorization per evaluation. `slope(k)` is element k's current slope.
    /// Allocates only when the slopes of two or more elements have changed.
    pub fn solve_with_slopes(&self, sys: &System, slope: impl Fn(usize) -> f64, rhs: &mut [f64]) {
        self.solve(rhs);
        // a plain loop: the adaptor chain it replaces was not inlined (a call per evaluation)
        let mut first = None;
        for (at, &k) in self.sloped.iter().enumerate() {
            let Some(change) = self.slope_change(sys, k, slope(k)) else {
                continue;
            };
            if first.is_none() {
                first = Some(change);
                continue;
            }
            let rest = self.sloped[at + 1..].iter();
            let all: Vec<_> = (first.into_iter().chain([change]))
                .chain(rest.filter_map(|&k| self.slope_change(sys, k, slope(k))))
                .collect();
            self.woodbury(&all, rhs);
            return;
        }
        // one gear (the common case): a scalar Woodbury step in the reused scratch vector,
        // the arithmetic of the general path's 1×1 LU
        if let Some(first) = first {
            self.woodbury_one(first, rhs);
        }
    }

    /// Element k's changed column, its row and the change of its slope; None if unchanged.
    #[inline]
    fn slope_change<'s>(
        &self,
        sys: &'s System,
        k: usize,
        slope: f64,
    ) -> Option<(&'s Rel, usize, f64)> {
        if slope == self.keys[k].slope {
            return None;
        }
        let row = self.element_rows[k].permanent?;
        let column = sys.switching[k].slope_column()?;
        Some((column, sys.nodes + row, slope - self.keys[k].slope))
    }

    /// `solve_with_slopes` for a single changed column, without allocating.
    fn woodbury_one(&self, (column, r, ds): (&Rel, usize, f64), rhs: &mut [f64]) {
        let mut u = self.scratch.borrow_mut();
        u.clear();
        u.resize(self.size, 0.0);
        match sparse_column(column, ds) {
            // a gear's column has two or three entries of the system's many
            Some((entries, len)) => self.factors.solve_sparse(&entries[..len], &mut u),
            None => {
                for &(i, c) in &column.terms {
                    u[i] += ds * c;
                }
                self.solve(&mut u);
            }
        }
        let s = 1.0 + u[r];
        if s == 0.0 {
            rhs.fill(f64::NAN);
            return;
        }
        let w = rhs[r] / s;
        rhs.iter_mut().zip(u.iter()).for_each(|(x, z)| *x -= w * z);
    }

    /// The Woodbury identity for several changed columns (Z = A⁻¹U, then an m×m solve).
    fn woodbury(&self, changed: &[(&Rel, usize, f64)], rhs: &mut [f64]) {
        // Z = A⁻¹U with U's columns Δs·ℓ in the node rows.
        let z: Vec<Vec<f64>> = changed
            .iter()
            .map(|&(column, _, ds)| {
                let mut u = vec![0.0; self.size];
                for &(i, c) in &column.terms {
                    u[i] += ds * c;
                }
                self.solve(&mut u);
                u
            })
            .collect();
        let m = changed.len();
        let s = DMatrix::from_fn(m, m, |i, j| (i == j) as u8 as f64 + z[j][changed[i].1]);
        let y = DVector::from_iterator(m, changed.iter().map(|&(_, r, _)| rhs[r]));
        match s.lu().solve(&y) {
            Some(w) => {
                for (j, zj) in z.iter().enumerate() {
                    rhs.iter_mut().zip(zj).for_each(|(x, z)| *x -= w[j] * z);
                }
            }
            // singular at this speed: no answer, and the driver reports the non-finite state
            None => rhs.fill(f64::NAN),
        }
    }
}

/// Most entries `sparse_column` takes.
const SPARSE_TERMS: usize = 4;

/// `ds·column` as `woodbury_one`'s dense vector would hold it (each entry `0 + Σ ds·c` over the
/// terms on its node, in order), its entries by increasing index; None for a long column.
fn sparse_column(column: &Rel, ds: f64) -> Option<([(usize, f64); SPARSE_TERMS], usize)> {
    if column.terms.len() > SPARSE_TERMS {
        return None;
    }
    let mut entries = [(0, 0.0); SPARSE_TERMS];
    let mut len = 0;
    for &(i, c) in &column.terms {
        match entries[..len].iter_mut().find(|(j, _)| *j == i) {
            Some(entry) => entry.1 += ds * c,
            None => {
                entries[len] = (i, 0.0 + ds * c);
                len += 1;
            }
        }
    }
    entries[..len].sort_unstable_by_key(|&(i, _)| i);
    Some((entries, len))
}

/// The rows of G in order — permanent constraints, the switching elements' permanent rows,
/// then their independent lock rows by rank — with their columns, and where each element's sit.
fn mode_rows<'a>(
    sys: &'a System,
    keys: &[ModeKey],
) -> (Vec<(&'a Rel, Column<'a>)>, Vec<ElementRows>) {
    let mut rows: Vec<(&Rel, Column)> = Vec::new();
    let mut basis = RowBasis::new(sys.nodes);
    // the kept rows without the prescribed motions: what holds a speed constant
    let mut fixed = sys.prescribes().then(|| RowBasis::new(sys.nodes));
    for c in &sys.constraints {
        basis.accept(&c.rel.terms);
        if let (Some(f), None) = (&mut fixed, &c.prescribed) {
            f.accept(&c.rel.terms);
        }
        rows.push((&c.rel, Column::Same));
    }
    let mut element_rows = vec![ElementRows::default(); sys.switching.len()];
    for (k, (e, key)) in sys.switching.iter().zip(keys).enumerate() {
        if let Some((rel, column)) = e.permanent_row(*key) {
            basis.accept(&rel.terms);
            if let Some(f) = &mut fixed {
                f.accept(&rel.terms);
            }
            element_rows[k].permanent = Some(rows.len());
            rows.push((rel, column));
        }
    }
    let mut ranks: Vec<u8> = sys.switching.iter().map(|e| e.lock_rank()).collect();
    ranks.sort_unstable();
    ranks.dedup();
    for rank in ranks {
        for (k, (e, key)) in sys.switching.iter().zip(keys).enumerate() {
            if key.locked && e.lock_rank() == rank && basis.accept(&e.motion().terms) {
                if let Some(f) = &mut fixed {
                    f.accept(&e.motion().terms);
                }
                element_rows[k].lock = Some(rows.len());
                rows.push((e.motion(), e.lock_column()));
            }
        }
    }
    // Elements whose motion the kept rows hold: their speed cannot change in this mode.
    for (e, rows) in sys.switching.iter().zip(&mut element_rows) {
        let determined = basis.depends(&e.motion().terms);
        rows.held = match &mut fixed {
            Some(f) => f.depends(&e.motion().terms),
            None => determined,
        };
        rows.forced = determined && !rows.held;
    }
    (rows, element_rows)
}

/// `[M C; G 0]` as triplets.
fn kkt_matrix(sys: &System, rows: &[(&Rel, Column)]) -> Triplets {
    let n = sys.nodes;
    let mut m = Triplets::new(n + rows.len());
    for i in 0..n {
        m.add(i, i, sys.mass[i]);
    }
    for (r, (row, column)) in rows.iter().enumerate() {
        for &(i, c) in &row.terms {
            m.add(n + r, i, c);
        }
        for (i, c) in column_entries(row, *column) {
            m.add(i, n + r, c);
        }
    }
    m
}

/// The element each row after the permanent constraints belongs to, and whether it is the
/// element's lock row (else its permanent row).
fn row_owners(sys: &System, element_rows: &[ElementRows], rows: usize) -> Vec<(usize, bool)> {
    let first = sys.constraints.len();
    let mut owners = vec![(0, false); rows - first];
    for (k, er) in element_rows.iter().enumerate() {
        if let Some(r) = er.permanent {
            owners[r - first] = (k, false);
        }
        if let Some(r) = er.lock {
            owners[r - first] = (k, true);
        }
    }
    owners
}

fn massless_nodes(sys: &System) -> Vec<usize> {
    (0..sys.nodes).filter(|&i| sys.mass[i] == 0.0).collect()
}

/// The shafts as the messages name them: `[J1.flange_b, spring.flange_a], …`.
pub fn shaft_names(sys: &System, nodes: &[usize]) -> String {
    let names: Vec<String> = (nodes.iter())
        .map(|&i| format!("[{}]", sys.node_label(i)))
        .collect();
    names.join(", ")
}

/// Whether some shaft's motion is determined by nothing — no inertia, no damper, no row — even
/// with every switching element locked (the most any mode holds). Such a model fails in every
/// mode; `check` reports it before a run.
pub fn undetermined_shafts(sys: &System) -> Option<Vec<usize>> {
    let keys: Vec<ModeKey> = (sys.switching.iter())
        .map(|_| ModeKey {
            locked: true,
            slope: 0.0,
        })
        .collect();
    let (rows, _) = mode_rows(sys, &keys);
    let g: Vec<&Rel> = rows.iter().map(|(rel, _)| *rel).collect();
    Massless::of(sys, &g).err()
}

fn singular_detail(sys: &System, keys: &[ModeKey], nodes: &[usize]) -> String {
    let massless = nodes;
    let locked: Vec<&str> = sys
        .switching
        .iter()
        .zip(keys)
        .filter(|(_, key)| key.locked)
        .map(|(e, _)| e.name())
        .collect();
    let mut msg = String::new();
    if !massless.is_empty() {
        msg += &format!(
            "; shafts without inertia: {} — give each an Inertia or a Damper, or hold it with a constraint",
            shaft_names(sys, massless)
        );
    }
    if !locked.is_empty() {
        msg += &format!("; locked elements: {}", locked.join(", "));
    }
    msg
}
