//! A model is a set: writing its components or connections in another order, or a `connect`
//! the other way round, gives bit-identical results (variables in the order written).

use stiction_core::{simulate, ModelSpec, SimResult};

fn assert_identical(a: &SimResult, b: &SimResult, what: &str) {
    assert_eq!(a.events, b.events, "{what}: events");
    assert_eq!(a.rows(), b.rows(), "{what}: rows");
    for name in &a.names {
        let (x, y) = (a.column(name).unwrap(), b.column(name).unwrap());
        let differ = x
            .iter()
            .zip(&y)
            .position(|(u, v)| u.to_bits() != v.to_bits());
        assert!(differ.is_none(), "{what}: {name} differs at row {differ:?}");
    }
}

#[test]
fn every_msl_example_gives_the_same_result_in_any_order() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/msl");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 10);
    for path in files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
    {
        let text = std::fs::read_to_string(path).unwrap();
        let spec = ModelSpec::from_toml(&text, dir).unwrap();
        let mut reversed = spec.clone();
        reversed.components.reverse();
        reversed.connections.reverse();
        for (a, b) in &mut reversed.connections {
            std::mem::swap(a, b);
        }
        let mut rotated = spec.clone();
        rotated.components.rotate_left(spec.components.len() / 2);
        rotated.connections.rotate_left(spec.connections.len() / 3);
        let what = path.file_name().unwrap().to_string_lossy();
        let base = simulate(&spec).unwrap();
        for other in [&reversed, &rotated] {
            let r = simulate(other).unwrap();
            assert_identical(&base, &r, &what);
        }
        // the variables stay in the order the model was written
        let first = &spec.components[0].name;
        assert!(simulate(&reversed).unwrap().names[1]
            .starts_with(&format!("{}.", reversed.components[0].name)));
        assert!(
            base.names[1].starts_with(&format!("{first}.")),
            "{what}: {}",
            base.names[1]
        );
    }
}
