//! The linear algebra the engine and the initialization need, behind two small interfaces:
//! - `LinearSolver` factors a square system given as triplets (the per-mode KKT system) into a
//!   `Factorization` that is solved many times. `DenseLu` for small systems, `BandLu` (RCM-ordered banded LU)
//!   for large ones, chosen by size in `SizedLu`. `Refactor` factors the modes of one structure
//!   in one fixed banded order, each resuming the last where it differs.
//! - `RowBasis` is the one rank test: rows offered in priority order are kept when independent
//!   of those kept before (locks of a mode, fixed start values); it also answers whether another
//!   row depends on the kept ones (a motion the mode holds). One tolerance, one place.

mod band;
mod basis;
mod dense;
mod refactor;
mod sparse;

pub use band::BandLu;
pub use basis::RowBasis;
pub use dense::DenseLu;
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
