//! Causal signal blocks (Modelica.Blocks): sources, math and time tables. The graph is evaluated
//! in dependency order; every block is a function of time and its inputs only.

mod blocks;
mod timetable;

use crate::components::Constructor;

/// All signal component types.
pub const REGISTRY: &[(&str, Constructor)] = &[
    ("Constant", blocks::constant),
    ("Step", blocks::step),
    ("Ramp", blocks::ramp),
    ("Sine", blocks::sine),
    ("Product", blocks::product),
    ("Feedback", blocks::feedback),
    ("Add", blocks::add),
    ("Gain", blocks::gain),
    ("TimeTable", timetable::time_table),
];

/// A block's output as a function of time and its inputs. `left` asks for the left limit at a
/// time event (the value just before a step), which the result needs for the row before an event.
pub trait Block: Send + Sync {
    fn eval(&self, t: f64, left: bool, u: &[f64]) -> f64;
}

pub struct BlockElem {
    pub owner: String,
    pub block: Box<dyn Block>,
    pub inputs: Vec<usize>,
    pub output: usize,
}

#[derive(Default)]
pub struct SignalGraph {
    pub slots: usize,
    /// In evaluation order (inputs before the blocks that read them).
    pub blocks: Vec<BlockElem>,
}

impl SignalGraph {
    pub fn eval(&self, t: f64, left: bool, values: &mut [f64]) {
        let mut u = [0.0; 4];
        for b in &self.blocks {
            for (k, &slot) in b.inputs.iter().enumerate() {
                u[k] = values[slot];
            }
            values[b.output] = b.block.eval(t, left, &u[..b.inputs.len()]);
        }
    }
}

/// `t` has reached `t0` (Modelica `time >= t0`); at a time event the left limit says not yet.
#[inline]
pub fn reached(t: f64, t0: f64, left: bool) -> bool {
    if left {
        t > t0
    } else {
        t >= t0
    }
}
