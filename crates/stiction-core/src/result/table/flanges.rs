//! The flange cut torques of a block of table rows, solved for all its rows at once. Row by
//! row, the solve (`FlangeTorques::solve`) cost more than a third of the whole table: about
//! thirty tiny sums and products, each a loop of its own. Here the known torques and component
//! sums are already in each row's frame (`frame.rs`: an element's torque, a law's, `J·a`), are
//! gathered into one plane each, `FlangeTorques::solve_rows` runs each step over all rows, and
//! the solved torques go back into the frames. Every row's arithmetic is `solve`'s, so the
//! torques are the same bits.

use super::frame::FlangePlan;
use crate::system::System;

/// Scratch space of the solve, kept across blocks.
#[derive(Default, Clone)]
pub(super) struct BlockFlanges {
    /// The known torques, then the component sums, each over the block's rows.
    values: Vec<f64>,
    /// Each port's torque over the block: `tau[port · rows + row]`.
    tau: Vec<f64>,
    rhs: Vec<f64>,
}

impl BlockFlanges {
    /// Solves the torques of the `n` frames (`stride` values apart) and writes them into the
    /// frames' slots of the solved ports.
    pub(super) fn solve(
        &mut self,
        plan: &FlangePlan,
        sys: &System,
        frames: &mut [f64],
        (stride, n): (usize, usize),
    ) {
        let sources = plan.known.iter().chain(&plan.totals);
        self.values.resize(sources.clone().count() * n, 0.0);
        // frame by frame rather than `step_by` and `extend` (a capacity check per value)
        for (plane, &slot) in self.values.chunks_exact_mut(n.max(1)).zip(sources) {
            let rows = plane.iter_mut().zip(frames.chunks_exact(stride));
            rows.for_each(|(v, f)| *v = f[slot as usize]);
        }
        let values = &self.values;
        let ft = &sys.flange_torques;
        // every mechanical port's torque is written; the others are never read
        self.tau.resize(ft.ports() * n, 0.0);
        let (known, totals) = values.split_at(plan.known.len() * n);
        ft.solve_rows(n, known, totals, &mut self.tau, &mut self.rhs);
        for &(p, slot) in &plan.unknown {
            let slot = slot as usize;
            let out = frames.chunks_exact_mut(stride);
            out.zip(&self.tau[p * n..(p + 1) * n])
                .for_each(|(f, x)| f[slot] = *x);
        }
    }
}
