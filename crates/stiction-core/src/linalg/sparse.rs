//! The nonzeros of a banded LU, for solving. A drivetrain's mode matrix keeps a row for every
//! lock it may have (`Refactor`'s slots): most rows of its band are zeros (the 1000-element
//! ladder: 300–1000 nonzeros in the 3500 places above the diagonal). The band's solve multiplied
//! them all, and each row's sum waited on the row solved just before through a product by zero:
//! one long chain of divisions. Solving over the nonzeros only does the same arithmetic in the
//! same order on every nonzero term, so the results are those of the band's solve (an exact
//! zero may come out as −0 where the band's gave +0, nothing else). `Banded::nonzeros` builds
//! it.

/// The factors' steps and nonzero entries, in the band's elimination order.
#[derive(Debug, Clone, Default)]
pub(super) struct SparseSolve {
    /// Forward steps that do anything: (step k, the row swapped with k, end of its multipliers
    /// in `lower`).
    pub(super) steps: Vec<(u32, u32, u32)>,
    /// (row i, multiplier) of each step, in order.
    pub(super) lower: Vec<(u32, f64)>,
    /// Where each row's entries of U (right of the diagonal) end in `upper`.
    pub(super) upper_end: Vec<u32>,
    /// (column j, entry) of U, row after row, columns increasing.
    pub(super) upper: Vec<(u32, f64)>,
    /// U's diagonal.
    pub(super) pivots: Vec<f64>,
}

impl SparseSolve {
    /// Solves in the factored order, in place: `Banded`'s forward and back substitution.
    pub fn solve(&self, y: &mut [f64]) {
        let mut at = 0;
        for &(k, p, end) in &self.steps {
            let k = k as usize;
            y.swap(k, p as usize);
            let yk = y[k];
            for &(i, m) in &self.lower[at..end as usize] {
                y[i as usize] -= m * yk;
            }
            at = end as usize;
        }
        let mut end = self.upper.len();
        for k in (0..self.pivots.len()).rev() {
            let start = k.checked_sub(1).map_or(0, |r| self.upper_end[r] as usize);
            // summed from −0, as `Iterator::sum` does: the same sum of the same products
            let s = (self.upper[start..end].iter()).fold(-0.0, |s, &(j, u)| s + u * y[j as usize]);
            y[k] = (y[k] - s) / self.pivots[k];
            end = start;
        }
    }

    /// Memory held, for the mode cache's budget.
    pub fn bytes(&self) -> usize {
        12 * self.steps.len() + 16 * (self.lower.len() + self.upper.len()) + 12 * self.pivots.len()
    }
}
