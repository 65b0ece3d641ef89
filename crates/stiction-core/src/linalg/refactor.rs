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

use super::band::{bandwidths, largest, positions, rcm_order, Banded};
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
        let mut lu = Banded::zeros(self.size(), self.kl, self.ku);
        let mut unknown_at = vec![ABSENT; self.size()];
        for (i, &s) in slots.iter().enumerate() {
            unknown_at[self.pos[s]] = i;
        }
        for &(r, c, v) in &matrix.entries {
            let k = lu.at(self.pos[slots[r]], self.pos[slots[c]]);
            lu.band[k] += v;
        }
        for (p, _) in unknown_at.iter().enumerate().filter(|(_, &u)| u == ABSENT) {
            let k = lu.at(p, p);
            lu.band[k] = 1.0;
        }
        (lu.band, unknown_at)
    }
}

/// One mode's factors over the slots.
struct SlotFactors {
    unknown_at: Vec<usize>,
    unknowns: usize,
    lu: Banded,
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
    lu: Banded,
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
        let n = self.layout.size();
        let mut lu = Banded::zeros(n, self.layout.kl, self.layout.ku);
        let mut windows = vec![0.0; (n / EVERY + 1) * lu.kl * lu.width];
        let last = self.last.take();
        self.steps = match &last {
            Some(old) => match changed_rows(&old.a, &a, lu.width) {
                Some(rows) => resume(&mut lu, &a, &mut windows, Some((old, rows))),
                None => {
                    (lu, windows) = (old.lu.clone(), old.windows.clone());
                    0
                }
            },
            None => resume(&mut lu, &a, &mut windows, None),
        };
        let (scale, smallest) = (largest(&a), lu.smallest_pivot());
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
            lu,
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
/// factorization and the rows where `a` differs from its matrix, it starts from the last factors
/// (copied) at the saved window before the first changed row, and stops at the first saved
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
            lu.clone_from(&old.lu);
            windows.copy_from_slice(&old.windows);
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
