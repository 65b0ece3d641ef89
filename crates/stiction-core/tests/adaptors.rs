//! The prescribed-motion constraint of the AngleToTorqueAdaptor in the engine: a shaft without
//! inertia that only the adaptor holds runs (and passes the model check) with the torque the
//! closed form gives; the TorqueToAngleAdaptor is a torque on its flange (MSL `flange.tau = tau`).

use stiction_core::check_model;
use stiction_core::{assemble, simulate, ModelSpec};

/// phi = sin t, w = cos t, a = −sin t on a spring-damper (c = 50, d = 2) to ground.
const PRESCRIBED: &str = r#"
format = 1
name = "prescribed"
connect = [
  ["phi.y", "adaptor.phi"],
  ["w.y", "adaptor.w"],
  ["a.y", "adaptor.a"],
  ["adaptor.flange", "sd.flange_a"],
  ["sd.flange_b", "ground.flange"],
]

[experiment]
StopTime = 4.0
Interval = 0.01

[components]
phi     = { type = "Sine", amplitude = 1.0, f = 0.15915494309189535 }
w       = { type = "Sine", amplitude = 1.0, f = 0.15915494309189535, phase = 1.5707963267948966 }
a       = { type = "Sine", amplitude = -1.0, f = 0.15915494309189535 }
adaptor = { type = "AngleToTorqueAdaptor" }
sd      = { type = "SpringDamper", c = 50.0, d = 2.0 }
ground  = { type = "Fixed" }
"#;

#[test]
fn a_prescribed_shaft_without_inertia_needs_the_spring_damper_torque() {
    let spec = ModelSpec::from_toml(PRESCRIBED, ".").unwrap();
    check_model(&assemble(&spec).unwrap()).expect("the adaptor's row holds the shaft");
    let r = simulate(&spec).expect("it runs");
    let (t, tau) = (r.column("time").unwrap(), r.column("adaptor.tau").unwrap());
    let phi = r.column("sd.phi_rel").unwrap();
    for ((t, tau), phi_rel) in t.iter().zip(&tau).zip(&phi) {
        assert!((phi_rel + t.sin()).abs() < 1e-13, "t = {t}");
        let exact = 50.0 * t.sin() + 2.0 * t.cos();
        assert!(
            (tau - exact).abs() < 1e-11,
            "t = {t}: {tau} against {exact}"
        );
    }
    assert!(t.len() > 400);
}

#[test]
fn without_the_adaptor_the_shaft_is_undetermined() {
    let text = PRESCRIBED
        .replace(r#"["adaptor.flange", "sd.flange_a"],"#, "")
        .replace(
            r#"type = "SpringDamper", c = 50.0, d = 2.0"#,
            r#"type = "Spring", c = 50.0"#,
        );
    let sys = assemble(&ModelSpec::from_toml(&text, ".").unwrap()).unwrap();
    assert!(check_model(&sys).is_err());
}

#[test]
fn torque_to_angle_decelerates_its_inertia_by_the_input() {
    let text = r#"
format = 1
name = "parabola"
connect = [["tau.y", "adaptor.tau"], ["adaptor.flange", "J.flange_b"]]

[experiment]
StopTime = 1.0
Interval = 0.1

[components]
tau     = { type = "Constant", k = 3.0 }
adaptor = { type = "TorqueToAngleAdaptor" }
J       = { type = "Inertia", J = 2.0, phi = 0.0, w = 0.0 }
"#;
    let r = simulate(&ModelSpec::from_toml(text, ".").unwrap()).unwrap();
    let last = |name: &str| *r.column(name).unwrap().last().unwrap();
    assert!((last("adaptor.a") + 1.5).abs() < 1e-13);
    assert!((last("adaptor.w") + 1.5).abs() < 1e-12);
    assert!((last("adaptor.phi") + 0.75).abs() < 1e-12);
}
