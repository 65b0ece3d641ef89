//! Chattering, as Modelica tools see it: one element changing its mode again and again within a
//! vanishing window of time (a Zeno-like accumulation of events), not a large number of events
//! overall — a clutch under a 5 Hz torque switches four times a second for as long as it runs.

use std::collections::{HashMap, VecDeque};

use crate::error::SimError;
use crate::model::Experiment;

/// This many mode changes of one element …
pub const CHANGES: usize = 25;
/// … within this fraction of the time scale (the span of the run, or the time itself) chatter.
pub const WINDOW: f64 = 1e-9;

pub struct ChatterWatch {
    recent: HashMap<String, VecDeque<f64>>,
    span: f64,
}

impl ChatterWatch {
    pub fn new(experiment: &Experiment) -> Self {
        Self {
            recent: HashMap::new(),
            span: experiment.stop_time - experiment.start_time,
        }
    }

    /// The window at time `t`.
    pub fn window(&self, t: f64) -> f64 {
        WINDOW * self.span.max(t.abs())
    }

    /// Notes a mode change of `element` at `t`; chattering is an error naming it.
    pub fn record(&mut self, element: &str, t: f64, cause: &str) -> Result<(), SimError> {
        let window = self.window(t);
        let times = self.recent.entry(element.to_string()).or_default();
        times.push_back(t);
        if times.len() > CHANGES {
            times.pop_front();
        }
        match times.front() {
            Some(&first) if times.len() == CHANGES && t - first <= window => {
                Err(SimError::Chattering {
                    time: t,
                    element: element.to_string(),
                    changes: CHANGES,
                    window,
                    cause: cause.to_string(),
                })
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn many_changes_at_one_instant_chatter_and_many_over_time_do_not() {
        let exp = Experiment {
            stop_time: 20_000.0,
            ..Experiment::default()
        };
        let mut steady = ChatterWatch::new(&exp);
        for k in 0..100_000 {
            steady.record("clutch1", k as f64 * 0.2, "slip").unwrap();
        }
        let mut zeno = ChatterWatch::new(&exp);
        let mut t = 10.0;
        let outcome = (0..1000).try_for_each(|k| {
            t += 1e-3 * 0.5f64.powi(k);
            zeno.record("brake", t, "bounce")
        });
        match outcome {
            Err(SimError::Chattering {
                element, changes, ..
            }) => {
                assert_eq!((element.as_str(), changes), ("brake", CHANGES))
            }
            other => panic!("{other:?}"),
        }
    }
}
