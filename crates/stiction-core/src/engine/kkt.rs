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
use crate::switching::lossy_gear::GearMode;
use crate::system::{Rel, System};

pub struct ModeMatrix {
    lu: LU<f64, Dyn, Dyn>,
    pub size: usize,
    /// Row of each friction element's multiplier (its torque) when locked and kept.
    pub friction_row: Vec<Option<usize>>,
    /// Row of each LossyGear's torque `τa`.
    pub gear_row: Vec<usize>,
    /// Row of each locked LossyGear's stuck loss torque `sa`, when kept.
    pub gear_lock_row: Vec<Option<usize>>,
    /// The gear modes this matrix was factored for.
    pub gear_modes: Vec<GearMode>,
    /// Friction elements (and gears) whose relative motion the mode's rows hold fixed: their
    /// speed cannot change, so it is not watched for zero crossings (no events from round-off).
    pub friction_held: Vec<bool>,
    pub gear_held: Vec<bool>,
}

/// How a row's multiplier acts on the nodes: along the row itself, the row plus `s·ℓ`, or
/// only along `ℓ` (a stuck LossyGear's loss torque).
enum Column<'a> {
    Same,
    Plus(&'a Rel, f64),
    Only(&'a Rel),
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
    pub fn factor(
        sys: &System,
        friction_locked: &[bool],
        gear_modes: &[GearMode],
        time: f64,
    ) -> Result<Self, SimError> {
        let n = sys.nodes;
        // (row, column) in row order.
        let mut rows: Vec<(&Rel, Column)> = Vec::new();
        let mut basis = Independent(Vec::new());
        for c in &sys.constraints {
            basis.accept(&c.rel, n);
            rows.push((&c.rel, Column::Same));
        }
        let mut gear_row = Vec::new();
        for (g, mode) in sys.lossy_gears.iter().zip(gear_modes) {
            basis.accept(&g.row, n);
            gear_row.push(rows.len());
            let column = if !mode.locked && mode.c1 != 0.0 {
                Column::Plus(&g.loss_col, mode.c1)
            } else {
                Column::Same
            };
            rows.push((&g.row, column));
        }
        let mut friction_row = vec![None; sys.frictions.len()];
        for (k, fe) in sys.frictions.iter().enumerate() {
            if friction_locked[k] && basis.accept(&fe.rel, n) {
                friction_row[k] = Some(rows.len());
                rows.push((&fe.rel, Column::Same));
            }
        }
        let mut gear_lock_row = vec![None; sys.lossy_gears.len()];
        for (k, (g, mode)) in sys.lossy_gears.iter().zip(gear_modes).enumerate() {
            if mode.locked && basis.accept(&g.lock_row, n) {
                gear_lock_row[k] = Some(rows.len());
                // the stuck loss torque acts through ℓ
                rows.push((&g.lock_row, Column::Only(&g.loss_col)));
            }
        }
        // Elements whose motion the kept rows hold: their speed cannot change in this mode.
        let friction_held = sys
            .frictions
            .iter()
            .map(|fe| basis.depends(&fe.rel, n))
            .collect();
        let gear_held = sys
            .lossy_gears
            .iter()
            .map(|g| basis.depends(&g.lock_row, n))
            .collect();
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
                detail: singular_detail(sys, friction_locked),
            });
        }
        Ok(Self {
            lu,
            size,
            friction_held,
            gear_held,
            friction_row,
            gear_row,
            gear_lock_row,
            gear_modes: gear_modes.to_vec(),
        })
    }

    /// Solves in place: on entry `[f; 0]`, on exit `[a; λ]`.
    pub fn solve(&self, rhs: &mut DVector<f64>) {
        if self.size > 0 {
            self.lu.solve_mut(rhs);
        }
    }

    /// Solves with rolling LossyGears whose loss slope `c1` differs from the factored one (the
    /// losses depend on the speed): each such gear's column changes by `Δc1·ℓ`, a rank-one
    /// change, so the factored matrix serves through the Woodbury identity instead of a new
    /// factorization per evaluation.
    /// `slope(k)` is gear k's current `c1`. Allocates only when a slope has changed.
    pub fn solve_with_gear_slopes(
        &self,
        sys: &System,
        slope: impl Fn(usize) -> f64,
        rhs: &mut DVector<f64>,
    ) {
        let n = sys.nodes;
        let differs = |k: usize, mode: &GearMode| !mode.locked && slope(k) != mode.c1;
        self.solve(rhs);
        if !self
            .gear_modes
            .iter()
            .enumerate()
            .any(|(k, mode)| differs(k, mode))
        {
            return;
        }
        let changed: Vec<(usize, f64)> = self
            .gear_modes
            .iter()
            .enumerate()
            .filter(|(k, mode)| differs(*k, mode))
            .map(|(k, mode)| (k, slope(k) - mode.c1))
            .collect();
        // Z = A⁻¹U with U's columns Δc1·ℓ in the node rows.
        let z: Vec<DVector<f64>> = changed
            .iter()
            .map(|&(k, dc1)| {
                let mut u = DVector::zeros(self.size);
                for &(i, c) in &sys.lossy_gears[k].loss_col.terms {
                    u[i] += dc1 * c;
                }
                self.solve(&mut u);
                u
            })
            .collect();
        let rows: Vec<usize> = changed.iter().map(|&(k, _)| n + self.gear_row[k]).collect();
        let m = changed.len();
        let s = DMatrix::from_fn(m, m, |i, j| (i == j) as u8 as f64 + z[j][rows[i]]);
        let y = DVector::from_iterator(m, rows.iter().map(|&r| rhs[r]));
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

fn singular_detail(sys: &System, locked: &[bool]) -> String {
    let massless: Vec<String> = (0..sys.nodes)
        .filter(|&i| sys.mass[i] == 0.0)
        .map(|i| format!("[{}]", sys.node_label(i)))
        .collect();
    let locked: Vec<&str> = (0..locked.len())
        .filter(|&k| locked[k])
        .map(|k| sys.frictions[k].name.as_str())
        .collect();
    let mut msg = String::new();
    if !massless.is_empty() {
        msg += &format!(
            "; shafts without inertia: {} — give each an Inertia or hold it with a constraint",
            massless.join(", ")
        );
    }
    if !locked.is_empty() {
        msg += &format!("; locked friction elements: {}", locked.join(", "));
    }
    msg
}
