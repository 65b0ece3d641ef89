//! Regression (found by the property tests): a locked clutch whose static limit dips below its
//! torque for a few milliseconds inside one long integrator step must break away there. The
//! step's samples showed a hump of the indicator without a sign change; the hump's top is
//! now searched on the dense output.

use stiction_core::{simulate, ModelSpec};

#[test]
fn a_locked_clutch_never_holds_more_than_its_static_limit() {
    let spec = ModelSpec::from_toml(include_str!("locked_hump.toml"), ".").unwrap();
    let r = simulate(&spec).unwrap();
    for clutch in ["c1", "c2", "c3"] {
        let col = |v: &str| r.column(&format!("{clutch}.{v}")).unwrap();
        let (locked, tau, limit) = (col("locked"), col("tau"), col("tau0_max"));
        for k in (0..locked.len()).filter(|&k| locked[k] == 1.0) {
            assert!(
                tau[k].abs() <= limit[k] + 1e-8,
                "{clutch} holds {} > {} at row {k}",
                tau[k].abs(),
                limit[k]
            );
        }
    }
    // c3 breaks away inside the step where f3's force dips (t ≈ 0.677)
    let dip = r
        .events
        .iter()
        .find(|e| e.component == "c3" && (e.time - 0.677).abs() < 2e-3);
    assert!(dip.is_some(), "{:?}", r.events);
}
