//! Fade (issue 32, beyond MSL): friction over the heat port's temperature (`mu_T`, `peak_T`,
//! `mu_table`) and over the normal force (`mu_fn`) against closed forms; the energy audit
//! closes with fade on; bad fade parameters are refused by name before any run.

use stiction_core::{simulate, ModelSpec, SimResult};

fn run(text: &str) -> SimResult {
    simulate(&ModelSpec::from_toml(text, ".").unwrap()).unwrap()
}

fn refused(text: &str) -> String {
    match ModelSpec::from_toml(text, ".").map(|spec| simulate(&spec)) {
        Err(e) => e.to_string(),
        Ok(Err(e)) => e.to_string(),
        Ok(Ok(_)) => panic!("accepted: {text}"),
    }
}

fn col(r: &SimResult, name: &str) -> Vec<f64> {
    r.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// The value of `name` at the row whose time is `t` (a row of the output grid).
fn at(r: &SimResult, name: &str, t: f64) -> f64 {
    let time = col(r, "time");
    let i = time
        .iter()
        .position(|&ti| (ti - t).abs() < 1e-12)
        .expect("a grid row");
    col(r, name)[i]
}

/// The first time a Boolean-as-real column becomes `value`.
fn first(r: &SimResult, name: &str, value: bool) -> f64 {
    let (t, x) = (col(r, "time"), col(r, name));
    t[x.iter()
        .position(|&v| (v > 0.5) == value)
        .expect("it turns")]
}

fn assert_rel(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol * want.abs(),
        "{what}: {got} vs {want} (relative {:e})",
        (got - want) / want
    );
}

fn audit_closes(r: &SimResult) {
    let audit = r.audit();
    assert!(!audit.is_empty());
    for a in audit {
        assert!(
            a.residual < 1e-8 * a.scale.max(1.0),
            "{}: residual {} of scale {}",
            a.component,
            a.residual,
            a.scale
        );
    }
}

// The adiabatic stop: J = 2 kg·m², w0 = 100 rad/s, fn = 500 N, cgeo = 1, C = 1000 J/K,
// T0 = 293.15 K, mu = mu0 − beta·(T − T0) with mu0 = 0.4, beta = 0.01 /K.
const J: f64 = 2.0;
const W0: f64 = 100.0;
const FN: f64 = 500.0;
const C: f64 = 1000.0;
const T0: f64 = 293.15;
const MU0: f64 = 0.4;
const BETA: f64 = 0.01;

/// `mu_T` as a two-row table, exactly the linear fade over [T0, T0 + 20 K] (the run heats the
/// disc by J·w0²/(2·C) = 10 K); `mu_pos` holds mu0, so `mu = mu0·mu_T(T)`.
fn adiabatic_stop(translational: bool) -> String {
    let t1 = T0 + 20.0;
    let factor1 = 1.0 - BETA / MU0 * (t1 - T0);
    let (mass, brake, ports) = if translational {
        (
            format!("type = \"Translational.Mass\", m = {J}, v = {{ start = {W0}, fixed = true }}"),
            "Translational.Brake",
            ("disc.flange_b", "brake.flange_a"),
        )
    } else {
        (
            format!("type = \"Inertia\", J = {J}, w = {{ start = {W0}, fixed = true }}"),
            "Brake",
            ("disc.flange_b", "brake.flange_a"),
        )
    };
    format!(
        r#"
name = "fade"
connect = [["{}", "{}"], ["press.y", "brake.f_normalized"], ["brake.heatPort", "cap.port"]]

[experiment]
StopTime = 2.0
Interval = 0.125
Tolerance = 1e-12

[components]
disc = {{ {mass} }}
brake = {{ type = "{brake}", fn_max = {FN}, cgeo = 1.0, useHeatPort = true, mu_pos = [[0.0, {MU0}]], mu_T = [[{T0}, 1.0], [{t1}, {factor1}]] }}
press = {{ type = "Constant", k = 1.0 }}
cap = {{ type = "HeatCapacitor", C = {C}, T = {{ start = {T0}, fixed = true }} }}
"#,
        ports.0, ports.1
    )
}

/// The closed form: `C·dT = tau·w·dt = −J·w·dw` gives `T(w) = T0 + J·(w0² − w²)/(2·C)`, so
/// `mu = A + B·w²` with `A = mu0 − beta·J·w0²/(2·C)`, `B = beta·J/(2·C)`, and
/// `J·dw/dt = −cgeo·fn·(A + B·w²)`: `atan(w·√(B/A)) = atan(w0·√(B/A)) − cgeo·fn·√(A·B)·t/J`,
/// the stop at `t_stop = J/(cgeo·fn·√(A·B))·atan(w0·√(B/A))`.
fn check_adiabatic(r: &SimResult, speed: &str) {
    let (a, b) = (MU0 - BETA * J * W0 * W0 / (2.0 * C), BETA * J / (2.0 * C));
    let rate = FN * (a * b).sqrt() / J;
    let theta0 = (W0 * (b / a).sqrt()).atan();
    let t_stop = theta0 / rate;
    assert_rel("stop instant", first(r, "brake.locked", true), t_stop, 1e-8);
    for t in [0.25, 0.5, 0.75, 1.0] {
        let w = (a / b).sqrt() * (theta0 - rate * t).tan();
        assert_rel(
            &format!("{speed} at {t} s"),
            at(r, &format!("disc.{speed}"), t),
            w,
            1e-8,
        );
        let temp = T0 + J * (W0 * W0 - w * w) / (2.0 * C);
        assert_rel(&format!("T at {t} s"), at(r, "cap.T", t), temp, 1e-8);
        let mu = MU0 - BETA * (temp - T0);
        assert_rel(&format!("mu at {t} s"), at(r, "brake.mu", t), mu, 1e-8);
    }
    let t_end = T0 + J * W0 * W0 / (2.0 * C);
    assert_rel("T after the stop", at(r, "cap.T", 2.0), t_end, 1e-10);
}

#[test]
fn an_adiabatic_stop_with_linear_fade_follows_its_closed_form() {
    let r = run(&adiabatic_stop(false));
    check_adiabatic(&r, "w");
    audit_closes(&r);
    // fn and lossPower stay physical: lossPower = tau·w with tau = mu·cgeo·fn
    assert_rel("fn", at(&r, "brake.fn", 0.5), FN, 1e-15);
    let (tau, w) = (at(&r, "brake.tau", 0.5), at(&r, "brake.w", 0.5));
    assert_rel("lossPower", at(&r, "brake.lossPower", 0.5), tau * w, 1e-12);
}

#[test]
fn the_translational_brake_fades_the_same_way() {
    let r = run(&adiabatic_stop(true));
    check_adiabatic(&r, "v");
    audit_closes(&r);
}

/// The same fade as a 2-D `mu_table` over (w, T): constant in w, linear in T.
#[test]
fn a_mu_table_linear_in_temperature_gives_the_same_stop() {
    let t1 = T0 + 20.0;
    let mu1 = MU0 - BETA * (t1 - T0);
    let text = adiabatic_stop(false).replace(
        &format!(
            "mu_pos = [[0.0, {MU0}]], mu_T = [[{T0}, 1.0], [{t1}, {}]]",
            1.0 - BETA / MU0 * (t1 - T0)
        ),
        &format!("mu_table = [[0.0, {T0}, {t1}], [0.0, {MU0}, {mu1}], [200.0, {MU0}, {mu1}]]"),
    );
    assert!(text.contains("mu_table"));
    check_adiabatic(&run(&text), "w");
}

/// A held brake heated through a conductor from a FixedTemperature: `T = Tf − (Tf − T0)·e^(−t)`
/// (C/G = 1 s); `peak_T` falls from 1.5 at 300 K to 1 at 400 K, so the static limit is
/// `peak·peak_T(T)·mu0·fn = 1.2·(1 + 0.5·e^(−t))·50 N·m`; a torque ramp 30·t breaks it away at
/// the root of `30·t = 60 + 30·e^(−t)`.
#[test]
fn a_held_brake_breaks_away_when_the_ramp_meets_its_faded_peak() {
    let text = r#"
name = "breakaway"
connect = [["load.flange", "disc.flange_a"], ["disc.flange_b", "brake.flange_a"],
           ["ramp.y", "load.tau"], ["press.y", "brake.f_normalized"],
           ["brake.heatPort", "cap.port"], ["cap.port", "wall.port_a"], ["wall.port_b", "hot.port"]]

[experiment]
StopTime = 3.0
Interval = 0.01
Tolerance = 1e-12

[components]
disc = { type = "Inertia", J = 1.0, w = { start = 0.0, fixed = true } }
load = { type = "Torque" }
ramp = { type = "Ramp", height = 300.0, duration = 10.0 }
brake = { type = "Brake", fn_max = 100.0, peak = 1.2, mu_pos = [[0.0, 0.5]], useHeatPort = true, peak_T = [[300.0, 1.5], [400.0, 1.0]] }
press = { type = "Constant", k = 1.0 }
cap = { type = "HeatCapacitor", C = 2.0, T = { start = 300.0, fixed = true } }
wall = { type = "ThermalConductor", G = 2.0 }
hot = { type = "FixedTemperature", T = 400.0 }
"#;
    let r = run(text);
    let mut t: f64 = 2.0; // Newton on 30·t − 60 − 30·e^(−t)
    for _ in 0..50 {
        t -= (30.0 * t - 60.0 - 30.0 * (-t).exp()) / (30.0 + 30.0 * (-t).exp());
    }
    assert_rel("breakaway", first(&r, "brake.locked", false), t, 1e-8);
    assert_rel(
        "T at 1 s",
        at(&r, "cap.T", 1.0),
        400.0 - 100.0 * (-1.0f64).exp(),
        1e-8,
    );
    let tau0_max = at(&r, "brake.tau0_max", 1.0);
    assert_rel(
        "tau0_max at 1 s",
        tau0_max,
        60.0 + 30.0 * (-1.0f64).exp(),
        1e-8,
    );
    audit_closes(&r);
}

/// `mu_fn`: the normal force ramps fn = F·(0.5 + 0.5·t) (F = 1000 N) and `mu_fn` falls
/// linearly from 1 at 0 to 0.5 at 2·F, so the torque is mu0·(fn − fn²/(4·F)) and
/// `w(t) = w0 − mu0/J·∫(fn − fn²/(4·F))dt`, a cubic in t.
#[test]
fn a_pressure_ramp_with_mu_fn_follows_its_closed_form() {
    let text = r#"
name = "mu_fn"
connect = [["disc.flange_b", "brake.flange_a"], ["press.y", "brake.f_normalized"]]

[experiment]
StopTime = 1.0
Interval = 0.125
Tolerance = 1e-12

[components]
disc = { type = "Inertia", J = 1.0, w = { start = 1000.0, fixed = true } }
brake = { type = "Brake", fn_max = 1000.0, mu_pos = [[0.0, 0.5]], mu_fn = [[0.0, 1.0], [2000.0, 0.5]] }
press = { type = "Ramp", offset = 0.5, height = 0.5, duration = 1.0 }
"#;
    let r = run(text);
    let (f, mu0) = (1000.0, 0.5);
    // ∫0^t fn = F·(0.5·t + 0.25·t²); ∫0^t fn² = F²·(0.25·t + 0.25·t² + t³/12)
    let w = |t: f64| {
        let i1 = f * (0.5 * t + 0.25 * t * t);
        let i2 = f * f * (0.25 * t + 0.25 * t * t + t * t * t / 12.0);
        1000.0 - mu0 * (i1 - i2 / (4.0 * f))
    };
    for t in [0.25, 0.5, 0.75, 1.0] {
        assert_rel(&format!("w at {t} s"), at(&r, "disc.w", t), w(t), 1e-9);
    }
    let fn_ = f * 0.75;
    assert_rel(
        "mu at 0.5 s",
        at(&r, "brake.mu", 0.5),
        mu0 * (1.0 - fn_ / (4.0 * f)),
        1e-12,
    );
}

const BASE: &str = r#"
name = "bad"
connect = [["disc.flange_b", "brake.flange_a"], ["press.y", "brake.f_normalized"], ["brake.heatPort", "cap.port"]]
[components]
disc = { type = "Inertia", J = 1.0 }
press = { type = "Constant", k = 1.0 }
cap = { type = "HeatCapacitor", C = 10.0 }
"#;

fn with_brake(brake: &str) -> String {
    format!("{BASE}brake = {{ type = \"Brake\", fn_max = 10.0, useHeatPort = true, {brake} }}\n")
}

#[test]
fn bad_fade_parameters_are_refused_by_name() {
    let cases = [
        (
            "mu_T = [[300.0, 1.0], [400.0, -0.1]]",
            "mu_T",
            "factors must be >= 0",
        ),
        (
            "mu_T = [[400.0, 1.0], [300.0, 0.5]]",
            "mu_T",
            "strictly increasing",
        ),
        ("mu_fn = [[0.0, -1.0]]", "mu_fn", "factors must be >= 0"),
        (
            "peak = 1.0, peak_T = [[300.0, 1.0], [400.0, 0.8]]",
            "peak_T",
            "peak*factor must stay >= 1",
        ),
        (
            "mu_table = [[0.0, 300.0], [0.0, 0.5], [0.0, 0.4]]",
            "mu_table",
            "strictly increasing",
        ),
        (
            "mu_table = [[0.0, 400.0, 300.0], [0.0, 0.5, 0.4]]",
            "mu_table",
            "temperatures",
        ),
        (
            "mu_table = [[0.0, 300.0], [0.0, -0.5]]",
            "mu_table",
            "coefficients must be >= 0",
        ),
        (
            "mu_table = [[0.0, 300.0, 400.0], [0.0, 0.5]]",
            "mu_table",
            "columns",
        ),
        ("mu_table = [[0.0, 300.0]]", "mu_table", "at least one row"),
        (
            "mu_table = [[0.0, 300.0], [0.0, 0.5]], mu_pos = [[0.0, 0.5]]",
            "mu_table",
            "not both",
        ),
        (
            "mu_table = [[0.0, 300.0], [0.0, 0.5]], mu_T = [[300.0, 1.0]]",
            "mu_table",
            "not both",
        ),
    ];
    for (brake, param, words) in cases {
        let e = refused(&with_brake(brake));
        assert!(
            e.contains("brake") && e.contains(param) && e.contains(words),
            "{brake}: {e}"
        );
    }
}

#[test]
fn a_fade_that_reads_the_temperature_needs_a_heat_capacitor_or_fixed_temperature() {
    // no heat port at all
    let text =
        with_brake("mu_T = [[300.0, 1.0]]").replace("useHeatPort = true", "useHeatPort = false");
    let e = refused(&text.replace(", [\"brake.heatPort\", \"cap.port\"]", ""));
    assert!(
        e.contains("brake") && e.contains("mu_T") && e.contains("useHeatPort = true"),
        "{e}"
    );
    // a heat port connected to nothing
    let e = refused(
        &with_brake("peak_T = [[300.0, 1.0]]").replace(", [\"brake.heatPort\", \"cap.port\"]", ""),
    );
    assert!(
        e.contains("brake.peak_T needs brake.heatPort connected"),
        "{e}"
    );
    // a heat port whose temperature is algebraic (a conductor to a fixed temperature)
    let text = with_brake("mu_T = [[300.0, 1.0]]")
        .replace("[\"brake.heatPort\", \"cap.port\"]", "[\"brake.heatPort\", \"g.port_a\"], [\"g.port_b\", \"amb.port\"]")
        .replace("cap = { type = \"HeatCapacitor\", C = 10.0 }", "g = { type = \"ThermalConductor\", G = 1.0 }\namb = { type = \"FixedTemperature\", T = 300.0 }");
    let e = refused(&text);
    assert!(
        e.contains(
            "brake.mu_T needs brake.heatPort connected to a HeatCapacitor or a FixedTemperature"
        ),
        "{e}"
    );
    // mu_fn alone reads no temperature: no heat port needed
    let text =
        with_brake("mu_fn = [[0.0, 1.0]]").replace("useHeatPort = true", "useHeatPort = false");
    let spec = ModelSpec::from_toml(
        &text.replace(", [\"brake.heatPort\", \"cap.port\"]", ""),
        ".",
    )
    .unwrap();
    simulate(&spec).unwrap();
}

/// A OneWayClutch slipping forward (w_rel = w0 > 0) with `mu_fn` holding a factor of 0.5 at its
/// normal force: it stops the disc at `J·w0/(0.5·mu0·fn)`.
#[test]
fn a_one_way_clutch_takes_the_fade_factors_too() {
    let text = r#"
name = "freewheel"
connect = [["ground.flange", "clutch.flange_a"], ["clutch.flange_b", "disc.flange_a"], ["press.y", "clutch.f_normalized"]]

[experiment]
StopTime = 1.0
Interval = 0.01
Tolerance = 1e-12

[components]
ground = { type = "Fixed" }
disc = { type = "Inertia", J = 2.0, w = { start = 10.0, fixed = true } }
clutch = { type = "OneWayClutch", fn_max = 100.0, mu_pos = [[0.0, 0.5]], mu_fn = [[0.0, 1.0], [200.0, 0.0]] }
press = { type = "Constant", k = 1.0 }
"#;
    let r = run(text);
    let t_stop = 2.0 * 10.0 / (0.5 * 0.5 * 100.0);
    assert_rel(
        "w at 0.4 s",
        at(&r, "disc.w", 0.4),
        10.0 - 0.4 / t_stop * 10.0,
        1e-9,
    );
    assert_rel("stop", first(&r, "clutch.stuck", true), t_stop, 1e-8);
    audit_closes(&r);
}
