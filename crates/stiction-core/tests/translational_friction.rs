//! The translational friction and compliant family (issue 31) against closed forms: a block
//! braked on a flat road stops at v0²/(2·mu·g) at t = v0/(mu·g); a mass on a spring with
//! Coulomb support friction loses 2·F_c/k of amplitude per half cycle and sticks at the first
//! turning point where the spring force is within the static friction; the energy audit
//! closes per element (½·m·v², ½·c·s², the friction loss); bad parameters are refused by name.

use stiction_core::{simulate, ModelSpec, SimResult};

const G: f64 = 9.81;

fn run(text: &str) -> SimResult {
    simulate(&ModelSpec::from_toml(text, ".").unwrap()).unwrap()
}

fn col(r: &SimResult, name: &str) -> Vec<f64> {
    r.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn last(r: &SimResult, name: &str) -> f64 {
    *col(r, name).last().unwrap()
}

/// The first time a Boolean-as-real column turns 1 (the interval grid holds event rows too).
fn first_true(r: &SimResult, name: &str) -> f64 {
    let (t, x) = (col(r, "time"), col(r, name));
    t[x.iter().position(|&v| v > 0.5).expect("it turns true")]
}

fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol * want.abs().max(1.0),
        "{what}: {got} vs {want} (off {:e})",
        got - want
    );
}

fn audit_closes(r: &SimResult) {
    let audit = r.audit();
    assert!(!audit.is_empty());
    for a in audit {
        assert!(
            a.residual < 1e-9 * a.scale.max(1.0),
            "{}: {}",
            a.component,
            a.residual
        );
    }
}

/// A block of mass m at v0 on a flat road, braked by `Translational.Brake` with a constant
/// normal force m·g (f_normalized = 1): the friction force is mu·m·g.
fn braked_block(m: f64, v0: f64, mu: f64) -> String {
    format!(
        r#"
name = "block"
connect = [["block.flange_b", "road.flange_a"], ["press.y", "road.f_normalized"]]

[experiment]
StopTime = 3.0
Interval = 0.01
Tolerance = 1e-10

[components]
block = {{ type = "Translational.Mass", m = {m}, s = {{ start = 0.0, fixed = true }}, v = {{ start = {v0}, fixed = true }} }}
road = {{ type = "Translational.Brake", fn_max = {fn_max}, mu_pos = [[0.0, {mu}]] }}
press = {{ type = "Constant", k = 1.0 }}
"#,
        fn_max = m * G
    )
}

#[test]
fn a_braked_block_stops_at_the_closed_form_distance_and_instant() {
    let (m, v0, mu) = (1200.0, 7.5, 0.8);
    let r = run(&braked_block(m, v0, mu));
    let distance = v0 * v0 / (2.0 * mu * G);
    let t_stop = v0 / (mu * G);
    assert_close("block.s", last(&r, "block.s"), distance, 1e-8);
    assert_close("stop instant", first_true(&r, "road.locked"), t_stop, 1e-8);
    // at rest (inside the engine's ±1e-10 m/s event band)
    assert!(last(&r, "block.v").abs() <= 1e-9);
    // sliding, the force is mu·m·g against the motion (road.f = flange force on the block)
    let (t, f) = (col(&r, "time"), col(&r, "road.f"));
    let i = t.iter().position(|&x| x > 0.5 * t_stop).unwrap();
    assert_close("road.f while sliding", f[i], mu * m * G, 1e-12);
    // stopped, nothing pushes: the brake holds with no force
    assert_eq!(last(&r, "road.f"), 0.0);
    // all of ½·m·v0² went into the brake
    let e0 = 0.5 * m * v0 * v0;
    assert_close("dissipated", last(&r, "system.dissipatedEnergy"), e0, 1e-8);
    audit_closes(&r);
}

#[test]
fn the_braked_blocks_energy_heats_the_brake_through_its_heat_port() {
    // the same stop with the brake's heatPort on a heat capacitor: ½·m·v0² raises it by 1/C
    let (m, v0, mu, c) = (2.0, 3.0, 0.5, 4.5);
    let text = braked_block(m, v0, mu)
        .replace(
            r#"["press.y", "road.f_normalized"]]"#,
            r#"["press.y", "road.f_normalized"], ["road.heatPort", "disc.port"]]"#,
        )
        .replace(
            "mu_pos = [[0.0, 0.5]] }",
            &format!(
                "mu_pos = [[0.0, 0.5]], useHeatPort = true }}\ndisc = {{ type = \"HeatCapacitor\", C = {c}, T = 293.15 }}"
            ),
        );
    assert!(text.contains("useHeatPort"), "{text}");
    let r = run(&text);
    let heat = 0.5 * m * v0 * v0;
    assert_close("disc.T", last(&r, "disc.T"), 293.15 + heat / c, 1e-9);
    assert_close(
        "road.heatPort.T",
        last(&r, "road.heatPort.T"),
        293.15 + heat / c,
        1e-9,
    );
    audit_closes(&r);
}

/// A mass on a spring to a wall, with Coulomb friction against its support (`SupportFriction`,
/// a constant `f_pos`), released at rest at s = x0 from the spring's rest position.
fn friction_oscillator(x0: f64) -> String {
    format!(
        r#"
name = "oscillator"
connect = [
  ["wall.flange", "spring.flange_a"],
  ["spring.flange_b", "mass.flange_a"],
  ["mass.flange_b", "friction.flange_a"],
]

[experiment]
StopTime = 3.0
Interval = 0.001
Tolerance = 1e-10

[components]
wall = {{ type = "Translational.Fixed" }}
spring = {{ type = "Translational.Spring", c = {K} }}
mass = {{ type = "Translational.Mass", m = {M}, s = {{ start = {x0}, fixed = true }}, v = {{ start = 0.0, fixed = true }} }}
friction = {{ type = "Translational.SupportFriction", f_pos = [[0.0, {FC}]] }}
"#
    )
}

const M: f64 = 1.0;
const K: f64 = 100.0;
const FC: f64 = 1.0;

#[test]
fn a_spring_mass_with_coulomb_friction_stops_at_the_amplitude_decay_closed_form() {
    let x0 = 0.105;
    let r = run(&friction_oscillator(x0));
    // each half cycle (π·√(m/k)) about the center ±F_c/k takes 2·F_c/k of amplitude: turning
    // points 0.105, −0.085, 0.065, −0.045, 0.025, −0.005; at −0.005 the spring's 0.5 N is
    // within the 1 N of static friction and it sticks there
    let step = 2.0 * FC / K;
    let mut x = x0;
    let mut half_cycles = 0;
    while K * x.abs() > FC {
        x = -(x.abs() - step) * x.signum();
        half_cycles += 1;
    }
    assert_eq!(half_cycles, 5);
    let half_period = std::f64::consts::PI * (M / K).sqrt();
    assert_close("rest position", last(&r, "mass.s"), x, 1e-8);
    assert!(last(&r, "mass.v").abs() <= 1e-9);
    // it turns 4 times (stuck for an instant, sliding on) and sticks for good at the 5th
    let (t, locked) = (col(&r, "time"), col(&r, "friction.locked"));
    let stuck_from = t[locked.iter().rposition(|&l| l < 0.5).unwrap() + 1];
    assert_close(
        "stop instant",
        stuck_from,
        half_cycles as f64 * half_period,
        1e-8,
    );
    // energy: ½·k·x0² = ½·k·x² + the friction's loss (F_c times the path travelled)
    let path: f64 = x0 + 2.0 * (0.085 + 0.065 + 0.045 + 0.025) + 0.005;
    assert_close(
        "dissipated",
        last(&r, "system.dissipatedEnergy"),
        FC * path,
        1e-8,
    );
    assert_close(
        "stored",
        last(&r, "system.potentialEnergy"),
        0.5 * K * x * x,
        1e-8,
    );
    audit_closes(&r);
}

#[test]
fn an_elasto_gap_pushes_but_never_pulls() {
    // a mass at 1 m/s hits a gap contact at the wall: the force is never positive (pulling)
    let text = r#"
name = "gap"
connect = [["wall.flange", "gap.flange_a"], ["gap.flange_b", "mass.flange_a"]]
[experiment]
StopTime = 0.2
Interval = 1e-4
Tolerance = 1e-10
[components]
wall = { type = "Translational.Fixed" }
gap = { type = "Translational.ElastoGap", c = 1e5, d = 400.0, s_rel0 = 0.05 }
mass = { type = "Translational.Mass", m = 1.0, s = { start = 0.1, fixed = true }, v = { start = -1.0, fixed = true } }
"#;
    let r = run(text);
    let f = col(&r, "gap.f");
    assert!(f.iter().all(|&x| x <= 0.0));
    assert!(f.iter().any(|&x| x < -10.0), "it does touch");
    // it bounces back, slower (the damper took some), and leaves the contact
    assert!(last(&r, "mass.v") > 0.0 && last(&r, "mass.v") < 1.0);
    assert_eq!(last(&r, "gap.f"), 0.0);
    let e = 0.5 * last(&r, "mass.v").powi(2);
    assert_close(
        "dissipated",
        last(&r, "system.dissipatedEnergy"),
        0.5 - e,
        1e-7,
    );
    audit_closes(&r);
}

fn error_of(text: &str) -> String {
    match ModelSpec::from_toml(text, ".") {
        Err(e) => e.to_string(),
        Ok(spec) => match simulate(&spec) {
            Ok(_) => panic!("accepted"),
            Err(e) => e.to_string(),
        },
    }
}

#[test]
fn bad_parameters_are_refused_by_name_before_any_run() {
    let block = braked_block(1.0, 1.0, 0.5);
    for (from, to, param) in [
        ("mu_pos = [[0.0, 0.5]]", "mu_pos = [[0.0, -0.5]]", "mu_pos"),
        ("fn_max = 9.81", "fn_max = -1.0", "fn_max"),
        (
            "mu_pos = [[0.0, 0.5]]",
            "mu_pos = [[0.0, 0.5]], peak = 0.5",
            "peak",
        ),
        (
            "mu_pos = [[0.0, 0.5]]",
            "mu_pos = [[0.0, 0.5]], cgeo = -1.0",
            "cgeo",
        ),
    ] {
        let text = block.replace(from, to);
        assert_ne!(text, block, "{to}");
        let e = error_of(&text);
        assert!(e.contains("road") && e.contains(param), "{param}: {e}");
    }
    let osc = friction_oscillator(0.1);
    for (from, to, who, param) in [
        ("c = 100", "c = -100", "spring", "c"),
        (
            "f_pos = [[0.0, 1]]",
            "f_pos = [[0.0, -1.0]]",
            "friction",
            "f_pos",
        ),
        (
            "f_pos = [[0.0, 1]]",
            "f_pos = [[0.0, 1]], v_small = 0.0",
            "friction",
            "v_small",
        ),
        (
            r#""Translational.Spring", c = 100"#,
            r#""Translational.ElastoGap", c = 100, d = 1.0, n = 0.5"#,
            "spring",
            "n",
        ),
        (
            r#""Translational.Spring", c = 100"#,
            r#""Translational.SpringDamper", c = 100, d = -1.0"#,
            "spring",
            "d",
        ),
    ] {
        let text = osc.replace(from, to);
        assert_ne!(text, osc, "{to}");
        let e = error_of(&text);
        assert!(e.contains(who) && e.contains(param), "{param}: {e}");
    }
}
