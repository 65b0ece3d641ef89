//! A run that records every variable as it goes (`run_recording_all`): the run advances in
//! short slices, and after each one hands the rows it recorded to the pool's threads, which
//! compute their variables (`result::recorded_while`), so that most of the table is done when
//! the run ends. The run itself is that of one `advance_to`, bit for bit (the slices pause
//! between integrator steps).

use std::sync::Arc;
use std::time::Duration;

use super::stepper::expected_rows;
use super::Simulation;
use crate::error::SimError;
use crate::result::{recorded_while, SimResult, MAX_TABLE_VALUES};
use crate::system::System;

/// The run's time between two hand-overs of rows: the pool's threads start this long after the
/// run, and each hand-over costs a copy of the rows, a lock and a wake-up.
const SLICE: Duration = Duration::from_micros(100);

/// The first slice: short, so that the pool's threads start early (CoupledClutches' run takes
/// 0.25 ms).
const FIRST_SLICE: Duration = Duration::from_micros(25);

/// Simulates `sys` from start to stop with every variable of every row computed by the time
/// it returns (`SimResult::table` is then at hand), on the pool's other threads while the run
/// goes on. `between` is called between slices of the run; returning false cancels it
/// (`SimError::Cancelled`).
pub fn run_recording_all(
    sys: Arc<System>,
    between: impl FnMut() -> bool,
) -> Result<SimResult, SimError> {
    let rows = expected_rows(&sys);
    run_with_room(sys, (rows, MAX_TABLE_VALUES), between)
}

/// `run_recording_all` with a table of room for about `rows` rows while the run goes on, and
/// of at most `limit` values.
fn run_with_room(
    sys: Arc<System>,
    room: (usize, f64),
    mut between: impl FnMut() -> bool,
) -> Result<SimResult, SimError> {
    let mut sim = Simulation::new(sys.clone())?;
    let stop = sys.experiment.stop_time;
    recorded_while(&sys, room, |feed| {
        let mut slice = FIRST_SLICE;
        while !sim.advance_for(stop, slice)? {
            slice = SLICE;
            feed.send(&sim.stepper.trajectory, &sim.stepper.discs);
            if !between() {
                return Err(SimError::Cancelled {
                    time: sim.stepper.now,
                });
            }
        }
        Ok(sim.into_result())
    })
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::Ordering;
    use std::sync::Arc;

    use super::{run_recording_all, run_with_room};
    use crate::assembly::CompiledModel;
    use crate::error::SimError;
    use crate::result::MAX_TABLE_VALUES;
    use crate::result::ROWS_BY_POOL;
    use crate::simulation::run;
    use crate::system::System;
    use crate::ModelSpec;

    fn example(name: &str) -> Arc<System> {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
        let text = std::fs::read_to_string(format!("{dir}/{name}.toml")).expect("example");
        let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
        CompiledModel::new(spec).expect("builds").system()
    }

    fn pool(threads: usize) -> rayon::ThreadPool {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
        pool.expect("a thread pool")
    }

    fn same_bits(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    /// Every variable recorded while the run goes on is the table computed after the run, bit
    /// for bit, and the run is the same run (events, statistics): with no pool thread to help,
    /// with one, and with three (chunks taken out of order, each thread bringing its discrete
    /// states up to date); HeatLosses' 20 323 rows exceed the rows a run expects (its 161 state
    /// events), so its last rows are computed after the run. HeatLosses' pool threads did
    /// compute rows while it ran; SimpleGearShift's and OneWayClutch's few rows are computed
    /// after their runs.
    #[test]
    fn recorded_while_running_equals_computed_after() {
        for name in [
            "CoupledClutches",
            "HeatLosses",
            "SimpleGearShift",
            "OneWayClutch",
        ] {
            let sys = example(name);
            let after = run(sys.clone()).expect("runs");
            let expected = after.table().expect("fits");
            for threads in [1, 2, 4] {
                let before = ROWS_BY_POOL.load(Ordering::Relaxed);
                let live = pool(threads).install(|| run_recording_all(sys.clone(), || true));
                let live = live.expect("runs");
                if name == "HeatLosses" && threads > 1 {
                    let by_pool = ROWS_BY_POOL.load(Ordering::Relaxed) - before;
                    assert!(
                        by_pool > 0,
                        "the pool's threads computed rows during the run"
                    );
                }
                assert!(live.has_ready_table(), "{name}: computed with the run");
                assert_eq!(live.events, after.events, "{name}, {threads} threads");
                assert_eq!(live.stats.steps, after.stats.steps, "{name}");
                let table = live.table().expect("fits");
                assert!(
                    same_bits(table, expected),
                    "{name}, {threads} threads: tables differ"
                );
            }
        }
    }

    /// A table with room for a tenth of its rows while the run goes on (more than a run
    /// must expect for its table to be computed as it goes) computes the rest after it, into
    /// the same table.
    #[test]
    fn rows_beyond_the_room_computed_after_the_run() {
        let sys = example("HeatLosses");
        let expected = run(sys.clone()).expect("runs").table_vec().expect("fits");
        let live = pool(2).install(|| run_with_room(sys, (2048, MAX_TABLE_VALUES), || true));
        let live = live.expect("runs");
        assert!(live.rows() > 20_000, "more rows than the room");
        assert!(same_bits(&live.table_vec().expect("fits"), &expected));
    }

    /// Cancelling between slices stops the run with `Cancelled`, and the pool's threads waiting
    /// for rows return (the next run on the pool completes).
    #[test]
    fn cancelled_between_slices() {
        let sys = example("HeatLosses");
        let pool = pool(2);
        let mut slices = 0;
        let cancelled = pool.install(|| {
            run_recording_all(sys.clone(), || {
                slices += 1;
                slices < 3
            })
        });
        assert!(matches!(cancelled, Err(SimError::Cancelled { time }) if time > 0.0));
        let again = pool
            .install(|| run_recording_all(sys, || true))
            .expect("runs");
        assert!(again.table().is_ok());
    }

    /// A run that panics while the pool's threads wait for its rows lets the panic go on (to
    /// the boundary that catches it) instead of waiting for them forever.
    #[test]
    fn a_panic_in_the_run_does_not_leave_the_pool_waiting() {
        let sys = example("HeatLosses");
        let pool = pool(2);
        let mut slices = 0;
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            pool.install(|| {
                run_recording_all(sys.clone(), || {
                    slices += 1;
                    assert!(slices < 3, "a panic between slices");
                    true
                })
            })
        }));
        assert!(outcome.is_err(), "the panic reaches the caller");
        assert!(pool.install(|| run_recording_all(sys, || true)).is_ok());
    }

    /// A table of more values than the limit is not computed while the run goes on, whether
    /// the room expected already exceeds it or only the rows recorded do; the run's result
    /// is whole, and its table computed when asked (under the engine's own limit) is the same.
    #[test]
    fn a_table_beyond_the_limit_is_left_to_the_result() {
        let sys = example("HeatLosses");
        let expected = run(sys.clone()).expect("runs").table_vec().expect("fits");
        let width = sys.outputs.len() + 1;
        // the room (2 432 rows) fits in the first limit, the 20 323 rows do not; nothing fits
        // in the second
        for limit in [1.0e6, 1.0e3] {
            let result = pool(2).install(|| run_with_room(sys.clone(), (2048, limit), || true));
            let result = result.expect("runs");
            assert!((result.rows() * width) as f64 > limit);
            assert!(
                !result.has_ready_table(),
                "limit {limit}: no table computed"
            );
            assert!(same_bits(&result.table_vec().expect("fits"), &expected));
        }
    }
}
