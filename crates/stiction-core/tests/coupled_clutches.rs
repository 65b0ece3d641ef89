//! The engine alone against the exact switch instants of MSL CoupledClutches (oracle table of
//! the project's reference material, an event-driven solution at rtol = atol = 1e-12).

use stiction_core::ModelSpec;

const MODEL: &str = include_str!("../../../examples/msl/CoupledClutches.toml");

/// (time, clutch, new mode) after initialization, from the oracle table.
const SWITCHES: &[(f64, &str, i8)] = &[
    (0.4, "clutch2", -1),
    (0.7096214746937467, "clutch2", 0),
    (0.791662359154753, "clutch1", 0),
    (0.8311085061376531, "clutch1", -1),
    (0.9, "clutch3", -1),
    (0.9068501927975855, "clutch1", 0),
    (1.0002958598946388, "clutch1", -1),
    (1.1439674924731575, "clutch3", 0),
    (1.25, "clutch1", 2),
];

fn run(tolerance: f64) -> stiction_core::SimResult {
    let mut spec = ModelSpec::from_toml(MODEL, ".").expect("the example parses");
    spec.experiment
        .set("Tolerance", tolerance)
        .expect("a valid setting");
    stiction_core::simulate(&spec).expect("the example simulates")
}

#[test]
fn switch_instants_match_the_exact_solution() {
    let r = run(1e-10);
    let switches: Vec<_> = r.events.iter().filter(|e| e.old_mode != 3).collect();
    assert_eq!(switches.len(), SWITCHES.len(), "{:#?}", r.events);
    for (event, &(time, clutch, mode)) in switches.iter().zip(SWITCHES) {
        assert_eq!((event.component.as_str(), event.new_mode), (clutch, mode));
        assert!(
            (event.time - time).abs() < 1e-8,
            "{clutch} at {} instead of {time}",
            event.time
        );
    }
}

#[test]
fn final_speeds_match_the_exact_solution() {
    let r = run(1e-10);
    let last = |name: &str| {
        *r.column(name)
            .expect("a result column")
            .last()
            .expect("rows")
    };
    let j1 = last("J1.w");
    let j2 = j1 + last("clutch1.w_rel");
    assert!((j1 - 3.247058272418844).abs() < 1e-7, "J1.w = {j1}");
    assert!((j2 - 2.4631871666495124).abs() < 1e-7, "J2.w = {j2}");
    assert!((last("J4.w") - 2.4631871666495133).abs() < 1e-7);
}

#[test]
fn energy_balances_to_solver_tolerance() {
    let r = run(1e-8);
    let col = |name: &str| r.column(name).expect("a result column");
    let (kin, pot, loss, work) = (
        col("system.kineticEnergy"),
        col("system.potentialEnergy"),
        col("system.dissipatedEnergy"),
        col("system.sourceWork"),
    );
    let e0 = kin[0] + pot[0];
    for i in 0..kin.len() {
        let balance = kin[i] + pot[i] + loss[i] - work[i];
        assert!(
            (balance - e0).abs() < 1e-6 * e0,
            "row {i}: {balance} vs {e0}"
        );
    }
}
