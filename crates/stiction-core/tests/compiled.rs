//! The compiled model: a variant made by overriding parameters, start values and experiment
//! settings gives exactly the result of the model file written with those values; a value that
//! changes the structure is compiled anew (or refused where the connections no longer fit),
//! never ignored; a bad name or value is refused before any run, naming component and parameter.

use stiction_core::{simulate, ModelError, ModelSpec, SimResult, Simulation};
use stiction_core::{CompiledModel, Recompiled};

const COUPLED: &str = include_str!("../../../examples/msl/CoupledClutches.toml");

fn spec(text: &str) -> ModelSpec {
    ModelSpec::from_toml(text, ".").expect("the model parses")
}

fn run(cm: &CompiledModel) -> SimResult {
    let mut sim = Simulation::new(cm.system()).expect("it initializes");
    sim.run().expect("it runs");
    sim.into_result()
}

fn assert_same(a: &SimResult, b: &SimResult) {
    assert_eq!(a.names, b.names);
    assert_eq!(a.events, b.events);
    for name in &a.names {
        let (x, y) = (a.column(name).unwrap(), b.column(name).unwrap());
        assert_eq!(x.len(), y.len(), "{name}");
        let differ = x
            .iter()
            .zip(&y)
            .position(|(u, v)| u.to_bits() != v.to_bits());
        assert!(differ.is_none(), "{name} differs at row {differ:?}");
    }
}

fn float(v: f64) -> toml::Value {
    toml::Value::Float(v)
}

#[test]
fn a_variant_equals_the_model_written_with_its_values() {
    let cm = CompiledModel::new(spec(COUPLED)).unwrap();
    let table: toml::Value = "x = [[0.0, 0.5], [1.0, 0.3], [5.0, 0.25]]"
        .parse::<toml::Table>()
        .unwrap()["x"]
        .clone();
    let (variant, how) = cm
        .with_report(&[
            ("clutch1.fn_max", float(35.0)),
            ("clutch2.mu_pos", table),
            ("J1.w", float(7.5)),
            ("sin1.f", float(3.0)),
            ("StopTime", float(1.2)),
        ])
        .unwrap();
    assert_eq!(
        how,
        Recompiled::Build,
        "no structural change: the topology is kept"
    );
    let written = COUPLED
        .replace(
            "clutch1 = { type = \"Clutch\", peak = 1.1, fn_max = 20.0 }",
            "clutch1 = { type = \"Clutch\", peak = 1.1, fn_max = 35.0 }",
        )
        .replace(
            "clutch2 = { type = \"Clutch\", peak = 1.1, fn_max = 20.0 }",
            "clutch2 = { type = \"Clutch\", peak = 1.1, fn_max = 20.0, mu_pos = [[0.0, 0.5], [1.0, 0.3], [5.0, 0.25]] }",
        )
        .replace("w = 10.0", "w = 7.5")
        .replace("amplitude = 10.0, f = 5.0", "amplitude = 10.0, f = 3.0")
        .replace("StopTime = 1.5", "StopTime = 1.2");
    let expected = simulate(&spec(&written)).unwrap();
    assert_same(&run(&variant), &expected);
    // the original is untouched, and differs from the variant
    let original = run(&cm);
    assert_same(&original, &simulate(&spec(COUPLED)).unwrap());
    assert_ne!(original.rows(), expected.rows());
}

#[test]
fn a_structural_change_is_compiled_anew_never_ignored() {
    let cm = CompiledModel::new(spec(COUPLED)).unwrap();
    // the fixed angle of the housing decides which ports are ground: a new topology
    let (moved, how) = cm.with_report(&[("fixed.phi0", float(0.5))]).unwrap();
    assert_eq!(how, Recompiled::Topology);
    let written = COUPLED.replace(
        "fixed = { type = \"Fixed\" }",
        "fixed = { type = \"Fixed\", phi0 = 0.5 }",
    );
    assert_same(&run(&moved), &simulate(&spec(&written)).unwrap());
    // without its support port, the torque source no longer fits its connections
    let err = cm
        .with(&[("torque.useSupport", toml::Value::Boolean(false))])
        .err()
        .expect("the connection to torque.support is refused");
    assert!(
        matches!(&err, ModelError::Connection { message, .. } if message.contains("no port 'support'")),
        "{err}"
    );
}

#[test]
fn bad_names_and_values_are_refused_before_any_run() {
    let cm = CompiledModel::new(spec(COUPLED)).unwrap();
    let refuse = |name: &str, value: toml::Value| cm.with(&[(name, value)]).err().unwrap();
    match refuse("clutch9.fn_max", float(1.0)) {
        ModelError::Component { component, .. } => assert_eq!(component, "clutch9"),
        other => panic!("{other}"),
    }
    match refuse("clutch1.fnmax", float(1.0)) {
        ModelError::Parameter {
            component,
            parameter,
            message,
            ..
        } => {
            assert_eq!(
                (component.as_str(), parameter.as_str()),
                ("clutch1", "fnmax")
            );
            assert!(
                message.contains("fn_max"),
                "suggests the right name: {message}"
            );
        }
        other => panic!("{other}"),
    }
    match refuse("clutch1.fn_max", float(-1.0)) {
        ModelError::Parameter { parameter, .. } => assert_eq!(parameter, "fn_max"),
        other => panic!("{other}"),
    }
    assert!(refuse("StopTme", float(2.0))
        .to_string()
        .contains("StopTme"));
    assert!(refuse("StopTime", float(-1.0))
        .to_string()
        .contains("StopTime"));
    let names = cm.parameter_names();
    for name in [
        "clutch1.fn_max",
        "clutch1.mu_pos",
        "J1.w",
        "sin1.f",
        "StopTime",
    ] {
        assert!(names.iter().any(|n| n == name), "{name} in {names:?}");
    }
}

#[test]
fn a_compiled_model_is_shared_by_threads() {
    fn shared<T: Send + Sync + Clone>() {}
    shared::<CompiledModel>();
    let cm = CompiledModel::new(spec(COUPLED)).unwrap();
    let finals: Vec<f64> = std::thread::scope(|s| {
        let handles: Vec<_> = [10.0, 20.0, 30.0]
            .into_iter()
            .map(|fn_max| {
                let cm = cm.clone();
                s.spawn(move || {
                    let v = cm.with(&[("clutch1.fn_max", float(fn_max))]).unwrap();
                    *run(&v).column("J1.w").unwrap().last().unwrap()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let one = |fn_max: f64| {
        let v = cm.with(&[("clutch1.fn_max", float(fn_max))]).unwrap();
        *run(&v).column("J1.w").unwrap().last().unwrap()
    };
    assert_eq!(finals, vec![one(10.0), one(20.0), one(30.0)]);
    assert_ne!(finals[0], finals[2]);
}
