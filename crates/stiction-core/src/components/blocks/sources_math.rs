//! Modelica.Blocks.Sources (Constant, Step, Ramp, Sine) and Math (Product, Feedback, Add, Gain).

use crate::components::decl::{OFFSET, START_TIME};
use std::f64::consts::PI;

use crate::components::{Component, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::signals::derivatives::{linear, product as leibniz, scaled};
use crate::signals::{reached, Block, Jet};
use crate::system::{Builder, Out};

/// A block component: its ports, the block itself, and its time events.
struct BlockComponent<B: Block + Clone + 'static> {
    inputs: &'static [&'static str],
    block: B,
    events: Events,
}

/// A block's time events: a few fixed instants, or edges that recur up to the stop time.
enum Events {
    Fixed(Vec<f64>),
    Recurring(Box<dyn Fn(f64, f64) -> Vec<f64> + Send + Sync>),
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

    fn time_events(&self, from: f64, until: f64) -> Vec<f64> {
        match &self.events {
            Events::Fixed(times) => times.clone(),
            Events::Recurring(edges) => edges(from, until),
        }
    }
}

pub(super) fn boxed<B: Block + Clone + 'static>(
    inputs: &'static [&'static str],
    block: B,
    events: Vec<f64>,
) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(BlockComponent {
        inputs,
        block,
        events: Events::Fixed(events),
    }))
}

#[derive(Clone)]
struct Constant(f64);
impl Block for Constant {
    fn eval(&self, _t: f64, _horizon: f64, _u: &[f64]) -> f64 {
        self.0
    }
    fn jet(&self, _t: f64, _horizon: f64, _u: &[Jet]) -> Option<Jet> {
        Some([self.0, 0.0, 0.0])
    }
}

pub fn constant(p: &Params) -> ModelResult<Box<dyn Component>> {
    let k = p.real("k [1] Constant output value", 1.0)?;
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
    /// Constant between events (the step itself is a time event).
    fn jet(&self, t: f64, horizon: f64, _u: &[Jet]) -> Option<Jet> {
        Some([self.eval(t, horizon, &[]), 0.0, 0.0])
    }
}

pub fn step(p: &Params) -> ModelResult<Box<dyn Component>> {
    let s = Step {
        height: p.real("height [1] Height of the step", 1.0)?,
        offset: p.real(OFFSET, 0.0)?,
        start_time: p.real(START_TIME, 0.0)?,
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
    /// The slope while rising (its start and end are time events).
    fn jet(&self, t: f64, horizon: f64, _u: &[Jet]) -> Option<Jet> {
        let end = self.start_time + self.duration;
        let rising = reached(t, self.start_time, horizon) && !reached(t, end, horizon);
        let slope = if rising {
            self.height / self.duration
        } else {
            0.0
        };
        Some([self.eval(t, horizon, &[]), slope, 0.0])
    }
}

pub fn ramp(p: &Params) -> ModelResult<Box<dyn Component>> {
    let r = Ramp {
        height: p.real("height [1] Height of the ramp", 1.0)?,
        duration: p.at_least(
            "duration",
            p.real("duration [s] Duration of the ramp (0 gives a step)", 2.0)?,
            0.0,
        )?,
        offset: p.real(OFFSET, 0.0)?,
        start_time: p.real(START_TIME, 0.0)?,
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
    fn time_scale(&self) -> f64 {
        1.0 / self.f.abs()
    }
    fn jet(&self, t: f64, horizon: f64, _u: &[Jet]) -> Option<Jet> {
        if !reached(t, self.start_time, horizon) {
            return Some([self.eval(t, horizon, &[]), 0.0, 0.0]);
        }
        let omega = 2.0 * PI * self.f;
        let arg = omega * (t - self.start_time) + self.phase;
        let (a, w2) = (self.amplitude, omega * omega);
        Some([
            self.eval(t, horizon, &[]),
            a * omega * arg.cos(),
            -a * w2 * arg.sin(),
        ])
    }
}

pub fn sine(p: &Params) -> ModelResult<Box<dyn Component>> {
    let s = Sine {
        amplitude: p.real("amplitude [1] Amplitude of the sine wave", 1.0)?,
        f: p.real("f [Hz] Frequency of the sine wave", 1.0)?,
        phase: p.real("phase [rad] Phase of the sine wave", 0.0)?,
        offset: p.real(OFFSET, 0.0)?,
        start_time: p.real(START_TIME, 0.0)?,
        continuous: p.boolean(
            "continuous true: y = offset + amplitude*sin(phase) before startTime",
            false,
        )?,
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
    fn jet(&self, _t: f64, _horizon: f64, u: &[Jet]) -> Option<Jet> {
        Some(leibniz(u[0], u[1]))
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
    fn jet(&self, _t: f64, _horizon: f64, u: &[Jet]) -> Option<Jet> {
        Some(linear(1.0, u[0], -1.0, u[1]))
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
    fn jet(&self, _t: f64, _horizon: f64, u: &[Jet]) -> Option<Jet> {
        Some(linear(self.k1, u[0], self.k2, u[1]))
    }
}

pub fn add(p: &Params) -> ModelResult<Box<dyn Component>> {
    let a = Add {
        k1: p.real("k1 [1] Gain of input signal u1", 1.0)?,
        k2: p.real("k2 [1] Gain of input signal u2", 1.0)?,
    };
    boxed(&["u1", "u2"], a, vec![])
}

#[derive(Clone)]
struct Gain(f64);
impl Block for Gain {
    fn eval(&self, _t: f64, _horizon: f64, u: &[f64]) -> f64 {
        self.0 * u[0]
    }
    fn jet(&self, _t: f64, _horizon: f64, u: &[Jet]) -> Option<Jet> {
        Some(scaled(self.0, u[0]))
    }
}

pub fn gain(p: &Params) -> ModelResult<Box<dyn Component>> {
    let k = p.required("k [1] Gain multiplied with the input signal")?;
    boxed(&["u"], Gain(k), vec![])
}

/// Modelica.Blocks.Sources.Pulse: `amplitude` for `width` % of each `period` from `startTime`,
/// `nperiod` periods (−1: for ever); every edge is a time event.
#[derive(Clone)]
struct Pulse {
    amplitude: f64,
    width: f64,
    period: f64,
    nperiod: i64,
    offset: f64,
    start_time: f64,
}

impl Pulse {
    fn period_start(&self, k: i64) -> f64 {
        self.start_time + k as f64 * self.period
    }

    /// Pulse edges in `[from, until]`, from the period containing `from`, at most
    /// `MAX_TIME_EVENTS` of them.
    fn edges(&self, from: f64, until: f64) -> Vec<f64> {
        let mut edges = Vec::new();
        let mut k = ((from - self.start_time) / self.period).floor().max(0.0) as i64;
        while self.period_start(k) <= until
            && (self.nperiod < 0 || k < self.nperiod)
            && edges.len() < crate::components::MAX_TIME_EVENTS
        {
            edges.push(self.period_start(k));
            edges.push(self.period_start(k) + self.width);
            k += 1;
        }
        edges
    }
}

impl Block for Pulse {
    fn eval(&self, t: f64, horizon: f64, _u: &[f64]) -> f64 {
        if self.nperiod == 0 || !reached(t, self.start_time, horizon) {
            return self.offset;
        }
        // The current period: the last period start that has been reached (edges are events).
        let mut k = ((t - self.start_time) / self.period).floor().max(0.0) as i64;
        while k > 0 && !reached(t, self.period_start(k), horizon) {
            k -= 1;
        }
        while reached(t, self.period_start(k + 1), horizon) {
            k += 1;
        }
        if self.nperiod > 0 && k >= self.nperiod {
            return self.offset;
        }
        let high = !reached(t, self.period_start(k) + self.width, horizon);
        self.offset + if high { self.amplitude } else { 0.0 }
    }
    /// Constant between its edges (each a time event).
    fn jet(&self, t: f64, horizon: f64, _u: &[Jet]) -> Option<Jet> {
        Some([self.eval(t, horizon, &[]), 0.0, 0.0])
    }
}

pub fn pulse(p: &Params) -> ModelResult<Box<dyn Component>> {
    let period = p.positive("period", p.real("period [s] Time for one period", 1.0)?)?;
    let width_percent = p.real("width [%] Width of the pulse in % of the period", 50.0)?;
    p.range("width", "(0, 100]");
    if !(width_percent > 0.0 && width_percent <= 100.0) {
        return Err(p.error(
            "width",
            format!("must be in (0, 100] %, got {width_percent}"),
        ));
    }
    let nperiod = p.real("nperiod [1] Number of periods (< 0: for ever)", -1.0)?;
    p.range("nperiod", "a whole number");
    if nperiod.fract() != 0.0 {
        return Err(p.error(
            "nperiod",
            format!("must be a whole number (−1: for ever), got {nperiod}"),
        ));
    }
    let block = Pulse {
        amplitude: p.real("amplitude [1] Amplitude of the pulse", 1.0)?,
        width: period * width_percent / 100.0,
        period,
        nperiod: nperiod as i64,
        offset: p.real(OFFSET, 0.0)?,
        start_time: p.real(START_TIME, 0.0)?,
    };
    let edges = block.clone();
    Ok(Box::new(BlockComponent {
        inputs: &[],
        block,
        events: Events::Recurring(Box::new(move |from, until| edges.edges(from, until))),
    }))
}
