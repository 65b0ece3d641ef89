//! The MSL examples against their MAP-LIB reference trajectories with the tube check the
//! Modelica Association runs (CSV Compare, 2e-3), from `cargo test`: a change to the engine is
//! caught without building the Python package. Same examples, signal lists and tolerance as the
//! Python tests (test_msl_reference.py, test_msl_family.py, test_lossy_gear.py).

use std::path::{Path, PathBuf};

use stiction_core::{compare, read_signal_list, CompareError, Reference, SignalReport};
use stiction_core::{simulate, ModelSpec, SimResult};
use stiction_core::{Columns, Side};

/// The CSV Compare tube size the Modelica Association uses for MSL.
const MSL_TOLERANCE: f64 = 2e-3;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn msl_data(file: &str) -> PathBuf {
    repo().join("tests/data/msl").join(file)
}

fn reference(example: &str) -> Reference {
    Reference::read(msl_data(&format!("{example}.csv"))).unwrap_or_else(|e| panic!("{e}"))
}

/// The example run with its model file's own experiment (the MSL settings, Tolerance 1e-6).
fn simulated(example: &str) -> SimResult {
    let dir = repo().join("examples/msl");
    let path = dir.join(format!("{example}.toml"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let spec = ModelSpec::from_toml(&text, dir).unwrap_or_else(|e| panic!("{example}: {e}"));
    simulate(&spec).unwrap_or_else(|e| panic!("{example}: {e}"))
}

/// What MSL compares: `<Example>.signals.txt`, or every reference column where MSL has no list.
fn signals(example: &str, reference: &Reference) -> Vec<String> {
    let list = msl_data(&format!("{example}.signals.txt"));
    if list.exists() {
        read_signal_list(&list).unwrap_or_else(|e| panic!("{e}"))
    } else {
        reference
            .names
            .iter()
            .filter(|n| *n != "time")
            .cloned()
            .collect()
    }
}

fn failed(report: &[SignalReport]) -> Vec<&SignalReport> {
    report.iter().filter(|s| !s.passed).collect()
}

fn failed_names(report: &[SignalReport]) -> Vec<&str> {
    failed(report).iter().map(|s| s.name.as_str()).collect()
}

/// The reference with `delta` added to one column: a "result" that is off by exactly that.
fn shifted(reference: &Reference, name: &str, delta: f64) -> Reference {
    let mut copy = reference.clone();
    let i = copy.names.iter().position(|n| n == name).expect("a column");
    copy.columns[i].iter_mut().for_each(|v| *v += delta);
    copy
}

fn range(values: &[f64]) -> f64 {
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    max - values.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Every listed signal lies inside the tube; and shifting any one of them by 1 % of its
/// reference range (5 tube half-heights) fails that signal and only it, so the check can fail.
fn check_example(example: &str, extra: &[&str]) {
    let result = simulated(example);
    let reference = reference(example);
    let mut listed = signals(example, &reference);
    listed.extend(extra.iter().map(|s| s.to_string()));
    // (MSL lists two signals of RollingWheel, at least three of the others)
    assert!(listed.len() >= 2, "{example}: {listed:?}");

    let (t, t_ref) = (result.column("time").unwrap(), &reference.columns[0]);
    assert_eq!(t[0], t_ref[0], "{example}: start time");
    let (end, ref_end) = (t[t.len() - 1], t_ref[t_ref.len() - 1]);
    assert!(
        (end - ref_end).abs() <= 1e-9 * ref_end.abs(),
        "{example}: end {end}"
    );

    let report = compare(&result, &reference, &listed, MSL_TOLERANCE).expect("comparable");
    let names: Vec<&str> = report.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, listed, "{example}");
    assert!(
        failed(&report).is_empty(),
        "{example}: {:#?}",
        failed(&report)
    );

    for name in &listed {
        let column = reference.column(name).expect("a reference column");
        let r = range(&column);
        let delta = if r > 0.0 { 0.01 * r } else { 1.0 };
        let off = shifted(&reference, name, -delta); // the result sits `delta` above it
        let report = compare(&result, &off, &listed, MSL_TOLERANCE).expect("comparable");
        assert_eq!(
            failed_names(&report),
            [name.as_str()],
            "{example}: 1 % off on {name}"
        );
    }
}

macro_rules! example_tests {
    ($($test:ident: $example:literal $(+ $extra:literal)*;)*) => {
        /// The examples compared here: every examples/msl model that has a reference CSV.
        const EXAMPLES: &[&str] = &[$($example),*];
        $(
            #[test]
            fn $test() {
                check_example($example, &[$($extra),*]);
            }
        )*
    };
}

example_tests! {
    coupled_clutches_stays_in_the_msl_tube: "CoupledClutches";
    friction_stays_in_the_msl_tube: "Friction";
    rolling_wheel_stays_in_the_msl_tube: "RollingWheel";
    simple_gear_shift_stays_in_the_msl_tube: "SimpleGearShift";
    first_stays_in_the_msl_tube: "First";
    one_way_clutch_stays_in_the_msl_tube: "OneWayClutch";
    one_way_clutch_disengaged_stays_in_the_msl_tube: "OneWayClutchDisengaged";
    lossy_gear_demo1_stays_in_the_msl_tube: "LossyGearDemo1";
    lossy_gear_demo3_stays_in_the_msl_tube: "LossyGearDemo3";
    backlash_stays_in_the_msl_tube: "Backlash";
    first_grounded_stays_in_the_msl_tube: "FirstGrounded";
    // at the default Tolerance by its springDamper.w_rel's nominal (1e-4, MSL's)
    elastic_bearing_stays_in_the_msl_tube: "ElasticBearing";
    eddy_current_brake_stays_in_the_msl_tube: "EddyCurrentBrake";
    // MSL 4.0.0 compares the bearing's start flags too (as test_lossy_gear.py does)
    lossy_gear_demo2_stays_in_the_msl_tube: "LossyGearDemo2"
        + "bearingFriction.startForward" + "bearingFriction.startBackward";
}

#[test]
fn every_example_with_a_reference_is_compared() {
    let mut with_reference: Vec<String> = std::fs::read_dir(repo().join("examples/msl"))
        .expect("examples/msl")
        .filter_map(|entry| {
            let path = entry.ok()?.path();
            // the .mo twins of the examples are tested from Python (test_modelica_import.py)
            if path.extension()? != "toml" {
                return None;
            }
            let stem = path.file_stem()?.to_str()?.to_string();
            msl_data(&format!("{stem}.csv")).exists().then_some(stem)
        })
        .collect();
    with_reference.sort();
    let mut compared: Vec<&str> = EXAMPLES.to_vec();
    compared.sort();
    assert_eq!(with_reference, compared);
}

// --- the tube itself, on the reference data ------------------------------------------------

/// Every reference file (Backlash and ElasticBearing too) read with the Rust reader.
fn all_references() -> Vec<Reference> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(repo().join("tests/data/msl"))
        .expect("tests/data/msl")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "{files:?}");
    files
        .iter()
        .map(|f| Reference::read(f).expect("a reference"))
        .collect()
}

#[test]
fn each_reference_passes_against_itself_and_half_a_tube_width_later() {
    for reference in all_references() {
        let all = &reference.names[1..];
        assert_eq!(reference.names[0], "time");
        let report = compare(&reference, &reference, all, MSL_TOLERANCE).expect("comparable");
        assert!(failed(&report).is_empty(), "{:?}", failed(&report));
        let t = &reference.columns[0];
        let late = shifted(
            &reference,
            "time",
            0.5 * MSL_TOLERANCE * (t[t.len() - 1] - t[0]),
        );
        let report = compare(&late, &reference, all, MSL_TOLERANCE).expect("comparable");
        assert!(failed(&report).is_empty(), "{:?}", failed(&report));
    }
}

#[test]
fn an_offset_of_three_tube_heights_fails_by_two_and_names_the_signal() {
    let reference = reference("CoupledClutches");
    let listed = read_signal_list(msl_data("CoupledClutches.signals.txt")).expect("a list");
    let y_half = MSL_TOLERANCE * range(&reference.column("J1.w").expect("J1.w"));
    let bad = shifted(&reference, "J1.w", 3.0 * y_half);
    let report = compare(&bad, &reference, &listed, MSL_TOLERANCE).expect("comparable");
    assert_eq!(failed_names(&report), ["J1.w"]);
    let verdict = failed(&report)[0];
    assert!((verdict.max_excess - 2.0).abs() < 1e-6, "{verdict:?}"); // the tube reaches +1 Y
    assert!(verdict.worst_time.is_some() && verdict.points_outside > 0);
    assert_eq!(verdict.y_half, y_half);
}

#[test]
fn a_jump_within_the_time_half_width_passes_and_a_later_one_fails() {
    // A unit step at t = 1 written twice, on [0, 2]; tolerance 0.01 gives X = 0.02 s, Y = 0.01.
    let table = |t: [f64; 6]| Reference {
        path: "step".into(),
        names: vec!["time".into(), "y".into()],
        columns: vec![t.to_vec(), vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]],
    };
    let reference = table([0.0, 0.5, 1.0, 1.0, 1.5, 2.0]);
    let step_at = |t: f64| table([0.0, 0.9, t, t, 1.2, 2.0]);
    let check = |t| compare(&step_at(t), &reference, &["y"], 0.01).expect("comparable");
    assert!(check(1.015)[0].passed && check(0.985)[0].passed);
    let late = check(1.03);
    assert!(
        !late[0].passed && late[0].worst_time == Some(1.03),
        "{late:?}"
    );
    assert!((late[0].x_half - 0.02).abs() < 1e-15 && (late[0].y_half - 0.01).abs() < 1e-15);
}

#[test]
fn nan_and_missing_signals_fail() {
    let reference = reference("First");
    let mut bad = reference.clone();
    bad.columns[2][100] = f64::NAN;
    bad.names[3] = "renamed".into();
    let report = compare(&bad, &reference, &reference.names, MSL_TOLERANCE).expect("comparable");
    assert_eq!(
        failed_names(&report),
        [&*reference.names[2], &*reference.names[3]]
    );
    assert_eq!(report[1].max_excess, f64::INFINITY);
    assert_eq!(report[2].missing, Some(Side::Result));
    let report = compare(&reference, &reference, &["nowhere"], MSL_TOLERANCE).expect("ok");
    assert_eq!(report[0].missing, Some(Side::Reference));
}

#[test]
fn bad_input_is_an_error_naming_the_file_or_signal() {
    let missing = Reference::read(msl_data("Nowhere.csv")).unwrap_err();
    assert!(missing.to_string().contains("Nowhere.csv"), "{missing}");
    let ragged = Reference::parse("\"time\",\"y\"\n0,1\n1,2,3\n", "ragged.csv").unwrap_err();
    assert!(matches!(ragged, CompareError::File(..)));
    assert_eq!(
        ragged.to_string(),
        "ragged.csv: line 3: 3 values for 2 names"
    );
    let text = Reference::parse("time,y\n0,1\n1,x\n", "text.csv").unwrap_err();
    assert_eq!(text.to_string(), "text.csv: line 3: 'x' is not a number");
    let ok = Reference::parse(
        "\u{feff}\"time\",\"a \"\"b\"\"\"\n# note\n0,1\n\n1,2\n",
        "ok",
    );
    let ok = ok.expect("a table");
    assert_eq!(ok.names, ["time", "a \"b\""]);
    assert_eq!(ok.columns, [vec![0.0, 1.0], vec![1.0, 2.0]]);

    let backward = Reference::parse("time,y\n1,0\n0,0\n", "backward.csv").expect("parses");
    let error = compare(&ok, &backward, &["y"], MSL_TOLERANCE).unwrap_err();
    assert_eq!(
        error.to_string(),
        "backward.csv: time decreases after row 0"
    );
    let mut short = ok.clone();
    short.columns[1].pop();
    let error = compare(&short, &ok, &["a \"b\""], MSL_TOLERANCE).unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("result: 'a \"b\"' has 1 values"),
        "{error}"
    );
    let good = Reference::parse("time,y\n0,1\n", "good.csv").expect("parses");
    let empty = Reference::parse("time,y\n", "empty.csv").expect("parses");
    let error = compare(&good, &empty, &["y"], MSL_TOLERANCE).unwrap_err();
    assert_eq!(error.to_string(), "empty.csv: the reference has no rows");
    assert!(matches!(
        compare(&ok, &ok, &["y"], 0.0),
        Err(CompareError::Tolerance(_))
    ));
}
