//! The linear algebra the engine and the initialization need, behind two small interfaces:
//! - `LinearSolver` factors a square system given as triplets (the per-mode KKT system) into a
//!   `Factorization` that is solved many times. `DenseLu` is today's implementation; a sparse or
//!   structured solver plugs in here without the engine changing.
//! - `RowBasis` is the one rank test: rows offered in priority order are kept when independent
//!   of those kept before (locks of a mode, fixed start values); it also answers whether another
//!   row depends on the kept ones (a motion the mode holds). One tolerance, one place.

use nalgebra::{DMatrix, Dyn, LU};

/// A row is dependent when what is left of it after removing the kept rows' directions is below
/// this fraction of its norm.
pub const RANK_TOLERANCE: f64 = 1e-10;

/// A pivot below this fraction of the largest matrix entry makes the system singular.
pub const PIVOT_TOLERANCE: f64 = 1e-13;

/// A square matrix as (row, column, value) entries; repeated entries add up.
#[derive(Debug, Clone, Default)]
pub struct Triplets {
    pub size: usize,
    pub entries: Vec<(usize, usize, f64)>,
}

impl Triplets {
    pub fn new(size: usize) -> Self {
        Self {
            size,
            entries: Vec::new(),
        }
    }

    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        if value != 0.0 {
            self.entries.push((row, col, value));
        }
    }
}

/// The matrix has no unique solution: its smallest pivot, relative to its largest entry.
#[derive(Debug, Clone, Copy)]
pub struct Singular {
    pub relative_pivot: f64,
}

/// A factored square matrix.
pub trait Factorization {
    fn size(&self) -> usize;
    /// Solves `A·x = b` in place (`b` on entry, `x` on exit).
    fn solve_in_place(&self, b: &mut [f64]);
}

/// Factors square matrices.
pub trait LinearSolver {
    fn factor(&self, matrix: &Triplets) -> Result<Box<dyn Factorization>, Singular>;
}

/// Dense LU with partial pivoting (nalgebra): right for the small drivetrains of the MSL
/// examples; its cost grows like n³.
#[derive(Debug, Clone, Copy, Default)]
pub struct DenseLu;

struct DenseFactors(LU<f64, Dyn, Dyn>);

impl Factorization for DenseFactors {
    fn size(&self) -> usize {
        self.0.l().nrows()
    }

    fn solve_in_place(&self, b: &mut [f64]) {
        if b.is_empty() {
            return;
        }
        let mut v = nalgebra::DVectorViewMut::from_slice(b, b.len());
        self.0.solve_mut(&mut v);
    }
}

impl LinearSolver for DenseLu {
    fn factor(&self, matrix: &Triplets) -> Result<Box<dyn Factorization>, Singular> {
        let n = matrix.size;
        let mut m = DMatrix::<f64>::zeros(n, n);
        for &(r, c, v) in &matrix.entries {
            m[(r, c)] += v;
        }
        let scale = m.iter().fold(0.0f64, |acc, v| acc.max(v.abs())).max(1e-300);
        let lu = m.lu();
        let u = lu.u();
        let smallest = (0..n)
            .map(|i| u[(i, i)].abs())
            .fold(f64::INFINITY, f64::min);
        if n > 0 && smallest <= PIVOT_TOLERANCE * scale {
            return Err(Singular {
                relative_pivot: smallest / scale,
            });
        }
        Ok(Box::new(DenseFactors(lu)))
    }
}

/// An orthonormal basis of the rows kept so far (modified Gram–Schmidt, i.e. a QR factorization
/// of the kept rows built one row at a time, which keeps the priority order).
pub struct RowBasis {
    dim: usize,
    kept: Vec<Vec<f64>>,
}

impl RowBasis {
    pub fn new(dim: usize) -> Self {
        Self {
            dim,
            kept: Vec::new(),
        }
    }

    /// The row's norm and what is left of it after removing the kept rows' directions.
    fn residual(&self, terms: &[(usize, f64)]) -> (f64, Vec<f64>) {
        let mut v = vec![0.0; self.dim];
        for &(i, c) in terms {
            v[i] += c;
        }
        let norm0 = norm(&v);
        for q in &self.kept {
            let dot: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(x, qi)| *x -= dot * qi);
        }
        (norm0, v)
    }

    /// Whether the row (sparse terms) is a nonzero combination of the kept rows.
    pub fn depends(&self, terms: &[(usize, f64)]) -> bool {
        let (norm0, v) = self.residual(terms);
        norm0 > 0.0 && norm(&v) <= RANK_TOLERANCE * norm0
    }

    /// Keeps the row if it is independent of the rows kept so far; a zero row is never kept.
    pub fn accept(&mut self, terms: &[(usize, f64)]) -> bool {
        let (norm0, mut v) = self.residual(terms);
        let left = norm(&v);
        if norm0 == 0.0 || left <= RANK_TOLERANCE * norm0 {
            return false;
        }
        v.iter_mut().for_each(|x| *x /= left);
        self.kept.push(v);
        true
    }

    pub fn rank(&self) -> usize {
        self.kept.len()
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_lu_solves_and_reports_a_singular_matrix() {
        let mut m = Triplets::new(2);
        m.add(0, 0, 2.0);
        m.add(0, 1, 1.0);
        m.add(1, 0, 1.0);
        m.add(1, 1, 3.0);
        let f = DenseLu.factor(&m).expect("regular");
        let mut b = [3.0, 5.0];
        f.solve_in_place(&mut b);
        assert!((b[0] - 0.8).abs() < 1e-15 && (b[1] - 1.4).abs() < 1e-15);
        let mut s = Triplets::new(2);
        s.add(0, 0, 1.0);
        s.add(0, 1, 2.0);
        s.add(1, 0, 2.0);
        s.add(1, 1, 4.0);
        assert!(DenseLu.factor(&s).is_err());
    }

    #[test]
    fn the_row_basis_keeps_rows_in_order_and_drops_dependent_ones() {
        let mut basis = RowBasis::new(3);
        assert!(basis.accept(&[(0, 1.0), (1, -1.0)]));
        assert!(basis.accept(&[(1, 1.0), (2, -1.0)]));
        // the third lock closes a cycle: phi0 − phi2 = (phi0 − phi1) + (phi1 − phi2)
        assert!(!basis.accept(&[(0, 1.0), (2, -1.0)]));
        assert!(basis.depends(&[(0, 2.0), (2, -2.0)]));
        assert!(!basis.depends(&[(0, 1.0)]));
        assert!(!basis.accept(&[]));
        assert_eq!(basis.rank(), 2);
    }
}
