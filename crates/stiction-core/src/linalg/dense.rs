//! Dense LU with partial pivoting (nalgebra), for the small systems of the MSL examples; up to
//! `INVERSE_UP_TO` unknowns the factors also keep the inverse.

use nalgebra::{DMatrix, Dyn, LU};

use super::{Factorization, LinearSolver, Singular, Triplets, PIVOT_TOLERANCE};

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
