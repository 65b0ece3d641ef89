//! The translational sources, sensors and vehicle (issue 31) on the rotational implementations:
//! MSL's Translational Vehicle and EddyCurrentBrake examples in the MAP-LIB tube, and closed
//! forms for each prescribed motion, each sensor on a mass under a constant force, a vehicle
//! held on a grade, a coasting vehicle, and the eddy current brake's energy balance.

use std::path::{Path, PathBuf};

use stiction_core::{compare, read_signal_list, Reference};
use stiction_core::{simulate, ModelSpec, SimResult};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn example(name: &str) -> SimResult {
    let dir = repo().join("examples/msl-translational");
    let text = std::fs::read_to_string(dir.join(format!("{name}.toml"))).unwrap();
    simulate(&ModelSpec::from_toml(&text, dir).unwrap()).unwrap()
}

fn model(components: &str, connect: &str, stop: f64) -> String {
    format!(
        "name = \"t\"\nconnect = [{connect}]\n\n[experiment]\nStopTime = {stop}\nInterval = 0.01\n\
         Tolerance = 1e-10\n\n[components]\n{components}\n"
    )
}

fn run(text: &str) -> SimResult {
    simulate(&ModelSpec::from_toml(text, ".").unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

fn col(r: &SimResult, name: &str) -> Vec<f64> {
    r.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn last(r: &SimResult, name: &str) -> f64 {
    *col(r, name).last().unwrap()
}

/// Every listed signal in the 2e-3 tube, and 1 % of its range off fails it.
fn in_the_tube(name: &str) {
    let data = repo().join("tests/data/msl-translational");
    let reference = Reference::read(data.join(format!("{name}.csv"))).unwrap();
    let listed = read_signal_list(data.join(format!("{name}.signals.txt"))).unwrap();
    let result = example(name);
    let report = compare(&result, &reference, &listed, 2e-3).unwrap();
    assert_eq!(report.len(), listed.len());
    assert!(report.iter().all(|s| s.passed), "{name}: {report:#?}");
    for signal in &listed {
        let mut off = reference.clone();
        let i = off.names.iter().position(|n| n == signal).unwrap();
        let (lo, hi) = off.columns[i]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        off.columns[i]
            .iter_mut()
            .for_each(|v| *v += 0.01 * (hi - lo));
        let report = compare(&result, &off, &listed, 2e-3).unwrap();
        assert!(!report.iter().find(|s| &s.name == signal).unwrap().passed);
    }
}

#[test]
fn vehicle_example_stays_in_the_msl_tube() {
    in_the_tube("Vehicle");
}

#[test]
fn eddy_current_brake_example_stays_in_the_msl_tube() {
    in_the_tube("EddyCurrentBrake");
}

#[test]
fn eddy_current_force_turns_the_kinetic_energy_into_heat() {
    // adiabatic capacitor C = 1 J/K: C·(T − T0) = ½·m·(v0² − v²) at every point
    let r = example("EddyCurrentBrake");
    let (t, v) = (col(&r, "heatCapacitor.T"), col(&r, "mass.v"));
    for (t, v) in t.iter().zip(&v) {
        let kinetic = 0.5 * (20.0f64.powi(2) - v * v);
        assert!((t - 293.15 - kinetic).abs() < 1e-5 * 200.0, "{t} {v}");
    }
    assert!(t.last().unwrap() - 293.15 > 199.0);
}

const MASS: &str = r#"mass = { type = "Translational.Mass", m = 3.0 }"#;

#[test]
fn speed_exact_on_a_ramp_pushes_with_m_times_the_slope() {
    let c = format!(
        "{MASS}\nsource = {{ type = \"Translational.Speed\", exact = true }}\n\
         ramp = {{ type = \"Ramp\", height = 2.0, duration = 1.0, startTime = 0.0 }}"
    );
    let conn = r#"["ramp.y", "source.v_ref"], ["source.flange", "mass.flange_a"]"#;
    let r = run(&model(&c, conn, 0.5));
    assert!((last(&r, "mass.v") - 1.0).abs() < 1e-9);
    assert!((last(&r, "mass.s") - 0.25).abs() < 1e-9);
    // the mass takes m·slope = 6 N at its flange, the source the opposite
    assert!((last(&r, "mass.flange_a.f") - 6.0).abs() < 1e-8);
    assert!((last(&r, "source.flange.f") + 6.0).abs() < 1e-8);
    assert!((last(&r, "source.v") - 1.0).abs() < 1e-9);
}

#[test]
fn position_filter_follows_its_critically_damped_step_response() {
    // MSL: a = ((s_ref − s)·w_crit − af·v)·w_crit/bf, af = 1.3617, bf = 0.6180
    let c = format!(
        "{MASS}\nsource = {{ type = \"Translational.Position\", f_crit = 2.0 }}\n\
         step = {{ type = \"Step\", height = 0.1, offset = 0.0, startTime = 0.0 }}"
    );
    let conn = r#"["step.y", "source.s_ref"], ["source.flange", "mass.flange_a"]"#;
    let r = run(&model(&c, conn, 0.6));
    let w = 2.0 * std::f64::consts::PI * 2.0;
    let f = |s: f64, v: f64| ((0.1 - s) * w - 1.3617 * v) * w / 0.6180;
    let (mut s, mut v, h) = (0.1, 0.0, 1e-5); // the filter starts at s_ref (MSL's s start)
    let (t, got) = (col(&r, "time"), col(&r, "mass.s"));
    let mut k = 0;
    for (i, &ti) in t.iter().enumerate() {
        while (k as f64) * h < ti - 1e-12 {
            // RK4 on (s, v)
            let (k1s, k1v) = (v, f(s, v));
            let (k2s, k2v) = (v + h / 2.0 * k1v, f(s + h / 2.0 * k1s, v + h / 2.0 * k1v));
            let (k3s, k3v) = (v + h / 2.0 * k2v, f(s + h / 2.0 * k2s, v + h / 2.0 * k2v));
            let (k4s, k4v) = (v + h * k3v, f(s + h * k3s, v + h * k3v));
            s += h / 6.0 * (k1s + 2.0 * k2s + 2.0 * k3s + k4s);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            k += 1;
        }
        assert!((got[i] - s).abs() < 1e-7, "t = {ti}: {} vs {s}", got[i]);
    }
}

#[test]
fn accelerate_and_move_prescribe_the_motion_they_are_given() {
    let c = format!(
        "{MASS}\nsource = {{ type = \"Translational.Accelerate\" }}\n\
         a = {{ type = \"Constant\", k = 1.5 }}"
    );
    let conn = r#"["a.y", "source.a_ref"], ["source.flange", "mass.flange_a"]"#;
    let r = run(&model(&c, conn, 2.0));
    assert!((last(&r, "mass.s") - 3.0).abs() < 1e-9 && (last(&r, "mass.v") - 3.0).abs() < 1e-9);
    assert!((last(&r, "source.flange.f") + 4.5).abs() < 1e-8);
    // Move: s = sin(t), v = cos(t), a = −sin(t)
    let c = format!(
        "{MASS}\nsource = {{ type = \"Translational.Move\" }}\n\
         u1 = {{ type = \"Sine\", f = 0.15915494309189535 }}\n\
         u2 = {{ type = \"Sine\", f = 0.15915494309189535, phase = 1.5707963267948966 }}\n\
         u3 = {{ type = \"Sine\", f = 0.15915494309189535, amplitude = -1.0 }}"
    );
    let conn = r#"["u1.y", "source.u[1]"], ["u2.y", "source.u[2]"], ["u3.y", "source.u[3]"],
                  ["source.flange", "mass.flange_a"]"#;
    let r = run(&model(&c, conn, 2.0));
    assert!((last(&r, "mass.s") - 2f64.sin()).abs() < 1e-8);
    assert!((last(&r, "mass.v") - 2f64.cos()).abs() < 1e-8);
    assert!((last(&r, "mass.flange_a.f") + 3.0 * 2f64.sin()).abs() < 1e-7);
}

#[test]
fn sensors_on_a_mass_under_a_constant_force_read_the_closed_form() {
    // F = 2 N on m = 4 kg from s0 = 1, v0 = 0.5: a = 0.5; a Fixed at 0.2 for the relative ones
    let c = r#"push = { type = "Translational.ConstantForce", f_constant = 2.0 }
body = { type = "Translational.Mass", m = 4.0, s = 1.0, v = 0.5 }
fixed = { type = "Translational.Fixed", s0 = 0.2 }
force = { type = "Translational.ForceSensor" }
power = { type = "Translational.PowerSensor" }
multi = { type = "Translational.MultiSensor" }
pos = { type = "Translational.PositionSensor" }
speed = { type = "Translational.SpeedSensor" }
acc = { type = "Translational.AccSensor" }
relPos = { type = "Translational.RelPositionSensor" }
relSpeed = { type = "Translational.RelSpeedSensor" }
relAcc = { type = "Translational.RelAccSensor" }"#;
    let conn = r#"["push.flange", "force.flange_a"], ["force.flange_b", "power.flange_a"],
        ["power.flange_b", "multi.flange_a"], ["multi.flange_b", "body.flange_a"],
        ["pos.flange", "body.flange_b"], ["speed.flange", "body.flange_b"],
        ["acc.flange", "body.flange_b"], ["relPos.flange_a", "fixed.flange"],
        ["relPos.flange_b", "body.flange_b"], ["relSpeed.flange_a", "fixed.flange"],
        ["relSpeed.flange_b", "body.flange_b"], ["relAcc.flange_a", "fixed.flange"],
        ["relAcc.flange_b", "body.flange_b"]"#;
    let r = run(&model(c, conn, 2.0));
    let t = 2.0;
    let (s, v) = (1.0 + 0.5 * t + 0.25 * t * t, 0.5 + 0.5 * t);
    for (name, want) in [
        ("pos.s", s),
        ("speed.v", v),
        ("acc.a", 0.5),
        ("relPos.s_rel", s - 0.2),
        ("relSpeed.v_rel", v),
        ("relAcc.a_rel", 0.5),
        ("force.f", 2.0),
        ("power.power", 2.0 * v),
        ("multi.f", 2.0),
        ("multi.v", v),
        ("multi.power", 2.0 * v),
    ] {
        let got = last(&r, name);
        assert!(
            (got - want).abs() < 1e-8 * want.abs().max(1.0),
            "{name}: {got} vs {want}"
        );
    }
}

#[test]
fn force_step_sign_force_and_force2_act_as_msl_says() {
    // ForceStep: 3 N from t = 0.5 on 3 kg: v(2) = 1.5; SignForce (Linear, v0 = 0.1) on a mass
    // moving at 1 m/s: −f_nominal·sign(v) brakes it at 1 m/s² until |v| = v0
    let c = r#"step = { type = "Translational.ForceStep", stepForce = 3.0, startTime = 0.5 }
a = { type = "Translational.Mass", m = 3.0, s = 0.0, v = 0.0 }
sign = { type = "Translational.SignForce", f_nominal = -2.0, reg = "Linear", v0 = 0.1 }
b = { type = "Translational.Mass", m = 2.0, s = 0.0, v = 1.0 }
pair = { type = "Translational.Force2" }
k = { type = "Constant", k = 5.0 }
c = { type = "Translational.Mass", m = 1.0, s = 0.0, v = 0.0 }
d = { type = "Translational.Mass", m = 4.0, s = 0.0, v = 0.0 }"#;
    let conn = r#"["step.flange", "a.flange_a"], ["sign.flange", "b.flange_a"],
        ["k.y", "pair.f"], ["pair.flange_a", "c.flange_a"], ["pair.flange_b", "d.flange_a"]"#;
    let r = run(&model(c, conn, 2.0));
    assert!((last(&r, "a.v") - 1.5).abs() < 1e-9);
    let (t, v) = (col(&r, "time"), col(&r, "b.v"));
    let i = t.iter().position(|&x| x >= 0.5).unwrap();
    assert!((v[i] - (1.0 - t[i])).abs() < 1e-9, "{}", v[i]);
    // Force2: flange_a.f = f, flange_b.f = −f — d pushed forward at 5/4, c back at 5/1
    assert!((last(&r, "d.a") - 1.25).abs() < 1e-9 && (last(&r, "c.a") + 5.0).abs() < 1e-9);
}

const G: f64 = 9.80665;

fn vehicle(extra: &str) -> String {
    format!(
        "car = {{ type = \"Translational.Vehicle\", m = 1200.0, J = 2.0, R = 0.3, A = 2.2, Cd = 0.3, \
         CrConstant = 0.012, inclinationConstant = 0.08, {extra} }}"
    )
}

#[test]
fn a_vehicle_on_a_grade_holds_still_or_keeps_its_speed_when_the_drive_balances_it() {
    let alpha = 0.08f64.atan();
    // standing: the regularized rolling resistance is 0, the drive holds m·g·sin(alpha)
    let hold = 1200.0 * G * alpha.sin() * 0.3;
    let c = format!(
        "{}\ndrive = {{ type = \"ConstantTorque\", tau_constant = {hold} }}",
        vehicle("s = 0.0, v = 0.0")
    );
    let r = run(&model(&c, r#"["drive.flange", "car.flangeR"]"#, 5.0));
    let worst = col(&r, "car.v").iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // (a grade force off by 0.1 % would leave it creeping at ~7e-6 m/s inside vReg)
    assert!(worst < 1e-8, "{worst}");
    // at 20 m/s the drive carries grade, rolling resistance and drag
    let v0 = 20.0;
    let force = 1200.0 * G * (alpha.sin() + 0.012 * alpha.cos()) + 0.3 * 2.2 * 1.2 * v0 * v0 / 2.0;
    let c = format!(
        "{}\ndrive = {{ type = \"ConstantTorque\", tau_constant = {} }}",
        vehicle("s = 0.0, v = 20.0"),
        force * 0.3
    );
    let r = run(&model(&c, r#"["drive.flange", "car.flangeR"]"#, 5.0));
    assert!(col(&r, "car.v").iter().all(|v| (v - v0).abs() < 1e-9));
    assert!((last(&r, "car.s") - 100.0).abs() < 1e-8);
    assert!((last(&r, "car.flangeR.phi") - 100.0 / 0.3).abs() < 1e-7);
}

#[test]
fn a_coasting_vehicle_decelerates_by_drag_and_rolling_resistance_in_closed_form() {
    // flat road: (m + J/R²)·v' = −(c·v² + k), c = Cd·A·rho/2, k = Cr·m·g:
    // v(t) = √(k/c)·tan(atan(v0·√(c/k)) − √(c·k)·t/M)
    let c = r#"car = { type = "Translational.Vehicle", m = 1200.0, J = 2.0, R = 0.3, A = 2.2, Cd = 0.3, CrConstant = 0.012, s = 0.0, v = 30.0 }"#;
    let r = run(&model(c, "", 20.0));
    let (cd, k, m) = (
        0.3 * 2.2 * 1.2 / 2.0,
        0.012 * 1200.0 * G,
        1200.0 + 2.0 / 0.09,
    );
    let theta0 = (30.0 * (cd / k).sqrt()).atan();
    for (t, v) in col(&r, "time").iter().zip(col(&r, "car.v")) {
        let want = (k / cd).sqrt() * (theta0 - (cd * k).sqrt() * t / m).tan();
        assert!((v - want).abs() < 1e-8 * 30.0, "t = {t}: {v} vs {want}");
    }
    assert!((last(&r, "car.fRoll.f") - k).abs() < 1e-9);
}

#[test]
fn a_vehicle_with_impossible_data_is_refused_by_name() {
    for (bad, parameter) in [
        ("A = -1.0", "A"),
        ("CrConstant = -0.01", "CrConstant"),
        ("m = 0.0", "m"),
        ("R = 0.0", "R"),
        ("Cd = -0.3", "Cd"),
    ] {
        let mut params = vec!["m = 1000.0", "J = 1.0", "R = 0.3"];
        params.retain(|p| !p.starts_with(parameter));
        params.push(bad);
        let text = model(
            &format!(
                "car = {{ type = \"Translational.Vehicle\", {} }}",
                params.join(", ")
            ),
            "",
            1.0,
        );
        let spec = ModelSpec::from_toml(&text, ".").unwrap();
        let Err(err) = simulate(&spec) else {
            panic!("{bad} was accepted")
        };
        let err = err.to_string();
        assert!(
            err.contains("car") && err.contains(&format!("'{parameter}'")),
            "{err}"
        );
    }
}

#[test]
fn every_element_of_the_translational_examples_balances_its_power() {
    // as tests/audit.rs for examples/msl: the power entering each element through its flanges
    // is what its own equations take (½·m·v² and ½·J·w² stored, drag, rolling and eddy losses)
    for name in ["Vehicle", "EddyCurrentBrake"] {
        let r = example(name);
        let audits = r.audit();
        assert!(audits.len() >= 2, "{name}");
        let scale = audits.iter().map(|a| a.scale).fold(1.0, f64::max);
        for a in &audits {
            eprintln!(
                "{name} {}: residual {:.2e} of {:.3} W, min dissipation {:.2e}, dissipated {:.4} J",
                a.component, a.residual, a.scale, a.min_dissipation, a.dissipated
            );
            assert!(
                a.residual <= 1e-9 * scale,
                "{name} {}: {:.3e}",
                a.component,
                a.residual
            );
            assert!(a.min_dissipation >= -1e-9 * scale, "{name} {}", a.component);
        }
    }
}
