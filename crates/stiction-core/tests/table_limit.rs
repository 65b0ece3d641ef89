//! The memory guard: a run keeps only its states, so it is refused only when they do not fit;
//! every variable at once (the table) is refused when asked for, and each variable alone is
//! still computed.

/// Too large for every variable at once: the table refused, each variable alone the same.
#[test]
fn a_table_too_large_is_refused_and_its_columns_come_one_at_a_time() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
    let text = std::fs::read_to_string(format!("{dir}/HeatLosses.toml")).expect("example");
    let spec = stiction_core::ModelSpec::from_toml(&text, dir).expect("valid model");
    let (full, mut r) = (
        stiction_core::simulate(&spec).unwrap(),
        stiction_core::simulate(&spec).unwrap(),
    );
    r.set_table_limit((r.rows() * r.names.len() - 1) as f64);
    let e = r.table().expect_err("refused");
    assert!(e.to_string().contains("more than fits in memory"), "{e}");
    assert_eq!(e.kind(), "UsageError");
    let table = full.table().expect("fits");
    for name in [
        "brake.tau",
        "inertia1.flange_b.tau",
        "system.kineticEnergy",
        "inertia1.w",
    ] {
        let c = r.names.iter().position(|n| n == name).expect(name);
        let alone = r.column(name).expect(name);
        let column = table.iter().skip(c).step_by(r.names.len());
        assert!(
            alone
                .iter()
                .zip(column)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{name}"
        );
    }
}
