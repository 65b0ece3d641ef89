//! A saved state, restored, continues exactly (==) as the run that never stopped: saved at
//! several points of CoupledClutches (explicit), right after a state event, in a run driven
//! by input events, under Solver = "auto" after its change to the implicit method, and under
//! Bdf and Esdirk34; restored in a fresh run, after a reset and in the run that saved it, each
//! time from the state's bytes (`SimState::to_bytes`).

mod common;

use common::flywheel_with_input;
use stiction_core::{ModelSpec, SimError};
use stiction_core::{SimState, Simulation};

const COUPLED: &str = include_str!("../../../examples/msl/CoupledClutches.toml");
const FLYWHEEL: &str = common::FLYWHEEL;
const STIFF_SHAFT: &str = include_str!("../../../examples/stiff/StiffShaft.toml");

fn spec(text: &str) -> ModelSpec {
    ModelSpec::from_toml(text, ".").expect("the model parses")
}

/// The model with `[experiment]` Solver set.
fn with_solver(text: &str, solver: &str) -> String {
    text.replace(
        "[experiment]\n",
        &format!("[experiment]\nSolver = \"{solver}\"\n"),
    )
}

/// The brake force a host drives the flywheel with: a ramp from 0.5 s, held at 1 from 1.5 s
/// (a new value at every output point of the ramp: an input event each).
fn force(t: f64) -> f64 {
    (t - 0.5).clamp(0.0, 1.0)
}

/// A run driven from `from` to `to` in steps of `h` as a co-simulation host drives it (the
/// input set at each point, when the model has one): every variable after each step.
fn drive(sim: &mut Simulation, from: usize, to: usize, h: f64) -> Vec<Vec<f64>> {
    let input = sim.inputs().first().map(|(name, _)| name.clone());
    (from..to)
        .map(|k| {
            if let Some(name) = &input {
                sim.set_input(name, force(k as f64 * h)).unwrap();
            }
            sim.advance_to((k + 1) as f64 * h).unwrap();
            sim.values().unwrap()
        })
        .collect()
}

/// Asserts `got` equals the uninterrupted rows from step `from` on, bit for bit.
fn assert_continues(
    got: &[Vec<f64>],
    whole: &[Vec<f64>],
    from: usize,
    names: &[String],
    what: &str,
) {
    for (j, (row, want)) in got.iter().zip(&whole[from..]).enumerate() {
        for (k, (u, v)) in row.iter().zip(want).enumerate() {
            assert!(
                u.to_bits() == v.to_bits(),
                "{what}: {} differs {} steps after the restore: {u} vs {v}",
                names[k],
                j + 1
            );
        }
    }
    assert_eq!(got.len(), whole.len() - from, "{what}");
}

/// Saves the run driven in steps of `h` after each of `points` steps, and checks that the
/// state restored in a fresh run, after a reset (and a different start), and in the run that
/// saved it once it went on, continues as the uninterrupted run to `steps`.
fn check_model(text: &str, h: f64, steps: usize, points: &[usize]) {
    let spec = spec(text);
    let mut whole = Simulation::from_spec(&spec).unwrap();
    let names = whole.names();
    let uninterrupted = drive(&mut whole, 0, steps, h);
    for &at in points {
        let mut original = Simulation::from_spec(&spec).unwrap();
        drive(&mut original, 0, at, h);
        let state = original.state().unwrap();
        // every restore below is from the state's bytes (what Python pickles, what the FMU's
        // serialized states carry): they hold all of it
        let saved = SimState::from_bytes(&state.to_bytes()).expect("its bytes read back");
        assert_eq!(saved, state, "the state read back from its bytes");
        drive(&mut original, at, steps, h); // it goes on, then goes back
        original.set_state(&saved).unwrap();
        let what = format!("{} saved after step {at}", spec.name);
        let back = drive(&mut original, at, steps, h);
        assert_continues(
            &back,
            &uninterrupted,
            at,
            &names,
            &format!("{what}, same run"),
        );
        let mut fresh = Simulation::from_spec(&spec).unwrap();
        let restored_in = |sim: &mut Simulation, label: &str| {
            sim.set_state(&saved).unwrap();
            let got = drive(sim, at, steps, h);
            assert_continues(
                &got,
                &uninterrupted,
                at,
                &names,
                &format!("{what}, {label}"),
            );
        };
        restored_in(&mut fresh, "fresh run");
        fresh.reset().unwrap();
        drive(&mut fresh, 0, at / 2, h);
        restored_in(&mut fresh, "after reset");
    }
}

#[test]
fn coupled_clutches_saved_anywhere_continues_exactly() {
    // 1.5 s in 10 ms steps; the clutches act from 0.1 s on
    check_model(COUPLED, 0.01, 150, &[0, 7, 33, 70, 121]);
}

#[test]
fn a_run_driven_by_input_events_continues_exactly() {
    // the host sets a new force at every step of the ramp (0.5–1.5 s): a hundred input events
    check_model(&flywheel_with_input(), 0.01, 300, &[40, 77, 151, 200]);
}

#[test]
fn the_implicit_methods_continue_exactly() {
    for solver in ["bdf", "esdirk34"] {
        check_model(&with_solver(COUPLED, solver), 0.01, 150, &[45, 90]);
    }
}

#[test]
fn an_auto_run_saved_after_its_change_of_method_continues_exactly() {
    // the stiff shaft changes to the implicit method at 0.32 ms; saved before and after
    let text = STIFF_SHAFT.replace("StopTime = 2.0", "StopTime = 0.8");
    let mut probe = Simulation::from_spec(&spec(&text)).unwrap();
    probe.advance_to(0.8).unwrap();
    assert_eq!(probe.into_result().stats.solver_switches, 1);
    check_model(&text, 0.02, 40, &[0, 1, 15, 30]);
}

/// Saved right after a state event (the run stopped there, FMI 3.0's early return), restored:
/// the same as the run that never stopped at its events.
#[test]
fn a_state_saved_right_after_an_event_continues_exactly() {
    let spec = spec(COUPLED);
    let mut whole = Simulation::from_spec(&spec).unwrap();
    let names = whole.names();
    let uninterrupted = drive(&mut whole, 0, 150, 0.01);
    let mut stopping = Simulation::from_spec(&spec).unwrap();
    stopping.set_stop_at_events(true);
    let mut saved: Vec<SimState> = Vec::new();
    while stopping.time() < 1.5 {
        stopping.advance_to(1.5).unwrap();
        saved.push(stopping.state().unwrap());
    }
    assert!(saved.len() >= 8, "{} stops", saved.len());
    for state in &saved[..saved.len() - 1] {
        let t = state.time();
        let next = (t / 0.01).floor() as usize + 1;
        let mut fresh = Simulation::from_spec(&spec).unwrap();
        fresh.set_state(state).unwrap();
        assert_eq!(fresh.time(), t);
        let got = drive(&mut fresh, next, 150, 0.01);
        let what = format!("saved at the event at {t}");
        assert_continues(&got, &uninterrupted, next, &names, &what);
    }
}

#[test]
fn a_state_of_another_model_is_refused() {
    let mut clutches = Simulation::from_spec(&spec(COUPLED)).unwrap();
    clutches.advance_to(0.4).unwrap();
    let saved = clutches.state().unwrap();
    // the same shape, another tolerance: its replay does not reach the saved state
    let finer = COUPLED.replace("Tolerance = 1e-6", "Tolerance = 1e-9");
    let mut run = Simulation::from_spec(&spec(&finer)).unwrap();
    let e = run.set_state(&saved).unwrap_err();
    assert!(matches!(e, SimError::Usage(_)), "{e}");
    assert!(e.to_string().contains("another model"), "{e}");
    let mut flywheel = Simulation::from_spec(&spec(FLYWHEEL)).unwrap();
    assert!(flywheel.set_state(&saved).is_err());
}
