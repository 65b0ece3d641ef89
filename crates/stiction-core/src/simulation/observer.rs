//! The observer hook: what a run hands every output row and mode change to while it goes
//! (streaming metrics, result writers), with the block of grid rows a sweep takes at once.

use crate::engine::eval::DiscreteState;
use crate::result::{EventRecord, RowView};

/// Receives every output row (grid points and both sides of each event) and every mode change
/// as the run produces them: streaming metrics and result writers plug in here.
pub trait Observer {
    fn row(&mut self, row: &RowView);
    fn event(&mut self, _event: &EventRecord) {}

    /// The states this observer reads of a grid row, when it reads no others (a sweep's
    /// metrics over angles and speeds): the grid rows inside a step then evaluate those alone
    /// on the step's quartic, the others left unevaluated (`grid_rows`). None: every state.
    fn states_read(&self) -> Option<&[usize]> {
        None
    }

    /// The grid rows inside one step, `n` states a row in `xs` (only `states_read` evaluated
    /// when it says which), all in one discrete state: row by row unless the observer takes a
    /// block at once.
    fn grid_rows(&mut self, ts: &[f64], xs: &[f64], disc: &DiscreteState, horizon: f64) {
        each_row(ts, xs, disc, horizon, |row| self.row(row));
    }
}

/// The rows of a block of grid rows (`n` states a row in `xs`, `n` = its length over the
/// times'), one `RowView` each, in order.
pub fn each_row(
    ts: &[f64],
    xs: &[f64],
    disc: &DiscreteState,
    horizon: f64,
    mut f: impl FnMut(&RowView),
) {
    let n = xs.len().checked_div(ts.len()).unwrap_or(0);
    for (i, &t) in ts.iter().enumerate() {
        f(&RowView {
            t,
            x: &xs[i * n..(i + 1) * n],
            disc,
            horizon,
        });
    }
}
