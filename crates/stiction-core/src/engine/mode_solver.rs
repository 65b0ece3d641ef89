//! How the modes' linear systems are factored. Above `BAND_FROM` unknowns every mode of one
//! system is factored in one fixed banded order over *slots* — the nodes, the permanent
//! constraints, and per switching element its permanent row (if some mode has one) and its
//! lock row — so that a mode change refactors only the band rows of the elements it changed
//! (`linalg::Refactor`). Smaller systems (the MSL examples) and modes with massless directions
//! (their extra rows have no slot) are factored from scratch by `SizedLu`.

use crate::linalg::{Factorization, LinearSolver, Refactor, Singular, SizedLu, SlotLayout};
use crate::linalg::{Triplets, BAND_FROM};
use crate::switching::element::{Column, ModeKey};
use crate::system::{Rel, System};

/// The entries a row's multiplier puts in the node rows: the row itself (C = Gᵀ), a scaled
/// extra column, or only another column (a rolling LossyGear's).
pub fn column_entries<'a>(
    row: &'a Rel,
    column: Column<'a>,
) -> impl Iterator<Item = (usize, f64)> + 'a {
    let (same, extra) = match column {
        Column::Same => (true, None),
        Column::Plus(col, s) => (true, Some((col, s))),
        Column::Only(col) => (false, Some((col, 1.0))),
    };
    let own = row.terms.iter().filter(move |_| same).copied();
    let more = extra
        .into_iter()
        .flat_map(|(col, s)| col.terms.iter().map(move |&(i, c)| (i, s * c)));
    own.chain(more)
}

/// Each row's slot: permanent constraints after the nodes, then per element its permanent
/// row's slot (when some mode has one) and its lock row's.
struct Slots {
    permanent: Vec<Option<usize>>,
    lock: Vec<usize>,
}

impl Slots {
    /// The slots of `sys` and the union of every mode's pattern over them.
    fn of(sys: &System) -> (Self, Triplets) {
        let n = sys.nodes;
        let mut next = n + sys.constraints.len();
        let mut pattern = Triplets::new(0);
        let mut add = |slot: usize, rel: &Rel, column: Column| {
            for &(i, _) in &rel.terms {
                pattern.entries.push((slot, i, 1.0));
            }
            for (i, _) in column_entries(rel, column) {
                pattern.entries.push((i, slot, 1.0));
            }
        };
        for (c, con) in sys.constraints.iter().enumerate() {
            add(n + c, &con.rel, Column::Same);
        }
        let (mut permanent, mut lock) = (Vec::new(), Vec::new());
        for e in &sys.switching {
            let keys = [true, false].map(|locked| ModeKey { locked, slope: 1.0 });
            let rows: Vec<_> = keys.iter().filter_map(|&k| e.permanent_row(k)).collect();
            permanent.push((!rows.is_empty()).then_some(next));
            for (rel, column) in rows {
                add(next, rel, column);
            }
            next += permanent.last().is_some_and(|p| p.is_some()) as usize;
            add(next, e.motion(), e.lock_column());
            lock.push(next);
            next += 1;
        }
        pattern.size = next;
        pattern.entries.extend((0..n).map(|i| (i, i, 1.0)));
        (Self { permanent, lock }, pattern)
    }
}

/// Factors the modes of one system: `SizedLu` from scratch, or over the slots resuming the
/// last mode factored.
#[derive(Default)]
pub struct ModeSolver {
    /// A solver for every mode (tests compare the paths), instead of the slots.
    fixed: Option<Box<dyn LinearSolver>>,
    /// Built at the first mode that takes the banded path.
    band: Option<(Slots, Refactor)>,
}

impl ModeSolver {
    /// Every mode factored from scratch by `solver`.
    pub fn with(solver: Box<dyn LinearSolver>) -> Self {
        Self {
            fixed: Some(solver),
            band: None,
        }
    }

    /// Factors a mode's matrix. `rows`: each row of G's owner after the constraints — (element,
    /// whether its lock row) — or `None` when some rows have no slot (massless directions).
    pub fn factor(
        &mut self,
        sys: &System,
        matrix: &Triplets,
        rows: Option<&[(usize, bool)]>,
    ) -> Result<Box<dyn Factorization>, Singular> {
        if let Some(solver) = &self.fixed {
            return solver.factor(matrix);
        }
        let Some(rows) = rows.filter(|_| matrix.size >= BAND_FROM) else {
            return SizedLu.factor(matrix);
        };
        let (slots, refactor) = self.band.get_or_insert_with(|| {
            let (slots, pattern) = Slots::of(sys);
            let layout = SlotLayout::new(pattern.size, &pattern.entries);
            (slots, Refactor::new(layout))
        });
        let constraints = sys.nodes + sys.constraints.len();
        let of_row = |&(k, lock): &(usize, bool)| match lock {
            true => Some(slots.lock[k]),
            false => slots.permanent[k],
        };
        let all = (0..constraints).map(Some).chain(rows.iter().map(of_row));
        match all.collect::<Option<Vec<usize>>>() {
            Some(index) => refactor.factor(matrix, &index),
            // a permanent row that neither probe key showed: no slot, so from scratch
            None => SizedLu.factor(matrix),
        }
    }

    /// Elimination steps of the last banded factorization (tests: what a mode change redid).
    pub fn last_steps(&self) -> Option<usize> {
        self.band.as_ref().map(|(_, r)| r.steps)
    }
}
