//! The resumable `Simulation`: advanced in pieces it gives one call's result bit for bit; a
//! model input set between pieces acts from that instant through an event; a saved state
//! continues as the original, and the same bit for bit wherever it is restored; misuse is a
//! typed error, never a panic.

mod common;

use common::flywheel_with_input;
use stiction_core::Simulation;
use stiction_core::{ModelSpec, SimError, SimResult};

const COUPLED: &str = include_str!("../../../examples/msl/CoupledClutches.toml");
const FLYWHEEL: &str = common::FLYWHEEL;

fn spec(text: &str) -> ModelSpec {
    ModelSpec::from_toml(text, ".").expect("the model parses")
}

/// Asserts two results have the same names, rows, values (bit for bit) and events.
fn assert_identical(a: &SimResult, b: &SimResult) {
    assert_eq!(a.names, b.names);
    let (ta, tb) = (a.column("time").unwrap(), b.column("time").unwrap());
    if let Some(row) = (0..ta.len().min(tb.len())).find(|&r| ta[r] != tb[r]) {
        panic!(
            "rows differ from row {row}: {:?} vs {:?}",
            &ta[row.saturating_sub(2)..(row + 3).min(ta.len())],
            &tb[row.saturating_sub(2)..(row + 3).min(tb.len())]
        );
    }
    assert_eq!(a.rows(), b.rows());
    assert_eq!(a.events, b.events);
    for name in &a.names {
        let (x, y) = (a.column(name).unwrap(), b.column(name).unwrap());
        for (row, (u, v)) in x.iter().zip(&y).enumerate() {
            assert!(
                u.to_bits() == v.to_bits(),
                "{name} differs at row {row}: {u} vs {v}"
            );
        }
    }
}

#[test]
fn advancing_in_pieces_is_bit_identical_to_one_call() {
    let whole = stiction_core::simulate(&spec(COUPLED)).unwrap();
    // pieces of uneven length, some ending on grid points and on event instants
    let mut sim = Simulation::from_spec(&spec(COUPLED)).unwrap();
    let mut targets: Vec<f64> = (1..=97).map(|k| k as f64 * 0.0153).collect();
    targets.extend([0.4, 0.9, 1.25, 1.5]);
    targets.sort_by(f64::total_cmp);
    for t in targets {
        sim.advance_to(t).unwrap();
        assert_eq!(sim.time(), t);
        // reading in between changes nothing
        let w = sim.get("J1.w").unwrap();
        assert!(w.is_finite());
    }
    assert!(sim.finished());
    let pieces = sim.into_result();
    assert_identical(&whole, &pieces);
    assert_eq!(whole.stats.steps, pieces.stats.steps);
}

#[test]
fn values_read_between_pieces_are_those_of_the_result() {
    let whole = stiction_core::simulate(&spec(COUPLED)).unwrap();
    let mut sim = Simulation::from_spec(&spec(COUPLED)).unwrap();
    let times = whole.column("time").unwrap();
    let w1 = whole.column("J1.w").unwrap();
    let tau = whole.column("clutch1.tau").unwrap();
    for row in [10, 333, 1234, 2999] {
        sim.advance_to(times[row]).unwrap();
        assert_eq!(sim.get("J1.w").unwrap().to_bits(), w1[row].to_bits());
        assert!((sim.get("clutch1.tau").unwrap() - tau[row]).abs() <= 1e-12);
    }
}

#[test]
fn an_input_set_between_pieces_acts_from_that_instant() {
    let mut sim = Simulation::from_spec(&spec(&flywheel_with_input())).unwrap();
    assert_eq!(sim.inputs(), vec![("brake.f_normalized".to_string(), 0.0)]);
    sim.advance_to(0.5).unwrap();
    let w_before = sim.get("flywheel.w").unwrap();
    assert!(
        (w_before - 100.0).abs() < 1e-9,
        "no braking before the input"
    );
    sim.set_input("brake.f_normalized", 1.0).unwrap();
    // the same value again is no event
    sim.set_input("brake.f_normalized", 1.0).unwrap();
    sim.advance_to(5.0).unwrap();
    let r = sim.into_result();
    assert_eq!(r.stats.input_events, 1);
    let engaged = r
        .events
        .iter()
        .find(|e| e.component == "brake" && e.cause.starts_with("input"))
        .expect("the brake engages at the input event");
    assert_eq!(engaged.time, 0.5);

    // the same run with the force as a step at 0.5 s (a time event instead)
    let stepped = FLYWHEEL.replace(
        "type = \"Ramp\", height = 1.0, duration = 0.2, startTime = 0.5",
        "type = \"Step\", height = 1.0, startTime = 0.5",
    );
    let reference = stiction_core::simulate(&spec(&stepped)).unwrap();
    let (t_in, w_in) = (r.column("time").unwrap(), r.column("flywheel.w").unwrap());
    let (t_ref, w_ref) = (
        reference.column("time").unwrap(),
        reference.column("flywheel.w").unwrap(),
    );
    // compare on the output grid (event rows differ where the stop instants differ slightly)
    let mut compared = 0;
    for (r, t) in t_ref.iter().enumerate() {
        if let Some(k) = t_in.iter().position(|u| u == t) {
            let (a, b) = (w_in[k], w_ref[r]);
            assert!((a - b).abs() <= 1e-4, "at {t}: {a} vs {b}");
            compared += 1;
        }
    }
    assert!(compared >= 5000, "{compared} rows compared");
    let stop = |events: &[stiction_core::EventRecord]| {
        events
            .iter()
            .find(|e| e.component == "brake" && e.new_mode == 0 && e.time > 0.5)
            .map(|e| e.time)
            .expect("the flywheel stops")
    };
    assert!((stop(&r.events) - stop(&reference.events)).abs() < 1e-6);
}

#[test]
fn a_saved_state_continues_as_the_original() {
    let mut sim = Simulation::from_spec(&spec(COUPLED)).unwrap();
    sim.advance_to(0.7).unwrap();
    let saved = sim.state().unwrap();
    let at_saving = sim.get("J3.w").unwrap();
    sim.advance_to(1.3).unwrap();
    let later: Vec<f64> = sim.values().unwrap();
    sim.set_state(&saved).unwrap();
    assert_eq!(sim.time(), 0.7);
    assert_eq!(sim.get("J3.w").unwrap(), at_saving);
    sim.advance_to(1.3).unwrap();
    let again = sim.values().unwrap();
    let names = sim.names();
    for name in [
        "J1.w",
        "J2.w",
        "J3.w",
        "J4.w",
        "clutch1.mode",
        "clutch3.mode",
    ] {
        let k = names.iter().position(|n| n == name).unwrap();
        assert!(
            (later[k] - again[k]).abs() <= 1e-5 * later[k].abs().max(1.0),
            "{name}: {} vs {}",
            later[k],
            again[k]
        );
    }
    // reset starts over
    sim.reset().unwrap();
    assert_eq!(sim.time(), 0.0);
    sim.run().unwrap();
    let fresh = stiction_core::simulate(&spec(COUPLED)).unwrap();
    assert_identical(&fresh, &sim.into_result());
}

#[test]
fn misuse_is_a_typed_error() {
    let mut sim = Simulation::from_spec(&spec(COUPLED)).unwrap();
    sim.advance_to(0.5).unwrap();
    assert!(matches!(sim.advance_to(0.4), Err(SimError::Usage(_))));
    assert!(matches!(sim.advance_to(f64::NAN), Err(SimError::Usage(_))));
    assert!(matches!(sim.advance_to(2.0), Err(SimError::Usage(_))));
    let e = sim.set_input("clutch1.f_normalized", 1.0).unwrap_err();
    assert!(e.to_string().contains("not an input"), "{e}");
    assert!(matches!(sim.get("J9.w"), Err(SimError::Usage(_))));
    sim.cancel();
    let e = sim.advance_to(1.0).unwrap_err();
    assert!(matches!(e, SimError::Cancelled { .. }), "{e}");
    assert_eq!(e.kind(), "SimulationCancelled");
}

#[test]
fn inputs_are_declared_unconnected_signal_inputs() {
    // undeclared and unconnected: still an error
    let open = FLYWHEEL.replace("  [\"press.y\", \"brake.f_normalized\"],\n", "");
    let e = Simulation::from_spec(&spec(&open)).err().expect("refused");
    assert!(e.to_string().contains("not connected"), "{e}");
    // declared but connected
    let both = FLYWHEEL.replace(
        "name = \"braked_flywheel\"",
        "name = \"braked_flywheel\"\ninputs = [\"brake.f_normalized\"]",
    );
    let e = Simulation::from_spec(&spec(&both)).err().expect("refused");
    assert!(e.to_string().contains("left unconnected"), "{e}");
    // not a signal input
    let flange = flywheel_with_input().replace(
        "inputs = [\"brake.f_normalized\"]",
        "inputs = [\"brake.f_normalized\", \"flywheel.flange_a\"]",
    );
    let e = Simulation::from_spec(&spec(&flange))
        .err()
        .expect("refused");
    assert!(e.to_string().contains("signal input port"), "{e}");
    // a start value other than 0
    let started = flywheel_with_input().replace(
        "inputs = [\"brake.f_normalized\"]",
        "inputs = [{ port = \"brake.f_normalized\", start = 1.0 }]",
    );
    let mut sim = Simulation::from_spec(&spec(&started)).unwrap();
    sim.advance_to(0.1).unwrap();
    assert!(
        sim.get("flywheel.w").unwrap() < 100.0,
        "braking from the start"
    );
}

#[test]
fn the_model_file_carries_its_format_version() {
    let v1 = format!("format = 1\n{COUPLED}");
    assert!(ModelSpec::from_toml(&v1, ".").is_ok());
    let v2 = format!("format = 2\n{COUPLED}");
    let e = ModelSpec::from_toml(&v2, ".").unwrap_err();
    assert!(e.to_string().contains("format 2 is newer"), "{e}");
}

#[test]
fn every_msl_example_advanced_in_pieces_is_bit_identical() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
    for name in [
        "Friction",
        "SimpleGearShift",
        "HeatLosses",
        "OneWayClutch",
        "LossyGearDemo2",
        "CompareBrakingTorque",
    ] {
        let text = std::fs::read_to_string(format!("{dir}/{name}.toml")).unwrap();
        let spec = ModelSpec::from_toml(&text, dir).unwrap();
        let whole = stiction_core::simulate(&spec).unwrap();
        let mut sim = Simulation::from_spec(&spec).unwrap();
        let stop = spec.experiment.stop_time;
        let piece = stop / 37.3;
        let mut t = 0.0;
        while t < stop {
            t = (t + piece).min(stop);
            sim.advance_to(t).unwrap();
        }
        assert!(sim.finished(), "{name}");
        assert_identical(&whole, &sim.into_result());
    }
}

#[test]
fn advancing_in_wall_clock_slices_is_bit_identical_to_one_call() {
    let spec = spec(COUPLED);
    let whole = stiction_core::simulate(&spec).unwrap();
    let mut sim = Simulation::from_spec(&spec).unwrap();
    let mut slices = 0;
    while !sim
        .advance_for(1.5, std::time::Duration::from_micros(20))
        .unwrap()
    {
        slices += 1;
    }
    assert!(slices > 3, "the run paused between steps: {slices}");
    assert_identical(&sim.into_result(), &whole);
}

const STIFF_SHAFT: &str = include_str!("../../../examples/stiff/StiffShaft.toml");

/// Restores `saved` in `sim` and advances it to `t`: every variable there.
fn continued(sim: &mut Simulation, saved: &stiction_core::SimState, t: f64) -> Vec<f64> {
    sim.set_state(saved).unwrap();
    sim.advance_to(t).unwrap();
    sim.values().unwrap()
}

#[test]
fn a_saved_state_continues_the_same_wherever_it_is_restored() {
    // CoupledClutches (explicit throughout) and the stiff shaft, saved before and after its
    // change to the implicit method (at 0.32 ms) and restored where the other method runs
    for (text, saved_at, later, end) in [
        (COUPLED, 0.7, 1.3, 1.5),
        (STIFF_SHAFT, 1e-4, 0.3, 0.5),
        (STIFF_SHAFT, 0.3, 0.31, 0.5),
    ] {
        let mut original = Simulation::from_spec(&spec(text)).unwrap();
        original.advance_to(saved_at).unwrap();
        let saved = original.state().unwrap();
        original.advance_to(later).unwrap();
        let here = continued(&mut original, &saved, end);
        let mut fresh = Simulation::from_spec(&spec(text)).unwrap();
        assert_eq!(
            continued(&mut fresh, &saved, end),
            here,
            "fresh run, {saved_at}"
        );
        fresh.reset().unwrap();
        fresh.advance_to(saved_at / 2.0).unwrap();
        assert_eq!(
            continued(&mut fresh, &saved, end),
            here,
            "after reset, {saved_at}"
        );
    }
}

#[test]
fn a_run_that_stops_at_its_state_events_is_the_same_run() {
    let whole = stiction_core::simulate(&spec(COUPLED)).unwrap();
    let mut sim = Simulation::from_spec(&spec(COUPLED)).unwrap();
    sim.set_stop_at_events(true);
    let mut stops = Vec::new();
    while sim.time() < 1.5 {
        sim.advance_to(1.5).unwrap();
        stops.push(sim.time());
    }
    // each stop but the end is at a logged mode change, or a hair before one (a start flag)
    for t in &stops[..stops.len() - 1] {
        let at_event = whole.events.iter().any(|e| (e.time - t).abs() < 1e-9);
        assert!(at_event, "{t} is not at an event");
    }
    assert!(stops.len() >= 8, "{stops:?}");
    let names = sim.names();
    let end = whole.rows() - 1;
    for (k, v) in sim.values().unwrap().iter().enumerate() {
        assert_eq!(*v, whole.column(&names[k]).unwrap()[end], "{}", names[k]);
    }
}
