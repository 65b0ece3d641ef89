//! Mode changes refactor only what they changed (`linalg::Refactor` through
//! `engine::ModeSolver`): over a sequence of modes of a large ladder — locks added and removed
//! one or several at a time, two brakes on one shaft whose second lock is dependent — the
//! incremental factors solve bit for bit as a factorization from scratch in the same order, and
//! to round-off as the dense LU (a LossyGear's non-symmetric column included); a change of one element redoes a few elimination steps only.

use stiction_core::CompiledModel;
use stiction_core::DenseLu;
use stiction_core::ModeKey;
use stiction_core::ModeMatrix;
use stiction_core::ModeSolver;
use stiction_core::ModelSpec;
use stiction_core::System;

/// N inertias joined alternately by clutches and spring-dampers, a brake on every fourth, a
/// second brake on the last inertia's shaft (its lock is dependent when both hold) and a
/// LossyGear from it to one more inertia.
fn ladder(n: usize) -> String {
    let mut comps = vec![
        "drive = { type = \"ConstantTorque\", tau_constant = 10.0 }".to_string(),
        "on = { type = \"Step\", startTime = 0.0 }".to_string(),
    ];
    let mut conns = vec!["[\"drive.flange\", \"J0.flange_a\"]".to_string()];
    for k in 0..n {
        comps.push(format!(
            "J{k} = {{ type = \"Inertia\", J = {} }}",
            1.0 + 0.01 * k as f64
        ));
        if k % 4 == 3 || k == n - 1 {
            comps.push(format!("brake{k} = {{ type = \"Brake\", fn_max = 50.0 }}"));
            conns.push(format!("[\"J{k}.flange_b\", \"brake{k}.flange_a\"]"));
            conns.push(format!("[\"on.y\", \"brake{k}.f_normalized\"]"));
        }
        if k == 0 {
            continue;
        }
        let link = if k % 2 == 1 { "clutch" } else { "sd" };
        let kind = if k % 2 == 1 {
            "type = \"Clutch\", fn_max = 20.0"
        } else {
            "type = \"SpringDamper\", c = 1000.0, d = 10.0"
        };
        comps.push(format!("{link}{k} = {{ {kind} }}"));
        conns.push(format!("[\"J{}.flange_b\", \"{link}{k}.flange_a\"]", k - 1));
        conns.push(format!("[\"{link}{k}.flange_b\", \"J{k}.flange_a\"]"));
        if k % 2 == 1 {
            conns.push(format!("[\"on.y\", \"clutch{k}.f_normalized\"]"));
        }
    }
    comps.push("extra = { type = \"Brake\", fn_max = 50.0 }".into());
    // a LossyGear: a permanent row whose column follows the loss slope (non-symmetric)
    comps.push(
        "gear = { type = \"LossyGear\", ratio = 2.0, lossTable = [[0.0, 0.8, 0.7, 1.0, 1.0]] }"
            .into(),
    );
    comps.push("Jg = { type = \"Inertia\", J = 0.5 }".into());
    conns.push(format!("[\"J{}.flange_b\", \"gear.flange_a\"]", n - 1));
    conns.push("[\"gear.flange_b\", \"Jg.flange_a\"]".into());
    conns.push(format!("[\"J{}.flange_b\", \"extra.flange_a\"]", n - 1));
    conns.push("[\"on.y\", \"extra.f_normalized\"]".into());
    format!(
        "name = \"Ladder\"\nconnect = [\n{}\n]\n[components]\n{}\n",
        conns.join(",\n"),
        comps.join("\n")
    )
}

fn system(n: usize) -> std::sync::Arc<System> {
    let dir = std::path::Path::new(".");
    let spec = ModelSpec::from_toml(&ladder(n), dir).expect("valid model");
    CompiledModel::new(spec).expect("compiles").system()
}

fn keys(locked: &[bool]) -> Vec<ModeKey> {
    (locked.iter())
        .map(|&locked| ModeKey { locked, slope: 0.0 })
        .collect()
}

fn solution(mm: &ModeMatrix) -> Vec<f64> {
    let mut x: Vec<f64> = (0..mm.size)
        .map(|i| ((i * 7 % 13) as f64 - 6.0) * 0.3)
        .collect();
    mm.solve(&mut x);
    x
}

#[test]
fn incremental_factors_equal_factors_from_scratch() {
    let sys = system(80);
    let count = sys.switching.len();
    let mut incremental = ModeSolver::default();
    let mut locked = vec![false; count];
    let named = |name: &str| (sys.switching.iter()).position(|e| e.name() == name);
    let (x, y) = (
        named("extra").expect("extra"),
        named("brake79").expect("brake79"),
    );
    let gear = named("gear").expect("gear");
    // a pseudo-random walk over modes: mostly one element at a time, sometimes several
    let mut seed: u64 = 12345;
    let mut small_changes = Vec::new();
    for step in 0..120 {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let flips = if step % 10 == 9 { 5 } else { 1 };
        for f in 0..flips {
            let k = ((seed >> (17 + 7 * f)) as usize) % count;
            locked[k] = !locked[k];
        }
        // now and then both brakes on the last shaft: the second lock is dependent
        if step % 7 == 0 {
            locked[x] = true;
            locked[y] = true;
        }
        let mut mode = keys(&locked);
        // the gear rolling with a loss slope, stuck, or ideal: changed with the several flips
        // (steps 9, 19, …)
        mode[gear] = ModeKey {
            locked: (step + 1) / 10 % 3 == 2,
            slope: [0.25, -0.4, 0.0][(step + 1) / 10 % 3],
        };
        let a = ModeMatrix::factor(&sys, &mode, 0.0, &mut incremental).expect("regular");
        let b = ModeMatrix::factor(&sys, &mode, 0.0, &mut ModeSolver::default()).expect("regular");
        let dense = ModeSolver::with(Box::new(DenseLu));
        let c = ModeMatrix::factor(&sys, &mode, 0.0, &mut { dense }).expect("regular");
        assert_eq!(a.size, c.size);
        let (xa, xb, xc) = (solution(&a), solution(&b), solution(&c));
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&xa),
            bits(&xb),
            "mode {step}: incremental differs from scratch"
        );
        let err = xa
            .iter()
            .zip(&xc)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-9, "mode {step}: {err} from the dense LU");
        if locked[x] && locked[y] {
            let rows = [a.element_rows[x].lock, a.element_rows[y].lock];
            assert_eq!(
                rows.iter().flatten().count(),
                1,
                "one of the two locks holds"
            );
        }
        if flips == 1 {
            small_changes.push(incremental.last_steps().expect("banded"));
        }
    }
    // one element's change redoes a window around its rows, not the ~220 slots
    small_changes.sort_unstable();
    let median = small_changes[small_changes.len() / 2];
    assert!(median <= 32, "median steps per single change: {median}");
}
