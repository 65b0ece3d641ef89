//! Modelica.Blocks.Sources (Constant, Step, Ramp, Sine) and Math (Product, Feedback, Add, Gain).

use std::f64::consts::PI;

use super::{reached, Block};
use crate::components::{Component, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out};

/// A block component: its ports, the block itself, and its time events.
struct BlockComponent<B: Block + Clone + 'static> {
    inputs: &'static [&'static str],
    block: B,
    events: Vec<f64>,
}

impl<B: Block + Clone + 'static> Component for BlockComponent<B> {
    fn ports(&self) -> Ports {
        Ports {
            signal_in: self.inputs.to_vec(),
            signal_out: vec!["y"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let inputs = self
            .inputs
            .iter()
            .map(|port| b.signal_in(port))
            .collect::<ModelResult<Vec<_>>>()?;
        let output = b.signal_out("y")?;
        for (port, &slot) in self.inputs.iter().zip(&inputs) {
            b.output(port, Out::Signal(slot));
        }
        b.output("y", Out::Signal(output));
        b.add_block(Box::new(self.block.clone()), inputs, output);
        Ok(())
    }

    fn time_events(&self) -> Vec<f64> {
        self.events.clone()
    }
}

fn boxed<B: Block + Clone + 'static>(
    inputs: &'static [&'static str],
    block: B,
    events: Vec<f64>,
) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(BlockComponent {
        inputs,
        block,
        events,
    }))
}

#[derive(Clone)]
struct Constant(f64);
impl Block for Constant {
    fn eval(&self, _t: f64, _horizon: f64, _u: &[f64]) -> f64 {
        self.0
    }
}

pub fn constant(p: &Params) -> ModelResult<Box<dyn Component>> {
    let k = p.real("k", 1.0)?;
    boxed(&[], Constant(k), vec![])
}

#[derive(Clone)]
struct Step {
    height: f64,
    offset: f64,
    start_time: f64,
}
impl Block for Step {
    fn eval(&self, t: f64, horizon: f64, _u: &[f64]) -> f64 {
        self.offset
            + if reached(t, self.start_time, horizon) {
                self.height
            } else {
                0.0
            }
    }
}

pub fn step(p: &Params) -> ModelResult<Box<dyn Component>> {
    let s = Step {
        height: p.real("height", 1.0)?,
        offset: p.real("offset", 0.0)?,
        start_time: p.real("startTime", 0.0)?,
    };
    let events = vec![s.start_time];
    boxed(&[], s, events)
}

#[derive(Clone)]
struct Ramp {
    height: f64,
    duration: f64,
    offset: f64,
    start_time: f64,
}
impl Block for Ramp {
    fn eval(&self, t: f64, horizon: f64, _u: &[f64]) -> f64 {
        let end = self.start_time + self.duration;
        self.offset
            + if !reached(t, self.start_time, horizon) {
                0.0
            } else if !reached(t, end, horizon) {
                (t - self.start_time) * self.height / self.duration
            } else {
                self.height
            }
    }
}

pub fn ramp(p: &Params) -> ModelResult<Box<dyn Component>> {
    let r = Ramp {
        height: p.real("height", 1.0)?,
        duration: p.at_least("duration", p.real("duration", 2.0)?, 0.0)?,
        offset: p.real("offset", 0.0)?,
        start_time: p.real("startTime", 0.0)?,
    };
    let events = vec![r.start_time, r.start_time + r.duration];
    boxed(&[], r, events)
}

#[derive(Clone)]
struct Sine {
    amplitude: f64,
    f: f64,
    phase: f64,
    offset: f64,
    start_time: f64,
    continuous: bool,
}
impl Block for Sine {
    fn eval(&self, t: f64, horizon: f64, _u: &[f64]) -> f64 {
        let before = if self.continuous {
            self.amplitude * self.phase.sin()
        } else {
            0.0
        };
        self.offset
            + if reached(t, self.start_time, horizon) {
                self.amplitude * (2.0 * PI * self.f * (t - self.start_time) + self.phase).sin()
            } else {
                before
            }
    }
}

pub fn sine(p: &Params) -> ModelResult<Box<dyn Component>> {
    let s = Sine {
        amplitude: p.real("amplitude", 1.0)?,
        f: p.real("f", 1.0)?,
        phase: p.real("phase", 0.0)?,
        offset: p.real("offset", 0.0)?,
        start_time: p.real("startTime", 0.0)?,
        continuous: p.boolean("continuous", false)?,
    };
    let events = vec![s.start_time];
    boxed(&[], s, events)
}

#[derive(Clone)]
struct Product;
impl Block for Product {
    fn eval(&self, _t: f64, _horizon: f64, u: &[f64]) -> f64 {
        u[0] * u[1]
    }
}

pub fn product(_p: &Params) -> ModelResult<Box<dyn Component>> {
    boxed(&["u1", "u2"], Product, vec![])
}

#[derive(Clone)]
struct Feedback;
impl Block for Feedback {
    fn eval(&self, _t: f64, _horizon: f64, u: &[f64]) -> f64 {
        u[0] - u[1]
    }
}

pub fn feedback(_p: &Params) -> ModelResult<Box<dyn Component>> {
    boxed(&["u1", "u2"], Feedback, vec![])
}

#[derive(Clone)]
struct Add {
    k1: f64,
    k2: f64,
}
impl Block for Add {
    fn eval(&self, _t: f64, _horizon: f64, u: &[f64]) -> f64 {
        self.k1 * u[0] + self.k2 * u[1]
    }
}

pub fn add(p: &Params) -> ModelResult<Box<dyn Component>> {
    let a = Add {
        k1: p.real("k1", 1.0)?,
        k2: p.real("k2", 1.0)?,
    };
    boxed(&["u1", "u2"], a, vec![])
}

#[derive(Clone)]
struct Gain(f64);
impl Block for Gain {
    fn eval(&self, _t: f64, _horizon: f64, u: &[f64]) -> f64 {
        self.0 * u[0]
    }
}

pub fn gain(p: &Params) -> ModelResult<Box<dyn Component>> {
    let k = p.required("k")?;
    boxed(&["u"], Gain(k), vec![])
}
