//! Metrics: one number per run, written as what they compute — `final(J4.w)`, `max(J1.w)`,
//! `min(…)`, `integral(brake.lossPower)`, `mean(…)`, `time_of(clutch2.locked)`,
//! `time_of(J1.w < 1)`, `events(clutch1)`, `events()`. An `Accumulator` takes the rows one by
//! one (the output grid and both sides of every event), so a sweep computes a metric while the
//! run goes and `SimResult::metric` replays the stored rows through the same code: the two agree
//! to the last bit.

use super::SimResult;
use crate::engine::eval::DiscreteState;
use crate::error::{ModelError, ModelResult};
use crate::model::near;
use crate::rel::Rel;
use crate::system::outputs::SwitchVar;
use crate::system::{Out, System};

/// A comparison in `time_of(x op value)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

impl Cmp {
    fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum MetricKind {
    Final,
    Max,
    Min,
    /// The trapezoid rule over the rows (`np.trapezoid(r[x], r.time)`).
    Integral,
    /// The integral over the span.
    Mean,
    /// The first instant the condition holds (`x` alone: x ≠ 0); NaN if it never does.
    TimeOf(Cmp, f64),
    /// Mode changes after initialization, of one element or of all.
    Events(Option<String>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Metric {
    /// As written; the column name.
    pub text: String,
    pub kind: MetricKind,
    /// The output variable it reads (none for `events`).
    pub variable: Option<String>,
    /// `time_of` over a speed: the switching elements whose lock holds it (`held_by`), so
    /// that it reads 0 while one of them is locked. Empty until `for_system`.
    pub held: Vec<usize>,
}

impl Metric {
    /// Parses a metric over a model's output `names` and switching `elements`.
    pub fn parse(text: &str, names: &[String], elements: &[String]) -> ModelResult<Self> {
        let error = |why: String| ModelError::File(format!("metric '{text}': {why}"));
        let trimmed = text.trim();
        let (func, arg) = trimmed
            .strip_suffix(')')
            .and_then(|s| s.split_once('('))
            .ok_or_else(|| {
                error(format!(
                    "write it as function(variable), one of {FUNCTIONS}"
                ))
            })?;
        let (func, arg) = (func.trim(), arg.trim());
        let variable = |name: &str| -> ModelResult<String> {
            if names.iter().any(|n| n == name) {
                return Ok(name.to_string());
            }
            Err(error(match near(name, names) {
                None => format!("unknown variable '{name}'"),
                Some((prefix, found)) => format!(
                    "unknown variable '{name}' (variables of {prefix}: {})",
                    found.join(", ")
                ),
            }))
        };
        let (kind, var) = match func {
            "final" => (MetricKind::Final, Some(variable(arg)?)),
            "max" => (MetricKind::Max, Some(variable(arg)?)),
            "min" => (MetricKind::Min, Some(variable(arg)?)),
            "integral" => (MetricKind::Integral, Some(variable(arg)?)),
            "mean" => (MetricKind::Mean, Some(variable(arg)?)),
            "time_of" => {
                let (name, cmp, value) = condition(arg).map_err(error)?;
                (MetricKind::TimeOf(cmp, value), Some(variable(name)?))
            }
            "events" if arg.is_empty() => (MetricKind::Events(None), None),
            "events" if elements.iter().any(|e| e == arg) => {
                (MetricKind::Events(Some(arg.to_string())), None)
            }
            "events" => {
                return Err(error(format!(
                    "'{arg}' is not a switching element (elements: {})",
                    elements.join(", ")
                )))
            }
            _ => {
                return Err(error(format!(
                    "unknown function '{func}' (one of {FUNCTIONS})"
                )))
            }
        };
        Ok(Metric {
            text: trimmed.to_string(),
            kind,
            variable: var,
            held: Vec::new(),
        })
    }

    /// The metric over `sys`: a `time_of` condition on a speed that a locked element holds
    /// reads that speed as 0 while the element is locked (`held_by`).
    pub fn for_system(mut self, sys: &System) -> Self {
        if let (MetricKind::TimeOf(..), Some(name)) = (&self.kind, &self.variable) {
            self.held = held_by(sys, name);
        }
        self
    }
}

/// The switching elements whose lock holds the speed variable `name`: its own relative speed
/// (`brake.w`, `clutch.w_rel`), or a speed the element's locked motion is (up to sign) — a
/// shaft a brake holds against its grounded support (`J.w`). A locked element keeps `a = 0`
/// and its slip where the event band left it (|w| ≈ 1e-10 rad/s, not 0), so "when does it
/// stop" reads such a speed as 0 while one of them is locked. Empty for any other variable.
pub fn held_by(sys: &System, name: &str) -> Vec<usize> {
    let Some((_, out)) = sys.outputs.iter().find(|(n, _)| n == name) else {
        return Vec::new();
    };
    match out {
        Out::Switch(k, SwitchVar::W) => vec![*k],
        Out::Speed(rel) => (sys.switching.iter().enumerate())
            .filter(|(_, e)| same_motion(e.motion(), rel))
            .map(|(k, _)| k)
            .collect(),
        _ => Vec::new(),
    }
}

/// Whether two rows are one motion up to its sign (the offsets, angles only, aside).
fn same_motion(a: &Rel, b: &Rel) -> bool {
    let sign = match (a.terms.first(), b.terms.first()) {
        (Some(x), Some(y)) if x.0 == y.0 && x.1 != 0.0 => y.1 / x.1,
        _ => return false,
    };
    (sign == 1.0 || sign == -1.0)
        && a.terms.len() == b.terms.len()
        && (a.terms.iter().zip(&b.terms)).all(|(x, y)| x.0 == y.0 && x.1 * sign == y.1)
}

const FUNCTIONS: &str = "final, max, min, integral, mean, time_of, events";

/// `x`, or `x op number`.
fn condition(arg: &str) -> Result<(&str, Cmp, f64), String> {
    // A table of pairs, alike in shape to the output lists of the components.
    for (op, cmp) in [
        ("<=", Cmp::Le),
        (">=", Cmp::Ge),
        ("==", Cmp::Eq),
        ("!=", Cmp::Ne),
        ("<", Cmp::Lt),
        (">", Cmp::Gt),
    ] {
        if let Some((name, value)) = arg.split_once(op) {
            let value: f64 = value
                .trim()
                .parse()
                .map_err(|_| format!("'{}' is not a number", value.trim()))?;
            return Ok((name.trim(), cmp, value));
        }
    }
    Ok((arg, Cmp::Ne, 0.0))
}

/// One metric accumulated over the rows of one run.
#[derive(Debug, Clone)]
pub struct Accumulator {
    kind: MetricKind,
    held: Vec<usize>,
    /// `time_of` over a held speed: a row meeting the condition while not held, kept until the
    /// next row shows whether it was the left row of a lock (the same instant, held).
    pending: Option<f64>,
    first_t: f64,
    last: Option<(f64, f64)>,
    acc: f64,
    count: usize,
}

impl Accumulator {
    pub fn new(metric: &Metric) -> Self {
        let acc = match metric.kind {
            MetricKind::Max => f64::NEG_INFINITY,
            MetricKind::Min => f64::INFINITY,
            MetricKind::TimeOf(..) => f64::NAN,
            _ => 0.0,
        };
        Self {
            kind: metric.kind.clone(),
            held: metric.held.clone(),
            pending: None,
            first_t: f64::NAN,
            last: None,
            acc,
            count: 0,
        }
    }

    /// The metric's variable at the next row.
    #[inline]
    pub fn row(&mut self, t: f64, v: f64) {
        match self.kind {
            MetricKind::Max => self.acc = self.acc.max(v),
            MetricKind::Min => self.acc = self.acc.min(v),
            MetricKind::Integral | MetricKind::Mean => {
                if let Some((t0, v0)) = self.last {
                    self.acc += (t - t0) * (v + v0) / 2.0;
                }
            }
            MetricKind::TimeOf(cmp, value) => {
                if self.acc.is_nan() && cmp.holds(v, value) {
                    self.acc = t;
                }
            }
            MetricKind::Final | MetricKind::Events(_) => {}
        }
        if self.last.is_none() {
            self.first_t = t;
        }
        self.last = Some((t, v));
    }

    /// The metric's variable at the next row, in the discrete state `disc`: a speed held by a
    /// locked element reads 0 (`Metric::held`), and so does the row just before its lock at
    /// the same instant (the event's left row, the slip already past the event band).
    #[inline(always)]
    pub fn row_in(&mut self, t: f64, v: f64, disc: &DiscreteState) {
        let MetricKind::TimeOf(cmp, value) = self.kind else {
            return self.row(t, v);
        };
        if self.held.is_empty() {
            return self.row(t, v);
        }
        let held = (self.held.iter()).any(|&k| disc.switching.get(k).is_some_and(|s| s.locked));
        if let Some(tp) = self.pending.take() {
            if !(held && t == tp) {
                self.acc = tp;
            }
        }
        if self.acc.is_nan() && cmp.holds(if held { 0.0 } else { v }, value) {
            if held {
                self.acc = t;
            } else {
                self.pending = Some(t);
            }
        }
        if self.last.is_none() {
            self.first_t = t;
        }
        self.last = Some((t, v));
    }

    /// `row_in` for rows `ts` (values `vs`) in one discrete state: the grid rows of a step,
    /// one loop a metric (its kind's branch taken once by the branch predictor, not re-read
    /// between metrics).
    #[inline(never)]
    pub fn rows_in(&mut self, ts: &[f64], vs: &[f64], disc: &DiscreteState) {
        let rows = ts.len().min(vs.len());
        let (ts, vs) = (&ts[..rows], &vs[..rows]);
        let (Some(&t_end), Some(&v_end)) = (ts.last(), vs.last()) else {
            return;
        };
        // what `row` does row by row for these kinds: the same `max`/`min` in the same order
        match self.kind {
            MetricKind::Max => self.acc = vs.iter().fold(self.acc, |a, &v| a.max(v)),
            MetricKind::Min => self.acc = vs.iter().fold(self.acc, |a, &v| a.min(v)),
            MetricKind::Final | MetricKind::Events(_) => {}
            _ => {
                for (&t, &v) in ts.iter().zip(vs) {
                    self.row_in(t, v, disc);
                }
                return;
            }
        }
        if self.last.is_none() {
            self.first_t = ts[0];
        }
        self.last = Some((t_end, v_end));
    }

    /// A mode change of `component` after initialization.
    pub fn event(&mut self, component: &str) {
        if let MetricKind::Events(ref which) = self.kind {
            if which.as_deref().is_none_or(|w| w == component) {
                self.count += 1;
            }
        }
    }

    pub fn value(&self) -> f64 {
        match self.kind {
            MetricKind::Final => self.last.map_or(f64::NAN, |(_, v)| v),
            MetricKind::Mean => match self.last {
                Some((t, _)) if t > self.first_t => self.acc / (t - self.first_t),
                _ => f64::NAN,
            },
            MetricKind::Events(_) => self.count as f64,
            MetricKind::TimeOf(..) if self.acc.is_nan() => self.pending.unwrap_or(f64::NAN),
            _ => self.acc,
        }
    }
}

impl SimResult {
    fn disc_at(&self, r: usize) -> &DiscreteState {
        &self.discs[self.trajectory.disc[r] as usize]
    }

    /// Per row, whether a locked element holds the speed variable `name` (`held_by`), or is
    /// about to at the same instant (the left row of its lock): the rows where "when does it
    /// stop" reads it as 0, as `time_of` does. All false for any other variable.
    pub fn held_rows(&self, name: &str) -> Vec<bool> {
        let held = held_by(&self.system, name);
        let t = &self.trajectory.t;
        let mut rows: Vec<bool> = (0..t.len())
            .map(|r| {
                let disc = self.disc_at(r);
                (held.iter()).any(|&k| disc.switching.get(k).is_some_and(|s| s.locked))
            })
            .collect();
        // the left row of a lock, at the same instant: its slip is already past the band
        for r in (0..t.len().saturating_sub(1)).rev() {
            if rows[r + 1] && t[r + 1] == t[r] {
                rows[r] = true;
            }
        }
        rows
    }

    /// A metric of this run (see the module): the value a sweep computes while the run goes.
    pub fn metric(&self, text: &str) -> ModelResult<f64> {
        let elements: Vec<String> = self
            .system
            .switching
            .iter()
            .map(|e| e.name().to_string())
            .collect();
        let metric = Metric::parse(text, &self.names, &elements)?.for_system(&self.system);
        let mut acc = Accumulator::new(&metric);
        if let Some(name) = &metric.variable {
            let t = self.column("time").unwrap_or_default();
            let v = self.column(name).unwrap_or_default();
            for (r, (&t, &v)) in t.iter().zip(&v).enumerate() {
                acc.row_in(t, v, self.disc_at(r));
            }
        }
        for e in self.events.iter().filter(|e| e.cause != "initialization") {
            acc.event(&e.component);
        }
        Ok(acc.value())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<String> {
        ["time", "J1.w", "J1.phi", "clutch1.locked"]
            .map(String::from)
            .to_vec()
    }

    fn metric(text: &str) -> Metric {
        Metric::parse(text, &names(), &["clutch1".to_string()]).unwrap()
    }

    fn over(text: &str, rows: &[(f64, f64)]) -> f64 {
        let mut acc = Accumulator::new(&metric(text));
        rows.iter().for_each(|&(t, v)| acc.row(t, v));
        acc.value()
    }

    #[test]
    fn metrics_compute_what_they_say() {
        // v = 2t on [0, 1] with an event pair at 0.5 (the same row twice)
        let rows = [(0.0, 0.0), (0.5, 1.0), (0.5, 1.0), (1.0, 2.0)];
        assert_eq!(over("final(J1.w)", &rows), 2.0);
        assert_eq!(over("max(J1.w)", &rows), 2.0);
        assert_eq!(over("min( J1.w )", &rows), 0.0);
        assert_eq!(over("integral(J1.w)", &rows), 1.0);
        assert_eq!(over("mean(J1.w)", &rows), 1.0);
        assert_eq!(over("time_of(J1.w >= 1)", &rows), 0.5);
        assert_eq!(over("time_of(J1.w)", &rows), 0.5);
        assert!(over("time_of(J1.w > 5)", &rows).is_nan());
        let mut events = Accumulator::new(&metric("events(clutch1)"));
        for c in ["clutch1", "clutch2", "clutch1"] {
            events.event(c);
        }
        assert_eq!(events.value(), 2.0);
    }

    #[test]
    fn a_held_speed_reads_zero_while_locked_and_on_the_left_row_of_its_lock() {
        use crate::switching::element::SwitchState;
        use crate::switching::logic::Discrete;
        let disc = |locked: bool| DiscreteState {
            switching: vec![SwitchState {
                pre: Discrete::INITIAL,
                locked,
                free: false,
                rel: Default::default(),
            }],
            relations: Vec::new(),
            inputs: Vec::new(),
        };
        let (sliding, locked) = (disc(false), disc(true));
        // sliding forward to a lock at t = 1 (its left row already 1e-10 past zero), then held
        let rows = [
            (0.0, 5.0, &sliding),
            (1.0, -1e-10, &sliding),
            (1.0, -1e-10, &locked),
            (2.0, -1e-10, &locked),
        ];
        let run = |text: &str, held: Vec<usize>| {
            let mut m = metric(text);
            m.held = held;
            let mut acc = Accumulator::new(&m);
            rows.iter().for_each(|&(t, v, d)| acc.row_in(t, v, d));
            acc.value()
        };
        assert!(run("time_of(J1.w < 0)", vec![0]).is_nan()); // it never turned backward
        assert_eq!(run("time_of(J1.w == 0)", vec![0]), 1.0);
        assert_eq!(run("time_of(J1.w < 0)", vec![]), 1.0); // the speed alone
        assert!(run("time_of(J1.w == 0)", vec![]).is_nan());
        assert_eq!(run("time_of(J1.w > 1)", vec![0]), 0.0);
        // a row meeting the condition, not followed by a lock at its instant, counts
        let mut m = metric("time_of(J1.w < 0)");
        m.held = vec![0];
        let mut acc = Accumulator::new(&m);
        acc.row_in(0.0, 5.0, &sliding);
        acc.row_in(1.0, -1e-3, &sliding);
        assert_eq!(acc.value(), 1.0); // the last row: held back, then taken
        acc.row_in(2.0, -1e-3, &sliding);
        assert_eq!(acc.value(), 1.0);
    }

    #[test]
    fn bad_metrics_say_what_is_wrong() {
        let err = |text: &str| {
            Metric::parse(text, &names(), &["clutch1".to_string()])
                .unwrap_err()
                .to_string()
        };
        assert!(err("max(J1.ww)").contains("variables of J1: J1.w, J1.phi"));
        assert!(err("median(J1.w)").contains("unknown function 'median'"));
        assert!(err("max J1.w").contains("function(variable)"));
        assert!(err("events(J1)").contains("not a switching element"));
        assert!(err("time_of(J1.w < fast)").contains("'fast' is not a number"));
    }
}
