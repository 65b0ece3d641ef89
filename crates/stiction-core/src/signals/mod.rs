//! The signal graph at run time: causal blocks (Modelica.Blocks) evaluated in dependency order,
//! each a function of time and its inputs only. The block components are in `components`.

pub mod derivatives;

pub use derivatives::{Derivative, Jet};

/// A block's output as a function of time and its inputs. `horizon` is the first time event not
/// handled yet: Modelica freezes `time >= t0` between events, so a switch at or after the horizon
/// has not happened, even where the integrator evaluates a little beyond it.
pub trait Block: Send + Sync {
    fn eval(&self, t: f64, horizon: f64, u: &[f64]) -> f64;
    /// The time over which the output turns smoothly (a sine's period; infinite for outputs
    /// that change only at time events or follow their inputs).
    fn time_scale(&self) -> f64 {
        f64::INFINITY
    }
    /// The output and its first two time derivatives from the inputs' (`derivatives`); `None`
    /// for a block whose output has no known derivative, at any time.
    fn jet(&self, _t: f64, _horizon: f64, _u: &[Jet]) -> Option<Jet> {
        None
    }
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
    /// Time derivatives of slots that motion sources follow exactly (usually none).
    pub derivatives: Vec<Derivative>,
}

impl SignalGraph {
    /// The shortest time scale of the blocks' own variation (`Block::time_scale`).
    pub fn time_scale(&self) -> f64 {
        (self.blocks.iter()).fold(f64::INFINITY, |m, b| m.min(b.block.time_scale()))
    }

    pub fn eval(&self, t: f64, horizon: f64, values: &mut [f64]) {
        let mut u = [0.0; 4];
        for b in &self.blocks {
            for (k, &slot) in b.inputs.iter().enumerate() {
                u[k] = values[slot];
            }
            values[b.output] = b.block.eval(t, horizon, &u[..b.inputs.len()]);
        }
        if !self.derivatives.is_empty() {
            self.eval_derivatives(t, horizon, values);
        }
    }
}

/// Two time events closer than the integrator can separate are one event (see the assembly).
#[inline]
pub fn same_instant(a: f64, b: f64) -> bool {
    a.is_finite() && b.is_finite() && (a - b).abs() <= 1e-10 * a.abs().max(b.abs()).max(1.0)
}

/// Modelica's `time >= t0` with frozen time relations: a switch at `t0` has happened once the
/// event at `t0` was handled, i.e. when `t0` lies before the horizon of unhandled events (and is
/// not part of the horizon's own event, merged with it). A switch at the same instant as `t`
/// has happened too: an event that close to the start is merged into the start. (One that
/// close to StopTime is merged into it: the horizon is StopTime once no time event is left.)
#[inline]
pub fn reached(t: f64, t0: f64, horizon: f64) -> bool {
    (t >= t0 || same_instant(t, t0)) && t0 < horizon && !same_instant(t0, horizon)
}
