//! Runs a model file N times and prints the median wall time: `cargo run --release --example
//! run_model -- MODEL.toml [N] [--no-table]`. For profiling the core without Python in the way
//! (`--no-table` leaves out computing every variable, to profile the run alone; `--all` runs
//! recording every variable as it goes, `run_recording_all`; `--column NAME` reads variable
//! NAME of each result in place of every variable). The model is compiled once and run N
//! times, as `Model.simulate` does from Python.

use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: run_model MODEL.toml [N]");
    let n: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(50)
        .max(1);
    let mode = args.next();
    let with_table = mode.as_deref() != Some("--no-table");
    let recording_all = mode.as_deref() == Some("--all");
    let column = (mode.as_deref() == Some("--column")).then(|| args.next().expect("a name"));
    let text = std::fs::read_to_string(&path).expect("readable model file");
    let dir = std::path::Path::new(&path)
        .parent()
        .unwrap_or(std::path::Path::new("."));
    let spec = stiction_core::ModelSpec::from_toml(&text, dir).expect("valid model");
    let model = stiction_core::CompiledModel::new(spec).expect("a model that compiles");
    let (mut run, mut table, mut wall) = (Vec::new(), Vec::new(), Vec::new());
    let mut last = None;
    for _ in 0..n {
        let t0 = Instant::now();
        let r = if recording_all {
            stiction_core::run_recording_all(model.system(), || true)
        } else {
            stiction_core::run(model.system())
        };
        let r = r.expect("simulation");
        run.push(t0.elapsed().as_secs_f64() * 1e3);
        wall.push(r.stats.wall_ms);
        let t1 = Instant::now();
        if let Some(name) = &column {
            std::hint::black_box(r.column(name).expect("a variable of the model"));
        } else if with_table {
            std::hint::black_box(r.table().expect("every variable fits in memory"));
        }
        table.push(t1.elapsed().as_secs_f64() * 1e3);
        last = Some(r);
    }
    run.sort_by(f64::total_cmp);
    table.sort_by(f64::total_cmp);
    wall.sort_by(f64::total_cmp);
    let r = last.expect("at least one run");
    println!(
        "{path}: median {:.3} ms to the result (min {:.3}; simulation alone median {:.3}, min {:.3}), \
         {:.3} ms more for all variables (min {:.3}, 90th percentile {:.3}); rows {}, columns {}, {:?}",
        run[n / 2],
        run[0],
        wall[n / 2],
        wall[0],
        table[n / 2],
        table[0],
        table[n * 9 / 10],
        r.rows(),
        r.names.len(),
        r.stats
    );
}
