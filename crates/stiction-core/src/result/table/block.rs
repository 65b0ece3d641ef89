//! The frames of a block of table rows: each evaluated row fills its frame (`frame.rs`), the
//! flange cut torques are solved for the whole block at once (`flanges.rs`), and the rows are
//! then written into the table as plain reads of their frames (`shape.rs`).

use super::flanges::BlockFlanges;
use super::shape::Shape;
use super::stretch::Stretch;
use crate::engine::eval::{DiscreteState, Workspace};
use crate::switching::element::ElementValues;
use crate::system::System;

/// Rows whose flange torques are solved together: enough to amortize each step of the solve,
/// few enough that their frames stay in cache.
pub(super) const BLOCK: usize = 64;

/// The frames of up to `BLOCK` evaluated rows.
pub(super) struct Block<'a> {
    shape: &'a Shape,
    frames: Vec<f64>,
    /// The discrete state whose variables each frame holds (`u32::MAX`: none yet).
    held: Vec<u32>,
    /// The discrete variables of each discrete state of the run, once computed (as long as
    /// the highest state met).
    discrete: Vec<Option<Box<[f64]>>>,
    /// The result rows held (consecutive), and whether each could be evaluated (a mode that
    /// cannot be factored leaves every variable but time NaN, as the row recorder does).
    pub rows: Vec<(usize, bool)>,
    flanges: BlockFlanges,
}

impl<'a> Block<'a> {
    /// An empty block of frames of `shape`.
    pub(super) fn new(shape: &'a Shape) -> Self {
        let mut frames = vec![0.0; BLOCK * shape.stride];
        // constants once: nothing else writes their slots
        for frame in frames.chunks_exact_mut(shape.stride) {
            for &(slot, c) in &shape.layout.constants {
                frame[slot as usize] = c;
            }
        }
        Self {
            shape,
            frames,
            held: vec![u32::MAX; BLOCK],
            discrete: Vec::new(),
            rows: Vec::with_capacity(BLOCK),
            flanges: BlockFlanges::default(),
        }
    }

    /// Fills the next frame from row `r`'s evaluation (at `t`, in discrete state `id`), if it has
    /// one.
    pub(super) fn push(
        &mut self,
        sys: &System,
        r: usize,
        (id, t): (u32, f64),
        row: Option<(&Workspace, &DiscreteState)>,
    ) {
        let i = self.rows.len();
        self.rows.push((r, row.is_some()));
        let Some((ws, disc)) = row else {
            return;
        };
        let (layout, stride) = (&self.shape.layout, self.shape.stride);
        let frame = &mut self.frames[i * stride..i * stride + self.shape.span];
        if self.held[i] != id {
            if id as usize >= self.discrete.len() {
                self.discrete.resize(id as usize + 1, None);
            }
            let values = self.discrete[id as usize].get_or_insert_with(|| {
                // a mode or flag is a function of the discrete state alone
                let none = ElementValues::default();
                let vars = layout.discrete.iter();
                let value = |&(k, var, _): &(usize, _, u32)| {
                    sys.switching[k].variable(&disc.switching[k], &none, var)
                };
                vars.map(value).collect()
            });
            for (&(.., slot), v) in layout.discrete.iter().zip(values.iter()) {
                frame[slot as usize] = *v;
            }
            self.held[i] = id;
        }
        layout.fill(frame, (sys, ws, disc), t);
    }

    /// Writes the held rows (times `t`, by row) into their stretch of the table and empties
    /// the block.
    pub(super) fn flush(&mut self, sys: &System, t: &[f64], out: &mut Stretch) {
        let Some(&(first, _)) = self.rows.first() else {
            return;
        };
        let Shape {
            layout,
            stride,
            span,
            reader,
        } = self.shape;
        let (n, stride, span) = (self.rows.len(), *stride, *span);
        let frames = &mut self.frames[..n * stride];
        if let Some(plan) = &layout.flanges {
            self.flanges.solve(plan, sys, frames, (stride, n));
        }
        let post = &layout.post;
        let (width, at, stream) = (out.width, first - out.first, out.stream);
        let rows = out.data[at * width..(at + n) * width].chunks_exact_mut(width);
        for ((out, frame), &(r, ok)) in rows.zip(frames.chunks_exact_mut(stride)).zip(&self.rows) {
            if !ok {
                out[0].write(t[r]);
                out[1..].iter_mut().for_each(|y| _ = y.write(f64::NAN));
                continue;
            }
            let frame = &mut frame[..span];
            // what reads a flange torque never needs the workspace
            post.run_frame(frame, |_| f64::NAN);
            if stream {
                reader.write::<true>(frame, out);
            } else {
                reader.write::<false>(frame, out);
            }
        }
        out.written += n * width;
        self.rows.clear();
    }
}
