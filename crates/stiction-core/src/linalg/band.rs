//! Banded LU after a reverse Cuthill–McKee ordering: the per-mode system of a drivetrain is a
//! graph of shafts and the couplings between neighbours, so ordered by RCM its bandwidth stays
//! small whatever its size; factoring costs O(n·b²) and a solve O(n·b) instead of n³ and n².

use std::cell::RefCell;

use super::sparse::SparseSolve;
use super::{Factorization, LinearSolver, Singular, Triplets, PIVOT_TOLERANCE};

/// RCM-ordered banded LU with partial pivoting (LAPACK `gbtrf`'s scheme).
#[derive(Debug, Clone, Copy, Default)]
pub struct BandLu;

/// A banded matrix in a fixed order and its elimination, step by step: row i holds columns
/// `i − kl ..= i + kl + ku` (room for the fill-in of row swaps), U after factoring. `kl` rows of
/// padding follow the last so that the rows step k works on (`k ..< k + kl`, the window) are
/// always there; `refactor` saves and restores windows to resume an elimination midway.
#[derive(Debug, Clone)]
// Alike in shape only to other field lists (the duplicate finder pairs plain structs).
pub(super) struct Banded {
    pub n: usize,
    pub kl: usize,
    pub ku: usize,
    pub width: usize,
    pub band: Vec<f64>,
    /// Multipliers of step k (below the pivot) and the row swapped with k.
    pub lower: Vec<f64>,
    pub pivot_row: Vec<usize>,
    /// |pivot| of each step (the smallest decides whether the matrix is singular).
    pub pivot_abs: Vec<f64>,
}

impl Banded {
    pub fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        let width = 2 * kl + ku + 1;
        Self {
            n,
            kl,
            ku,
            width,
            band: vec![0.0; (n + kl) * width],
            lower: vec![0.0; n * kl],
            pivot_row: vec![0; n],
            pivot_abs: vec![f64::INFINITY; n],
        }
    }

    /// Index of entry (i, j) in `band`.
    pub fn at(&self, i: usize, j: usize) -> usize {
        i * self.width + (j + self.kl - i)
    }

    /// Row i's storage.
    pub fn row(&self, i: usize) -> std::ops::Range<usize> {
        i * self.width..(i + 1) * self.width
    }

    /// Elimination step k: the largest entry of column k among rows `k ..= k + kl` is the
    /// pivot, the rows below lose their column-k entries.
    pub fn step(&mut self, k: usize) {
        let (n, kl) = (self.n, self.kl);
        let last_row = (k + kl).min(n - 1);
        let last_col = (k + kl + self.ku).min(n - 1);
        let p = (k..=last_row)
            .max_by(|&a, &b| {
                (self.band[self.at(a, k)].abs()).total_cmp(&self.band[self.at(b, k)].abs())
            })
            .unwrap_or(k);
        self.pivot_row[k] = p;
        if p != k {
            for j in k..=last_col {
                let (a, b) = (self.at(k, j), self.at(p, j));
                self.band.swap(a, b);
            }
        }
        let pivot = self.band[self.at(k, k)];
        self.pivot_abs[k] = pivot.abs();
        if pivot == 0.0 {
            return;
        }
        for i in k + 1..=last_row {
            let m = self.band[self.at(i, k)] / pivot;
            self.lower[k * kl + (i - k - 1)] = m;
            if m == 0.0 {
                continue;
            }
            for j in k + 1..=last_col {
                let u = self.band[self.at(k, j)];
                let idx = self.at(i, j);
                self.band[idx] -= m * u;
            }
        }
    }

    /// The nonzeros of the factors, for solving (`sparse.rs`).
    pub fn nonzeros(&self) -> SparseSolve {
        let lu = self;
        let (n, kl) = (lu.n, lu.kl);
        let mut s = SparseSolve::default();
        for k in 0..n {
            let p = lu.pivot_row[k];
            let start = s.lower.len();
            let below = (k + 1..n).take(kl);
            for (i, &m) in below.zip(&lu.lower[k * kl..(k + 1) * kl]) {
                if m != 0.0 {
                    s.lower.push((i as u32, m));
                }
            }
            if p != k || s.lower.len() > start {
                s.steps.push((k as u32, p as u32, s.lower.len() as u32));
            }
        }
        for k in 0..n {
            let row = &lu.band[lu.row(k)];
            let right = (k + 1..n).zip(&row[kl + 1..]);
            s.upper
                .extend((right.filter(|(_, &u)| u != 0.0)).map(|(j, &u)| (j as u32, u)));
            s.upper_end.push(s.upper.len() as u32);
            s.pivots.push(row[kl]);
        }
        s
    }

    pub fn smallest_pivot(&self) -> f64 {
        self.pivot_abs.iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// A matrix factored in the order `perm` (`perm[i]`: the original row/column at position i).
struct BandFactors {
    perm: Vec<usize>,
    /// The factors' nonzeros (`sparse.rs`).
    lu: SparseSolve,
    /// The permuted right-hand side, kept so that a solve allocates nothing.
    scratch: RefCell<Vec<f64>>,
}

/// Reverse Cuthill–McKee over the symmetric pattern: breadth first from a vertex of least
/// degree in each connected part, neighbours by increasing degree, then reversed.
pub fn rcm_order(n: usize, entries: &[(usize, usize, f64)]) -> Vec<usize> {
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(r, c, _) in entries {
        if r != c {
            adj[r].push(c);
            adj[c].push(r);
        }
    }
    adj.iter_mut().for_each(|a| {
        a.sort_unstable();
        a.dedup();
    });
    let mut by_degree: Vec<usize> = (0..n).collect();
    by_degree.sort_by_key(|&v| (adj[v].len(), v));
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for &start in &by_degree {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut head = order.len();
        order.push(start);
        while head < order.len() {
            let v = order[head];
            head += 1;
            let mut next: Vec<usize> = adj[v].iter().copied().filter(|&u| !seen[u]).collect();
            next.sort_by_key(|&u| (adj[u].len(), u));
            for u in next {
                seen[u] = true;
                order.push(u);
            }
        }
    }
    order.reverse();
    order
}

/// Lower and upper bandwidth of the matrix in the order `pos` (position of each index).
pub fn bandwidths(entries: &[(usize, usize, f64)], pos: &[usize]) -> (usize, usize) {
    entries.iter().fold((0, 0), |(kl, ku), &(r, c, _)| {
        let (i, j) = (pos[r], pos[c]);
        (kl.max(i.saturating_sub(j)), ku.max(j.saturating_sub(i)))
    })
}

/// The positions of an order (`pos[perm[i]] = i`).
pub fn positions(perm: &[usize]) -> Vec<usize> {
    let mut pos = vec![0; perm.len()];
    perm.iter().enumerate().for_each(|(i, &p)| pos[p] = i);
    pos
}

/// The largest entry's magnitude (the scale pivots are judged against).
pub fn largest<'a>(values: impl IntoIterator<Item = &'a f64>) -> f64 {
    (values.into_iter())
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(1e-300)
}

impl LinearSolver for BandLu {
    fn factor(&self, matrix: &Triplets) -> Result<Box<dyn Factorization>, Singular> {
        let n = matrix.size;
        let perm = rcm_order(n, &matrix.entries);
        let pos = positions(&perm);
        let (kl, ku) = bandwidths(&matrix.entries, &pos);
        let mut lu = Banded::zeros(n, kl, ku);
        for &(r, c, v) in &matrix.entries {
            let k = lu.at(pos[r], pos[c]);
            lu.band[k] += v;
        }
        let scale = largest(&lu.band);
        (0..n).for_each(|k| lu.step(k));
        let smallest = lu.smallest_pivot();
        if n > 0 && smallest <= PIVOT_TOLERANCE * scale {
            return Err(Singular {
                relative_pivot: smallest / scale,
            });
        }
        Ok(Box::new(BandFactors {
            perm,
            lu: lu.nonzeros(),
            scratch: RefCell::new(Vec::with_capacity(n)),
        }))
    }
}

impl Factorization for BandFactors {
    fn size(&self) -> usize {
        self.perm.len()
    }

    fn bytes(&self) -> usize {
        self.lu.bytes() + 16 * self.perm.len()
    }

    fn solve_in_place(&self, b: &mut [f64]) {
        let mut scratch = self.scratch.borrow_mut();
        scratch.clear();
        scratch.extend(self.perm.iter().map(|&p| b[p]));
        self.lu.solve(scratch.as_mut_slice());
        (self.perm.iter().zip(scratch.iter())).for_each(|(&p, &v)| b[p] = v);
    }
}
