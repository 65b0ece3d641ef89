//! Shafts without inertia: a spring in series with a damper (the shaft between them has an
//! algebraic speed) runs and matches the closed form; two springs in series with nothing
//! between them are reported by the model check, naming the shafts.

use stiction_core::check_model;
use stiction_core::{assemble, simulate, ModelSpec};

const SERIES: &str = r#"
format = 1
name = "series"
connect = [
  ["J1.flange_b", "spring.flange_a"],
  ["spring.flange_b", "damper.flange_a"],
  ["damper.flange_b", "fixed.flange"],
]

[experiment]
StopTime = 0.5
Interval = 0.01
Tolerance = 1e-10

[components]
J1     = { type = "Inertia", J = 1.0, phi = 0.0, w = 1.0 }
spring = { type = "Spring", c = 100.0, phi_rel = 0.0 }
damper = { type = "Damper", d = 25.0 }
fixed  = { type = "Fixed" }
"#;

/// (φ1, w1, φn) at `t_end` from the reduced equations J·w1' = −c(φ1 − φn), d·φn' = c(φ1 − φn)
/// (J = 1, c = 100, d = 25), by classical Runge–Kutta at 1e-5 s (error far below 1e-10).
fn reference(t_end: f64) -> [f64; 3] {
    let f = |y: [f64; 3]| [y[1], -100.0 * (y[0] - y[2]), 4.0 * (y[0] - y[2])];
    let (mut y, h) = ([0.0, 1.0, 0.0], 1e-5);
    for _ in 0..(t_end / h).round() as usize {
        let k1 = f(y);
        let k2 = f(std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]));
        let k3 = f(std::array::from_fn(|i| y[i] + 0.5 * h * k2[i]));
        let k4 = f(std::array::from_fn(|i| y[i] + h * k3[i]));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    y
}

#[test]
fn a_spring_in_series_with_a_damper_runs_as_the_reduced_equations() {
    let spec = ModelSpec::from_toml(SERIES, ".").unwrap();
    check_model(&assemble(&spec).unwrap()).expect("the damper determines the shaft");
    let r = simulate(&spec).expect("it runs");
    let last = |name: &str| *r.column(name).unwrap().last().unwrap();
    let [phi1, w1, phin] = reference(0.5);
    assert!((last("J1.w") - w1).abs() < 1e-8, "{} {w1}", last("J1.w"));
    assert!((last("damper.phi_rel") + phin).abs() < 1e-8);
    // the damper's speed is the algebraic one: c(φ1 − φn)/d
    assert!((last("damper.w_rel") + 4.0 * (phi1 - phin)).abs() < 1e-8);
}

#[test]
fn two_springs_in_series_are_reported_with_their_shafts() {
    let text = SERIES
        .replace(
            r#"type = "Damper", d = 25.0"#,
            r#"type = "Spring", c = 50.0"#,
        )
        .replace("damper", "spring2");
    let sys = assemble(&ModelSpec::from_toml(&text, ".").unwrap()).unwrap();
    let err = check_model(&sys).unwrap_err().to_string();
    assert!(
        err.contains("not determined: [spring.flange_b, spring2.flange_a]"),
        "{err}"
    );
}
