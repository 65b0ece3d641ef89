//! Derived variables (`[variables]`) are output variables of the core: the result's column,
//! a metric of a single run and the same metric in a sweep agree to the last bit (the table
//! engine and the row recorder combine the same leaves with the same arithmetic), `der()` reads
//! the recorded derivative, a variant may set a `[parameters]` number they read, and what the
//! core cannot compute is refused naming the variable and the construct.

use stiction_core::{run_variants, CancelHandle, CompiledModel, ModelSpec, Plan, Simulation};

const COUPLED: &str = include_str!("../../../examples/msl/CoupledClutches.toml");

const VARIABLES: &str = r#"
[variables]
slip = "J1.w - J2.w"
loss = "clutch1.tau * der(clutch1.phi_rel)"
cut = "2 * J1.flange_a.tau + time"
hot = "if slip > 1 then sqrt(abs(slip)) elseif slip < -1 then -1 else Modelica.Math.max(slip, -0.5)"
kw = "k * J1.w"
rate = "der(J2.flange_b.phi) - der(J2.phi)"

[parameters]
k = 2
"#;

fn model(extra: &str) -> Result<CompiledModel, String> {
    let spec =
        ModelSpec::from_toml(&format!("{COUPLED}{extra}"), ".").map_err(|e| e.to_string())?;
    CompiledModel::new(spec).map_err(|e| e.to_string())
}

fn refused(extra: &str) -> String {
    match model(extra) {
        Ok(_) => panic!("accepted: {extra}"),
        Err(e) => e,
    }
}

fn run(cm: &CompiledModel) -> stiction_core::SimResult {
    let mut sim = Simulation::new(cm.system()).unwrap();
    sim.run().unwrap();
    sim.into_result()
}

#[test]
fn derived_variables_are_result_variables() {
    let cm = model(VARIABLES).unwrap();
    let r = run(&cm);
    let col = |n: &str| r.column(n).unwrap();
    let (w1, w2) = (col("J1.w"), col("J2.w"));
    let slip: Vec<f64> = w1.iter().zip(&w2).map(|(a, b)| a - b).collect();
    assert_eq!(col("slip"), slip);
    let loss: Vec<f64> = (col("clutch1.tau").iter().zip(col("clutch1.w_rel")))
        .map(|(t, w)| t * w)
        .collect();
    assert_eq!(col("loss"), loss);
    let cut: Vec<f64> = (col("J1.flange_a.tau").iter().zip(col("time")))
        .map(|(tau, t)| 2.0 * tau + t)
        .collect();
    assert_eq!(col("cut"), cut);
    assert!(col("rate").iter().all(|&x| x == 0.0));
    assert_eq!(col("kw"), w1.iter().map(|w| 2.0 * w).collect::<Vec<_>>());
    let hot = col("hot");
    for (h, s) in hot.iter().zip(&slip) {
        let expected = match *s {
            s if s > 1.0 => s.abs().sqrt(),
            s if s < -1.0 => -1.0,
            s => s.max(-0.5),
        };
        assert_eq!(h.to_bits(), expected.to_bits());
    }
    // the running simulation reads them too (the FMU's outputs)
    let mut sim = Simulation::new(cm.system()).unwrap();
    sim.advance_to(0.5).unwrap();
    let at = sim.get("slip").unwrap();
    assert_eq!(at, sim.get("J1.w").unwrap() - sim.get("J2.w").unwrap());
}

#[test]
fn sweep_metrics_of_derived_variables_equal_single_runs_to_the_bit() {
    let cm = model(VARIABLES).unwrap();
    let metrics: Vec<String> = [
        "max(slip)",
        "min(slip)",
        "integral(loss)",
        "final(cut)",
        "mean(hot)",
        "time_of(slip < 1)",
        "integral(kw)",
    ]
    .map(String::from)
    .to_vec();
    let plan = Plan::new(&cm, &metrics, &["slip".to_string()]).unwrap();
    let variants: Vec<Vec<(String, toml::Value)>> = [(10.0, 2.0), (25.0, 3.5)]
        .iter()
        .map(|&(fn_max, k)| {
            vec![
                ("clutch1.fn_max".to_string(), toml::Value::Float(fn_max)),
                ("k".to_string(), toml::Value::Float(k)),
            ]
        })
        .collect();
    let outcomes = run_variants(&cm, &variants, &plan, Some(2), &CancelHandle::new());
    for (variant, outcome) in variants.iter().zip(&outcomes) {
        assert!(outcome.error.is_none(), "{:?}", outcome.error);
        let pairs: Vec<(&str, toml::Value)> = variant
            .iter()
            .map(|(n, v)| (n.as_str(), v.clone()))
            .collect();
        let r = run(&cm.with(&pairs).unwrap());
        for (text, value) in metrics.iter().zip(&outcome.metrics) {
            let single = r.metric(text).unwrap();
            assert_eq!(
                single.to_bits(),
                value.to_bits(),
                "{text}: {single} vs {value}"
            );
        }
        let slip = r.column("slip").unwrap();
        let max = slip.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(max, outcome.metrics[0]);
        let k = variant[1].1.as_float().unwrap();
        let kw: Vec<f64> = r.column("J1.w").unwrap().iter().map(|w| k * w).collect();
        assert_eq!(r.column("kw").unwrap(), kw);
    }
}

#[test]
fn what_the_core_cannot_compute_is_refused_by_name() {
    let err = |vars: &str| refused(&format!("\n[variables]\n{vars}\n"));
    let e = err(r#"m = "der(clutch1.mode)""#);
    assert!(
        e.contains("variable 'm'") && e.contains("der(clutch1.mode)") && e.contains("derivative"),
        "{e}"
    );
    let e = err("a = \"J1.w\"\nb = \"der(a)\"");
    assert!(
        e.contains("variable 'b'") && e.contains("derived variable"),
        "{e}"
    );
    let e = err(r#"x = "J1.ww + 1""#);
    assert!(
        e.contains("unknown variable 'J1.ww'") && e.contains("J1.w"),
        "{e}"
    );
    let e = err(r#"x = "later + 1"
later = "J1.w""#);
    assert!(e.contains("unknown variable 'later'"), "{e}");
    let e = err(r#"J1 = "J2.w""#);
    assert!(e.contains("variable 'J1': the name is already used"), "{e}");
    let e = err(r#"s = "brake.mu_pos[1, 2]""#);
    assert!(
        e.contains("variable 's'") && e.contains("subscripts"),
        "{e}"
    );
    let e = err(r#"s = "median(J1.w)""#);
    assert!(e.contains("unknown function 'median'"), "{e}");
    let e = refused("\n[parameters]\nk = \"2*x\"\n");
    assert!(e.contains("parameter 'k'"), "{e}");
}

#[test]
fn a_model_without_derived_variables_has_the_outputs_it_had() {
    let plain = model("").unwrap();
    let with = model(VARIABLES).unwrap();
    let names = |cm: &CompiledModel| -> Vec<String> {
        cm.system().outputs.iter().map(|(n, _)| n.clone()).collect()
    };
    let (a, b) = (names(&plain), names(&with));
    assert_eq!(&b[..a.len()], &a[..]);
    assert_eq!(&b[a.len()..], ["slip", "loss", "cut", "hot", "kw", "rate"]);
}
