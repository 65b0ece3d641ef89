//! The energy audit per element on every MSL example: the power entering each component through
//! its reported flange torques equals what its own equations take (inertia `J·w·a`, laws
//! `tau·w_rel`, friction `lossPower`, gears nothing) at every row, and no passive element ever
//! dissipates negative power.

use stiction_core::{simulate, ModelSpec};

#[test]
fn every_element_of_every_msl_example_balances_its_power() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10);
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap();
        let r = simulate(&ModelSpec::from_toml(&text, dir).unwrap()).unwrap();
        let audits = r.audit();
        // (EddyCurrentBrake: a brake and an inertia)
        assert!(audits.len() >= 2, "{path:?}: {} elements", audits.len());
        // the event band (|w_rel| ≤ 1e-10 while stuck) lets a held torque do about 1e-10·tau of work
        let scale = audits.iter().map(|a| a.scale).fold(1.0, f64::max);
        let allowed = |a: &stiction_core::ElementAudit| 1e-9 * scale + 2e-10 * a.torque;
        for a in &audits {
            eprintln!(
                "{:?} {}: residual {:.2e} of {:.3} W, min dissipation {:.2e}, in {:.4} J, dissipated {:.4} J",
                path.file_stem().unwrap(),
                a.component,
                a.residual,
                a.scale,
                a.min_dissipation,
                a.energy_in,
                a.dissipated
            );
            assert!(
                a.withheld <= 1e-9 * scale + a.torque * a.slip_bound,
                "{path:?} {}: withholds {:.3e} W beyond its slip bound",
                a.component,
                a.withheld
            );
            assert!(
                a.residual <= allowed(a),
                "{path:?} {}: power in and power taken differ by {:.3e} W (scale {scale:.3e})",
                a.component,
                a.residual
            );
            if a.passive {
                assert!(
                    a.min_dissipation >= -allowed(a),
                    "{path:?} {}: a passive element delivered {:.3e} W",
                    a.component,
                    -a.min_dissipation
                );
            }
        }
    }
}
