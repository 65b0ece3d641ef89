//! Banded LU after a reverse Cuthill–McKee ordering: the per-mode system of a drivetrain is a
//! graph of shafts and the couplings between neighbours, so ordered by RCM its bandwidth stays
//! small whatever its size; factoring costs O(n·b²) and a solve O(n·b) instead of n³ and n².

use std::cell::RefCell;

use super::{Factorization, LinearSolver, Singular, Triplets, PIVOT_TOLERANCE};

/// RCM-ordered banded LU with partial pivoting (LAPACK `gbtrf`'s scheme).
#[derive(Debug, Clone, Copy, Default)]
pub struct BandLu;

struct BandFactors {
    /// `perm[i]`: the original row/column at position i.
    perm: Vec<usize>,
    kl: usize,
    /// Row i holds columns `i − kl ..= i + kl + ku` (U after factoring).
    width: usize,
    band: Vec<f64>,
    /// Multipliers of step k (below the pivot) and the row swapped with k.
    lower: Vec<f64>,
    pivot_row: Vec<usize>,
    /// The permuted right-hand side, kept so that a solve allocates nothing.
    scratch: RefCell<Vec<f64>>,
}

impl BandFactors {
    fn at(&self, i: usize, j: usize) -> usize {
        i * self.width + (j + self.kl - i)
    }

    fn n(&self) -> usize {
        self.perm.len()
    }
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
fn bandwidths(entries: &[(usize, usize, f64)], pos: &[usize]) -> (usize, usize) {
    entries.iter().fold((0, 0), |(kl, ku), &(r, c, _)| {
        let (i, j) = (pos[r], pos[c]);
        (kl.max(i.saturating_sub(j)), ku.max(j.saturating_sub(i)))
    })
}

impl LinearSolver for BandLu {
    fn factor(&self, matrix: &Triplets) -> Result<Box<dyn Factorization>, Singular> {
        let n = matrix.size;
        let perm = rcm_order(n, &matrix.entries);
        let mut pos = vec![0; n];
        perm.iter().enumerate().for_each(|(i, &p)| pos[p] = i);
        let (kl, ku) = bandwidths(&matrix.entries, &pos);
        let width = 2 * kl + ku + 1;
        let mut f = BandFactors {
            perm,
            kl,
            width,
            band: vec![0.0; n * width],
            lower: vec![0.0; n * kl],
            pivot_row: vec![0; n],
            scratch: RefCell::new(Vec::with_capacity(n)),
        };
        for &(r, c, v) in &matrix.entries {
            let k = f.at(pos[r], pos[c]);
            f.band[k] += v;
        }
        let scale = f
            .band
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(1e-300);
        let smallest = eliminate(&mut f, ku);
        if n > 0 && smallest <= PIVOT_TOLERANCE * scale {
            return Err(Singular {
                relative_pivot: smallest / scale,
            });
        }
        Ok(Box::new(f))
    }
}

/// Factors in place; returns the smallest pivot's magnitude.
fn eliminate(f: &mut BandFactors, ku: usize) -> f64 {
    let (n, kl) = (f.n(), f.kl);
    let mut smallest = f64::INFINITY;
    for k in 0..n {
        let last_row = (k + kl).min(n - 1);
        let last_col = (k + kl + ku).min(n - 1);
        let p = (k..=last_row)
            .max_by(|&a, &b| {
                f.band[f.at(a, k)]
                    .abs()
                    .total_cmp(&f.band[f.at(b, k)].abs())
            })
            .unwrap_or(k);
        f.pivot_row[k] = p;
        if p != k {
            for j in k..=last_col {
                let (a, b) = (f.at(k, j), f.at(p, j));
                f.band.swap(a, b);
            }
        }
        let pivot = f.band[f.at(k, k)];
        smallest = smallest.min(pivot.abs());
        if pivot == 0.0 {
            continue;
        }
        for i in k + 1..=last_row {
            let m = f.band[f.at(i, k)] / pivot;
            f.lower[k * kl + (i - k - 1)] = m;
            if m == 0.0 {
                continue;
            }
            for j in k + 1..=last_col {
                let u = f.band[f.at(k, j)];
                let idx = f.at(i, j);
                f.band[idx] -= m * u;
            }
        }
    }
    smallest
}

impl Factorization for BandFactors {
    fn size(&self) -> usize {
        self.n()
    }

    fn solve_in_place(&self, b: &mut [f64]) {
        let (kl, width) = (self.kl, self.width);
        let mut scratch = self.scratch.borrow_mut();
        scratch.clear();
        scratch.extend(self.perm.iter().map(|&p| b[p]));
        let y = scratch.as_mut_slice();
        // row by row through the stored factors (no index arithmetic per entry); the zips
        // stop at the matrix's last row
        if kl > 0 {
            let steps = self.lower.chunks_exact(kl).zip(&self.pivot_row);
            for (k, (lower, &p)) in steps.enumerate() {
                y.swap(k, p);
                let (head, below) = y.split_at_mut(k + 1);
                let yk = head[k];
                for (yi, m) in below.iter_mut().zip(lower) {
                    *yi -= m * yk;
                }
            }
        }
        for (k, row) in self.band.chunks_exact(width).enumerate().rev() {
            let (head, right) = y.split_at_mut(k + 1);
            let s: f64 = (row[kl + 1..].iter().zip(right.iter()))
                .map(|(u, v)| u * v)
                .sum();
            head[k] = (head[k] - s) / row[kl];
        }
        self.perm.iter().zip(y.iter()).for_each(|(&p, &v)| b[p] = v);
    }
}
