//! SlipWheel (stiction's own tyre contact, issue 31) at its closed forms: a braked wheel rolls
//! (contact stuck) at the rolling deceleration, its contact breaks away at the instant the
//! stuck force reaches peak·mu·fN, and the car then skids v_lock²/(2·mu_k·g) to rest; bad
//! input is refused by name.

use stiction_core::{simulate, ModelSpec, SimResult};

const J: f64 = 1.0; // wheel (and brake disc) inertia [kg.m2]
const R: f64 = 0.3; // wheel radius [m]
const M: f64 = 400.0; // the car's share [kg]
const G: f64 = 9.81;
const MU_K: f64 = 0.8; // tyre sliding coefficient (mu_pos, constant)
const PEAK: f64 = 1.25; // mu_s = peak·mu_k = 1.0
const V0: f64 = 20.0;
/// The brake's sliding torque mu_b·cgeo·fn_max·f_normalized with f_normalized = t/4:
/// 0.4·0.1·100 kN/4 s = 1000 N.m/s.
const K: f64 = 1000.0;

/// The model: the wheel's hub an Inertia, braked by a rotational Brake whose pressure rises
/// linearly (a Ramp into f_normalized, the brake's mu constant so its sliding torque is K·t
/// while the wheel turns); a SlipWheel with normal force m·g carries the car, a
/// Translational.Mass. Nothing else acts (no drag, no rolling resistance).
fn model(extra: &str) -> String {
    format!(
        r#"
name = "lockup"
connect = [
  ["brake.flange_b", "hub.flange_a"],
  ["hub.flange_b", "tyre.flangeR"],
  ["tyre.flangeT", "car.flange_a"],
  ["pedal.y", "brake.f_normalized"],
]

[experiment]
StopTime = 4.0
Interval = 0.01
Tolerance = 1e-10

[components]
hub = {{ type = "Inertia", J = {J}, phi = 0.0, w = {{ start = {w0}, fixed = true }} }}
brake = {{ type = "Brake", fn_max = 1e5, cgeo = 0.1, mu_pos = [[0.0, 0.4]] }}
pedal = {{ type = "Ramp", height = 1.0, duration = 4.0 }}
tyre = {{ type = "SlipWheel", radius = {R}, mu_pos = [[0.0, {MU_K}]], peak = {PEAK}, fNConstant = {fn} {extra} }}
car = {{ type = "Translational.Mass", m = {M}, s = 0.0, v = {{ start = {V0}, fixed = true }} }}
"#,
        w0 = V0 / R,
        fn = M * G,
    )
}

fn run(text: &str) -> SimResult {
    simulate(&ModelSpec::from_toml(text, ".").unwrap()).unwrap()
}

fn last(r: &SimResult, name: &str) -> f64 {
    *r.column(name).unwrap().last().unwrap()
}

/// The first time `name` is `value` (booleans and modes are exact).
fn first_time(r: &SimResult, name: &str, pred: impl Fn(f64) -> bool) -> f64 {
    let t = r.column("time").unwrap();
    let x = r.column(name).unwrap();
    *t.iter().zip(&x).find(|(_, x)| pred(**x)).expect(name).0
}

#[test]
fn a_braked_slip_wheel_rolls_locks_and_skids_at_the_closed_forms() {
    let r = run(&model(""));
    let inertia = J + M * R * R; // the rolling wheel's inertia at the hub
                                 // rolling: the stuck contact's force m·a = −m·K·t·R/inertia reaches peak·mu_k·m·g when
                                 // K·t = peak·mu_k·g·inertia/R (the issue's mu_s·g·(J + m·R²)/R)
    let t_lock = PEAK * MU_K * G * inertia / (R * K);
    let v_lock = V0 - K * R * t_lock * t_lock / (2.0 * inertia);
    let s_lock = V0 * t_lock - K * R * t_lock.powi(3) / (6.0 * inertia);
    let t_stop = t_lock + v_lock / (MU_K * G);
    let s_stop = s_lock + v_lock * v_lock / (2.0 * MU_K * G);
    assert!(t_stop < 4.0 && v_lock > 5.0, "{t_lock} {v_lock} {t_stop}");

    let t_slip = first_time(&r, "tyre.locked", |l| l < 0.5);
    assert!((t_slip - t_lock).abs() < 1e-8, "{t_slip} vs {t_lock}");
    // it starts sliding backward (the rim slower than the road): a skid, not a spin
    assert!((first_time(&r, "tyre.startBackward", |b| b > 0.5) - t_lock).abs() < 1e-8);
    let (t, v) = (r.column("time").unwrap(), r.column("car.v").unwrap());
    let s = r.column("car.s").unwrap();
    let f = r.column("tyre.f").unwrap();
    for (i, &t) in t.iter().enumerate() {
        let (want_v, want_s) = if t <= t_lock {
            let a = K * R * t * t / (2.0 * inertia);
            (V0 - a, V0 * t - K * R * t.powi(3) / (6.0 * inertia))
        } else if t <= t_stop {
            let d = t - t_lock;
            (
                v_lock - MU_K * G * d,
                s_lock + v_lock * d - 0.5 * MU_K * G * d * d,
            )
        } else {
            (0.0, s_stop)
        };
        assert!(
            (v[i] - want_v).abs() < 1e-8,
            "t = {t}: v {} vs {want_v}",
            v[i]
        );
        assert!(
            (s[i] - want_s).abs() < 1e-8,
            "t = {t}: s {} vs {want_s}",
            s[i]
        );
        // skidding, the contact force is the sliding one, −mu_k·m·g
        if t > t_lock + 1e-6 && t < t_stop - 1e-6 {
            assert!((f[i] + MU_K * M * G).abs() < 1e-6, "t = {t}: f {}", f[i]);
        }
    }
    // the car skids v_lock²/(2·mu_k·g) further, to rest; the brake holds the wheel locked
    assert!(
        (last(&r, "car.s") - s_stop).abs() < 1e-8,
        "{}",
        last(&r, "car.s")
    );
    assert_eq!(last(&r, "brake.locked"), 1.0);
    assert_eq!(last(&r, "tyre.locked"), 1.0);
    assert!(last(&r, "hub.w").abs() < 1e-9);
    // the energy the car had went into the brake and the skid, element by element
    for a in r.audit() {
        assert!(
            a.residual < 1e-6 * a.scale.max(1.0),
            "{}: {}",
            a.component,
            a.residual
        );
    }
}

#[test]
fn a_normal_force_input_of_zero_frees_the_contact() {
    // fN from a signal: with the wheel lifted (fN = 0) the contact transmits nothing, the car
    // coasts at v0 while the brake stops the wheel alone
    let text = model("")
        .replace(
            &format!(", fNConstant = {}", M * G),
            ", useNormalForceInput = true",
        )
        .replace(
            "[\"pedal.y\", \"brake.f_normalized\"],",
            "[\"pedal.y\", \"brake.f_normalized\"],\n  [\"lift.y\", \"tyre.fN\"],",
        )
        .replace(
            "[components]",
            "[components]\nlift = { type = \"Constant\", k = 0.0 }",
        );
    let r = run(&text);
    assert!((last(&r, "car.v") - V0).abs() < 1e-9);
    assert_eq!(last(&r, "tyre.free"), 1.0);
    assert!(last(&r, "hub.w").abs() < 1e-9);
}

#[test]
fn bad_wheels_are_refused_by_name() {
    for (bad, names) in [
        ("radius = 0.3", "radius = 0.0"),
        ("radius = 0.3", "radius = -1.0"),
        ("mu_pos = [[0.0, 0.8]]", "mu_pos = [[0.0, -0.8]]"),
    ] {
        let text = model("").replace(&bad.replace("0.3", &R.to_string()), names);
        let err = match ModelSpec::from_toml(&text, ".") {
            Err(e) => e.to_string(),
            Ok(m) => simulate(&m).map(|_| ()).unwrap_err().to_string(),
        };
        let param = names.split(' ').next().unwrap();
        assert!(err.contains("tyre") && err.contains(param), "{err}");
    }
}
