//! The linear algebra the engine and the initialization need, behind two small interfaces:
//! - `LinearSolver` factors a square system given as triplets (the per-mode KKT system) into a
//!   `Factorization` that is solved many times. `DenseLu` for small systems, `BandLu` (RCM-ordered banded LU)
//!   for large ones, chosen by size in `SizedLu`. `Refactor` factors the modes of one structure
//!   in one fixed banded order, each resuming the last where it differs.
//! - `RowBasis` is the one rank test: rows offered in priority order are kept when independent
//!   of those kept before (locks of a mode, fixed start values); it also answers whether another
//!   row depends on the kept ones (a motion the mode holds). One tolerance, one place.

use nalgebra::{DMatrix, Dyn, LU};

mod band;
mod basis;
mod refactor;

pub use band::BandLu;
pub use basis::RowBasis;
pub use refactor::{Refactor, SlotLayout};

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
    /// Memory held (bytes, about), for a cache's budget.
    fn bytes(&self) -> usize;
    /// Solves `A·x = b` in place (`b` on entry, `x` on exit).
    fn solve_in_place(&self, b: &mut [f64]);
    /// `solve_in_place` of the `b` that is zero but at `entries` (indices increasing, each
    /// once) into `x`, all zeros on entry: a rank-one correction's right-hand side has a few
    /// entries of many.
    fn solve_sparse(&self, entries: &[(usize, f64)], x: &mut [f64]) {
        for &(i, v) in entries {
            x[i] = v;
        }
        self.solve_in_place(x);
    }
}

/// Factors square matrices.
pub trait LinearSolver {
    fn factor(&self, matrix: &Triplets) -> Result<Box<dyn Factorization>, Singular>;
}

/// From this many unknowns on, `SizedLu` uses the banded LU.
pub const BAND_FROM: usize = 40;

/// Dense LU for small systems (the MSL examples keep their exact arithmetic), banded LU after
/// a reverse Cuthill–McKee ordering for large ones (cost linear in the drivetrain's size).
#[derive(Debug, Clone, Copy, Default)]
pub struct SizedLu;

impl LinearSolver for SizedLu {
    fn factor(&self, matrix: &Triplets) -> Result<Box<dyn Factorization>, Singular> {
        if matrix.size < BAND_FROM {
            DenseLu.factor(matrix)
        } else {
            BandLu.factor(matrix)
        }
    }
}

/// Dense LU with partial pivoting (nalgebra): right for the small drivetrains of the MSL
/// examples; its cost grows like n³.
#[derive(Debug, Clone, Copy, Default)]
pub struct DenseLu;

/// Up to this many unknowns a factored matrix also keeps its inverse, and a solve is one
/// matrix–vector product (n² multiply-adds, about a third of nalgebra's generic substitutions
/// at the MSL examples' 4–10 unknowns, where a mode is solved hundreds of times per factoring).
const INVERSE_UP_TO: usize = 16;

/// Calls `f::<N>(args)` with the order `n` (1 to `INVERSE_UP_TO`) known at compile time.
macro_rules! with_order {
    ($n:expr, $f:ident $args:tt) => {
        with_order!(@ $n, $f $args; 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
    };
    (@ $n:expr, $f:ident $args:tt; $($k:literal)*) => {
        match $n {
            $($k => $f::<$k> $args,)*
            n => unreachable!("an inverse is kept up to {INVERSE_UP_TO} unknowns, not {n}"),
        }
    };
}

struct DenseFactors {
    lu: LU<f64, Dyn, Dyn>,
    /// The order (nalgebra's `lu.l()` would build L to tell it).
    n: usize,
    /// `A⁻¹` column by column, for small systems.
    inverse: Option<Vec<f64>>,
    /// Whether every entry of the inverse is finite, so that a zero entry of `b` adds only
    /// signed zeros (`solve_in_place` leaves its column out).
    finite: bool,
}

impl DenseFactors {
    fn new(lu: LU<f64, Dyn, Dyn>) -> Self {
        let n = lu.lu_internal().nrows();
        let inverse = (n <= INVERSE_UP_TO)
            .then(|| lu.try_inverse())
            .flatten()
            .map(|inv| inv.as_slice().to_vec());
        let finite = (inverse.iter().flatten()).all(|v| v.is_finite());
        Self {
            lu,
            n,
            inverse,
            finite,
        }
    }
}

impl Factorization for DenseFactors {
    fn size(&self) -> usize {
        self.n
    }

    fn bytes(&self) -> usize {
        16 * self.size() * self.size()
    }

    fn solve_in_place(&self, b: &mut [f64]) {
        if b.is_empty() {
            return;
        }
        if let Some(inv) = &self.inverse {
            // x = Σⱼ bⱼ·(column j of A⁻¹), with the order known at compile time: x stays in
            // registers (a loop of unknown length kept it in memory, a load and a store per
            // multiply-add)
            with_order!(b.len(), solve_by_inverse(inv, b, self.finite));
            return;
        }
        let mut v = nalgebra::DVectorViewMut::from_slice(b, b.len());
        self.lu.solve_mut(&mut v);
    }

    /// With the inverse: the columns of the entries only, the same sums as `solve_in_place`
    /// (which leaves out the columns of the zeros when the inverse is finite).
    fn solve_sparse(&self, entries: &[(usize, f64)], x: &mut [f64]) {
        let n = x.len();
        match &self.inverse {
            Some(inv) if self.finite && n > 0 => {
                with_order!(n, solve_sparse_by_inverse(inv, entries, x));
            }
            _ => {
                for &(i, v) in entries {
                    x[i] = v;
                }
                self.solve_in_place(x);
            }
        }
    }
}

/// `Σⱼ bⱼ·(column j of A⁻¹)` into `out` for an order-`N` inverse stored column by column, from
/// +0, over the `(j, bⱼ)` of `b` in order; with the order known at compile time the sums stay
/// in registers. A mode's right-hand side is mostly zeros (its lock rows, the shafts no torque
/// acts on). A finite a·0 is ±0, and adding ±0 changes no sum that started at +0 (it is +0 or
/// nonzero, never -0): with a finite inverse, the same bits without the column.
#[inline]
fn combine_columns<const N: usize>(
    inv: &[f64],
    b: impl Iterator<Item = (usize, f64)>,
    finite: bool,
    out: &mut [f64],
) {
    let mut x = [0.0; N];
    for (j, bj) in b {
        if bj == 0.0 && finite {
            continue;
        }
        let column: &[f64; N] = (inv[j * N..(j + 1) * N]).try_into().expect("a column of N");
        for (xi, a) in x.iter_mut().zip(column) {
            *xi += a * bj;
        }
    }
    out.copy_from_slice(&x);
}

/// `b ← A⁻¹·b` through `combine_columns`.
#[inline]
fn solve_by_inverse<const N: usize>(inv: &[f64], b: &mut [f64], finite: bool) {
    let rhs: [f64; N] = (&*b).try_into().expect("order N");
    combine_columns::<N>(inv, rhs.into_iter().enumerate(), finite, b);
}

/// `x ← A⁻¹·b` for `b` zero but at `entries`, through `combine_columns` (a finite inverse).
#[inline]
fn solve_sparse_by_inverse<const N: usize>(inv: &[f64], entries: &[(usize, f64)], x: &mut [f64]) {
    combine_columns::<N>(inv, entries.iter().copied(), true, x);
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
        Ok(Box::new(DenseFactors::new(lu)))
    }
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

    /// A KKT-like system of a chain: masses (some zero), locks between neighbours, a
    /// non-symmetric column (a LossyGear's), pivots needed on the zero masses.
    fn chain_system(n: usize) -> Triplets {
        let locks: Vec<usize> = (0..n - 1).filter(|k| k % 3 != 1).collect();
        let mut m = Triplets::new(n + locks.len());
        for i in 0..n {
            m.add(
                i,
                i,
                if i % 5 == 4 {
                    0.0
                } else {
                    1.0 + i as f64 * 0.1
                },
            );
        }
        for (r, &k) in locks.iter().enumerate() {
            m.add(n + r, k, 1.0);
            m.add(n + r, k + 1, -2.0);
            m.add(k, n + r, 1.0);
            m.add(k + 1, n + r, -2.0 + 0.3 * (r % 2) as f64);
        }
        for k in (0..n - 1).filter(|k| k % 3 == 1) {
            m.add(k, k + 1, -0.5);
            m.add(k + 1, k, -0.5);
            m.add(k, k, 0.5);
            m.add(k + 1, k + 1, 0.5);
        }
        m
    }

    #[test]
    fn the_banded_lu_agrees_with_the_dense_one() {
        for n in [1, 2, 7, 60, 200] {
            let m = chain_system(n);
            let b: Vec<f64> = (0..m.size).map(|i| (i as f64 * 0.7).sin()).collect();
            let (mut x, mut y) = (b.clone(), b.clone());
            DenseLu.factor(&m).expect("regular").solve_in_place(&mut x);
            BandLu.factor(&m).expect("regular").solve_in_place(&mut y);
            let err = x
                .iter()
                .zip(&y)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-10, "n = {n}: {err}");
        }
        let mut s = chain_system(30);
        s.add(0, 0, -1.0); // node 0 now massless and free: singular
        s.entries.retain(|&(r, c, _)| r != 30 && c != 30);
        s.add(30, 30, 1.0);
        assert!(DenseLu.factor(&s).is_err() && BandLu.factor(&s).is_err());
    }

    #[test]
    fn the_graph_rank_test_agrees_with_the_general_one() {
        let rows: Vec<Vec<(usize, f64)>> = vec![
            vec![(0, 1.0), (1, -1.0)],
            vec![(2, 3.0), (1, -3.0)],
            vec![(0, 2.0), (2, -2.0)], // cycle
            vec![(3, 1.0)],
            vec![(4, -1.0), (3, 1.0), (4, 2.0)], // φ3 + φ4: a general row
            vec![(4, 1.0)],                      // dependent now
            vec![(5, 1.0), (5, -1.0)],           // zero
        ];
        let (mut graph, mut dense) = (RowBasis::new(6), basis::Dense::new(6));
        for row in &rows[..4] {
            assert_eq!(graph.accept(row), dense.accept(row));
            assert_eq!(
                graph.depends(&[(0, 1.0), (3, -1.0)]),
                dense.depends(&[(0, 1.0), (3, -1.0)])
            );
        }
        assert!(!graph.depends(&[(0, 1.0), (3, -1.0)]) && graph.rank() == 3);
        assert!(graph.depends(&[(0, 1.0), (2, -1.0)]));
        for row in &rows[4..] {
            assert_eq!(graph.accept(row), dense.accept(row));
        }
        assert_eq!(graph.rank(), 4);
    }

    /// Where dense and banded LU cross over (`BAND_FROM`): prints, asserts nothing.
    /// `cargo test --release -p stiction-core linalg::tests::crossover -- --ignored --nocapture`
    #[test]
    #[ignore]
    fn crossover() {
        for n in [8, 16, 24, 32, 48, 64, 128] {
            let m = chain_system(n);
            let time = |solver: &dyn LinearSolver| {
                let start = std::time::Instant::now();
                for _ in 0..200 {
                    let f = solver.factor(&m).expect("regular");
                    let mut b = vec![1.0; m.size];
                    for _ in 0..10 {
                        f.solve_in_place(&mut b);
                    }
                }
                start.elapsed().as_secs_f64() / 200.0 * 1e6
            };
            println!(
                "size {:>4}: dense {:>8.1} us, band {:>8.1} us (factor + 10 solves)",
                m.size,
                time(&DenseLu),
                time(&BandLu)
            );
        }
    }
}
