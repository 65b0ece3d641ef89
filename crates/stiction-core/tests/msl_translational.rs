//! MSL's Translational examples (examples/msl-translational) against their MAP-LIB reference
//! trajectories (tests/data/msl-translational) in the CSV Compare tube (2e-3), as
//! msl_reference.rs does for the Rotational ones: every listed signal inside the tube, and
//! each one moved by 1 % of its range fails that signal and only it.

use std::path::{Path, PathBuf};

use stiction_core::{compare, read_signal_list, Reference};
use stiction_core::{simulate, ModelSpec, SimResult};

const MSL_TOLERANCE: f64 = 2e-3;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn data(file: &str) -> PathBuf {
    repo().join("tests/data/msl-translational").join(file)
}

fn simulated(example: &str) -> SimResult {
    let dir = repo().join("examples/msl-translational");
    let path = dir.join(format!("{example}.toml"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let spec = ModelSpec::from_toml(&text, dir).unwrap_or_else(|e| panic!("{example}: {e}"));
    simulate(&spec).unwrap_or_else(|e| panic!("{example}: {e}"))
}

fn check_example(example: &str) {
    let result = simulated(example);
    let reference = Reference::read(data(&format!("{example}.csv"))).expect("a reference");
    let listed = read_signal_list(data(&format!("{example}.signals.txt"))).expect("a list");
    assert!(listed.len() >= 3, "{example}: {listed:?}");
    let report = compare(&result, &reference, &listed, MSL_TOLERANCE).expect("comparable");
    assert_eq!(report.len(), listed.len(), "{example}");
    let failed: Vec<_> = report.iter().filter(|s| !s.passed).collect();
    assert!(failed.is_empty(), "{example}: {failed:#?}");
    for name in &listed {
        let mut off = reference.clone();
        let i = off.names.iter().position(|n| n == name).expect("a column");
        let column = &mut off.columns[i];
        let max = column.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let range = max - column.iter().copied().fold(f64::INFINITY, f64::min);
        let delta = if range > 0.0 { 0.01 * range } else { 1.0 };
        column.iter_mut().for_each(|v| *v -= delta);
        let report = compare(&result, &off, &listed, MSL_TOLERANCE).expect("comparable");
        let failed: Vec<&str> = (report.iter().filter(|s| !s.passed))
            .map(|s| s.name.as_str())
            .collect();
        assert_eq!(failed, [name.as_str()], "{example}: 1 % off on {name}");
    }
}

#[test]
fn brake_stays_in_the_msl_tube() {
    check_example("Brake");
}

#[test]
fn preload_stays_in_the_msl_tube() {
    check_example("PreLoad");
}

#[test]
fn friction_stays_in_the_msl_tube() {
    check_example("Friction");
}

/// Every listed signal, `brake.startBackward` included: the brake engages at t = 1e-15 s with
/// a holding force of −2.8e-13 N (round-off of the absolute positions in `springDamper1.s_rel`,
/// c = 1e4, where Dymola's relative state is 0 exactly). Its `sa < −f0_max` relation, with
/// `f0_max = 0` at the initialization, is a start condition only beyond the event band there,
/// so the engaging brake locks, as in the reference.
#[test]
fn heat_losses_stays_in_the_msl_tube() {
    check_example("HeatLosses");
}
