//! The signal graph at run time: causal blocks (Modelica.Blocks) evaluated in dependency order,
//! each a function of time and its inputs only, and sensors (Rotational.Sensors), whose outputs
//! read the mechanical state or the linear solve. The block components are in `components`.
//!
//! The graph is evaluated in three stages (`Stage`): blocks that depend on time and model inputs
//! only (cached per instant by the engine), then sensors of angles and speeds and the blocks
//! downstream of them (after the node angles and speeds are known), then sensors of
//! accelerations and cut torques and their blocks (after the linear solve). A graph without
//! sensors has only the first stage.

use crate::rel::Rel;

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

/// When a signal is known within one evaluation: from time and the model inputs alone, once
/// the node angles and speeds are, or only after the linear solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    Time,
    State,
    Solved,
}

/// What a sensor measures.
#[derive(Debug, Clone)]
pub enum Measure {
    /// An angle (absolute, or relative with an offset): `rel·phi + offset`.
    Angle(Rel),
    Speed(Rel),
    Accel(Rel),
    /// The multiplier of a permanent constraint (a torque sensor's rigid row), times a factor.
    Torque(usize, f64),
    /// That torque times a speed: the power through the flange.
    Power(usize, f64, Rel),
}

impl Measure {
    pub fn stage(&self) -> Stage {
        match self {
            Measure::Angle(_) | Measure::Speed(_) => Stage::State,
            _ => Stage::Solved,
        }
    }
}

/// A sensor's output: `measure` written into `slot`.
pub struct Sensor {
    pub owner: String,
    /// The output port's name (`w`, `tau`, …), for messages.
    pub port: &'static str,
    pub measure: Measure,
    pub slot: usize,
}

/// What the later stages read besides the signals.
pub struct Mechanics<'a> {
    pub phi: &'a [f64],
    pub w: &'a [f64],
    pub a: &'a [f64],
    pub constraint_tau: &'a [f64],
}

#[derive(Default)]
pub struct SignalGraph {
    pub slots: usize,
    /// In evaluation order (inputs before the blocks that read them). Until the assembly
    /// stages the graph, every block; then those of `Stage::Time`.
    pub blocks: Vec<BlockElem>,
    /// The sensors and blocks of `Stage::State` and of `Stage::Solved`, in evaluation order.
    pub state: StagePart,
    pub solved: StagePart,
    /// Time derivatives of slots that motion sources follow exactly (usually none).
    pub derivatives: Vec<Derivative>,
}

/// The sensors of one stage, then the blocks that depend on them.
#[derive(Default)]
pub struct StagePart {
    pub sensors: Vec<Sensor>,
    pub blocks: Vec<BlockElem>,
}

impl StagePart {
    pub fn is_empty(&self) -> bool {
        self.sensors.is_empty() && self.blocks.is_empty()
    }

    pub fn eval(&self, t: f64, horizon: f64, m: &Mechanics, values: &mut [f64]) {
        for s in &self.sensors {
            values[s.slot] = match &s.measure {
                Measure::Angle(rel) => rel.angle(m.phi),
                Measure::Speed(rel) => rel.dot(m.w),
                Measure::Accel(rel) => rel.dot(m.a),
                Measure::Torque(k, c) => c * m.constraint_tau[*k],
                Measure::Power(k, c, rel) => c * m.constraint_tau[*k] * rel.dot(m.w),
            };
        }
        eval_blocks(&self.blocks, t, horizon, values);
    }
}

impl SignalGraph {
    /// The shortest time scale of the blocks' own variation (`Block::time_scale`).
    pub fn time_scale(&self) -> f64 {
        (self.blocks.iter())
            .chain(&self.state.blocks)
            .chain(&self.solved.blocks)
            .fold(f64::INFINITY, |m, b| m.min(b.block.time_scale()))
    }

    /// Some blocks of `Stage::Time` (indices into `blocks`, in their order) and no
    /// derivatives: the outputs `eval` gives them when their inputs are among these blocks'
    /// outputs or the model inputs (a result computing one variable alone).
    pub fn eval_some(&self, some: &[usize], t: f64, horizon: f64, values: &mut [f64]) {
        let blocks = some.iter().map(|&i| &self.blocks[i]);
        eval_blocks(blocks, t, horizon, values);
    }

    /// The blocks of `Stage::Time`.
    pub fn eval(&self, t: f64, horizon: f64, values: &mut [f64]) {
        eval_blocks(&self.blocks, t, horizon, values);
        if !self.derivatives.is_empty() {
            self.eval_derivatives(t, horizon, values);
        }
    }
}

fn eval_blocks<'a>(
    blocks: impl IntoIterator<Item = &'a BlockElem>,
    t: f64,
    horizon: f64,
    values: &mut [f64],
) {
    let mut u = [0.0; 4];
    for b in blocks {
        for (k, &slot) in b.inputs.iter().enumerate() {
            u[k] = values[slot];
        }
        values[b.output] = b.block.eval(t, horizon, &u[..b.inputs.len()]);
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
