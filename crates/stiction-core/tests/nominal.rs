//! Start values' `nominal`: the integrator controls each state to an absolute error of
//! Tolerance·nominal (Dymola's DASSL scaling), so a small oscillation is resolved at the
//! default Tolerance of 1e-6 once its variables say how small they are.

use stiction_core::{simulate, ModelSpec, SimResult};

/// An inertia of J = 1 on a spring-damper to ground (c = 1e4, d = 0.2: 100 rad/s, damping ratio
/// 0.001) released at w = 1e-4 rad/s: the angle swings within 1e-6 rad, the speed within 1e-4.
fn oscillator(phi_rel: &str, w_rel: &str) -> String {
    format!(
        r#"
format = 1
name = "small_oscillation"
connect = [["ground.flange", "spring.flange_a"], ["spring.flange_b", "J.flange_a"]]

[experiment]
StopTime = 5.0
Interval = 0.01

[components]
ground = {{ type = "Fixed" }}
spring = {{ type = "SpringDamper", c = 1e4, d = 0.2, phi_rel = {phi_rel}, w_rel = {w_rel} }}
J = {{ type = "Inertia", J = 1.0 }}
"#
    )
}

const W0: f64 = 1e-4;

fn run(text: &str) -> SimResult {
    simulate(&ModelSpec::from_toml(text, ".").unwrap()).expect("it runs")
}

/// The largest error of `J.w` against the damped oscillation, relative to its start `W0`.
fn speed_error(r: &SimResult) -> f64 {
    let (sigma, omega) = (0.1, (1e4f64 - 0.01).sqrt());
    let exact =
        |t: f64| W0 * (-sigma * t).exp() * ((omega * t).cos() - sigma / omega * (omega * t).sin());
    let (t, w) = (r.column("time").unwrap(), r.column("J.w").unwrap());
    (t.iter().zip(w))
        .map(|(&t, w)| (w - exact(t)).abs())
        .fold(0.0, f64::max)
        / W0
}

#[test]
fn the_nominal_scales_the_error_control_of_a_small_oscillation() {
    let plain = run(&oscillator(
        "{ start = 0, fixed = true }",
        "{ start = 1e-4, fixed = true }",
    ));
    let scaled = run(&oscillator(
        "{ start = 0, fixed = true, nominal = 1e-6 }",
        "{ start = 1e-4, fixed = true, nominal = 1e-4 }",
    ));
    let (e_plain, e_scaled) = (speed_error(&plain), speed_error(&scaled));
    println!("relative speed error: {e_plain:e} without nominals, {e_scaled:e} with");
    // an absolute tolerance of 1e-6 on states of size 1e-6 and 1e-4 does not resolve them
    assert!(e_plain > 1e-2, "without nominals: {e_plain}");
    assert!(e_scaled < 1e-3, "with nominals: {e_scaled}");
}

#[test]
fn a_nominal_of_one_changes_nothing() {
    let plain = run(&oscillator("0", "1e-4"));
    let one = run(&oscillator(
        "{ start = 0, fixed = true, nominal = 1 }",
        "{ start = 1e-4, fixed = true, nominal = 1.0 }",
    ));
    let bits = |r: &SimResult| {
        r.column("J.w")
            .unwrap()
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&plain), bits(&one));
}

#[test]
fn a_nominal_that_is_not_positive_is_refused_by_name() {
    for bad in ["0", "-1e-4"] {
        let text = oscillator(
            "0",
            &format!("{{ start = 1e-4, fixed = true, nominal = {bad} }}"),
        );
        let err = ModelSpec::from_toml(&text, ".")
            .and_then(|spec| stiction_core::assemble(&spec).map(|_| ()))
            .expect_err("refused")
            .to_string();
        assert!(
            err.contains("spring") && err.contains("w_rel") && err.contains("nominal"),
            "{err}"
        );
    }
}

/// A start value set anew (a sweep's variant, an FMU host, `params=`) is a value: the nominal
/// the model gave its variable stays, on both the general and the sweep's path.
#[test]
fn a_start_value_set_anew_keeps_its_nominal() {
    use stiction_core::{run, CompiledModel};
    let model = |w_rel: &str| {
        let text = oscillator("{ start = 0, fixed = true, nominal = 1e-6 }", w_rel);
        CompiledModel::new(ModelSpec::from_toml(&text, ".").unwrap()).unwrap()
    };
    let w = |r: SimResult| {
        r.column("J.w")
            .unwrap()
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    let given = model("{ start = 2e-4, fixed = true, nominal = 1e-4 }");
    let base = model("{ start = 1e-4, fixed = true, nominal = 1e-4 }");
    let expected = w(run(given.system()).unwrap());
    let set = [("spring.w_rel", toml::Value::Float(2e-4))];
    assert_eq!(w(run(base.with(&set).unwrap().system()).unwrap()), expected);
    assert_eq!(
        w(run(base.variant_system(&set).unwrap()).unwrap()),
        expected
    );
    let speed_error = |r: SimResult| {
        let (sigma, omega) = (0.1, (1e4f64 - 0.01).sqrt());
        let exact = |t: f64| {
            2e-4 * (-sigma * t).exp() * ((omega * t).cos() - sigma / omega * (omega * t).sin())
        };
        let (t, w) = (r.column("time").unwrap(), r.column("J.w").unwrap());
        (t.iter().zip(w))
            .map(|(&t, w)| (w - exact(t)).abs())
            .fold(0.0, f64::max)
            / 2e-4
    };
    assert!(speed_error(run(base.with(&set).unwrap().system()).unwrap()) < 1e-3);
}
