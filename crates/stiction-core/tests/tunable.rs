//! Tunable parameters of a running `Simulation`: a change is an event at that instant (the
//! same as an input's jump), it acts from there exactly as the closed form says, a saved state
//! after it restores bit for bit, and a fixed parameter or a bad value is a typed error that
//! leaves the run usable.

use stiction_core::Simulation;
use stiction_core::{ModelError, ModelSpec, SimError, SimResult};

/// A flywheel (J = 2, w = 100) braked with a constant normal force: fn_max·f_normalized, the
/// force a model input at `f` (so that a force step can also be an input's jump); mu = 0.4
/// at every speed, cgeo = 0.1, no static peak.
fn braked(fn_max: f64, f: f64) -> ModelSpec {
    let text = format!(
        r#"
name = "braked"
connect = [["flywheel.flange_b", "brake.flange_a"]]
inputs = [{{ port = "brake.f_normalized", start = {f:?} }}]

[experiment]
StopTime = 6.0
Interval = 0.01
Tolerance = 1e-8

[components]
flywheel = {{ type = "Inertia", J = 2.0, phi = 0.0, w = 100.0 }}
brake = {{ type = "Brake", fn_max = {fn_max:?}, mu_pos = [[0.0, 0.4]], peak = 1.0, cgeo = 0.1 }}
"#
    );
    ModelSpec::from_toml(&text, ".").expect("the model parses")
}

/// The instant the brake locks the flywheel (its mode becomes Stuck = 0).
fn stop_time(r: &SimResult) -> f64 {
    (r.events.iter())
        .find(|e| e.component == "brake" && e.new_mode == 0 && e.time > 0.0)
        .map(|e| e.time)
        .expect("the flywheel stops")
}

#[test]
fn a_raised_brake_force_stops_the_shaft_when_the_closed_form_says() {
    let mut sim = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    sim.advance_to(2.0).unwrap();
    // decelerating at 0.4·0.1·500/2 = 10 rad/s²
    assert!((sim.get("flywheel.w").unwrap() - 80.0).abs() < 1e-9);
    sim.set_parameter("brake.fn_max", 2000.0).unwrap();
    assert_eq!(sim.time(), 2.0);
    sim.run().unwrap();
    let r = sim.into_result();
    // from 80 rad/s at 40 rad/s²: at rest 2 s later
    assert!((stop_time(&r) - 4.0).abs() < 1e-9, "{}", stop_time(&r));
    assert_eq!(r.stats.input_events, 1);
    let change = (r.events.iter())
        .find(|e| e.cause.starts_with("parameter brake.fn_max set to 2000"))
        .map(|e| e.time);
    assert_eq!(
        change, None,
        "the brake keeps sliding: no mode change at the event"
    );
    // both sides of the instant are recorded, each with its own parameters
    let (t, fnorm) = (r.column("time").unwrap(), r.column("brake.fn").unwrap());
    let k = t.iter().position(|&u| u == 2.0).unwrap();
    assert_eq!(t[k + 1], 2.0);
    assert_eq!((fnorm[k], fnorm[k + 1]), (500.0, 2000.0));
    assert_eq!(fnorm[0], 500.0);
}

#[test]
fn a_parameter_change_is_the_same_event_as_an_input_jump_bit_for_bit() {
    // fn_max 500 → 2000 at f = 1, against fn_max = 2000 with f 0.25 → 1: the same normal
    // force, exactly, before and after
    let mut tuned = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    let mut input = Simulation::from_spec(&braked(2000.0, 0.25)).unwrap();
    for t in [0.37, 1.234, 2.5] {
        tuned.advance_to(t).unwrap();
        input.advance_to(t).unwrap();
    }
    tuned.set_parameter("brake.fn_max", 2000.0).unwrap();
    input.set_input("brake.f_normalized", 1.0).unwrap();
    tuned.run().unwrap();
    input.run().unwrap();
    let (a, b) = (tuned.into_result(), input.into_result());
    assert_eq!(a.rows(), b.rows());
    for name in [
        "time",
        "flywheel.w",
        "flywheel.phi",
        "brake.tau",
        "brake.mode",
    ] {
        let (x, y) = (a.column(name).unwrap(), b.column(name).unwrap());
        let same = x.iter().zip(&y).all(|(u, v)| u.to_bits() == v.to_bits());
        assert!(same, "{name} differs");
    }
    assert_eq!(stop_time(&a), stop_time(&b));
}

#[test]
fn a_change_equals_a_force_that_steps_at_that_time() {
    // the same brake with its force from a Step at 2 s (a time event): the same stop
    let step = r#"
name = "stepped"
connect = [["flywheel.flange_b", "brake.flange_a"], ["press.y", "brake.f_normalized"]]

[experiment]
StopTime = 6.0
Interval = 0.01
Tolerance = 1e-8

[components]
flywheel = { type = "Inertia", J = 2.0, phi = 0.0, w = 100.0 }
brake = { type = "Brake", fn_max = 2000.0, mu_pos = [[0.0, 0.4]], peak = 1.0, cgeo = 0.1 }
press = { type = "Step", offset = 0.25, height = 0.75, startTime = 2.0 }
"#;
    let reference = stiction_core::simulate(&ModelSpec::from_toml(step, ".").unwrap()).unwrap();
    let mut sim = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    sim.advance_to(2.0).unwrap();
    sim.set_parameter("brake.fn_max", 2000.0).unwrap();
    sim.run().unwrap();
    let r = sim.into_result();
    assert!((stop_time(&r) - stop_time(&reference)).abs() < 1e-9);
    let (w, w_ref) = (
        r.column("flywheel.w").unwrap(),
        reference.column("flywheel.w").unwrap(),
    );
    let (t, t_ref) = (r.column("time").unwrap(), reference.column("time").unwrap());
    let mut compared = 0;
    for (k, u) in t_ref.iter().enumerate() {
        if let Some(j) = t.iter().position(|v| v == u) {
            assert!(
                (w[j] - w_ref[k]).abs() < 1e-8,
                "at {u}: {} vs {}",
                w[j],
                w_ref[k]
            );
            compared += 1;
        }
    }
    assert!(compared > 500, "{compared}");
}

#[test]
fn a_state_saved_after_a_change_restores_bit_for_bit() {
    let mut sim = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    sim.advance_to(1.0).unwrap();
    sim.set_parameter("brake.fn_max", 900.0).unwrap();
    sim.advance_to(1.5).unwrap();
    sim.set_input("brake.f_normalized", 0.5).unwrap();
    sim.advance_to(2.25).unwrap();
    sim.set_parameters(&[("brake.fn_max", 3000.0.into()), ("brake.cgeo", 0.2.into())])
        .unwrap();
    sim.advance_to(2.5).unwrap();
    let saved = sim.state().unwrap();
    assert_eq!(saved.parameters.len(), 2);
    sim.advance_to(3.0).unwrap();
    let later = sim.values().unwrap();
    // in a fresh run of the model (its parameters as at the start), and after a reset
    let mut other = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    other.set_state(&saved).unwrap();
    other.advance_to(3.0).unwrap();
    sim.reset().unwrap();
    sim.set_state(&saved).unwrap();
    sim.advance_to(3.0).unwrap();
    for again in [other.values().unwrap(), sim.values().unwrap()] {
        let same = later
            .iter()
            .zip(&again)
            .all(|(u, v)| u.to_bits() == v.to_bits());
        assert!(same, "{later:?} vs {again:?}");
    }
}

#[test]
fn fixed_parameters_and_bad_values_are_refused_by_name() {
    let spec = braked(500.0, 1.0);
    let mut sim = Simulation::from_spec(&spec).unwrap();
    sim.advance_to(1.0).unwrap();
    let w = sim.get("flywheel.w").unwrap();
    let refused = |e: SimError, parameter: &str| match e {
        SimError::Model(ModelError::Parameter {
            component,
            parameter: p,
            ..
        }) => assert_eq!(format!("{component}.{p}"), parameter),
        other => panic!("{parameter}: {other:?}"),
    };
    // a start value, a Boolean that changes the ports, a value out of range
    refused(
        sim.set_parameter("flywheel.w", 3.0).unwrap_err(),
        "flywheel.w",
    );
    let e = sim.set_parameters(&[("brake.useHeatPort", true.into())]);
    refused(e.unwrap_err(), "brake.useHeatPort");
    refused(
        sim.set_parameter("brake.peak", 0.5).unwrap_err(),
        "brake.peak",
    );
    refused(
        sim.set_parameter("brake.nope", 1.0).unwrap_err(),
        "brake.nope",
    );
    // an inertia that vanishes makes the shaft's speed algebraic: refused
    refused(
        sim.set_parameter("flywheel.J", 0.0).unwrap_err(),
        "flywheel.J",
    );
    let e = sim.set_parameter("StopTime", 3.0).unwrap_err();
    assert!(matches!(e, SimError::Model(ModelError::File(_))), "{e:?}");
    // nothing changed: the run goes on as if no call had been made
    assert_eq!(sim.get("flywheel.w").unwrap(), w);
    assert!(sim.parameter_changes().is_empty());
    sim.run().unwrap();
    assert!((sim.get("flywheel.w").unwrap() - 40.0).abs() < 1e-9);
}

#[test]
fn a_new_inertia_refactors_the_mode_and_acts_from_then_on() {
    let mut sim = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    sim.advance_to(1.0).unwrap(); // w = 90
    sim.set_parameter("flywheel.J", 4.0).unwrap(); // 5 rad/s² from now: at rest 18 s later
    sim.advance_to(3.0).unwrap();
    assert!((sim.get("flywheel.w").unwrap() - 80.0).abs() < 1e-9);
    // a gear ratio is fixed: the angles it ties are positions the run has reached
    let gear = r#"
name = "geared"
connect = [["a.flange_b", "gear.flange_a"], ["gear.flange_b", "b.flange_a"]]
[components]
a = { type = "Inertia", J = 1.0, w = 1.0 }
gear = { type = "IdealGear", ratio = 2.0 }
b = { type = "Inertia", J = 1.0 }
"#;
    let mut geared = Simulation::from_spec(&ModelSpec::from_toml(gear, ".").unwrap()).unwrap();
    geared.advance_to(0.1).unwrap();
    let e = geared.set_parameter("gear.ratio", 3.0).unwrap_err();
    assert!(e.to_string().contains("'ratio'"), "{e}");
    assert!(e.to_string().contains("fixed"), "{e}");
}

#[test]
fn recorded_rows_keep_their_parameters_across_a_restore() {
    let mut sim = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    sim.advance_to(1.0).unwrap();
    let saved = sim.state().unwrap(); // before any change
    sim.set_parameter("brake.fn_max", 2000.0).unwrap();
    sim.advance_to(2.0).unwrap();
    sim.set_state(&saved).unwrap(); // fn_max is 500 again from 1 s
    sim.advance_to(3.0).unwrap();
    assert_eq!(sim.get("brake.fn").unwrap(), 500.0);
    let r = sim.into_result();
    let (t, fnorm) = (r.column("time").unwrap(), r.column("brake.fn").unwrap());
    // rows to 2 s as they were recorded (500, then 2000 from 1 s), then the restored run's
    let at = |time: f64, after: usize| (after..t.len()).find(|&k| t[k] == time).unwrap();
    let first = at(1.5, 0);
    assert_eq!((fnorm[0], fnorm[first]), (500.0, 2000.0));
    let again = at(1.5, first + 1);
    assert_eq!((fnorm[again], fnorm[t.len() - 1]), (500.0, 500.0));
}

/// A spring (c = 100) in series with a damper to ground, the shaft between them without
/// inertia: its speed is algebraic, c(φ1 − φn)/d, so the factorization depends on d.
const SERIES: &str = r#"
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

/// (φ1, w1, φn) at `t_end` of J·w1' = −c(φ1 − φn), d·φn' = c(φ1 − φn) (J = 1, c = 100),
/// d = 25 until `t1`, then `d2`; classical Runge–Kutta at 1e-5 s.
fn series_reference(t1: f64, d2: f64, t_end: f64) -> [f64; 3] {
    let f = |y: [f64; 3], d: f64| [y[1], -100.0 * (y[0] - y[2]), 100.0 / d * (y[0] - y[2])];
    let (mut y, h) = ([0.0, 1.0, 0.0], 1e-5);
    for k in 0..(t_end / h).round() as usize {
        let d = if (k as f64) < (t1 / h).round() {
            25.0
        } else {
            d2
        };
        let k1 = f(y, d);
        let k2 = f(std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]), d);
        let k3 = f(std::array::from_fn(|i| y[i] + 0.5 * h * k2[i]), d);
        let k4 = f(std::array::from_fn(|i| y[i] + h * k3[i]), d);
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    y
}

#[test]
fn a_new_damping_on_a_shaft_without_inertia_takes_its_algebraic_speed_anew() {
    let mut sim = Simulation::from_spec(&ModelSpec::from_toml(SERIES, ".").unwrap()).unwrap();
    sim.advance_to(0.2).unwrap();
    sim.set_parameter("damper.d", 50.0).unwrap();
    // right after the change the damper's speed is the new algebraic one, c(φ1 − φn)/d
    let [phi1, _, phin] = series_reference(0.2, 50.0, 0.2);
    let w_rel = sim.get("damper.w_rel").unwrap();
    assert!((w_rel + 2.0 * (phi1 - phin)).abs() < 1e-8, "{w_rel}");
    sim.run().unwrap();
    let [_, w1, phin] = series_reference(0.2, 50.0, 0.5);
    assert!((sim.get("J1.w").unwrap() - w1).abs() < 1e-8);
    assert!((sim.get("damper.phi_rel").unwrap() + phin).abs() < 1e-8);
}

#[test]
fn a_sine_source_takes_a_new_amplitude_and_frequency() {
    // J = 1 driven by 2·sin(2π·1·t) until 0.3 s, then 5·sin(2π·4·t): w from the integrals
    let text = r#"
name = "driven"
connect = [["sine.y", "torque.tau"], ["torque.flange", "J.flange_a"]]
[experiment]
StopTime = 1.0
Tolerance = 1e-10
[components]
J = { type = "Inertia", J = 1.0, phi = 0.0, w = 0.0 }
torque = { type = "Torque" }
sine = { type = "Sine", amplitude = 2.0, f = 1.0 }
"#;
    let mut sim = Simulation::from_spec(&ModelSpec::from_toml(text, ".").unwrap()).unwrap();
    sim.advance_to(0.3).unwrap();
    let changes = [("sine.amplitude", 5.0.into()), ("sine.f", 4.0.into())];
    sim.set_parameters(&changes).unwrap();
    sim.run().unwrap();
    let tau = std::f64::consts::TAU;
    let cos = |f: f64, t: f64| (tau * f * t).cos();
    let w1 = 2.0 / tau * (1.0 - cos(1.0, 0.3));
    let w = w1 + 5.0 / (tau * 4.0) * (cos(4.0, 0.3) - cos(4.0, 1.0));
    assert!(
        (sim.get("J.w").unwrap() - w).abs() < 1e-7,
        "{}",
        sim.get("J.w").unwrap()
    );
}

#[test]
fn a_lowered_brake_force_releases_a_held_shaft_at_that_instant() {
    // 10 N·m against a brake that holds up to 0.4·0.1·1000 = 40 N·m; from 1 s it holds 4
    let text = r#"
name = "held"
connect = [["drive.flange", "flywheel.flange_a"], ["flywheel.flange_b", "brake.flange_a"],
           ["press.y", "brake.f_normalized"]]
[experiment]
StopTime = 2.0
Tolerance = 1e-10
[components]
flywheel = { type = "Inertia", J = 2.0, phi = 0.0, w = 0.0 }
drive = { type = "ConstantTorque", tau_constant = 10.0 }
brake = { type = "Brake", fn_max = 1000.0, mu_pos = [[0.0, 0.4]], peak = 1.0, cgeo = 0.1 }
press = { type = "Constant", k = 1.0 }
"#;
    let mut sim = Simulation::from_spec(&ModelSpec::from_toml(text, ".").unwrap()).unwrap();
    sim.advance_to(1.0).unwrap();
    assert_eq!(sim.get("flywheel.w").unwrap(), 0.0);
    sim.set_parameter("brake.fn_max", 100.0).unwrap();
    sim.run().unwrap();
    // sliding from 1 s at (10 − 4)/2 = 3 rad/s²
    assert!((sim.get("flywheel.w").unwrap() - 3.0).abs() < 1e-9);
    let r = sim.into_result();
    // MSL's startForward is set at the change (the brake no longer locks); its mode becomes
    // Forward as soon as the speed leaves zero
    let release = (r.events.iter()).find(|e| e.component == "brake" && e.time > 0.0);
    let release = release.expect("the brake lets go");
    assert!(
        release.time >= 1.0 && release.time - 1.0 < 1e-9,
        "{release:?}"
    );
    let (t, a) = (r.column("time").unwrap(), r.column("flywheel.a").unwrap());
    let k = t.iter().position(|&u| u == 1.0).unwrap();
    assert_eq!((t[k + 1], a[k]), (1.0, 0.0), "left and right rows");
    assert!((a[k + 1] - 3.0).abs() < 1e-12, "{}", a[k + 1]);
}

#[test]
fn every_variable_of_a_row_is_computed_with_the_parameters_of_its_time() {
    let mut sim = Simulation::from_spec(&braked(500.0, 1.0)).unwrap();
    sim.advance_to(1.0).unwrap(); // w = 90 at 10 rad/s²
    sim.set_parameter("flywheel.J", 4.0).unwrap(); // 5 rad/s² from now
    sim.advance_to(3.0).unwrap();
    let r = sim.into_result();
    let t = r.column("time").unwrap();
    let energy = r.column("system.kineticEnergy").unwrap();
    let accel = r.column("flywheel.a").unwrap();
    let at = |time: f64| t.iter().position(|&x| (x - time).abs() < 1e-12).unwrap();
    // ½·J·w² with the J of each row's time, however the table is filled (blocks of rows)
    let (before, after) = (at(0.5), at(2.0));
    assert!(
        (energy[before] - 0.5 * 2.0 * 95.0 * 95.0).abs() < 1e-6,
        "{}",
        energy[before]
    );
    assert!(
        (energy[after] - 0.5 * 4.0 * 85.0 * 85.0).abs() < 1e-6,
        "{}",
        energy[after]
    );
    assert!((accel[before] + 10.0).abs() < 1e-9 && (accel[after] + 5.0).abs() < 1e-9);
}

#[test]
fn flange_torques_of_a_row_split_the_drive_by_the_inertias_of_its_time() {
    let geared = r#"
name = "geared"
connect = [["drive.flange", "a.flange_a"], ["a.flange_b", "gear.flange_a"], ["gear.flange_b", "b.flange_a"]]
[experiment]
StopTime = 2.0
Interval = 0.01
[components]
drive = { type = "ConstantTorque", tau_constant = 2.0 }
a = { type = "Inertia", J = 1.0 }
gear = { type = "IdealGear", ratio = 1.0 }
b = { type = "Inertia", J = 1.0 }
"#;
    let mut sim = Simulation::from_spec(&ModelSpec::from_toml(geared, ".").unwrap()).unwrap();
    sim.advance_to(1.0).unwrap();
    sim.set_parameter("b.J", 3.0).unwrap();
    sim.advance_to(2.0).unwrap();
    let r = sim.into_result();
    let (t, cut) = (
        r.column("time").unwrap(),
        r.column("b.flange_a.tau").unwrap(),
    );
    let at = |time: f64| t.iter().position(|&x| (x - time).abs() < 1e-12).unwrap();
    // the gear passes J_b/(J_a + J_b) of the drive's 2 N·m: 1 N·m, then 1.5 N·m
    assert!((cut[at(0.5)] - 1.0).abs() < 1e-12, "{}", cut[at(0.5)]);
    assert!((cut[at(1.5)] - 1.5).abs() < 1e-12, "{}", cut[at(1.5)]);
}
