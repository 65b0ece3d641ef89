//! How a table row reads its frame (`frame.rs`): the frame's layout, the frames' spacing, and
//! each column's index in its page. The same for every run of a system, so built once and kept
//! with the system (`System::derived`).

use std::mem::MaybeUninit;

use super::frame::Layout;
use super::ops::PAGE;
use super::stretch::put;
use super::{compile, Flat};
use crate::system::System;

/// Values between the end of one frame's pages and the start of the next: one cache line. At a
/// stride of whole pages (2 KiB), slot `k` of every frame of a block fell in the same few cache
/// sets, more frames than the L1 cache has ways: CoupledClutches' table 0.73 ms on one thread,
/// 0.65 ms with this line between frames (HeatLosses 11.3 → 10.3 ms).
const PAD: usize = 8;

/// The frame of a table row (what it holds, `Layout`) and how the row reads it: the same for
/// every run of a system, so built once and kept with the system (`System::derived`).
pub(super) struct Shape {
    pub layout: Layout,
    /// Values from one frame to the next: its pages (`span`) and `PAD`.
    pub stride: usize,
    /// Values per frame: whole pages.
    pub span: usize,
    pub reader: Reader,
}

/// How a table row reads its frame: each column's index in its page, and the runs of columns
/// read from one page.
pub(super) struct Reader {
    index: Vec<u8>,
    runs: Vec<Run>,
}

/// Columns `start..end` of a table row, read from page `page` of its frame.
struct Run {
    page: usize,
    start: usize,
    end: usize,
}

impl Shape {
    /// The shape of a table of time and the outputs of `sys` (all, or only output `only`).
    pub(super) fn new(sys: &System, only: Option<usize>) -> Self {
        let mut general = Vec::new();
        let flat: Vec<Flat> = (sys.outputs.iter().enumerate())
            .filter(|&(i, _)| only.is_none_or(|o| o == i))
            .map(|(_, (_, out))| compile(out, 1.0, &mut general))
            .collect();
        let layout = Layout::new(sys, &flat, &general);
        let span = layout.len.div_ceil(PAGE).max(1) * PAGE;
        let slots: Vec<usize> = std::iter::once(layout.time)
            .chain(layout.columns.iter().copied())
            .map(|s| s as usize)
            .collect();
        let index = slots.iter().map(|s| (s % PAGE) as u8).collect();
        let mut runs: Vec<Run> = Vec::new();
        for (c, s) in slots.iter().enumerate() {
            match runs.last_mut() {
                Some(run) if run.page == s / PAGE => run.end = c + 1,
                _ => runs.push(Run {
                    page: s / PAGE,
                    start: c,
                    end: c + 1,
                }),
            }
        }
        Self {
            layout,
            stride: span + PAD,
            span,
            reader: Reader { index, runs },
        }
    }
}

impl Reader {
    /// One table row from its frame (past the caches: `STREAM`).
    #[inline]
    pub(super) fn write<const STREAM: bool>(&self, frame: &[f64], out: &mut [MaybeUninit<f64>]) {
        for run in &self.runs {
            let page: &[f64; PAGE] = (frame[run.page * PAGE..(run.page + 1) * PAGE])
                .try_into()
                .expect("whole pages");
            let cells = out[run.start..run.end].iter_mut();
            cells
                .zip(&self.index[run.start..run.end])
                .for_each(|(y, &i)| put::<STREAM>(y, page[usize::from(i)]));
        }
    }
}
