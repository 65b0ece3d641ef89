//! Rotational.Sensors in the engine: each sensor against a closed form, sensor signals driving
//! components through blocks (a brake controlled by a measured speed), and the algebraic loops
//! refused by name.

use stiction_core::{assemble, simulate, ModelSpec, SimResult};

fn run(text: &str) -> SimResult {
    simulate(&ModelSpec::from_toml(text, ".").unwrap()).expect("it runs")
}

fn col(r: &SimResult, name: &str) -> Vec<f64> {
    r.column(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
}

/// A constant torque of 2 N.m through a MultiSensor into a flywheel of J = 0.5, with every
/// absolute and relative sensor on it: w = 4t, phi = 2t², a = 4; the cut torque is J·a = 2.
const FLYWHEEL: &str = r#"
format = 1
name = "flywheel"
connect = [
  ["source.flange", "multi.flange_a"],
  ["multi.flange_b", "torqueSensor.flange_a"],
  ["torqueSensor.flange_b", "powerSensor.flange_a"],
  ["powerSensor.flange_b", "J.flange_a"],
  ["J.flange_b", "angle.flange"],
  ["J.flange_b", "speed.flange"],
  ["J.flange_b", "acc.flange"],
  ["relAngle.flange_a", "ground.flange"],
  ["relAngle.flange_b", "J.flange_b"],
  ["relSpeed.flange_a", "ground.flange"],
  ["relSpeed.flange_b", "J.flange_b"],
  ["relAcc.flange_a", "J.flange_b"],
  ["relAcc.flange_b", "ground.flange"],
]

[experiment]
StopTime = 2.0
Interval = 0.01

[components]
source = { type = "ConstantTorque", tau_constant = 2.0 }
multi = { type = "MultiSensor" }
torqueSensor = { type = "TorqueSensor" }
powerSensor = { type = "PowerSensor" }
J = { type = "Inertia", J = 0.5, phi = { start = 0.0, fixed = true }, w = { start = 0.0, fixed = true } }
angle = { type = "AngleSensor" }
speed = { type = "SpeedSensor" }
acc = { type = "AccSensor" }
relAngle = { type = "RelAngleSensor" }
relSpeed = { type = "RelSpeedSensor" }
relAcc = { type = "RelAccSensor" }
ground = { type = "Fixed" }
"#;

#[test]
fn every_sensor_reads_the_flywheel_closed_form() {
    let r = run(FLYWHEEL);
    let t = col(&r, "time");
    let close = |name: &str, exact: &dyn Fn(f64) -> f64, tol: f64| {
        for (t, v) in t.iter().zip(col(&r, name)) {
            let e = exact(*t);
            assert!(
                (v - e).abs() <= tol * (1.0 + e.abs()),
                "{name} at t = {t}: {v} against {e}"
            );
        }
    };
    close("angle.phi", &|t| 2.0 * t * t, 1e-9);
    close("relAngle.phi_rel", &|t| 2.0 * t * t, 1e-9);
    close("speed.w", &|t| 4.0 * t, 1e-9);
    close("relSpeed.w_rel", &|t| 4.0 * t, 1e-9);
    close("multi.w", &|t| 4.0 * t, 1e-9);
    close("acc.a", &|_| 4.0, 1e-12);
    close("relAcc.a_rel", &|_| -4.0, 1e-12);
    // the cut torque is what the flywheel needs, J·a = 2 (the source's torque)
    close("multi.tau", &|_| 2.0, 1e-12);
    close("torqueSensor.tau", &|_| 2.0, 1e-12);
    close("torqueSensor.flange_a.tau", &|_| 2.0, 1e-12);
    close("torqueSensor.flange_b.tau", &|_| -2.0, 1e-12);
    close("speed.flange.tau", &|_| 0.0, 0.0);
    close("powerSensor.power", &|t| 8.0 * t, 1e-9);
    close("multi.power", &|t| 8.0 * t, 1e-9);
    // the energy through the sensor is the flywheel's kinetic energy: ∫ power dt = J·w²/2
    let p = col(&r, "multi.power");
    let energy: f64 = (t.windows(2).zip(p.windows(2)))
        .map(|(t, p)| 0.5 * (t[1] - t[0]) * (p[0] + p[1]))
        .sum();
    let kinetic = *col(&r, "system.kineticEnergy").last().unwrap();
    assert!(
        (energy - kinetic).abs() < 1e-9 * kinetic,
        "{energy} against {kinetic}"
    );
    assert!((kinetic - 0.25 * 64.0).abs() < 1e-8);
}

/// A flywheel spinning at w0 = 10, braked with f_normalized = k·w from a SpeedSensor through a
/// Gain: while it slides, J·w' = −mu·cgeo·fn_max·k·w, so w = w0·exp(−mu·cgeo·fn_max·k·t/J).
const SPEED_BRAKE: &str = r#"
format = 1
name = "speed_brake"
connect = [
  ["J.flange_b", "brake.flange_a"],
  ["J.flange_a", "speed.flange"],
  ["speed.w", "gain.u"],
  ["gain.y", "brake.f_normalized"],
]

[experiment]
StopTime = 3.0
Interval = 0.01
Tolerance = 1e-8

[components]
J = { type = "Inertia", J = 2.0, w = { start = 10.0, fixed = true } }
speed = { type = "SpeedSensor" }
gain = { type = "Gain", k = 0.05 }
brake = { type = "Brake", fn_max = 20.0, cgeo = 1.5, mu_pos = [[0.0, 0.4]] }
"#;

#[test]
fn a_brake_driven_by_the_measured_speed_decays_exponentially() {
    let r = run(SPEED_BRAKE);
    let rate = 0.4 * 1.5 * 20.0 * 0.05 / 2.0;
    let (t, w) = (col(&r, "time"), col(&r, "J.w"));
    for (t, w) in t.iter().zip(&w) {
        let exact = 10.0 * (-rate * t).exp();
        assert!(
            (w - exact).abs() < 1e-6 * 10.0,
            "t = {t}: {w} against {exact}"
        );
    }
    let (fnorm, s) = (col(&r, "gain.y"), col(&r, "speed.w"));
    for ((f, s), w) in fnorm.iter().zip(&s).zip(&w) {
        assert_eq!(s, w);
        assert!((f - 0.05 * w).abs() < 1e-15 * w.abs().max(1.0));
    }
}

#[test]
fn a_cut_torque_driving_a_brake_is_refused_by_name() {
    let text = SPEED_BRAKE
        .replace(
            r#"["J.flange_a", "speed.flange"],"#,
            r#"["J.flange_a", "speed.flange_b"], ["speed.flange_a", "ground.flange"],"#,
        )
        .replace(r#"["speed.w", "gain.u"]"#, r#"["speed.tau", "gain.u"]"#)
        .replace(
            r#"speed = { type = "SpeedSensor" }"#,
            "speed = { type = \"TorqueSensor\" }\nground = { type = \"Fixed\" }",
        );
    let err = assemble(&ModelSpec::from_toml(&text, ".").unwrap())
        .err()
        .expect("an algebraic loop")
        .to_string();
    assert!(err.contains("brake") && err.contains("speed.tau"), "{err}");
    assert!(
        err.contains("f_normalized") && err.contains("algebraic loop"),
        "{err}"
    );
}

#[test]
fn an_acceleration_driving_a_torque_is_refused_by_name() {
    let text = r#"
format = 1
name = "acc_loop"
connect = [
  ["J.flange_a", "acc.flange"],
  ["acc.a", "gain.u"],
  ["gain.y", "source.tau"],
  ["source.flange", "J.flange_b"],
]
[components]
J = { type = "Inertia", J = 1.0 }
acc = { type = "AccSensor" }
gain = { type = "Gain", k = -0.5 }
source = { type = "Torque" }
"#;
    let err = assemble(&ModelSpec::from_toml(text, ".").unwrap())
        .err()
        .expect("an algebraic loop")
        .to_string();
    assert!(
        err.contains("source") && err.contains("acc.a") && err.contains("'tau'"),
        "{err}"
    );
}

#[test]
fn a_speed_feeding_a_torque_source_is_a_damper() {
    // tau = −d·w through a SpeedSensor and a Gain: w = w0·exp(−d·t/J), as a Damper to ground
    let text = r#"
format = 1
name = "speed_feedback"
connect = [
  ["J.flange_a", "speed.flange"],
  ["speed.w", "gain.u"],
  ["gain.y", "source.tau"],
  ["source.flange", "J.flange_b"],
]
[experiment]
StopTime = 2.0
Interval = 0.01
Tolerance = 1e-9
[components]
J = { type = "Inertia", J = 0.5, w = { start = 3.0, fixed = true } }
speed = { type = "SpeedSensor" }
gain = { type = "Gain", k = -2.0 }
source = { type = "Torque" }
"#;
    let r = run(text);
    for (t, w) in col(&r, "time").iter().zip(col(&r, "J.w")) {
        let exact = 3.0 * (-4.0 * t).exp();
        assert!((w - exact).abs() < 1e-6, "t = {t}: {w} against {exact}");
    }
}

#[test]
fn a_speed_sensor_on_a_shaft_without_inertia_sees_its_algebraic_speed() {
    // J —d1— n —d2— ground, and tau = −k·w_n on n from a SpeedSensor: n has no inertia, so
    // w_n = d1·w_J/(d1 + d2 + k) and J·w_J' = −d1·(d2 + k)/(d1 + d2 + k)·w_J
    let text = r#"
format = 1
name = "massless_feedback"
connect = [
  ["J.flange_b", "d1.flange_a"],
  ["d1.flange_b", "d2.flange_a"],
  ["d2.flange_b", "ground.flange"],
  ["d1.flange_b", "speed.flange"],
  ["speed.w", "gain.u"],
  ["gain.y", "source.tau"],
  ["source.flange", "d1.flange_b"],
]
[experiment]
StopTime = 2.0
Interval = 0.01
Tolerance = 1e-9
[components]
J = { type = "Inertia", J = 1.0, w = { start = 5.0, fixed = true } }
d1 = { type = "Damper", d = 3.0 }
d2 = { type = "Damper", d = 1.0 }
ground = { type = "Fixed" }
speed = { type = "SpeedSensor" }
gain = { type = "Gain", k = -2.0 }
source = { type = "Torque" }
"#;
    let r = run(text);
    let rate = 3.0 * 3.0 / 6.0;
    let (t, w, wn) = (col(&r, "time"), col(&r, "J.w"), col(&r, "speed.w"));
    for ((t, w), wn) in t.iter().zip(&w).zip(&wn) {
        let exact = 5.0 * (-rate * t).exp();
        assert!((w - exact).abs() < 1e-6, "t = {t}: {w} against {exact}");
        assert!(
            (wn - 0.5 * w).abs() < 1e-9,
            "t = {t}: w_n = {wn}, w_J = {w}"
        );
    }
}
