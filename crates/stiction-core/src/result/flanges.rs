//! The flange cut torques of a block of table rows, solved for all its rows at once. Row by
//! row, the solve (`FlangeTorques::solve`) cost more than a third of the whole table: a handful
//! of values read through `value` and about thirty tiny sums and products, each a loop of its
//! own. Here each known torque and component sum is read from the block's copied arrays (an
//! element's torque, a law's torque, `J·a`; `source.rs`), only the rare other shapes go through
//! `value` while the row's workspace is at hand, and `FlangeTorques::solve_rows` runs each step
//! over all rows. Every row's arithmetic is `solve`'s, so the torques are the same bits.

use super::source::{Read, Source};
use crate::engine::eval::{DiscreteState, Workspace};
use crate::switching::element::ElementValues;
use crate::system::System;

/// The block's copied arrays a known torque or a sum reads (each row after row).
pub(super) struct Planes<'a> {
    pub a: &'a [f64],
    pub law_tau: &'a [f64],
    pub elements: &'a [ElementValues],
}

pub(super) struct BlockFlanges {
    /// The known torques, then the component sums (`known_outs`, `total_outs`).
    sources: Vec<Source>,
    known: usize,
    /// How many sources only `value` reads, and their values row after row.
    others: usize,
    pending: Vec<f64>,
    /// Each source's values over the block (one plane of rows per source).
    values: Vec<f64>,
    /// Each port's torque over the block: `tau[port · rows + row]`.
    pub tau: Vec<f64>,
    rhs: Vec<f64>,
}

impl BlockFlanges {
    pub(super) fn new(sys: &System) -> Self {
        let ft = &sys.flange_torques;
        let sources: Vec<Source> = (ft.known_outs().chain(ft.total_outs()))
            .map(Source::of)
            .collect();
        let others = sources.iter().filter(|s| !s.in_block()).count();
        Self {
            known: ft.known_outs().count(),
            sources,
            others,
            pending: Vec::new(),
            values: Vec::new(),
            tau: Vec::new(),
            rhs: Vec::new(),
        }
    }

    /// Whether a source reads the switching elements' values (the block must copy them).
    pub(super) fn reads_elements(&self) -> bool {
        (self.sources.iter()).any(|s| matches!(s.read, Read::Field(..)))
    }

    /// At an evaluated row: the sources only `value` reads, while its workspace is at hand.
    pub(super) fn push(&mut self, sys: &System, ws: &Workspace, disc: &DiscreteState) {
        let others = self.sources.iter().filter(|s| !s.in_block());
        (self.pending).extend(others.map(|s| s.eval(sys, ws, disc, &[])));
    }

    /// At a row without an evaluation (its values are not read).
    pub(super) fn pad(&mut self) {
        self.pending.resize(self.pending.len() + self.others, 0.0);
    }

    /// Every port's torque at each of the block's `n` rows, into `tau`.
    pub(super) fn solve(&mut self, sys: &System, n: usize, planes: &Planes) {
        let (nodes, laws, ne) = (sys.nodes.max(1), sys.laws.len(), sys.switching.len());
        let values = &mut self.values;
        values.clear();
        let mut other = 0;
        // one `match` per source, then a loop over the rows
        for s in &self.sources {
            match &s.read {
                Read::Field(k, f) => {
                    let rows = planes.elements[*k..].iter().step_by(ne).take(n);
                    values.extend(rows.map(|v| s.scaled(f(v))));
                }
                Read::LawTau(k) => {
                    let rows = planes.law_tau[*k..].iter().step_by(laws).take(n);
                    values.extend(rows.map(|&x| s.scaled(x)));
                }
                Read::Accel(rel) => {
                    let rows = planes.a.chunks_exact(nodes).take(n);
                    values.extend(rows.map(|a| s.scaled(rel.dot(a))));
                }
                Read::Const(c) => values.extend(std::iter::repeat_n(s.scaled(*c), n)),
                // read at `push`, factor included
                _ => {
                    let rows = self.pending[other..].iter().step_by(self.others).take(n);
                    values.extend(rows);
                    other += 1;
                }
            }
        }
        let ft = &sys.flange_torques;
        // every mechanical port's torque is written; the others are never read
        self.tau.resize(ft.ports() * n, 0.0);
        let (known, totals) = self.values.split_at(self.known * n);
        ft.solve_rows(n, known, totals, &mut self.tau, &mut self.rhs);
        self.pending.clear();
    }
}
