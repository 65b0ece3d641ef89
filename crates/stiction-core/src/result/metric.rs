//! Metrics: one number per run, written as what they compute — `final(J4.w)`, `max(J1.w)`,
//! `min(…)`, `integral(brake.lossPower)`, `mean(…)`, `time_of(clutch2.locked)`,
//! `time_of(J1.w < 1)`, `events(clutch1)`, `events()`. An `Accumulator` takes the rows one by
//! one (the output grid and both sides of every event), so a sweep computes a metric while the
//! run goes and `SimResult::metric` replays the stored rows through the same code: the two agree
//! to the last bit.

use super::SimResult;
use crate::error::{ModelError, ModelResult};

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
            let prefix = name.split('.').next().unwrap_or(name);
            let near: Vec<&str> = (names.iter())
                .filter(|n| n.split('.').next() == Some(prefix))
                .map(String::as_str)
                .collect();
            Err(error(if near.is_empty() {
                format!("unknown variable '{name}'")
            } else {
                format!(
                    "unknown variable '{name}' (variables of {prefix}: {})",
                    near.join(", ")
                )
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
        })
    }
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
            first_t: f64::NAN,
            last: None,
            acc,
            count: 0,
        }
    }

    /// The metric's variable at the next row.
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
            _ => self.acc,
        }
    }
}

impl SimResult {
    /// A metric of this run (see the module): the value a sweep computes while the run goes.
    pub fn metric(&self, text: &str) -> ModelResult<f64> {
        let elements: Vec<String> = self
            .system
            .switching
            .iter()
            .map(|e| e.name().to_string())
            .collect();
        let metric = Metric::parse(text, &self.names, &elements)?;
        let mut acc = Accumulator::new(&metric);
        if let Some(name) = &metric.variable {
            let t = self.column("time").unwrap_or_default();
            let v = self.column(name).unwrap_or_default();
            t.iter().zip(&v).for_each(|(&t, &v)| acc.row(t, v));
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
