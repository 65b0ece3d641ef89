//! Sweeps: many variants of one compiled model, run in parallel (rayon), each giving its
//! metrics and, if asked, trajectories on the output grid. The compiled model is shared
//! read-only; each variant builds its system and runs its own `Simulation` on one thread. A
//! variant that fails (an invalid value, a solver failure) gives its error as its status and
//! never stops the others. Results come back in the order of the variants, whatever the number
//! of threads: they are the same to the last bit.

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Instant;

use rayon::prelude::*;

use crate::assembly::CompiledModel;
use crate::engine::eval::DiscreteState;
use crate::error::ModelResult;
use crate::model::Experiment;
use crate::result::{Accumulator, EventRecord, Metric, Probe, RowView};
use crate::simulation::{each_row, CancelHandle, Observer, Simulation};

/// An override: a parameter, start value or experiment setting by name, and its value.
pub type Override = (String, toml::Value);

/// What each variant reports.
#[derive(Debug, Clone)]
pub struct Plan {
    pub metrics: Vec<Metric>,
    /// Variables kept as trajectories on the output grid.
    pub outputs: Vec<String>,
}

impl Plan {
    /// Checks the metrics and outputs against the compiled model's variables.
    pub fn new(cm: &CompiledModel, metrics: &[String], outputs: &[String]) -> ModelResult<Self> {
        let sys = cm.system();
        let names: Vec<String> = sys.outputs.iter().map(|(n, _)| n.clone()).collect();
        let elements: Vec<String> = sys.switching.iter().map(|e| e.name().to_string()).collect();
        let metrics = metrics
            .iter()
            .map(|m| Metric::parse(m, &names, &elements).map(|m| m.for_system(&sys)))
            .collect::<ModelResult<Vec<_>>>()?;
        for name in outputs {
            if !names.contains(name) {
                return Err(crate::error::ModelError::File(format!(
                    "output '{name}' is not a variable of the model"
                )));
            }
        }
        Ok(Plan {
            metrics,
            outputs: outputs.to_vec(),
        })
    }

    /// The variables a run must probe: those of the metrics, then the outputs.
    fn probed(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for name in self.metrics.iter().filter_map(|m| m.variable.as_ref()) {
            if !names.contains(name) {
                names.push(name.clone());
            }
        }
        for name in &self.outputs {
            if !names.contains(name) {
                names.push(name.clone());
            }
        }
        names
    }
}

/// One variant's outcome.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// One value per metric (NaN where the variant failed).
    pub metrics: Vec<f64>,
    /// One trajectory per output, on the output grid (empty where the variant failed).
    pub trajectories: Vec<Vec<f64>>,
    /// None when it ran to the end; otherwise the error, as the user would read it.
    pub error: Option<String>,
    pub wall_s: f64,
}

/// Runs one variant.
pub fn run_variant(
    cm: &CompiledModel,
    overrides: &[Override],
    plan: &Plan,
    cancel: &CancelHandle,
) -> Outcome {
    let started = Instant::now();
    let result = run(cm, overrides, plan, cancel).map_err(|error| match cancel.is_cancelled() {
        true => "cancelled".to_string(),
        false => error,
    });
    let wall_s = started.elapsed().as_secs_f64();
    match result {
        Ok((metrics, trajectories)) => Outcome {
            metrics,
            trajectories,
            error: None,
            wall_s,
        },
        Err(error) => Outcome {
            metrics: vec![f64::NAN; plan.metrics.len()],
            trajectories: Vec::new(),
            error: Some(error),
            wall_s,
        },
    }
}

/// Runs the variants on `workers` threads (every core when None), in their order. Once
/// `cancel` is set, the runs under way stop at their next step and they and the variants not
/// started yet report "cancelled".
pub fn run_variants(
    cm: &CompiledModel,
    variants: &[Vec<Override>],
    plan: &Plan,
    workers: Option<usize>,
    cancel: &CancelHandle,
) -> Vec<Outcome> {
    let one = |overrides: &Vec<Override>| {
        if cancel.is_cancelled() {
            return Outcome {
                metrics: vec![f64::NAN; plan.metrics.len()],
                trajectories: Vec::new(),
                error: Some("cancelled".into()),
                wall_s: 0.0,
            };
        }
        run_variant(cm, overrides, plan, cancel)
    };
    if workers == Some(1) {
        return variants.iter().map(one).collect();
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(workers.unwrap_or(0))
        .build();
    match pool {
        Ok(pool) => pool.install(|| variants.par_iter().map(one).collect()),
        // no threads to be had: run them here
        Err(_) => variants.iter().map(one).collect(),
    }
}

type Values = (Vec<f64>, Vec<Vec<f64>>);

fn run(
    cm: &CompiledModel,
    overrides: &[Override],
    plan: &Plan,
    cancel: &CancelHandle,
) -> Result<Values, String> {
    let pairs: Vec<(&str, toml::Value)> = overrides
        .iter()
        .map(|(n, v)| (n.as_str(), v.clone()))
        .collect();
    let sys = cm.variant_system(&pairs).map_err(|e| e.to_string())?;
    let probe = Probe::new(sys.clone(), &plan.probed()).map_err(|e| e.to_string())?;
    let watch = Rc::new(RefCell::new(Watch::new(plan, probe, &sys.experiment)));
    let mut sim = Simulation::new(sys).map_err(|e| e.to_string())?;
    sim.set_recording(false);
    sim.share_cancel(cancel);
    let states = watch.borrow().probe.states_read();
    sim.set_observer(Box::new(Shared(watch.clone(), states)));
    sim.run().map_err(|e| e.to_string())?;
    drop(sim);
    let watch = Rc::try_unwrap(watch)
        .map_err(|_| "internal: the observer outlived its run".to_string())?
        .into_inner();
    watch.finish()
}

/// The metrics and trajectories of one run, fed row by row.
struct Watch {
    probe: Probe,
    /// For each metric, the index of its variable among the probed ones.
    metric_column: Vec<Option<usize>>,
    accumulators: Vec<Accumulator>,
    output_column: Vec<usize>,
    grid: Grid,
    trajectories: Vec<Vec<f64>>,
    error: Option<String>,
    /// One metric's variable over a block of rows (`metric_rows`).
    column: Vec<f64>,
}

impl Watch {
    fn new(plan: &Plan, probe: Probe, experiment: &Experiment) -> Self {
        let probed = plan.probed();
        let column = |name: &String| probed.iter().position(|n| n == name);
        let grid = Grid::new(experiment);
        Watch {
            metric_column: (plan.metrics.iter())
                .map(|m| m.variable.as_ref().and_then(column))
                .collect(),
            accumulators: plan.metrics.iter().map(Accumulator::new).collect(),
            output_column: plan.outputs.iter().filter_map(column).collect(),
            trajectories: vec![vec![f64::NAN; grid.points()]; plan.outputs.len()],
            grid,
            probe,
            error: None,
            column: Vec::new(),
        }
    }

    fn finish(self) -> Result<Values, String> {
        if let Some(error) = self.error {
            return Err(error);
        }
        let metrics = self.accumulators.iter().map(Accumulator::value).collect();
        Ok((metrics, self.trajectories))
    }

    /// Rows `ts` (states `xs`, `n` a row) in one discrete state into the metrics, when every
    /// variable is read from the state alone and no trajectory is kept: each metric takes
    /// its column of the block in the rows' order, as `row` would give them to it one by one
    /// (the metrics are independent, so the same bits).
    fn metric_rows(&mut self, ts: &[f64], xs: &[f64], n: usize, disc: &DiscreteState) {
        let Watch {
            probe,
            metric_column,
            accumulators,
            column,
            ..
        } = self;
        for (acc, c) in accumulators.iter_mut().zip(metric_column.iter()) {
            let Some(c) = *c else { continue };
            column.clear();
            probe.direct_column(c, (xs, n, ts.len()), disc, column);
            acc.rows_in(ts, column, disc);
        }
    }

    /// One row: the probed variables into the metrics, and onto the output grid.
    fn row(&mut self, row: &RowView) {
        if self.error.is_some() {
            return;
        }
        let values = match self.probe.values(row) {
            Ok(values) => values,
            Err(e) => {
                self.error = Some(e.to_string());
                return;
            }
        };
        for (acc, column) in self.accumulators.iter_mut().zip(&self.metric_column) {
            if let Some(c) = column {
                acc.row_in(row.t, values[*c], row.disc);
            }
        }
        if self.trajectories.is_empty() {
            return;
        }
        if let Some(k) = self.grid.point(row.t) {
            for (traj, &c) in self.trajectories.iter_mut().zip(&self.output_column) {
                traj[k] = values[c];
            }
        }
    }
}

/// The observer handed to the `Simulation`; the sweep reads the `Watch` after the run. With
/// the states its variables are read from, when they need no others (`Probe::states_read`).
struct Shared(Rc<RefCell<Watch>>, Option<Vec<usize>>);

impl Observer for Shared {
    fn row(&mut self, row: &RowView) {
        self.0.borrow_mut().row(row);
    }

    fn states_read(&self) -> Option<&[usize]> {
        self.1.as_deref()
    }

    /// The rows of a step under one borrow of the `Watch`: metrics over variables read from
    /// the state alone take them one metric at a time (`Watch::metric_rows`).
    fn grid_rows(&mut self, ts: &[f64], xs: &[f64], disc: &DiscreteState, horizon: f64) {
        let mut watch = self.0.borrow_mut();
        if watch.error.is_none() && watch.probe.is_direct() && watch.trajectories.is_empty() {
            let n = xs.len().checked_div(ts.len()).unwrap_or(0);
            watch.metric_rows(ts, xs, n, disc);
            return;
        }
        each_row(ts, xs, disc, horizon, |row| watch.row(row));
    }

    fn event(&mut self, event: &EventRecord) {
        if event.cause != "initialization" {
            for acc in &mut self.0.borrow_mut().accumulators {
                acc.event(&event.component);
            }
        }
    }
}

/// Which rows fall on the output grid: a later row at the same instant (the right side of an
/// event there) replaces the earlier one.
struct Grid {
    experiment: Experiment,
    next: usize,
    /// `grid_len() + 1`, once: a division and a `ceil` that each row's test made again.
    points: usize,
}

impl Grid {
    fn new(experiment: &Experiment) -> Self {
        Grid {
            experiment: experiment.clone(),
            next: 0,
            points: experiment.grid_len() + 1,
        }
    }

    fn points(&self) -> usize {
        self.points
    }

    fn point(&mut self, t: f64) -> Option<usize> {
        let eps = 1e-12 * t.abs().max(1.0);
        while self.next < self.points() && self.experiment.grid_time(self.next) < t - eps {
            self.next += 1;
        }
        let on_grid =
            self.next < self.points() && (self.experiment.grid_time(self.next) - t).abs() <= eps;
        on_grid.then_some(self.next)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelSpec;

    const COUPLED: &str = include_str!("../../../examples/msl/CoupledClutches.toml");

    fn probe_of(metrics: &[&str]) -> Probe {
        let cm = CompiledModel::new(ModelSpec::from_toml(COUPLED, ".").unwrap()).unwrap();
        let metrics: Vec<String> = metrics.iter().map(|m| m.to_string()).collect();
        let plan = Plan::new(&cm, &metrics, &[]).unwrap();
        Probe::new(cm.system(), &plan.probed()).unwrap()
    }

    /// Rows given as blocks (`Accumulator::rows_in`, what a sweep's grid rows take) give
    /// every metric the bits they give one by one (`row_in`, what a single run's rows take),
    /// whatever the blocks: extremes inside a block, at its ends, blocks of one row.
    #[test]
    fn a_block_of_rows_gives_each_metric_what_single_rows_give() {
        let names: Vec<String> = ["time", "J1.w"].map(String::from).to_vec();
        let disc = DiscreteState {
            switching: Vec::new(),
            relations: Vec::new(),
            inputs: Vec::new(),
        };
        let ts: Vec<f64> = (0..40).map(|i| 0.025 * i as f64).collect();
        let vs: Vec<f64> = (0..40)
            .map(|i| 3.1 * (0.37 * i as f64).sin() + 0.1)
            .collect();
        for text in [
            "max(J1.w)",
            "min(J1.w)",
            "final(J1.w)",
            "integral(J1.w)",
            "mean(J1.w)",
            "time_of(J1.w > 2)",
        ] {
            let metric = Metric::parse(text, &names, &[]).unwrap();
            let mut one = Accumulator::new(&metric);
            (ts.iter().zip(&vs)).for_each(|(&t, &v)| one.row_in(t, v, &disc));
            for size in 1..=7 {
                let mut blocks = Accumulator::new(&metric);
                for (t, v) in ts.chunks(size).zip(vs.chunks(size)) {
                    blocks.rows_in(t, v, &disc);
                }
                assert_eq!(
                    blocks.value().to_bits(),
                    one.value().to_bits(),
                    "{text}, {size}"
                );
            }
        }
    }

    /// The path `metrics_read_from_the_states_alone_equal_single_runs` (tests/sweep.rs) checks
    /// is the one taken: speeds and modes read two states; a torque needs every state.
    #[test]
    fn metrics_over_speeds_read_their_states_alone() {
        let probe = probe_of(&[
            "max(J1.w)",
            "max(J4.w)",
            "time_of(clutch3.locked)",
            "events()",
        ]);
        assert!(probe.is_direct());
        assert_eq!(probe.states_read().map(|s| s.len()), Some(2));
        let probe = probe_of(&["max(J1.w)", "max(clutch1.tau)"]);
        assert!(!probe.is_direct());
        assert_eq!(probe.states_read(), None);
    }
}
