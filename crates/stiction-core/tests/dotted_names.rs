//! Hierarchical component names (`clutch.c1`, as Modelica tools flatten a user's class):
//! a model whose components are renamed into a path runs bit for bit as the original, its
//! variables, parameters, ports and events carry the dotted names, and a name that is the start
//! of another component's path is refused naming both.

use stiction_core::{simulate, CompiledModel, ModelError, ModelSpec, SimResult, Simulation};

const COUPLED: &str = include_str!("../../../examples/msl/CoupledClutches.toml");

fn spec(text: &str) -> ModelSpec {
    ModelSpec::from_toml(text, ".").expect("the model parses")
}

/// CoupledClutches with `clutch1` → `clutch.c1` and `J2` → `J2.inner` (names that sort as the
/// originals do: the components are compiled in their sorted order, and another order would
/// round differently).
fn renamed() -> String {
    COUPLED
        .replace("\"clutch1.", "\"clutch.c1.")
        .replace("\nclutch1 = {", "\n\"clutch.c1\" = {")
        .replace("\"J2.", "\"J2.inner.")
        .replace("\nJ2 = {", "\n\"J2.inner\" = {")
}

fn rename(name: &str) -> String {
    for (old, new) in [("clutch1.", "clutch.c1."), ("J2.", "J2.inner.")] {
        if let Some(rest) = name.strip_prefix(old) {
            return format!("{new}{rest}");
        }
    }
    name.to_string()
}

fn assert_same_renamed(original: &SimResult, dotted: &SimResult) {
    let expected: Vec<String> = original.names.iter().map(|n| rename(n)).collect();
    assert_eq!(dotted.names, expected);
    for (name, new) in original.names.iter().zip(&expected) {
        let (x, y) = (original.column(name).unwrap(), dotted.column(new).unwrap());
        let same = x.len() == y.len() && x.iter().zip(&y).all(|(u, v)| u.to_bits() == v.to_bits());
        assert!(same, "{new} differs from {name}");
    }
    let events = |r: &SimResult| -> Vec<(u64, String)> {
        (r.events.iter())
            .map(|e| (e.time.to_bits(), e.component.clone()))
            .collect()
    };
    let renamed_events: Vec<(u64, String)> = (events(original).into_iter())
        .map(|(t, c)| {
            (
                t,
                if c == "clutch1" {
                    "clutch.c1".into()
                } else {
                    c
                },
            )
        })
        .collect();
    assert_eq!(events(dotted), renamed_events);
}

#[test]
fn a_model_with_dotted_names_runs_as_the_original() {
    let original = simulate(&spec(COUPLED)).unwrap();
    let dotted = simulate(&spec(&renamed())).unwrap();
    assert!(dotted.names.iter().any(|n| n == "clutch.c1.flange_a.tau"));
    assert!(dotted.names.iter().any(|n| n == "J2.inner.w"));
    assert!(dotted.events.iter().any(|e| e.component == "clutch.c1"));
    assert_same_renamed(&original, &dotted);
}

#[test]
fn parameters_of_a_dotted_component_are_set_by_their_full_name() {
    let cm = CompiledModel::new(spec(COUPLED)).unwrap();
    let dotted = CompiledModel::new(spec(&renamed())).unwrap();
    let run = |cm: &CompiledModel| {
        let mut sim = Simulation::new(cm.system()).unwrap();
        sim.run().unwrap();
        sim.into_result()
    };
    let a = cm
        .with(&[("clutch1.fn_max", 35.0.into()), ("J2.w", 1.5.into())])
        .unwrap();
    let b = (dotted.with(&[
        ("clutch.c1.fn_max", 35.0.into()),
        ("J2.inner.w", 1.5.into()),
    ]))
    .unwrap();
    assert_same_renamed(&run(&a), &run(&b));
    // a parameter name is the last segment: the component is the path before it
    match dotted
        .with(&[("clutch.c1.fnmax", 1.0.into())])
        .err()
        .unwrap()
    {
        ModelError::Parameter {
            component,
            parameter,
            ..
        } => assert_eq!(
            (component.as_str(), parameter.as_str()),
            ("clutch.c1", "fnmax")
        ),
        other => panic!("{other}"),
    }
    // in a running simulation too
    let mut sim = Simulation::from_spec(&spec(&renamed())).unwrap();
    sim.advance_to(0.5).unwrap();
    sim.set_parameter("clutch.c1.fn_max", 35.0).unwrap();
    let e = sim.set_parameter("clutch.fn_max", 35.0).unwrap_err();
    assert!(e.to_string().contains("'clutch'"), "{e}");
}

#[test]
fn an_unknown_variable_is_answered_with_its_component_s_variables() {
    let r = simulate(&spec(&renamed())).unwrap();
    let e = r.metric("max(clutch.c1.w_rlx)").unwrap_err().to_string();
    assert!(e.contains("variables of clutch.c1: "), "{e}");
    assert!(e.contains("clutch.c1.tau,"), "{e}");
    let text = renamed() + "\n[variables]\nslip = \"J2.inner.w - J3.w\"\nbad = \"J2.inner.ww\"\n";
    let e = simulate(&spec(&text)).err().expect("refused").to_string();
    assert!(e.contains("variables of J2.inner: J2.inner."), "{e}");
}

#[test]
fn a_name_that_starts_another_component_s_path_is_refused_naming_both() {
    let text = renamed().replace(
        "fixed = { type = \"Fixed\" }",
        "fixed = { type = \"Fixed\" }\nclutch = { type = \"Inertia\", J = 1.0 }",
    );
    let e = CompiledModel::new(spec(&text)).err().expect("refused");
    let message = e.to_string();
    assert!(
        matches!(&e, ModelError::Component { component, .. } if component == "clutch"),
        "{message}"
    );
    assert!(message.contains("clutch.c1"), "{message}");
    // a bad path is refused when read
    for bad in ["front..clutch", "front.", "front.1clutch"] {
        let text = COUPLED.replace("\nclutch1 = {", &format!("\n\"{bad}\" = {{"));
        let e = ModelSpec::from_toml(&text, ".")
            .expect_err("refused")
            .to_string();
        assert!(
            e.contains(bad) && e.contains("identifiers joined by dots"),
            "{e}"
        );
    }
}
