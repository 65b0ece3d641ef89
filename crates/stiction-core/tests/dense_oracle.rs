//! The banded, incremental per-mode solve that large drivetrains take (`engine::ModeSolver`
//! above `BAND_FROM` unknowns) against the dense LU as the oracle, on whole runs of the
//! generated chain and ladder of 100 elements (`tests/data`, written by `stiction.testing`;
//! `tests/run/test_scaling.py` checks they are still what it generates): the same events at the
//! same instants to round-off, the same trajectory to round-off.

use std::sync::Arc;

use stiction_core::assemble;
use stiction_core::DenseLu;
use stiction_core::ModelSpec;
use stiction_core::SimResult;
use stiction_core::Simulation;

fn runs(file: &str) -> (SimResult, SimResult) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data");
    let text = std::fs::read_to_string(format!("{dir}/{file}")).expect("fixture");
    let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
    let sys = Arc::new(assemble(&spec).expect("assembles"));
    let mut banded = Simulation::new(sys.clone()).expect("starts");
    let mut dense = Simulation::with_linear_solver(sys, Box::new(DenseLu)).expect("starts");
    banded.run().expect("banded run");
    dense.run().expect("dense run");
    (banded.into_result(), dense.into_result())
}

fn assert_same_run(file: &str, speed_scale: f64) {
    let (banded, dense) = runs(file);
    assert_eq!(banded.events.len(), dense.events.len(), "{file}: events");
    // the order within one instant follows the solve's elimination order: compare by element
    let by_element = |r: &SimResult| {
        let mut events = r.events.clone();
        events.sort_by(|a, b| {
            (&a.component, a.time)
                .partial_cmp(&(&b.component, b.time))
                .unwrap()
        });
        events
    };
    for (b, d) in by_element(&banded).iter().zip(&by_element(&dense)) {
        assert_eq!(
            (&b.component, b.old_mode, b.new_mode),
            (&d.component, d.old_mode, d.new_mode)
        );
        assert!(
            (b.time - d.time).abs() <= 1e-12,
            "{file}: {} at {} / {}",
            b.component,
            b.time,
            d.time
        );
    }
    // A cascade of events within nanoseconds (the ladder's brakes closing) may be recorded as
    // one instant or two, a round-off decision: the rows differ by an event's pair, so the dense
    // run's speeds are interpolated at the banded run's times (speeds are continuous).
    let (tb, td) = (
        banded.column("time").unwrap(),
        dense.column("time").unwrap(),
    );
    let speeds = (banded.names.iter()).filter(|n| n.ends_with(".w") && n.starts_with('J'));
    let mut worst: f64 = 0.0;
    for name in speeds {
        let (b, d) = (banded.column(name).unwrap(), dense.column(name).unwrap());
        for (t, wb) in tb.iter().zip(&b) {
            worst = worst.max((wb - interpolated(&td, &d, *t)).abs());
        }
    }
    eprintln!("{file}: speeds differ by at most {worst:e}");
    assert!(
        worst <= 1e-11 * speed_scale,
        "{file}: speeds differ by {worst}"
    );
}

#[test]
fn the_chain_of_100_clutches_runs_as_with_the_dense_lu() {
    assert_same_run("chain100.toml", 10.0);
}

#[test]
fn the_ladder_of_100_elements_runs_as_with_the_dense_lu() {
    assert_same_run("ladder100.toml", 10.0);
}

/// `y` at `t` by linear interpolation in the nondecreasing `ts` (the last row at a repeated time).
fn interpolated(ts: &[f64], y: &[f64], t: f64) -> f64 {
    let k = ts.partition_point(|&s| s <= t);
    if k == 0 || ts[k - 1] == t || k == ts.len() {
        return y[k.saturating_sub(1)];
    }
    let (t0, t1) = (ts[k - 1], ts[k]);
    y[k - 1] + (y[k] - y[k - 1]) * (t - t0) / (t1 - t0)
}
