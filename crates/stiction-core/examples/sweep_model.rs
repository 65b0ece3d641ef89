//! Runs issue 34's sweep in the core, without Python: `cargo run --release --example
//! sweep_model -- MODEL.toml [N] [WORKERS] [METRIC...]`. The first N variants of the
//! 25×20×20 grid of `clutch1.fn_max` (40…64), `clutch2.fn_max` (40…59) and `J1.J`
//! (0.90…1.09), as the sweep benchmark builds them; prints the wall time. For profiling a
//! sweep's per-variant cost (`valgrind --tool=callgrind`, `perf record`).

use std::time::Instant;

use stiction_core::{run_variants, CancelHandle, CompiledModel, ModelSpec, Override, Plan};

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: sweep_model MODEL.toml [N] [WORKERS] [METRIC...]");
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(10_000);
    let workers: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let mut metrics: Vec<String> = args.collect();
    if metrics.is_empty() {
        metrics = ["max(J1.w)", "max(J4.w)", "events()"]
            .map(String::from)
            .to_vec();
    }
    let text = std::fs::read_to_string(&path).expect("readable model file");
    let dir = std::path::Path::new(&path)
        .parent()
        .unwrap_or(std::path::Path::new("."));
    let spec = ModelSpec::from_toml(&text, dir).expect("valid model");
    let model = CompiledModel::new(spec).expect("a model that compiles");
    let plan = Plan::new(&model, &metrics, &[]).expect("metrics of the model");
    let variants: Vec<Vec<Override>> = (0..n).map(variant).collect();
    let t0 = Instant::now();
    let outcomes = run_variants(
        &model,
        &variants,
        &plan,
        Some(workers),
        &CancelHandle::new(),
    );
    let wall = t0.elapsed().as_secs_f64();
    let failed = outcomes.iter().filter(|o| o.error.is_some()).count();
    let checksum: f64 = outcomes.iter().flat_map(|o| &o.metrics).sum();
    println!(
        "{n} variants on {workers} workers: {wall:.3} s ({failed} failed, checksum {checksum:e})"
    );
}

/// The k-th variant of the grid, in `itertools.product`'s order.
fn variant(k: usize) -> Vec<Override> {
    let (a, b, c) = (k / 400 % 25, k / 20 % 20, k % 20);
    vec![
        ("clutch1.fn_max".into(), toml::Value::Integer(40 + a as i64)),
        ("clutch2.fn_max".into(), toml::Value::Integer(40 + b as i64)),
        ("J1.J".into(), toml::Value::Float(0.9 + 0.01 * c as f64)),
    ]
}
