//! The translational domain on the one engine (issue 31): a wheel rolling a mass accelerates and
//! stops at the closed forms, the energy audit counts ½·m·v², the speed-dependent forces are the
//! rotational laws acting on a force, and joining the domains wrongly is refused by name.

use stiction_core::{simulate, ModelSpec, SimResult};

/// An inertia J driving a rolling wheel of radius R that pushes a mass m.
fn wheel_model(drive: &str, extra: &str) -> String {
    format!(
        r#"
name = "wheel"
connect = [
  ["drive.flange", "hub.flange_a"],
  ["hub.flange_b", "wheel.flangeR"],
  ["wheel.flangeT", "car.flange_a"],
  {extra}
]

[experiment]
StopTime = 2.0
Interval = 0.01
Tolerance = 1e-10

[components]
hub = {{ type = "Inertia", J = 0.8, phi = 0.0, w = {{ start = 0.0, fixed = true }} }}
wheel = {{ type = "IdealRollingWheel", radius = 0.3 }}
car = {{ type = "Translational.Mass", m = 25.0 }}
{drive}
"#
    )
}

fn run(text: &str) -> SimResult {
    simulate(&ModelSpec::from_toml(text, ".").unwrap()).unwrap()
}

fn last(r: &SimResult, name: &str) -> f64 {
    *r.column(name).unwrap().last().unwrap()
}

const J: f64 = 0.8;
const R: f64 = 0.3;
const M: f64 = 25.0;

#[test]
fn a_constant_torque_accelerates_wheel_and_mass_at_the_closed_form() {
    let r = run(&wheel_model(
        r#"drive = { type = "ConstantTorque", tau_constant = 12.0 }"#,
        "",
    ));
    let a = 12.0 * R / (J + M * R * R);
    for (name, expected) in [
        ("car.a", a),
        ("car.v", a * 2.0),
        ("car.s", a * 2.0),
        ("hub.a", a / R),
        ("hub.w", a * 2.0 / R),
    ] {
        let got = last(&r, name);
        let want = if name == "car.s" {
            0.5 * a * 4.0
        } else {
            expected
        };
        assert!(
            (got - want).abs() < 1e-8 * want.abs(),
            "{name}: {got} vs {want}"
        );
    }
    // the flanges report s and f: the wheel pushes the mass with f = m·a, the mass's flange
    // takes it (flangeT.f = −car.flange_a.f), and the torque balance holds through the radius
    let f = last(&r, "car.flange_a.f");
    assert!((f - M * a).abs() < 1e-8 * M * a, "{f}");
    assert!((last(&r, "wheel.flangeT.f") + f).abs() < 1e-9);
    let tau_r = last(&r, "wheel.flangeR.tau");
    assert!((tau_r + R * last(&r, "wheel.flangeT.f")).abs() < 1e-9);
    assert_eq!(last(&r, "car.flange_b.s"), last(&r, "car.s"));
    // energy: ½·J·w² + ½·m·v² is the work of the torque; no element loses any
    let (w, v) = (last(&r, "hub.w"), last(&r, "car.v"));
    let kinetic = 0.5 * J * w * w + 0.5 * M * v * v;
    assert!((last(&r, "system.kineticEnergy") - kinetic).abs() < 1e-9 * kinetic);
    assert!((last(&r, "system.sourceWork") - kinetic).abs() < 1e-7 * kinetic);
    for a in r.audit() {
        assert!(
            a.residual < 1e-9 * a.scale.max(1.0),
            "{}: {}",
            a.component,
            a.residual
        );
    }
}

#[test]
fn a_braked_rolling_wheel_stops_at_the_closed_form() {
    // the brake on the hub: tau = mu·fn_max·f_normalized = 0.5·40 = 20 N.m, the car at 3 m/s
    let text = wheel_model(
        r#"drive = { type = "Brake", fn_max = 40.0, mu_pos = [[0.0, 0.5]] }
press = { type = "Constant", k = 1.0 }"#,
        r#"["press.y", "drive.f_normalized"],"#,
    )
    .replace(
        "w = { start = 0.0, fixed = true }",
        "w = { start = 10.0, fixed = true }",
    )
    .replace("drive.flange\"", "drive.flange_a\"");
    let r = run(&text);
    let decel = 20.0 * R / (J + M * R * R);
    let v0 = 10.0 * R;
    let t_stop = v0 / decel;
    let (t, v) = (r.column("time").unwrap(), r.column("car.v").unwrap());
    // decelerating at the closed form before the stop, held after it
    for (t, v) in t.iter().zip(&v) {
        let want = (v0 - decel * t).max(0.0);
        assert!(
            (v - want).abs() < 1e-8,
            "t = {t}: v = {v}, closed form {want}"
        );
    }
    let stopped = t
        .iter()
        .zip(r.column("drive.locked").unwrap())
        .find(|(_, l)| *l > 0.5);
    let t_locked = *stopped.expect("the brake locks").0;
    assert!((t_locked - t_stop).abs() < 1e-8, "{t_locked} vs {t_stop}");
    let distance = v0 * v0 / (2.0 * decel);
    assert!(
        (last(&r, "car.s") - distance).abs() < 1e-8,
        "{}",
        last(&r, "car.s")
    );
}

#[test]
fn the_speed_dependent_forces_are_the_rotational_laws_acting_on_a_force() {
    // a linear drag f = f_nominal·v/v_nominal on a mass: v = v0·exp(−k·t/m), k = 4 N/(m/s)
    let text = r#"
name = "drag"
connect = [["drag.flange", "car.flange_b"]]
[experiment]
StopTime = 3.0
Interval = 0.01
Tolerance = 1e-10
[components]
car = { type = "Translational.Mass", m = 2.0, v = { start = 5.0, fixed = true } }
drag = { type = "Translational.LinearSpeedDependentForce", f_nominal = -8.0, v_nominal = 2.0, ForceDirection = false }
"#;
    let r = run(text);
    let (t, v) = (r.column("time").unwrap(), r.column("car.v").unwrap());
    for (t, v) in t.iter().zip(&v) {
        let want = 5.0 * (-4.0 * t / 2.0).exp();
        assert!((v - want).abs() < 1e-7, "t = {t}: {v} vs {want}");
    }
    // MSL's PartialForce.f = flange.f: the drag's reaction, opposite to the force on the mass
    let f = last(&r, "drag.f");
    assert!((f - 4.0 * last(&r, "car.v")).abs() < 1e-9, "{f}");
    // the work of the drag is what the mass lost
    let lost = 0.5 * 2.0 * (25.0 - last(&r, "car.v").powi(2));
    assert!((last(&r, "system.sourceWork") + lost).abs() < 1e-6 * lost);
}

#[test]
fn force_input_and_constant_force_push_with_msl_signs() {
    let text = r#"
name = "push"
connect = [
  ["k.y", "push.f"],
  ["push.flange", "car.flange_a"],
  ["load.flange", "car.flange_b"],
  ["push.support", "ground.flange"],
]
[experiment]
StopTime = 1.0
Interval = 0.1
[components]
k = { type = "Constant", k = 7.0 }
push = { type = "Translational.Force", useSupport = true }
ground = { type = "Translational.Fixed", s0 = 0.0 }
load = { type = "Translational.ConstantForce", f_constant = -3.0 }
car = { type = "Translational.Mass", m = 2.0 }
"#;
    let r = run(text);
    assert!((last(&r, "car.a") - 2.0).abs() < 1e-12);
    assert_eq!(last(&r, "push.f"), 7.0); // the input: the accelerating force
    assert_eq!(last(&r, "load.f"), 3.0); // MSL: f = flange.f = −f_constant
    assert_eq!(last(&r, "push.support.f"), 7.0);
    assert_eq!(last(&r, "ground.flange.s"), 0.0);
}

#[test]
fn ideal_gear_r2t_transmits_at_its_ratio() {
    // phi = ratio·s: s'' = ratio·T/(m + J·ratio²)
    let text = wheel_model(
        r#"drive = { type = "ConstantTorque", tau_constant = 12.0 }"#,
        "",
    )
    .replace(
        r#"{ type = "IdealRollingWheel", radius = 0.3 }"#,
        r#"{ type = "IdealGearR2T", ratio = 20.0 }"#,
    );
    let r = run(&text);
    let a = 20.0 * 12.0 / (M + J * 400.0);
    assert!((last(&r, "car.a") - a).abs() < 1e-9 * a);
    assert!((last(&r, "hub.phi") - 20.0 * last(&r, "car.s")).abs() < 1e-9);
}

fn refused(text: &str) -> String {
    let spec = ModelSpec::from_toml(text, ".");
    match spec {
        Err(e) => e.to_string(),
        Ok(spec) => match simulate(&spec) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("not refused: {text}"),
        },
    }
}

#[test]
fn joining_a_rotational_to_a_translational_flange_is_refused_by_name() {
    let text = wheel_model(
        r#"drive = { type = "ConstantTorque", tau_constant = 12.0 }"#,
        r#"["hub.flange_b", "car.flange_b"],"#,
    );
    let msg = refused(&text);
    for part in [
        "rotational flange 'hub.flange_b'",
        "translational flange 'car.flange_b'",
        "IdealRollingWheel",
        "IdealGearR2T",
    ] {
        assert!(msg.contains(part), "{msg}");
    }
}

#[test]
fn bad_parameters_are_refused_by_name() {
    let base = wheel_model(
        r#"drive = { type = "ConstantTorque", tau_constant = 12.0 }"#,
        "",
    );
    for (from, to, words) in [
        ("m = 25.0", "m = 0.0", ["car", "'m'", "> 0"]),
        (
            "radius = 0.3",
            "radius = -0.3",
            ["wheel", "'radius'", "> 0"],
        ),
    ] {
        let msg = refused(&base.replace(from, to));
        for w in words {
            assert!(msg.contains(w), "{to}: {msg}");
        }
    }
}

#[test]
fn a_mass_of_length_l_has_its_flanges_l_apart_around_its_center() {
    // wheel → car (L = 2) → trailer (L = 4): positions add up along the rigid chain
    let text = wheel_model(
        r#"drive = { type = "ConstantTorque", tau_constant = 12.0 }
trailer = { type = "Translational.Mass", m = 5.0, L = 4.0 }"#,
        r#"["car.flange_b", "trailer.flange_a"],"#,
    )
    .replace("m = 25.0 }", "m = 25.0, L = 2.0 }");
    let r = run(&text);
    let s_t = last(&r, "wheel.flangeT.s");
    assert!(s_t > 0.1);
    assert!((last(&r, "car.s") - (s_t + 1.0)).abs() < 1e-12);
    assert!((last(&r, "car.flange_b.s") - (s_t + 2.0)).abs() < 1e-12);
    assert!((last(&r, "trailer.s") - (s_t + 4.0)).abs() < 1e-12);
    assert!((last(&r, "trailer.flange_b.s") - (s_t + 6.0)).abs() < 1e-12);
    // one node: both masses accelerate together, at the wheel's closed form with m = 30
    let a = 12.0 * R / (J + 30.0 * R * R);
    assert!((last(&r, "trailer.a") - a).abs() < 1e-9 * a);
    // the wheel's row is on absolute positions (MSL: flangeR.phi·radius = flangeT.s): a car
    // started with its center at 5 puts flangeT at 4 and the hub at 4/R
    let started = run(&text
        .replace("L = 2.0 }", "L = 2.0, s = { start = 5.0, fixed = true } }")
        .replace("phi = 0.0,", ""));
    let phi0 = started.column("hub.phi").unwrap()[0];
    assert!((phi0 - 4.0 / R).abs() < 1e-12, "{phi0}");
}

#[test]
fn fixed_positions_and_lengths_must_agree() {
    let held = |s_b: f64| {
        format!(
            r#"
name = "held"
connect = [["a.flange", "car.flange_a"], ["car.flange_b", "b.flange"]]
[experiment]
StopTime = 1.0
[components]
a = {{ type = "Translational.Fixed", s0 = 0.5 }}
car = {{ type = "Translational.Mass", m = 1.0, L = 1.5 }}
b = {{ type = "Translational.Fixed", s0 = {s_b} }}
"#
        )
    };
    let r = run(&held(2.0));
    assert_eq!(last(&r, "car.s"), 1.25);
    let msg = refused(&held(2.5));
    assert!(
        msg.contains("'s0'") && msg.contains("different position 2"),
        "{msg}"
    );
    // both flanges of a mass of length 1.5 on one rigid set: a loop that does not close
    let looped = held(2.0).replace(
        r#"["car.flange_b", "b.flange"]"#,
        r#"["car.flange_b", "a.flange"]"#,
    );
    let msg = refused(&looped);
    assert!(msg.contains("car") && msg.contains("1.5 apart"), "{msg}");
}

#[test]
fn a_held_mass_reports_each_flange_at_its_own_position() {
    let text = r#"
name = "held"
connect = [["a.flange", "car.flange_a"]]
[experiment]
StopTime = 1.0
[components]
a = { type = "Translational.Fixed", s0 = 0.5 }
car = { type = "Translational.Mass", m = 1.0, L = 1.5 }
"#;
    let r = run(text);
    assert_eq!(last(&r, "car.flange_a.s"), 0.5);
    assert_eq!(last(&r, "car.s"), 1.25);
    assert_eq!(last(&r, "car.flange_b.s"), 2.0);
}

#[test]
fn a_start_speed_is_the_speed_whatever_the_flanges_offsets() {
    // the car's center is L/2 beyond its flange, the wheel's row has that constant: neither
    // is a speed (the start speed 3 m/s is the car's and the hub's 3/R)
    let text = wheel_model(
        r#"drive = { type = "ConstantTorque", tau_constant = 0.0 }"#,
        "",
    )
    .replace(
        "m = 25.0 }",
        "m = 25.0, L = 2.0, v = { start = 3.0, fixed = true } }",
    )
    .replace(
        "w = { start = 0.0, fixed = true }",
        "w = { start = 1.0, fixed = false }",
    );
    let r = run(&text);
    assert!((r.column("car.v").unwrap()[0] - 3.0).abs() < 1e-12);
    assert!((last(&r, "hub.w") - 3.0 / R).abs() < 1e-9);
}
