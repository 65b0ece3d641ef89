//! Tests of `run_recording_all`: the table recorded while the run goes on against the table
//! computed after it, the room and the memory guard, cancelling, panics, and the pool's other
//! users. Serial: they count the rows the pool computed (`ROWS_BY_POOL`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use super::{run_recording_all, run_with_room};
use crate::assembly::CompiledModel;
use crate::error::SimError;
use crate::result::MAX_TABLE_VALUES;
use crate::result::ROWS_BY_POOL;
use crate::simulation::run;
use crate::system::System;
use crate::ModelSpec;

fn example_model(name: &str) -> CompiledModel {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
    let text = std::fs::read_to_string(format!("{dir}/{name}.toml")).expect("example");
    let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
    CompiledModel::new(spec).expect("builds")
}

fn example(name: &str) -> Arc<System> {
    example_model(name).system()
}

/// One test at a time: each counts the rows the pool's threads computed.
fn serial() -> MutexGuard<'static, ()> {
    static SERIAL: Mutex<()> = Mutex::new(());
    SERIAL.lock().unwrap_or_else(PoisonError::into_inner)
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
/// compute rows while it ran (its first slices paused, so that a pool thread woken late still
/// finds the run going on: in its 3 ms run, one did not always take a chunk before the end);
/// SimpleGearShift's and OneWayClutch's few rows are computed after their runs.
#[test]
fn recorded_while_running_equals_computed_after() {
    let _serial = serial();
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
            let mut slices = 0;
            let paused = || {
                slices += 1;
                if slices <= 3 {
                    std::thread::sleep(std::time::Duration::from_millis(2));
                }
                true
            };
            let live = pool(threads).install(|| run_recording_all(sys.clone(), paused));
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
    let _serial = serial();
    let sys = example("HeatLosses");
    let expected = run(sys.clone()).expect("runs").table_vec().expect("fits");
    let live = pool(2).install(|| run_with_room(sys, (2048, MAX_TABLE_VALUES), || true));
    let live = live.expect("runs");
    assert!(live.rows() > 20_000, "more rows than the room");
    assert!(same_bits(&live.table_vec().expect("fits"), &expected));
}

/// Cancelling between slices stops the run with `Cancelled`; the pool's jobs take nothing more
/// and the next run on the pool completes.
#[test]
fn cancelled_between_slices() {
    let _serial = serial();
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

/// A run that panics while the pool's jobs compute its rows lets the panic go on (to the
/// boundary that catches it), and the pool runs the next run.
#[test]
fn a_panic_in_the_run_does_not_leave_the_pool_waiting() {
    let _serial = serial();
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
    let _serial = serial();
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

/// A long recorded run does not hold the pool's other thread for itself: a job another caller
/// puts in the pool runs while the run still integrates (the pool job computing its rows lets
/// waiting jobs run between its chunks, and never waits for rows). The run is long (40 s of
/// HeatLosses, rows as dense) and is cancelled as soon as the other job has run, so that a
/// loaded machine, where the pool's thread gets the processor late, only makes it wait longer.
#[test]
fn a_long_recorded_run_lets_other_jobs_into_the_pool() {
    let _serial = serial();
    let model = example_model("HeatLosses");
    let long = [("StopTime", toml::Value::Float(40.0))];
    let sys = model.with(&long).expect("a variant").system();
    let pool = pool(2);
    let other_job_ran = AtomicBool::new(false);
    let before = ROWS_BY_POOL.load(Ordering::Relaxed);
    let outcome = std::thread::scope(|s| {
        let run = s.spawn(|| {
            let between = || !other_job_ran.load(Ordering::Relaxed);
            pool.install(|| run_recording_all(sys, between))
        });
        // until the pool's other thread is into the rows of the run (past its start, when it
        // may still run out of chunks and leave, which would let the job in trivially)
        let computed = || ROWS_BY_POOL.load(Ordering::Relaxed) - before;
        while computed() < 1024 && !run.is_finished() {
            std::thread::yield_now();
        }
        pool.install(|| other_job_ran.store(true, Ordering::Relaxed));
        run.join().expect("the run does not panic")
    });
    assert!(
        matches!(outcome, Err(SimError::Cancelled { .. })),
        "another caller's job waited for the run to end"
    );
}
