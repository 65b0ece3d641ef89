//! MSL's prescribed-motion sources (`Sources.Speed`, `Position`, `Accelerate`, `Move`) against
//! closed forms: the exact variants follow their inputs (and the inputs' exact derivatives),
//! the filters follow their linear ODEs' solutions, and the work of each source is what its
//! inertia takes (the energy audit closes).

use stiction_core::{simulate, ModelSpec, SimResult};

/// A source `src` of `src_type` driving an inertia J = 2 (flange_a), fed by `signals`.
fn drive(src_type: &str, params: &str, signals: &str, connects: &str, stop: f64) -> SimResult {
    let text = format!(
        r#"
format = 1
name = "motion"
connect = [{connects} ["src.flange", "J.flange_a"]]

[experiment]
StopTime = {stop}
Interval = 0.01
Tolerance = 1e-8

[components]
src = {{ type = "{src_type}"{params} }}
J   = {{ type = "Inertia", J = 2.0 }}
{signals}
"#
    );
    let spec = ModelSpec::from_toml(&text, ".").unwrap();
    simulate(&spec).unwrap()
}

fn col(r: &SimResult, name: &str) -> Vec<f64> {
    r.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// Every row: |got − want(t)| ≤ tol.
fn follows(r: &SimResult, name: &str, tol: f64, want: impl Fn(f64) -> f64) {
    for (t, v) in col(r, "time").iter().zip(col(r, name)) {
        let w = want(*t);
        assert!((v - w).abs() <= tol, "{name} at t = {t}: {v} against {w}");
    }
}

/// The source's work is the inertia's gain of kinetic energy (nothing else stores or loses).
fn work_is_kinetic_energy(r: &SimResult, tol: f64) {
    let (work, kinetic) = (col(r, "system.sourceWork"), col(r, "system.kineticEnergy"));
    for (w, k) in work.iter().zip(&kinetic) {
        let gain = k - kinetic[0];
        assert!(
            (w - gain).abs() <= tol * (1.0 + k.abs()),
            "work {w} against {gain}"
        );
    }
    let audits = r.audit();
    for a in &audits {
        assert!(
            a.residual <= 1e-8 * a.scale.max(1.0),
            "{}: residual {}",
            a.component,
            a.residual
        );
    }
}

#[test]
fn exact_speed_on_a_ramp_takes_j_times_the_slope() {
    // w_ref rises by 10 rad/s over 2 s from t = 0.5: a = 5, tau = J·a = 10 while it rises
    let r = drive(
        "Speed",
        ", exact = true",
        r#"ramp = { type = "Ramp", height = 10.0, duration = 2.0, startTime = 0.5, offset = 1.0 }"#,
        r#"["ramp.y", "src.w_ref"],"#,
        3.0,
    );
    let ramp = |t: f64| 1.0 + 10.0 * ((t - 0.5) / 2.0).clamp(0.0, 1.0);
    follows(&r, "J.w", 1e-12, ramp);
    follows(&r, "src.w", 1e-12, ramp);
    follows(&r, "src.a", 0.0, |_| 0.0); // MSL's dummy
    let (t, tau) = (col(&r, "time"), col(&r, "J.flange_a.tau"));
    for (t, tau) in t.iter().zip(&tau) {
        if (*t - 0.5).abs() > 1e-9 && (*t - 2.5).abs() > 1e-9 {
            let want = if *t > 0.5 && *t < 2.5 { 10.0 } else { 0.0 };
            assert!((tau - want).abs() < 1e-9, "t = {t}: tau {tau}");
        }
    }
    // phi = ∫ w, from phi(0) = 0 (MSL: phi(start = 0, fixed = true))
    let phi = |t: f64| {
        let s = (t - 0.5).clamp(0.0, 2.0);
        t + 2.5 * s * s + 10.0 * (t - 2.5).max(0.0)
    };
    follows(&r, "src.phi", 1e-6, phi);
    work_is_kinetic_energy(&r, 1e-6);
}

#[test]
fn filtered_speed_answers_a_step_as_a_first_order_lag() {
    // f_crit = 2 Hz: w = 3·(1 − exp(−w_crit (t − 0.1))) after the step at 0.1
    let r = drive(
        "Speed",
        ", f_crit = 2.0",
        r#"step = { type = "Step", height = 3.0, startTime = 0.1 }"#,
        r#"["step.y", "src.w_ref"],"#,
        1.0,
    );
    let w_crit = 2.0 * std::f64::consts::PI * 2.0;
    let w = |t: f64| 3.0 * (1.0 - (-w_crit * (t - 0.1).max(0.0)).exp());
    follows(&r, "J.w", 1e-5, w);
    let (t, a) = (col(&r, "time"), col(&r, "src.a"));
    for (k, (t, a)) in t.iter().zip(&a).enumerate() {
        // both rows of the step: a jumps from 0 to 3·w_crit
        let want = if *t < 0.1 || (*t == 0.1 && t_next_is_same(&r, k)) {
            0.0
        } else {
            (3.0 - w(*t)) * w_crit
        };
        assert!(
            (a - want).abs() <= 1e-4 * w_crit,
            "t = {t}: a {a} against {want}"
        );
    }
    work_is_kinetic_energy(&r, 1e-6);
}

/// Whether row `k` is the left row of an event (the next row has the same time).
fn t_next_is_same(r: &SimResult, k: usize) -> bool {
    let t = col(r, "time");
    k + 1 < t.len() && t[k + 1] == t[k]
}

#[test]
fn filtered_speed_starts_at_its_input() {
    // MSL: initial equation w = w_ref
    let r = drive(
        "Speed",
        "",
        r#"c = { type = "Constant", k = 7.0 }"#,
        r#"["c.y", "src.w_ref"],"#,
        0.5,
    );
    follows(&r, "J.w", 1e-12, |_| 7.0);
    follows(&r, "J.flange_a.tau", 1e-9, |_| 0.0);
}

#[test]
fn exact_position_on_a_sine_gives_angle_speed_and_acceleration_exactly() {
    // phi_ref = 2 sin(πt) + 0.3
    let r = drive(
        "Position",
        ", exact = true",
        r#"s = { type = "Sine", amplitude = 2.0, f = 0.5, offset = 0.3 }"#,
        r#"["s.y", "src.phi_ref"],"#,
        2.0,
    );
    let pi = std::f64::consts::PI;
    follows(&r, "J.phi", 1e-12, |t| 2.0 * (pi * t).sin() + 0.3);
    follows(&r, "J.w", 1e-12, |t| 2.0 * pi * (pi * t).cos());
    follows(&r, "J.a", 1e-11, |t| -2.0 * pi * pi * (pi * t).sin());
    follows(&r, "J.flange_a.tau", 1e-10, |t| {
        -4.0 * pi * pi * (pi * t).sin()
    });
    // the work is integrated at Tolerance = 1e-8
    work_is_kinetic_energy(&r, 1e-6);
}

#[test]
fn exact_position_differentiates_through_math_blocks() {
    // phi_ref = (t ramp) · sin t, through a Product and a Gain of −1 and a Feedback
    let signals = r#"
r = { type = "Ramp", height = 10.0, duration = 10.0 }
s = { type = "Sine", f = 0.15915494309189535 }
p = { type = "Product" }
g = { type = "Gain", k = -1.0 }
"#;
    let connects = r#"["r.y", "p.u1"], ["s.y", "p.u2"], ["p.y", "g.u"], ["g.y", "src.phi_ref"],"#;
    let r = drive("Position", ", exact = true", signals, connects, 3.0);
    follows(&r, "J.phi", 1e-12, |t| -t * t.sin());
    follows(&r, "J.w", 1e-12, |t| -(t.sin() + t * t.cos()));
    follows(&r, "J.a", 1e-11, |t| -(2.0 * t.cos() - t * t.sin()));
}

#[test]
fn filtered_position_answers_a_step_as_its_second_order_filter() {
    // bf/w² φ'' + af/w φ' + φ = phi_ref: underdamped, φ = 1 + e^{σt}(−cos ωt + σ/ω sin ωt)
    let (af, bf) = (1.3617, 0.6180);
    let w_crit = 2.0 * std::f64::consts::PI * 1.5;
    let sigma = -af * w_crit / (2.0 * bf);
    let omega = w_crit * (4.0 * bf - af * af).sqrt() / (2.0 * bf);
    let r = drive(
        "Position",
        ", f_crit = 1.5",
        r#"step = { type = "Step", height = 1.0, startTime = 0.2 }"#,
        r#"["step.y", "src.phi_ref"],"#,
        1.5,
    );
    let phi = |t: f64| {
        let s = (t - 0.2).max(0.0);
        1.0 + (sigma * s).exp() * (-(omega * s).cos() + sigma / omega * (omega * s).sin())
    };
    follows(&r, "J.phi", 1e-5, phi);
    follows(&r, "src.phi", 1e-5, phi);
    work_is_kinetic_energy(&r, 1e-6);
}

#[test]
fn accelerate_integrates_a_constant_acceleration() {
    let r = drive(
        "Accelerate",
        ", phi = { start = 0.5 }",
        r#"c = { type = "Constant", k = 4.0 }"#,
        r#"["c.y", "src.a_ref"],"#,
        2.0,
    );
    follows(&r, "J.phi", 1e-9, |t| 0.5 + 2.0 * t * t);
    follows(&r, "src.w", 1e-9, |t| 4.0 * t);
    follows(&r, "src.a", 1e-12, |_| 4.0);
    follows(&r, "J.flange_a.tau", 1e-9, |_| 8.0);
    work_is_kinetic_energy(&r, 1e-8);
}

#[test]
fn move_follows_its_three_inputs() {
    let signals = r#"
p = { type = "Sine", f = 0.15915494309189535 }
v = { type = "Sine", f = 0.15915494309189535, phase = 1.5707963267948966 }
a = { type = "Sine", amplitude = -1.0, f = 0.15915494309189535 }
"#;
    let connects = r#"["p.y", "src.u[1]"], ["v.y", "src.u[2]"], ["a.y", "src.u[3]"],"#;
    let r = drive("Move", "", signals, connects, 4.0);
    follows(&r, "J.phi", 1e-12, f64::sin);
    follows(&r, "src.phi", 1e-12, f64::sin);
    follows(&r, "J.w", 1e-12, f64::cos);
    follows(&r, "J.flange_a.tau", 1e-11, |t| -2.0 * t.sin());
}

#[test]
fn exact_motion_from_a_model_input_is_refused_by_name() {
    let text = r#"
format = 1
name = "refused"
inputs = ["src.w_ref"]
connect = [["src.flange", "J.flange_a"]]

[components]
src = { type = "Speed", exact = true }
J   = { type = "Inertia", J = 2.0 }
"#;
    let err = simulate(&ModelSpec::from_toml(text, ".").unwrap())
        .err()
        .expect("refused")
        .to_string();
    assert!(err.contains("src") && err.contains("w_ref"), "{err}");
    assert!(err.contains("model input 'src.w_ref'"), "{err}");
    // filtered, the same input is fine
    let filtered = text.replace("exact = true", "exact = false");
    simulate(&ModelSpec::from_toml(&filtered, ".").unwrap())
        .expect("the filter needs no derivative");
}

#[test]
fn a_bad_critical_frequency_is_named() {
    let text = r#"
format = 1
name = "bad"
connect = [["c.y", "src.w_ref"], ["src.flange", "J.flange_a"]]

[components]
c   = { type = "Constant", k = 1.0 }
src = { type = "Speed", f_crit = 0.0 }
J   = { type = "Inertia", J = 2.0 }
"#;
    let err = simulate(&ModelSpec::from_toml(text, ".").unwrap())
        .err()
        .expect("refused")
        .to_string();
    assert!(err.contains("src") && err.contains("f_crit"), "{err}");
}

#[test]
fn a_speed_with_support_drives_relative_to_its_housing() {
    // the housing turns at 1 rad/s (ConstantSpeed); the source adds 2 rad/s on top
    let text = r#"
format = 1
name = "support"
connect = [
  ["c.y", "src.w_ref"], ["src.flange", "J.flange_a"],
  ["src.support", "housing.flange"],
]

[experiment]
StopTime = 1.0
Interval = 0.1

[components]
c       = { type = "Constant", k = 2.0 }
src     = { type = "Speed", exact = true, useSupport = true }
housing = { type = "ConstantSpeed", w_fixed = 1.0 }
J       = { type = "Inertia", J = 2.0 }
"#;
    let r = simulate(&ModelSpec::from_toml(text, ".").unwrap()).unwrap();
    follows(&r, "J.w", 1e-12, |_| 3.0);
    follows(&r, "src.w", 1e-12, |_| 2.0);
}
