//! Refactoring only what a mode change changed. The systems of one drivetrain's modes are all
//! parts of one pattern: every row that some mode can hold has a fixed *slot* (nodes, the
//! permanent rows, each element's lock row). Ordered once by RCM over the union of the modes'
//! patterns, each mode's matrix is that pattern with its absent rows made identity rows
//! (decoupled: their unknowns solve to 0 and never take part in the elimination), so every
//! mode has the same band and a mode change alters only the few band rows of the elements that
//! changed.
//!
//! The banded elimination (`Banded::step`) works on a window of `kl` rows; steps before the
//! first changed row (less `kl`) are those of the previous factorization, and once the changed
//! rows are all behind and the window equals the previous factorization's window at the same
//! step, so is everything after. So the previous factorization's windows are kept every
//! `EVERY` steps: a new mode resumes from the last window before its first changed row and
//! stops at the first saved window after its last one that it reproduces — the elimination's
//! arithmetic, step for step, so the factors are bit for bit those of a factorization from
//! scratch in the same order.

use std::cell::RefCell;
use std::rc::Rc;

use super::band::{bandwidths, largest, positions, rcm_order, Banded};
use super::sparse::SparseSolve;
use super::{Factorization, Singular, Triplets, PIVOT_TOLERANCE};

/// Steps between saved windows: a resumed elimination repeats at most this many steps.
const EVERY: usize = 8;

/// Marks a slot the current mode does not use.
const ABSENT: usize = usize::MAX;

/// The fixed order of a structure's slots and the band it gives.
#[derive(Debug, Clone)]
pub struct SlotLayout {
    perm: Vec<usize>,
    pos: Vec<usize>,
    kl: usize,
    ku: usize,
}

impl SlotLayout {
    /// RCM order of `size` slots over the union `pattern` of every mode's entries (values
    /// ignored).
    pub fn new(size: usize, pattern: &[(usize, usize, f64)]) -> Self {
        let perm = rcm_order(size, pattern);
        let pos = positions(&perm);
        let (kl, ku) = bandwidths(pattern, &pos);
        Self { perm, pos, kl, ku }
    }

    pub fn size(&self) -> usize {
        self.perm.len()
    }

    /// The mode's matrix (`slots[i]`: the slot of its unknown i) in band storage, and the mode's
    /// unknown at each position (`ABSENT`: an identity row).
    fn assemble(&self, matrix: &Triplets, slots: &[usize]) -> (Vec<f64>, Vec<usize>) {
        let (kl, width) = (self.kl, 2 * self.kl + self.ku + 1);
        let mut band = vec![0.0; (self.size() + kl) * width];
        let mut unknown_at = vec![ABSENT; self.size()];
        for (i, &s) in slots.iter().enumerate() {
            unknown_at[self.pos[s]] = i;
        }
        // entry (i, j) at i·width + j + kl − i, as `Banded::at`
        for &(r, c, v) in &matrix.entries {
            let (i, j) = (self.pos[slots[r]], self.pos[slots[c]]);
            band[i * width + j + kl - i] += v;
        }
        for (p, _) in unknown_at.iter().enumerate().filter(|(_, &u)| u == ABSENT) {
            band[p * width + kl] = 1.0;
        }
        (band, unknown_at)
    }
}

/// One mode's factors over the slots.
struct SlotFactors {
    unknown_at: Vec<usize>,
    unknowns: usize,
    /// The factors' nonzeros (`sparse.rs`).
    lu: SparseSolve,
    scratch: RefCell<Vec<f64>>,
}

impl Factorization for SlotFactors {
    fn size(&self) -> usize {
        self.unknowns
    }

    fn bytes(&self) -> usize {
        self.lu.bytes() + 8 * self.unknown_at.len()
    }

    fn solve_in_place(&self, b: &mut [f64]) {
        let mut y = self.scratch.borrow_mut();
        y.clear();
        y.extend((self.unknown_at.iter()).map(|&u| if u == ABSENT { 0.0 } else { b[u] }));
        self.lu.solve(y.as_mut_slice());
        for (&u, &v) in self.unknown_at.iter().zip(y.iter()) {
            if u != ABSENT {
                b[u] = v;
            }
        }
    }
}

/// The last factorization, which the next one resumes: its matrix and saved windows.
struct Last {
    a: Vec<f64>,
    lu: Rc<Banded>,
    windows: Vec<f64>,
}

/// Factors the modes of one structure, each from the last one factored.
pub struct Refactor {
    layout: SlotLayout,
    last: Option<Last>,
    /// Elimination steps the last `factor` took (a whole factorization takes `layout.size()`).
    pub steps: usize,
}

impl Refactor {
    pub fn new(layout: SlotLayout) -> Self {
        Self {
            layout,
            last: None,
            steps: 0,
        }
    }

    /// Factors the mode's matrix (`slots[i]`: the slot of its unknown i), resuming the last
    /// factorization where it differs.
    pub fn factor(
        &mut self,
        matrix: &Triplets,
        slots: &[usize],
    ) -> Result<Box<dyn Factorization>, Singular> {
        let (a, unknown_at) = self.layout.assemble(matrix, slots);
        let (n, kl, ku) = (self.layout.size(), self.layout.kl, self.layout.ku);
        let last = self.last.take();
        let (lu, windows, steps) = match &last {
            Some(old) => match changed_rows(&old.a, &a, old.lu.width) {
                Some(rows) => {
                    let (mut lu, mut windows) = ((*old.lu).clone(), old.windows.clone());
                    let steps = resume(&mut lu, &a, &mut windows, Some((old, rows)));
                    (Rc::new(lu), windows, steps)
                }
                None => (old.lu.clone(), old.windows.clone(), 0),
            },
            None => {
                let mut lu = Banded::zeros(n, kl, ku);
                let mut windows = vec![0.0; (n / EVERY + 1) * kl * lu.width];
                let steps = resume(&mut lu, &a, &mut windows, None);
                (Rc::new(lu), windows, steps)
            }
        };
        self.steps = steps;
        // judged against the mode's own entries, as a factorization of it alone (not the 1s
        // of the identity rows)
        let rows = a.chunks_exact(lu.width).zip(&unknown_at);
        let used = rows.filter(|(_, &u)| u != ABSENT).flat_map(|(row, _)| row);
        let scale = largest(used);
        let smallest = lu.smallest_pivot();
        if n > 0 && smallest <= PIVOT_TOLERANCE * scale {
            // the saved windows are this matrix's now: the next mode starts afresh
            return Err(Singular {
                relative_pivot: smallest / scale,
            });
        }
        self.last = Some(Last {
            a,
            lu: lu.clone(),
            windows,
        });
        Ok(Box::new(SlotFactors {
            unknown_at,
            unknowns: slots.len(),
            lu: lu.nonzeros(),
            scratch: RefCell::new(Vec::with_capacity(n)),
        }))
    }
}

/// The first and last band rows where two matrices differ (bit patterns).
fn changed_rows(old: &[f64], new: &[f64], width: usize) -> Option<(usize, usize)> {
    let differs = |(_, (a, b)): &(usize, (&[f64], &[f64]))| {
        a.iter()
            .zip(b.iter())
            .any(|(x, y)| x.to_bits() != y.to_bits())
    };
    let rows = || {
        old.chunks_exact(width)
            .zip(new.chunks_exact(width))
            .enumerate()
    };
    let first = rows().find(differs)?.0;
    let last = rows().rev().find(differs).map_or(first, |(i, _)| i);
    Some((first, last))
}

/// Runs the elimination of `a` into `lu`, saving windows every `EVERY` steps. With the last
/// factorization and the rows where `a` differs from its matrix, `lu` and `windows` hold the
/// last factors and windows (copies) and it starts at the saved window before the first changed row, and stops at the first saved
/// window after the last changed row that equals the old one. Returns the steps taken.
fn resume(
    lu: &mut Banded,
    a: &[f64],
    windows: &mut [f64],
    from: Option<(&Last, (usize, usize))>,
) -> usize {
    let (n, kl, w) = (lu.n, lu.kl, lu.width);
    let window = |k: usize| k * w..(k + kl) * w;
    let saved = |k: usize| (k / EVERY) * kl * w..(k / EVERY + 1) * kl * w;
    let start = match from {
        Some((old, (first, _))) => {
            // rows before `first` are unchanged: so are the steps before `first − kl`
            let start = first.saturating_sub(kl) / EVERY * EVERY;
            if start > 0 {
                lu.band[window(start)].copy_from_slice(&old.windows[saved(start)]);
            }
            start
        }
        None => 0,
    };
    if start == 0 {
        lu.band[window(0)].copy_from_slice(&a[window(0)]);
    }
    for k in start..n {
        if k % EVERY == 0 {
            if let Some((old, (_, last))) = from {
                // rows entering from step k on are unchanged; the window decides the rest
                if k > start && last < k + kl && same_window(lu, &old.windows[saved(k)], k) {
                    lu.band[window(k)].copy_from_slice(&old.lu.band[window(k)]);
                    return k - start;
                }
            }
            windows[saved(k)].copy_from_slice(&lu.band[window(k)]);
        }
        // row k + kl enters the window (the padding rows past n stay zero)
        if k + kl < n {
            let r = lu.row(k + kl);
            lu.band[r.clone()].copy_from_slice(&a[r]);
        }
        lu.step(k);
    }
    n - start
}

/// Whether the window of `lu` at step k equals `saved` in every column from k on (the columns
/// before k are eliminated and never read again).
fn same_window(lu: &Banded, saved: &[f64], k: usize) -> bool {
    let (kl, w) = (lu.kl, lu.width);
    (0..kl).all(|d| {
        let row = &lu.band[lu.row(k + d)];
        let old = &saved[d * w..(d + 1) * w];
        // row k + d stores column j at offset j + kl − (k + d): columns from k at kl − d on
        (row[kl - d..].iter().zip(&old[kl - d..])).all(|(x, y)| x.to_bits() == y.to_bits())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{DenseLu, LinearSolver};

    /// A chain of `n` masses (mass `mass(i)`) with a lock slot between each pair: the locks in
    /// `locked` hold; slots: nodes, then lock k at `n + k`.
    fn chain(n: usize, locked: &[usize], mass: impl Fn(usize) -> f64) -> (Triplets, Vec<usize>) {
        let mut m = Triplets::new(n + locked.len());
        (0..n).for_each(|i| m.add(i, i, mass(i)));
        let mut slots: Vec<usize> = (0..n).collect();
        for (r, &k) in locked.iter().enumerate() {
            for (i, c) in [(k, 1.0), (k + 1, -1.0 - 0.1 * k as f64)] {
                m.add(n + r, i, c);
                m.add(i, n + r, c);
            }
            slots.push(n + k);
        }
        (m, slots)
    }

    #[test]
    fn a_singular_mode_is_refused_and_the_next_one_starts_afresh() {
        let n = 50;
        let pattern = chain(n, &(0..n - 1).collect::<Vec<_>>(), |_| 1.0).0;
        let layout = SlotLayout::new(pattern.size, &pattern.entries);
        let mut refactor = Refactor::new(layout.clone());
        for (locked, massless) in [
            (vec![3, 4, 20], None),
            (vec![3, 20], Some(30)),
            (vec![3], None),
        ] {
            let mass = |i: usize| {
                if Some(i) == massless {
                    0.0
                } else {
                    1.0 + i as f64
                }
            };
            let (m, slots) = chain(n, &locked, mass);
            let got = refactor.factor(&m, &slots);
            let fresh = Refactor::new(layout.clone()).factor(&m, &slots);
            assert_eq!(got.is_err(), massless.is_some());
            assert_eq!(fresh.is_err(), massless.is_some());
            let (Ok(got), Ok(fresh)) = (got, fresh) else {
                continue;
            };
            let b: Vec<f64> = (0..m.size).map(|i| (i as f64).cos()).collect();
            let (mut x, mut y, mut z) = (b.clone(), b.clone(), b.clone());
            got.solve_in_place(&mut x);
            fresh.solve_in_place(&mut y);
            DenseLu.factor(&m).expect("regular").solve_in_place(&mut z);
            assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
            assert!(x.iter().zip(&z).all(|(p, q)| (p - q).abs() < 1e-12));
        }
    }
}
