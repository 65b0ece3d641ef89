//! Parses and compiles a model file N times and prints the median wall time: `cargo run
//! --release --example compile_model -- MODEL.toml [N]`. For profiling what `Model.load` costs
//! in the engine (the TOML parse and the compile), without a run or Python in the way.

use std::time::Instant;

// The Python extension's allocator: the compile allocates in the tens of thousands.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: compile_model MODEL.toml [N]");
    let n: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(50)
        .max(1);
    let text = std::fs::read_to_string(&path).expect("readable model file");
    let dir = std::path::Path::new(&path)
        .parent()
        .unwrap_or(std::path::Path::new("."));
    let (mut parse, mut compile) = (Vec::new(), Vec::new());
    for _ in 0..n {
        let t0 = Instant::now();
        let doc = text.parse::<toml::Table>().expect("a TOML file");
        let spec = stiction_core::ModelSpec::from_table(&doc, dir).expect("valid model");
        parse.push(t0.elapsed().as_secs_f64() * 1e3);
        let t1 = Instant::now();
        let model = stiction_core::CompiledModel::new(spec).expect("a model that compiles");
        compile.push(t1.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(model);
    }
    parse.sort_by(f64::total_cmp);
    compile.sort_by(f64::total_cmp);
    println!(
        "parse+spec {:.3} ms (min {:.3}), compile {:.3} ms (min {:.3}) over {n}",
        parse[n / 2],
        parse[0],
        compile[n / 2],
        compile[0]
    );
}
