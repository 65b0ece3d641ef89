//! `MassWithStopAndFriction` (issue 31) against closed forms: pushed from rest by a constant
//! force F against Coulomb friction alone, it reaches its stop at
//! `t = sqrt(2·m·(smax − L/2 − s0)/(F − F_Coulomb))`, is put there at rest (MSL's `reinit`) and
//! stays; the kinetic energy the stop removes counts as dissipated, so the run's energy closes,
//! and the element's own audit;
//! bad parameters are refused by name.

use stiction_core::{simulate, ModelSpec, SimResult};

fn spec(text: &str) -> Result<ModelSpec, String> {
    ModelSpec::from_toml(text, ".").map_err(|e| e.to_string())
}

fn run(text: &str) -> SimResult {
    simulate(&spec(text).unwrap()).unwrap()
}

fn col(r: &SimResult, name: &str) -> Vec<f64> {
    r.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn pushed(force: f64, extra: &str) -> String {
    format!(
        r#"
name = "stop"
connect = [["push.flange", "mass.flange_a"]]

[experiment]
StopTime = 3.0
Interval = 0.01
Tolerance = 1e-10

[components]
push = {{ type = "Translational.ConstantForce", f_constant = {force} }}
mass = {{ type = "Translational.MassWithStopAndFriction", m = 2.0, L = 0.2, smax = 1.1, smin = -1.0, F_prop = 0.0, F_Coulomb = 3.0, F_Stribeck = 0.0, fexp = 2.0, s = {{ start = 0.0, fixed = true }}, v = {{ start = 0.0, fixed = true }}{extra} }}
"#
    )
}

#[test]
fn a_pushed_mass_hits_its_stop_at_the_closed_form_instant_and_stays() {
    let (f, fc, m, l, smax) = (10.0, 3.0, 2.0, 0.2, 1.1);
    let r = run(&pushed(f, ""));
    let top = smax - l / 2.0;
    let t_hit = (2.0 * m * top / (f - fc)).sqrt();
    let hits: Vec<_> = (r.events.iter())
        .filter(|e| e.cause.contains("hard stop"))
        .collect();
    assert_eq!(hits.len(), 1, "{:#?}", r.events);
    assert!(
        (hits[0].time - t_hit).abs() < 1e-8,
        "{} vs {t_hit}",
        hits[0].time
    );
    // from the stop on: on it, at rest, locked, the friction holding the push
    let (t, s, v) = (col(&r, "time"), col(&r, "mass.s"), col(&r, "mass.v"));
    let locked = col(&r, "mass.locked");
    let f_fric = col(&r, "mass.f");
    let after: Vec<usize> = (0..t.len()).filter(|&i| t[i] > t_hit + 1e-6).collect();
    assert!(after.len() > 100);
    for &i in &after {
        assert!((s[i] - top).abs() < 1e-12, "s = {} at {}", s[i], t[i]);
        assert_eq!(v[i], 0.0, "at {}", t[i]);
        assert_eq!(locked[i], 1.0);
        assert!((f_fric[i] - f).abs() < 1e-9, "f = {}", f_fric[i]);
    }
    // before it: the closed-form parabola
    for i in (0..t.len()).filter(|&i| t[i] < t_hit - 1e-6) {
        let want = 0.5 * (f - fc) / m * t[i] * t[i];
        assert!(
            (s[i] - want).abs() < 1e-8,
            "s({}) = {} vs {want}",
            t[i],
            s[i]
        );
    }
}

#[test]
fn the_kinetic_energy_the_stop_removes_is_dissipated() {
    let (f, fc, m, top) = (10.0, 3.0, 2.0, 1.0);
    let r = run(&pushed(f, ""));
    let (kin, loss, work) = (
        col(&r, "system.kineticEnergy"),
        col(&r, "system.dissipatedEnergy"),
        col(&r, "system.sourceWork"),
    );
    // the balance closes on every row, across the reset too
    for i in 0..kin.len() {
        let balance = kin[i] + loss[i] - work[i];
        assert!(balance.abs() < 1e-7, "row {i}: {balance}");
    }
    // the push did F·top, friction took F_Coulomb·top, the stop the rest: ½·m·v_hit²
    let v_hit2 = 2.0 * (f - fc) / m * top;
    let (work, lost) = (*work.last().unwrap(), *loss.last().unwrap());
    assert!((work - f * top).abs() < 1e-7, "work {work}");
    assert!(
        (lost - (fc * top + 0.5 * m * v_hit2)).abs() < 1e-7,
        "dissipated {lost}"
    );
}

/// The element's own audit holds the reset too: its `dissipated` is its friction loss plus the
/// kinetic energy the stop removed (`reset_loss`), and its energy in equals that (at rest at
/// both ends).
#[test]
fn the_elements_audit_counts_the_reset_as_dissipated() {
    let (f, fc, m, top) = (10.0, 3.0, 2.0, 1.0);
    let r = run(&pushed(f, ""));
    let audit = r.audit();
    let mass = (audit.iter().find(|a| a.component == "mass")).expect("the mass audited");
    let kinetic_at_hit = 0.5 * m * 2.0 * (f - fc) / m * top;
    assert!(
        (mass.reset_loss - kinetic_at_hit).abs() < 1e-7,
        "reset loss {} vs {kinetic_at_hit}",
        mass.reset_loss
    );
    let friction = fc * top;
    assert!(
        (mass.dissipated - (friction + mass.reset_loss)).abs() < 1e-7,
        "dissipated {} vs {friction} + {}",
        mass.dissipated,
        mass.reset_loss
    );
    assert!((mass.energy_in - mass.dissipated).abs() < 1e-7, "{mass:?}");
    // nothing else resets
    for a in audit.iter().filter(|a| a.component != "mass") {
        assert_eq!(a.reset_loss, 0.0, "{a:?}");
    }
}

/// Shaken between its stops by a sine force, the mass hits them again and again: over the run
/// its energy in equals its dissipated plus the kinetic energy it gained, to the trapezoid
/// rule's error on the grid, only with the resets counted (they are a large share).
#[test]
fn a_shaken_mass_between_its_stops_closes_its_audit() {
    let text = pushed(0.0, "")
        .replace(
            r#"push = { type = "Translational.ConstantForce", f_constant = 0 }"#,
            r#"push = { type = "Translational.Force" }
sine = { type = "Sine", amplitude = 80.0, f = 0.5 }"#,
        )
        .replace(
            r#"connect = [["push.flange", "mass.flange_a"]]"#,
            r#"connect = [["push.flange", "mass.flange_a"], ["sine.y", "push.f"]]"#,
        )
        .replace("Interval = 0.01", "Interval = 1e-4")
        .replace("StopTime = 3.0", "StopTime = 6.0");
    let r = run(&text);
    let hits = (r.events.iter())
        .filter(|e| e.cause.contains("hard stop"))
        .count();
    assert!(hits >= 4, "{:#?}", r.events);
    let v = col(&r, "mass.v");
    let gained = 0.5 * 2.0 * (v.last().unwrap().powi(2) - v[0].powi(2));
    let audit = r.audit();
    let mass = (audit.iter().find(|a| a.component == "mass")).expect("the mass audited");
    assert!(mass.reset_loss > 0.1 * mass.dissipated, "{mass:?}");
    let open = mass.energy_in - mass.dissipated - gained;
    assert!(open.abs() < 1e-5 * mass.energy_in, "{open} of {mass:?}");
    let unreset = open + mass.reset_loss;
    assert!(unreset.abs() > 1e3 * open.abs(), "{mass:?}");
    // the run's own balance agrees with the element's
    let lost = *col(&r, "system.dissipatedEnergy").last().unwrap();
    assert!(
        (lost - mass.dissipated).abs() < 1e-5 * lost,
        "{lost} vs {mass:?}"
    );
}

#[test]
fn a_mass_pulled_off_its_upper_stop_slides_to_the_lower_one_and_stays() {
    // started on the upper stop at rest, pulled back by more than f0_max = 1.001·F_Coulomb
    let text = pushed(-7.0, "").replace(
        "start = 0.0, fixed = true }, v",
        "start = 1.0, fixed = true }, v",
    );
    let r = run(&text);
    let s = col(&r, "mass.s");
    let last = *s.last().unwrap();
    // reaches the lower stop smin + L/2 = -0.9 at t = sqrt(2·m·1.9/(7 − 3)) and stays
    assert!((last + 0.9).abs() < 1e-12, "{last}");
    let hit = (r.events.iter().find(|e| e.cause.contains("hard stop"))).expect("a stop");
    let t_hit = (2.0f64 * 2.0 * 1.9 / 4.0).sqrt();
    assert!((hit.time - t_hit).abs() < 1e-8, "{} vs {t_hit}", hit.time);
}

#[test]
fn bad_parameters_are_refused_by_name() {
    for (extra, name) in [
        (", m = 0.0", "m"),
        (", F_Coulomb = -1.0", "F_Coulomb"),
        (", F_Stribeck = -1.0", "F_Stribeck"),
        (", F_prop = -1.0", "F_prop"),
        (", smax = -0.9", "smax"),
    ] {
        let text = pushed(10.0, "").replace("fexp = 2.0,", &format!("fexp = 2.0{extra},"));
        let text = dedupe(&text);
        let err = match spec(&text).and_then(|s| simulate(&s).map_err(|e| e.to_string())) {
            Err(e) => e,
            Ok(_) => panic!("{extra} accepted"),
        };
        assert!(err.contains(name) && err.contains("mass"), "{extra}: {err}");
    }
}

#[test]
fn a_start_outside_the_stops_is_refused_by_name() {
    // s = 1.2 puts the right end at 1.3, beyond smax = 1.1 (MSL's initial assert)
    let text = pushed(10.0, "").replace(
        "start = 0.0, fixed = true }, v",
        "start = 1.2, fixed = true }, v",
    );
    let err = simulate(&spec(&text).unwrap())
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(err.contains("mass") && err.contains("smax"), "{err}");
    let text = pushed(10.0, "").replace(
        "start = 0.0, fixed = true }, v",
        "start = -0.95, fixed = true }, v",
    );
    let err = simulate(&spec(&text).unwrap())
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(err.contains("mass") && err.contains("smin"), "{err}");
}

/// The later of a repeated key wins: drop the earlier one (TOML refuses duplicates).
fn dedupe(text: &str) -> String {
    let mut out = text.to_string();
    for key in ["m", "F_Coulomb", "F_Stribeck", "F_prop", "smax"] {
        let first = format!(" {key} = ");
        let n = out.matches(&first).count();
        if n > 1 {
            let i = out.find(&first).unwrap();
            let end = i + out[i..].find(',').unwrap() + 1;
            out.replace_range(i..end, "");
        }
    }
    out
}
