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

use nalgebra::{DMatrix, DVector, Dyn, LU};

use crate::error::SimError;
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
}

pub struct ModeMatrix {
    lu: LU<f64, Dyn, Dyn>,
    pub size: usize,
    /// Each switching element's rows.
    pub element_rows: Vec<ElementRows>,
    /// The mode this matrix was factored for.
    pub keys: Vec<ModeKey>,
}

/// Keeps rows that are linearly independent of those kept before (Gram–Schmidt).
struct Independent(Vec<Vec<f64>>);

impl Independent {
    /// The row's norm and what is left of it after removing the kept rows' directions.
    fn residual(&self, rel: &Rel, n: usize) -> (f64, Vec<f64>) {
        let mut v = vec![0.0; n];
        for &(i, c) in &rel.terms {
            v[i] += c;
        }
        let norm0 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for q in &self.0 {
            let dot: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(x, qi)| *x -= dot * qi);
        }
        (norm0, v)
    }

    /// Whether the row is a combination of the rows kept so far.
    fn depends(&self, rel: &Rel, n: usize) -> bool {
        let (norm0, v) = self.residual(rel, n);
        norm0 > 0.0 && v.iter().map(|x| x * x).sum::<f64>().sqrt() <= 1e-10 * norm0
    }

    /// Keeps the row if it is independent of the rows kept so far.
    fn accept(&mut self, rel: &Rel, n: usize) -> bool {
        let (norm0, mut v) = self.residual(rel, n);
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm0 == 0.0 || norm <= 1e-10 * norm0 {
            return false;
        }
        v.iter_mut().for_each(|x| *x /= norm);
        self.0.push(v);
        true
    }
}

impl ModeMatrix {
    pub fn factor(sys: &System, keys: &[ModeKey], time: f64) -> Result<Self, SimError> {
        let n = sys.nodes;
        // (row, column) in row order.
        let mut rows: Vec<(&Rel, Column)> = Vec::new();
        let mut basis = Independent(Vec::new());
        for c in &sys.constraints {
            basis.accept(&c.rel, n);
            rows.push((&c.rel, Column::Same));
        }
        let mut element_rows = vec![ElementRows::default(); sys.switching.len()];
        for (k, (e, key)) in sys.switching.iter().zip(keys).enumerate() {
            if let Some((rel, column)) = e.permanent_row(*key) {
                basis.accept(rel, n);
                element_rows[k].permanent = Some(rows.len());
                rows.push((rel, column));
            }
        }
        let mut ranks: Vec<u8> = sys.switching.iter().map(|e| e.lock_rank()).collect();
        ranks.sort_unstable();
        ranks.dedup();
        for rank in ranks {
            for (k, (e, key)) in sys.switching.iter().zip(keys).enumerate() {
                if key.locked && e.lock_rank() == rank && basis.accept(e.motion(), n) {
                    element_rows[k].lock = Some(rows.len());
                    rows.push((e.motion(), e.lock_column()));
                }
            }
        }
        // Elements whose motion the kept rows hold: their speed cannot change in this mode.
        for (e, rows) in sys.switching.iter().zip(&mut element_rows) {
            rows.held = basis.depends(e.motion(), n);
        }
        let size = n + rows.len();
        let mut m = DMatrix::<f64>::zeros(size, size);
        for i in 0..n {
            m[(i, i)] = sys.mass[i];
        }
        for (r, (row, column)) in rows.iter().enumerate() {
            for &(i, c) in &row.terms {
                m[(n + r, i)] = c;
            }
            let (same, extra) = match *column {
                Column::Same => (true, None),
                Column::Plus(col, s) => (true, Some((col, s))),
                Column::Only(col) => (false, Some((col, 1.0))),
            };
            if same {
                for &(i, c) in &row.terms {
                    m[(i, n + r)] += c;
                }
            }
            if let Some((col, s)) = extra {
                for &(i, c) in &col.terms {
                    m[(i, n + r)] += s * c;
                }
            }
        }
        let scale = m.iter().fold(0.0f64, |acc, v| acc.max(v.abs())).max(1e-300);
        let lu = m.lu();
        let u = lu.u();
        let smallest = (0..size)
            .map(|i| u[(i, i)].abs())
            .fold(f64::INFINITY, f64::min);
        if size > 0 && smallest <= 1e-13 * scale {
            return Err(SimError::SingularMode {
                time,
                detail: singular_detail(sys, keys),
            });
        }
        Ok(Self {
            lu,
            size,
            element_rows,
            keys: keys.to_vec(),
        })
    }

    /// Solves in place: on entry `[f; 0]`, on exit `[a; λ]`.
    pub fn solve(&self, rhs: &mut DVector<f64>) {
        if self.size > 0 {
            self.lu.solve_mut(rhs);
        }
    }

    /// Solves with elements whose loss slope differs from the factored one (a LossyGear whose
    /// losses depend on the speed): each such element's permanent column changes by `Δs·ℓ`, a
    /// rank-one change, so the factored matrix serves through the Woodbury identity instead of
    /// a new factorization per evaluation. `slope(k)` is element k's current slope.
    /// Allocates only when a slope has changed.
    pub fn solve_with_slopes(
        &self,
        sys: &System,
        slope: impl Fn(usize) -> f64,
        rhs: &mut DVector<f64>,
    ) {
        self.solve(rhs);
        let changed: Vec<(&Rel, usize, f64)> = sys
            .switching
            .iter()
            .zip(&self.keys)
            .enumerate()
            .filter(|(k, (_, key))| !key.locked && slope(*k) != key.slope)
            .filter_map(|(k, (e, key))| {
                let row = self.element_rows[k].permanent?;
                Some((e.slope_column()?, sys.nodes + row, slope(k) - key.slope))
            })
            .collect();
        if changed.is_empty() {
            return;
        }
        // Z = A⁻¹U with U's columns Δs·ℓ in the node rows.
        let z: Vec<DVector<f64>> = changed
            .iter()
            .map(|&(column, _, ds)| {
                let mut u = DVector::zeros(self.size);
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
                    rhs.axpy(-w[j], zj, 1.0);
                }
            }
            // singular at this speed: no answer, and the driver reports the non-finite state
            None => rhs.fill(f64::NAN),
        }
    }
}

fn singular_detail(sys: &System, keys: &[ModeKey]) -> String {
    let massless: Vec<String> = (0..sys.nodes)
        .filter(|&i| sys.mass[i] == 0.0)
        .map(|i| format!("[{}]", sys.node_label(i)))
        .collect();
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
            "; shafts without inertia: {} — give each an Inertia or hold it with a constraint",
            massless.join(", ")
        );
    }
    if !locked.is_empty() {
        msg += &format!("; locked elements: {}", locked.join(", "));
    }
    msg
}
