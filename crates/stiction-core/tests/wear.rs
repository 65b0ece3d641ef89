//! Pad wear (issue 32, the `wear` record of the friction elements) against closed forms: an
//! inertia braked to rest with constant mu wears `alpha·J·w0²/2` (energy), `k·fn·r_eff·θ/H`
//! with θ = w0²/(2·decel) (Archard), `factor(T)·J·w0²/2` at a fixed temperature (Arrhenius);
//! Archard and energy agree when `alpha = k/(mu·H)`; nothing wears while stuck; the pad's limit
//! stops the run at the closed-form instant; bad records are refused by name before any run.

use stiction_core::{simulate, ModelSpec, SimError, SimResult};

const R: f64 = 8.314_462_618;

fn run(text: &str) -> Result<SimResult, SimError> {
    simulate(&ModelSpec::from_toml(text, ".").unwrap())
}

fn col(r: &SimResult, name: &str) -> Vec<f64> {
    r.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn last(r: &SimResult, name: &str) -> f64 {
    *col(r, name).last().unwrap()
}

fn assert_rel(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol * want.abs(),
        "{what}: {got} vs {want} (relative {:e})",
        (got - want) / want
    );
}

/// An inertia J at w0 braked by a constant-mu Brake (fn = fn_max), the brake's `extra`
/// parameters and components appended.
fn stop(j: f64, w0: f64, mu: f64, fn_max: f64, cgeo: f64, wear: &str, extra: &str) -> String {
    format!(
        r#"
name = "stop"
connect = [["J1.flange_b", "brake.flange_a"], ["brake.flange_b", "J2.flange_a"], ["press.y", "brake.f_normalized"]{extra_connect}]

[experiment]
StopTime = 2.0
Interval = 0.01
Tolerance = 1e-8

[components]
J1 = {{ type = "Inertia", J = {j1}, phi = 0.0, w = {w0} }}
J2 = {{ type = "Inertia", J = {j2} }}
brake = {{ type = "Brake", fn_max = {fn_max}, cgeo = {cgeo}, mu_pos = [[0.0, {mu}]], wear = {wear}{heat} }}
press = {{ type = "Constant", k = 1.0 }}
{extra}
"#,
        j1 = 0.75 * j,
        j2 = 0.25 * j,
        extra_connect = if extra.is_empty() {
            ""
        } else if extra.contains("Conductor") {
            r#", ["brake.heatPort", "disc.port_a"]"#
        } else {
            r#", ["brake.heatPort", "disc.port"]"#
        },
        heat = if extra.is_empty() {
            ""
        } else {
            ", useHeatPort = true"
        },
    )
}

/// (J, w0, mu, fn_max, cgeo): stops at J·w0/(mu·cgeo·fn) = 0.5 s.
const CASE: (f64, f64, f64, f64, f64) = (2.0, 30.0, 0.4, 1500.0, 0.2);

fn case_stop(wear: &str, extra: &str) -> Result<SimResult, SimError> {
    let (j, w0, mu, fn_max, cgeo) = CASE;
    run(&stop(j, w0, mu, fn_max, cgeo, wear, extra))
}

#[test]
fn energy_wear_of_a_stop_is_alpha_times_the_kinetic_energy() {
    let (j, w0, ..) = CASE;
    let alpha = 3e-13;
    let r = case_stop(&format!(r#"{{ model = "energy", alpha = {alpha} }}"#), "").unwrap();
    assert_rel(
        "wearVolume",
        last(&r, "brake.wearVolume"),
        alpha * j * w0 * w0 / 2.0,
        1e-10,
    );
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
fn archard_wear_of_a_stop_is_k_fn_times_the_slid_distance_over_h() {
    let (j, w0, mu, fn_max, cgeo) = CASE;
    let (k, h, r_eff) = (2e-4, 3e8, 0.15);
    let wear = format!(r#"{{ model = "archard", k = {k}, H = {h}, r_eff = {r_eff} }}"#);
    let r = case_stop(&wear, "").unwrap();
    let decel = mu * cgeo * fn_max / j;
    let angle = w0 * w0 / (2.0 * decel);
    let want = k * fn_max * r_eff * angle / h;
    assert_rel("wearVolume", last(&r, "brake.wearVolume"), want, 1e-10);
}

/// Two identical drivetrains in one run (the same steps), a sine torque making them stick and
/// slip: Archard's wear equals the energy wear with alpha = k/(mu·H) and r_eff = cgeo.
#[test]
fn archard_and_energy_wear_agree_when_alpha_is_k_over_mu_h() {
    let (mu, k, h, cgeo, fn_max) = (0.35, 1e-4, 2e8, 0.12, 400.0);
    let alpha = k / (mu * h);
    let half = |n: &str, wear: &str| {
        format!(
            r#"
J{n} = {{ type = "Inertia", J = 0.5, phi = 0.0, w = 3.0 }}
brake{n} = {{ type = "Brake", fn_max = {fn_max}, cgeo = {cgeo}, mu_pos = [[0.0, {mu}]], wear = {wear} }}
drive{n} = {{ type = "Torque" }}
"#
        )
    };
    let mut text = String::from(
        r#"
name = "pair"
connect = [["J1.flange_b", "brake1.flange_a"], ["J2.flange_b", "brake2.flange_a"],
  ["drive1.flange", "J1.flange_a"], ["drive2.flange", "J2.flange_a"],
  ["sine.y", "drive1.tau"], ["sine.y", "drive2.tau"],
  ["press.y", "brake1.f_normalized"], ["press.y", "brake2.f_normalized"]]

[experiment]
StopTime = 3.0
Interval = 0.01
Tolerance = 1e-8

[components]
sine = { type = "Sine", amplitude = 25.0, f = 1.0 }
press = { type = "Sine", amplitude = 0.4, f = 0.7, offset = 0.7 }
"#,
    );
    text += &half(
        "1",
        &format!(r#"{{ model = "archard", k = {k}, H = {h}, r_eff = {cgeo} }}"#),
    );
    text += &half("2", &format!(r#"{{ model = "energy", alpha = {alpha} }}"#));
    let r = run(&text).unwrap();
    let (a, e) = (col(&r, "brake1.wearVolume"), col(&r, "brake2.wearVolume"));
    assert!(last(&r, "brake1.wearVolume") > 0.0);
    for (x, y) in a.iter().zip(&e) {
        assert!((x - y).abs() <= 1e-10 * y.abs().max(1e-30), "{x} vs {y}");
    }
    // it sticks on the way, held against the sine torque, and wears nothing meanwhile
    let locked = col(&r, "brake1.locked");
    assert!(locked.iter().any(|&l| l > 0.5));
    for i in 1..a.len() {
        if locked[i - 1] > 0.5 && locked[i] > 0.5 {
            assert_eq!(
                a[i].to_bits(),
                a[i - 1].to_bits(),
                "wear grew while held, row {i}"
            );
        }
    }
}

#[test]
fn nothing_wears_while_the_brake_holds() {
    let r = case_stop(r#"{ model = "energy", alpha = 1e-12 }"#, "").unwrap();
    let (t, v, locked) = (
        col(&r, "time"),
        col(&r, "brake.wearVolume"),
        col(&r, "brake.locked"),
    );
    let first = locked.iter().position(|&l| l > 0.5).expect("it stops");
    assert!(t[first] < 0.6 && *t.last().unwrap() > 1.9);
    let held = &v[first..];
    assert!(held[0] > 0.0);
    assert!(
        held.iter().all(|x| x.to_bits() == held[0].to_bits()),
        "the worn volume changed while stuck"
    );
}

#[test]
fn arrhenius_wear_at_a_fixed_temperature_is_its_factor_times_the_energy() {
    let (j, w0, ..) = CASE;
    let (alpha0, k0, e, t_th, temp) = (1e-13, 4e-9, 6.0e4, 500.0, 650.0);
    let wear = format!(
        r#"{{ model = "arrhenius", alpha0 = {alpha0}, k0 = {k0}, E = {e}, T_threshold = {t_th} }}"#
    );
    let fixed = format!(r#"disc = {{ type = "FixedTemperature", T = {temp} }}"#);
    let r = case_stop(&wear, &fixed).unwrap();
    let factor = alpha0 + k0 * ((-e / (R * temp)).exp() - (-e / (R * t_th)).exp());
    assert_rel(
        "wearVolume",
        last(&r, "brake.wearVolume"),
        factor * j * w0 * w0 / 2.0,
        1e-10,
    );
    // below the threshold: the energy law alone
    let cold = r#"disc = { type = "FixedTemperature", T = 300.0 }"#;
    let r = case_stop(&wear, cold).unwrap();
    assert_rel(
        "wearVolume (cold)",
        last(&r, "brake.wearVolume"),
        alpha0 * j * w0 * w0 / 2.0,
        1e-10,
    );
}

#[test]
fn the_pad_limit_stops_the_run_at_the_closed_form_instant() {
    let (j, w0, mu, fn_max, cgeo) = CASE;
    let (alpha, area, h0, h_min) = (1e-9, 1e-3, 0.012, 0.0115);
    let wear = format!(
        r#"{{ model = "energy", alpha = {alpha}, A = {area}, thickness = {h0}, thickness_min = {h_min} }}"#
    );
    let limit = area * (h0 - h_min);
    // alpha·(J·w0²/2 − J·w²/2) = limit, w = w0 − decel·t
    let w_star = (w0 * w0 - 2.0 * limit / (alpha * j)).sqrt();
    let t_star = (w0 - w_star) / (mu * cgeo * fn_max / j);
    assert!(t_star > 0.0 && t_star < 0.5);
    match case_stop(&wear, "") {
        Err(SimError::WearLimit { time, element, .. }) => {
            assert_eq!(element, "brake");
            assert_rel("limit instant", time, t_star, 1e-9);
        }
        Err(other) => panic!("another error: {other}"),
        Ok(_) => panic!("the run went on past the pad's limit"),
    }
    // above the limit: the thickness left is reported
    let ok = format!(r#"{{ model = "energy", alpha = {alpha}, A = {area}, thickness = {h0} }}"#);
    let r = case_stop(&ok, "").unwrap();
    let worn = alpha * j * w0 * w0 / 2.0;
    assert_rel(
        "thickness",
        last(&r, "brake.thickness"),
        h0 - worn / area,
        1e-12,
    );
}

#[test]
fn bad_wear_records_are_refused_by_name() {
    let refused = |wear: &str, extra: &str, words: &[&str]| {
        let err = match case_stop(wear, extra) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{wear} was accepted"),
        };
        for w in words.iter().chain(&["brake"]) {
            assert!(err.contains(w), "{wear}: '{err}' lacks '{w}'");
        }
    };
    refused(
        r#"{ model = "magic", k = 1 }"#,
        "",
        &["wear", "unknown model \"magic\""],
    );
    refused(
        r#"{ model = "archard", k = -1, H = 1e8, r_eff = 0.1 }"#,
        "",
        &["'k' must be >= 0"],
    );
    refused(
        r#"{ model = "archard", k = 1e-4, r_eff = 0.1 }"#,
        "",
        &["needs 'H'"],
    );
    refused(
        r#"{ model = "energy", alpha = 1e-12, beta = 2 }"#,
        "",
        &["unknown key 'beta'"],
    );
    refused(
        r#"{ model = "arrhenius", k0 = 1e-9, E = 5e4, T_threshold = 500 }"#,
        "",
        &["useHeatPort"],
    );
    refused(
        r#"{ model = "energy", alpha = 1e-12, thickness_min = 0.001 }"#,
        "",
        &["'A' and 'thickness'"],
    );
    refused(r#""energy""#, "", &["expected a table"]);
    // a heat port whose temperature is algebraic (a conductor to ambient, no capacity)
    let algebraic = r#"disc = { type = "ThermalConductor", G = 1.0 }"#;
    let wear = r#"{ model = "arrhenius", k0 = 1e-9, E = 5e4, T_threshold = 500 }"#;
    refused(wear, algebraic, &["its wear depends on the temperature"]);
}

/// A Clutch engaging two inertias at different speeds wears alpha times the energy its slip
/// dissipates, `J1·J2/(J1 + J2)·Δw²/2`, and nothing once they turn together.
#[test]
fn a_clutch_wears_alpha_times_its_slip_energy() {
    let (j1, j2, w1, w2, alpha) = (1.5, 0.5, 40.0, 10.0, 2e-13);
    let text = format!(
        r#"
name = "engage"
connect = [["J1.flange_b", "clutch.flange_a"], ["clutch.flange_b", "J2.flange_a"], ["press.y", "clutch.f_normalized"]]

[experiment]
StopTime = 1.0
Interval = 0.01
Tolerance = 1e-8

[components]
J1 = {{ type = "Inertia", J = {j1}, phi = 0.0, w = {w1} }}
J2 = {{ type = "Inertia", J = {j2}, phi = 0.0, w = {w2} }}
clutch = {{ type = "Clutch", fn_max = 500.0, cgeo = 0.1, mu_pos = [[0.0, 0.3]], wear = {{ model = "energy", alpha = {alpha} }} }}
press = {{ type = "Constant", k = 1.0 }}
"#
    );
    let r = run(&text).unwrap();
    let dw = w1 - w2;
    let want = alpha * j1 * j2 / (j1 + j2) * dw * dw / 2.0;
    assert_rel("wearVolume", last(&r, "clutch.wearVolume"), want, 1e-10);
}
