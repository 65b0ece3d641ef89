//! The evaluation split for the crossing searches and the event iteration
//! (`evaluate_switching`, completed by `heat_and_energy`) against the whole `evaluate`, and
//! the grid rows' quartic (its AVX build where the CPU has it) against the single-row one.

use std::mem::MaybeUninit;

use super::Simulation;
use crate::assembly::CompiledModel;
use crate::engine::eval::{evaluate, evaluate_switching, heat_and_energy, Workspace};
use crate::engine::{indicator_count, indicators};
use crate::model::ModelSpec;

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Everything an evaluation leaves in a workspace that a reader may take, as bits.
fn read(ws: &Workspace) -> Vec<Vec<u64>> {
    let elements = (ws.elements.iter())
        .flat_map(|v| [v.phi, v.w, v.a, v.tau, v.sa, v.loss, v.tau_loss, v.slope])
        .collect::<Vec<_>>();
    [
        &ws.phi[..],
        &ws.w,
        &ws.a,
        &ws.signals,
        &ws.law_tau,
        &ws.law_loss,
        &ws.constraint_tau,
        &elements,
        &ws.heat_in,
        &ws.temps,
        &ws.heat_net,
        &ws.energy,
        &[ws.rates.0, ws.rates.1],
        &ws.wear,
    ]
    .iter()
    .map(|v| bits(v))
    .collect()
}

/// Along HeatLosses' run (every kind of switching element, a heat network, modes changing at
/// 161 events), at the state where each advance stops and in its mode: the crossing
/// indicators from `evaluate_switching` are `evaluate`'s bit for bit, and completed, the whole
/// workspace is.
#[test]
fn switching_evaluation_completed_is_the_whole_evaluation() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
    let text = std::fs::read_to_string(format!("{dir}/HeatLosses.toml")).expect("example");
    let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
    let sys = CompiledModel::new(spec).expect("builds").system();
    let mut sim = Simulation::new(sys.clone()).expect("starts");
    let nz = indicator_count(&sys);
    let mut modes = std::collections::HashSet::new();
    for k in 1..=40 {
        sim.advance_to(0.025 * k as f64).expect("runs");
        let x = sim.stepper.x.clone();
        let phase = sim.stepper.phase.borrow();
        let (t, disc, mm, horizon) = (sim.stepper.now, &phase.disc, &phase.mm, phase.horizon);
        modes.insert(format!(
            "{:?}",
            disc.switching
                .iter()
                .map(|s| s.pre.mode)
                .collect::<Vec<_>>()
        ));
        let (mut whole, mut split) = (Workspace::new(&sys), Workspace::new(&sys));
        let (mut z_whole, mut z_split) = (vec![0.0; nz], vec![0.0; nz]);
        evaluate(&sys, mm, disc, t, &x, horizon, &mut whole);
        indicators(&sys, disc, &whole, &mut z_whole);
        evaluate_switching(&sys, mm, disc, t, &x, horizon, &mut split);
        indicators(&sys, disc, &split, &mut z_split);
        assert_eq!(bits(&z_whole), bits(&z_split), "indicators at t = {t}");
        heat_and_energy(&sys, disc, &x, &mut split);
        assert_eq!(read(&whole), read(&split), "workspace at t = {t}");
        let all = |ws: &Workspace| format!("{:?}", ws.elements);
        assert_eq!(all(&whole), all(&split), "element values at t = {t}");
    }
    assert!(modes.len() > 3, "the run went through few modes: {modes:?}");
}

/// The grid rows' block evaluation (into written and into unwritten memory, on this CPU's
/// build) is the single-row quartic bit for bit, at the step's end too, with a state count
/// that leaves a remainder after four lanes.
#[test]
fn grid_rows_equal_single_rows() {
    use super::dense::{Stages, StepPoly};
    let n = 11;
    let f = |t: f64, j: usize| (1.0 + j as f64 * 0.37 + t).sin() * (j as f64 + 0.5);
    let (t0, t1) = (0.3, 0.3137);
    let y0: Vec<f64> = (0..n).map(|j| f(t0, j) * 0.1).collect();
    let y1: Vec<f64> = (0..n).map(|j| f(t1, j) * 0.1).collect();
    let mut stages = Stages::default();
    stages.begin(&(0..n).map(|j| f(t0, j)).collect::<Vec<_>>());
    for i in 1..7 {
        stages.record(
            &(0..n)
                .map(|j| f(t0 + 0.002 * i as f64, j))
                .collect::<Vec<_>>(),
        );
    }
    assert!(stages.end());
    let mut poly = StepPoly::default();
    poly.set((t0, &y0), (t1, &y1), &stages);
    let times: Vec<f64> = (0..=23).map(|k| t0 + (t1 - t0) * k as f64 / 22.0).collect();
    let mut written = vec![0.0; times.len() * n];
    assert_eq!(poly.eval_rows(&times, t1, &mut written[..]), written.len());
    let mut room = vec![MaybeUninit::<f64>::uninit(); times.len() * n];
    assert_eq!(poly.eval_rows(&times, t1, &mut room[..]), room.len());
    let mut row = vec![0.0; n];
    for (r, &t) in times.iter().enumerate() {
        poly.eval(t.min(t1), &mut row);
        assert_eq!(bits(&row), bits(&written[r * n..(r + 1) * n]), "row at {t}");
        // SAFETY: `eval_rows` wrote all of `room` (its count checked above)
        let block: Vec<f64> = room[r * n..(r + 1) * n]
            .iter()
            .map(|v| unsafe { v.assume_init() })
            .collect();
        assert_eq!(bits(&row), bits(&block), "row at {t} into unwritten memory");
    }
}
