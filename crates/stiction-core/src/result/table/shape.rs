//! How a table row reads its frame (`frame.rs`): the frame's layout, the frames' spacing, and
//! each column's index in its page. The same for every run of a system, so built once and kept
//! with the system (`System::derived`).

use std::mem::MaybeUninit;

use super::frame::Layout;
use super::ops::PAGE;
use super::stretch::put;
use crate::result::output_expr::{compile, Flat};
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
    /// One table row from its frame (past the caches: `STREAM`). Four cells per pass: the
    /// compiler does not unroll a loop of streaming stores itself, and HeatLosses' 4.4 million
    /// streamed cells took a tenth longer one by one.
    #[inline]
    pub(super) fn write<const STREAM: bool>(&self, frame: &[f64], out: &mut [MaybeUninit<f64>]) {
        for run in &self.runs {
            let page: &[f64; PAGE] = (frame[run.page * PAGE..(run.page + 1) * PAGE])
                .try_into()
                .expect("whole pages");
            let read = |i: &u8| page[usize::from(*i)];
            let (cells, index) = (
                &mut out[run.start..run.end],
                &self.index[run.start..run.end],
            );
            let (mut cells, mut index) = (cells.chunks_exact_mut(4), index.chunks_exact(4));
            for (y, i) in (&mut cells).zip(&mut index) {
                let (y, i): (&mut [_; 4], &[u8; 4]) =
                    (y.try_into().expect("4"), i.try_into().expect("4"));
                let [y0, y1, y2, y3] = y;
                put::<STREAM>(y0, read(&i[0]));
                put::<STREAM>(y1, read(&i[1]));
                put::<STREAM>(y2, read(&i[2]));
                put::<STREAM>(y3, read(&i[3]));
            }
            let rest = cells.into_remainder().iter_mut().zip(index.remainder());
            rest.for_each(|(y, i)| put::<STREAM>(y, read(i)));
        }
    }
}
