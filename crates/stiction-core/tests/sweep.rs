//! Sweeps in the core: every metric equals the same metric of a single run of that variant, to
//! the last bit; trajectories equal the single run's signals on the output grid; the outcome
//! does not depend on the number of threads; a failing variant reports its error and the
//! others run.

use stiction_core::CancelHandle;
use stiction_core::CompiledModel;
use stiction_core::{run_variants, Override, Plan};
use stiction_core::{ModelSpec, SimResult, Simulation};

const COUPLED: &str = include_str!("../../../examples/msl/CoupledClutches.toml");
const FLYWHEEL: &str = include_str!("../../../examples/braked_flywheel.toml");

const METRICS: &[&str] = &[
    "final(J4.w)",
    "max(J1.w)",
    "min(clutch1.tau)",
    "integral(clutch1.lossPower)",
    "mean(J2.w)",
    "time_of(clutch3.locked)",
    "time_of(J1.w < 5)",
    "events(clutch1)",
    "events()",
];

fn compiled(text: &str) -> CompiledModel {
    CompiledModel::new(ModelSpec::from_toml(text, ".").unwrap()).unwrap()
}

fn single(cm: &CompiledModel, overrides: &[Override]) -> SimResult {
    let pairs: Vec<(&str, toml::Value)> = overrides
        .iter()
        .map(|(n, v)| (n.as_str(), v.clone()))
        .collect();
    let mut sim = Simulation::new(cm.with(&pairs).unwrap().system()).unwrap();
    sim.run().unwrap();
    sim.into_result()
}

fn variants(names: &[&str], values: &[[f64; 2]]) -> Vec<Vec<Override>> {
    values
        .iter()
        .map(|v| {
            names
                .iter()
                .zip(v)
                .map(|(n, x)| (n.to_string(), toml::Value::Float(*x)))
                .collect()
        })
        .collect()
}

/// The single run's value at each grid time: the last row at that instant.
fn on_grid(r: &SimResult, name: &str, grid: &[f64]) -> Vec<f64> {
    let (t, v) = (r.column("time").unwrap(), r.column(name).unwrap());
    grid.iter()
        .map(|&tg| {
            let row = t
                .iter()
                .rposition(|&ti| (ti - tg).abs() <= 1e-12 * tg.abs().max(1.0));
            v[row.expect("every grid time has a row")]
        })
        .collect()
}

#[test]
fn sweep_metrics_and_trajectories_equal_single_runs_whatever_the_threads() {
    let cm = compiled(COUPLED);
    let metrics: Vec<String> = METRICS.iter().map(|m| m.to_string()).collect();
    let outputs = vec!["J1.w".to_string(), "clutch2.mode".to_string()];
    let plan = Plan::new(&cm, &metrics, &outputs).unwrap();
    let vs = variants(
        &["clutch1.fn_max", "sin1.f"],
        &[[20.0, 5.0], [8.0, 3.0], [40.0, 7.5], [15.0, 1.0]],
    );
    let cancel = CancelHandle::new();
    let one = run_variants(&cm, &vs, &plan, Some(1), &cancel);
    let two = run_variants(&cm, &vs, &plan, Some(2), &cancel);
    let exp = &cm.spec().experiment;
    let grid: Vec<f64> = (0..=exp.grid_len()).map(|k| exp.grid_time(k)).collect();
    for (k, overrides) in vs.iter().enumerate() {
        assert!(one[k].error.is_none(), "{:?}", one[k].error);
        let r = single(&cm, overrides);
        for (m, text) in METRICS.iter().enumerate() {
            let expected = r.metric(text).unwrap();
            let (a, b) = (one[k].metrics[m], two[k].metrics[m]);
            assert!(
                a.to_bits() == expected.to_bits() || (a.is_nan() && expected.is_nan()),
                "variant {k} {text}: sweep {a}, single run {expected}"
            );
            assert!(
                a.to_bits() == b.to_bits(),
                "threads change {text}: {a} vs {b}"
            );
        }
        for (o, name) in outputs.iter().enumerate() {
            assert_eq!(one[k].trajectories[o], on_grid(&r, name, &grid), "{name}");
            assert_eq!(one[k].trajectories[o], two[k].trajectories[o]);
        }
    }
    // the variants differ from each other: the overrides acted
    assert_ne!(one[0].metrics[0], one[1].metrics[0]);
}

/// Metrics over angles, speeds and modes alone read a few states of each grid row, a block
/// of rows at a time (`Observer::states_read`, `Watch::metric_rows`): still the single run's
/// values to the last bit, with and without a trajectory kept (which takes the rows one by
/// one), on the sweep parameters (`J1.J` among them).
#[test]
fn metrics_read_from_the_states_alone_equal_single_runs() {
    const DIRECT: &[&str] = &[
        "max(J1.w)",
        "max(J4.w)",
        "min(J2.w)",
        "final(J3.phi)",
        "integral(J4.w)",
        "mean(J1.phi)",
        "time_of(J1.w < 5)",
        "time_of(clutch3.locked)",
        "max(clutch2.locked)",
        "events()",
    ];
    let cm = compiled(COUPLED);
    let metrics: Vec<String> = DIRECT.iter().map(|m| m.to_string()).collect();
    let names = ["clutch1.fn_max", "clutch2.fn_max", "J1.J"];
    let vs: Vec<Vec<Override>> = [[40.0, 59.0, 0.9], [64.0, 40.0, 1.09], [20.0, 20.0, 1.0]]
        .iter()
        .map(|v| {
            (names.iter().zip(v))
                .map(|(n, x)| (n.to_string(), toml::Value::Float(*x)))
                .collect()
        })
        .collect();
    let cancel = CancelHandle::new();
    let exp = &cm.spec().experiment;
    let grid: Vec<f64> = (0..=exp.grid_len()).map(|k| exp.grid_time(k)).collect();
    for outputs in [vec![], vec!["J3.w".to_string()]] {
        let plan = Plan::new(&cm, &metrics, &outputs).unwrap();
        let swept = run_variants(&cm, &vs, &plan, Some(2), &cancel);
        for (k, overrides) in vs.iter().enumerate() {
            assert!(swept[k].error.is_none(), "{:?}", swept[k].error);
            let r = single(&cm, overrides);
            for (m, text) in DIRECT.iter().enumerate() {
                let (a, expected) = (swept[k].metrics[m], r.metric(text).unwrap());
                assert!(
                    a.to_bits() == expected.to_bits() || (a.is_nan() && expected.is_nan()),
                    "variant {k} {text} (outputs {outputs:?}): sweep {a}, single run {expected}"
                );
            }
            if !outputs.is_empty() {
                assert_eq!(swept[k].trajectories[0], on_grid(&r, "J3.w", &grid));
            }
        }
        assert_ne!(swept[0].metrics[4], swept[1].metrics[4]);
    }
}

#[test]
fn a_failing_variant_reports_its_error_and_the_others_run() {
    let cm = compiled(FLYWHEEL);
    let metrics = vec![
        "integral(brake.lossPower)".to_string(),
        "time_of(brake.locked)".to_string(),
    ];
    let plan = Plan::new(&cm, &metrics, &[]).unwrap();
    let vs = variants(
        &["brake.fn_max", "flywheel.w"],
        &[[2000.0, 100.0], [-5.0, 100.0], [3000.0, 80.0]],
    );
    let out = run_variants(&cm, &vs, &plan, None, &CancelHandle::new());
    let error = out[1]
        .error
        .as_deref()
        .expect("the negative fn_max is refused");
    assert!(
        error.contains("brake") && error.contains("fn_max"),
        "{error}"
    );
    assert!(out[1].metrics.iter().all(|m| m.is_nan()));
    for k in [0, 2] {
        assert!(out[k].error.is_none(), "{:?}", out[k].error);
        // the brake dissipates the flywheel's kinetic energy: ½·J·w² (J = 2)
        let w0 = if k == 0 { 100.0 } else { 80.0 };
        let loss = out[k].metrics[0];
        assert!(
            (loss - w0 * w0).abs() < 1e-3 * w0 * w0,
            "variant {k}: {loss}"
        );
        assert!(
            out[k].metrics[1] > 0.5,
            "it locks after the brake is applied"
        );
    }
    // cancelled before starting: every variant says so
    let stop = CancelHandle::new();
    stop.cancel();
    let cancelled = run_variants(&cm, &vs, &plan, Some(2), &stop);
    assert!(cancelled
        .iter()
        .all(|o| o.error.as_deref() == Some("cancelled")));
}

#[test]
fn bad_metrics_and_outputs_are_refused_before_any_run() {
    let cm = compiled(COUPLED);
    let plan = |m: &str, o: &[&str]| {
        let outputs: Vec<String> = o.iter().map(|s| s.to_string()).collect();
        Plan::new(&cm, &[m.to_string()], &outputs)
    };
    assert!(plan("max(J1.ww)", &[])
        .unwrap_err()
        .to_string()
        .contains("J1.ww"));
    assert!(plan("max(J1.w)", &["J9.w"])
        .unwrap_err()
        .to_string()
        .contains("J9.w"));
}

#[test]
fn cancelling_a_sweep_stops_the_runs_under_way() {
    // four runs of 20 000 s take many seconds each; the cancel comes after 100 ms
    let cm = compiled(COUPLED);
    let plan = Plan::new(&cm, &["max(J1.w)".to_string()], &[]).unwrap();
    let vs = variants(&["StopTime", "Interval"], &[[2e4, 1.0]; 4]);
    let cancel = CancelHandle::new();
    let started = std::time::Instant::now();
    let outcomes = std::thread::scope(|s| {
        s.spawn(|| {
            std::thread::sleep(std::time::Duration::from_millis(100));
            cancel.cancel();
        });
        run_variants(&cm, &vs, &plan, Some(2), &cancel)
    });
    let stopped = started.elapsed().as_secs_f64();
    assert!(outcomes
        .iter()
        .all(|o| o.error.as_deref() == Some("cancelled")));
    assert!(
        stopped < 3.0,
        "the sweep went on for {stopped} s after the cancel"
    );
}
