//! Fuzzing every input the core parses (proptest; cargo-fuzz needs a nightly toolchain): model
//! files mutated at random — lines dropped, duplicated or swapped, numbers replaced by extreme
//! or non-finite values, text cut short, bytes flipped — starting from the shipped examples
//! (the corpus). Whatever comes in, the core answers with a value or a typed error: never a
//! panic, never a hang (runs are short and carry a step limit and a wall-clock timeout).
//! CI runs the default budget; `PROPTEST_CASES=100000 cargo test --release --test fuzz` runs
//! a long campaign.

use std::panic::{catch_unwind, AssertUnwindSafe};

use proptest::prelude::*;
use stiction_core::{simulate, ModelSpec};

/// The corpus: every model file shipped in `examples/`.
fn corpus() -> Vec<String> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples");
    let mut texts = Vec::new();
    for dir in [root.to_string(), format!("{root}/msl")] {
        let mut paths: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        paths.sort();
        for path in paths
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        {
            texts.push(std::fs::read_to_string(path).unwrap());
        }
    }
    assert!(texts.len() >= 10, "the corpus is the shipped examples");
    texts
}

#[derive(Debug, Clone)]
enum Mutation {
    DropLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    Number(usize, f64),
    Truncate(usize),
    FlipByte(usize, u8),
}

const EXTREMES: &[f64] = &[
    0.0,
    -0.0,
    -1.0,
    1e-300,
    -1e300,
    1e300,
    f64::INFINITY,
    f64::NAN,
    1e-9,
    4e7,
];

fn mutation() -> impl Strategy<Value = Mutation> {
    let index = 0usize..10_000;
    prop_oneof![
        index.clone().prop_map(Mutation::DropLine),
        index.clone().prop_map(Mutation::DuplicateLine),
        (index.clone(), index.clone()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        (
            index.clone(),
            prop_oneof![prop::sample::select(EXTREMES), any::<f64>()]
        )
            .prop_map(|(i, v)| Mutation::Number(i, v)),
        index.clone().prop_map(Mutation::Truncate),
        (index, any::<u8>()).prop_map(|(i, b)| Mutation::FlipByte(i, b)),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let n = lines.len().max(1);
    match *m {
        Mutation::DropLine(i) if !lines.is_empty() => {
            lines.remove(i % n);
        }
        Mutation::DuplicateLine(i) if !lines.is_empty() => {
            let line = lines[i % n].clone();
            lines.insert(i % n, line);
        }
        Mutation::SwapLines(a, b) if !lines.is_empty() => lines.swap(a % n, b % n),
        Mutation::Number(i, v) => {
            let numbers: Vec<(usize, usize, usize)> = lines
                .iter()
                .enumerate()
                .flat_map(|(l, line)| number_spans(line).into_iter().map(move |(s, e)| (l, s, e)))
                .collect();
            if let Some(&(l, s, e)) = numbers.get(i % numbers.len().max(1)) {
                let shown = if v.is_nan() {
                    "nan".into()
                } else if v.is_infinite() {
                    format!("{}inf", if v < 0.0 { "-" } else { "" })
                } else {
                    format!("{v:e}")
                };
                lines[l].replace_range(s..e, &shown);
            }
        }
        Mutation::Truncate(i) => {
            let joined = lines.join("\n");
            let cut = (i % (joined.len() + 1)).min(joined.len());
            let cut = (0..=cut)
                .rev()
                .find(|&c| joined.is_char_boundary(c))
                .unwrap_or(0);
            return joined[..cut].to_string();
        }
        Mutation::FlipByte(i, b) => {
            let mut bytes = lines.join("\n").into_bytes();
            if !bytes.is_empty() {
                let k = i % bytes.len();
                bytes[k] = b;
            }
            return String::from_utf8_lossy(&bytes).into_owned();
        }
        _ => {}
    }
    lines.join("\n")
}

/// Byte ranges of the numbers in a line.
fn number_spans(line: &str) -> Vec<(usize, usize)> {
    let bytes = line.as_bytes();
    let mut spans = Vec::new();
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k].is_ascii_digit() && (k == 0 || !bytes[k - 1].is_ascii_alphanumeric()) {
            let start = if k > 0 && bytes[k - 1] == b'-' {
                k - 1
            } else {
                k
            };
            let mut end = k;
            while end < bytes.len()
                && (bytes[end].is_ascii_digit() || b".eE+-".contains(&bytes[end]))
            {
                end += 1;
            }
            spans.push((start, end));
            k = end;
        } else {
            k += 1;
        }
    }
    spans
}

/// Parses, assembles and runs briefly; any outcome but a panic is fine.
fn exercise(text: &str) {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let Ok(mut spec) =
            ModelSpec::from_toml(text, concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples"))
        else {
            return;
        };
        let e = &mut spec.experiment;
        e.stop_time = e.stop_time.min(e.start_time + 0.05);
        e.limits.max_steps = Some(20_000);
        e.limits.timeout = Some(2.0);
        let _ = simulate(&spec);
    }));
    assert!(outcome.is_ok(), "the core panicked on:\n{text}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_model_files_never_panic(seed in 0usize..1000, mutations in prop::collection::vec(mutation(), 1..4)) {
        let corpus = corpus();
        let mut text = corpus[seed % corpus.len()].clone();
        for m in &mutations {
            text = apply(&text, m);
        }
        exercise(&text);
    }
}

#[test]
fn the_corpus_itself_runs() {
    for text in corpus() {
        exercise(&text);
    }
}
