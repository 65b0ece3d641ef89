//! The MSL regression check: does a result stay inside the tube around a reference?
//!
//! This is the comparison the Modelica Association runs on the MAP-LIB reference results (CSV
//! Compare, tube method, relative tolerance 2e-3): the one implementation, which the MSL tests
//! here and Python's `stiction` comparison (through the binding's `_core.tube` and
//! `_core.check_signal`) both run. For each signal:
//!
//! * `X = tol · (t_max − t_min)` of the reference is the tube half-width in time,
//! * `Y = tol · max(y_max − y_min, 1e-15 · max(1, |y|max))` (finite values) its half-height,
//!   but at least `FLOOR` (1e-9, as Python's default `floor`): a signal exactly 0 in the
//!   reference passes round-off of 1e-12 in the result (MSL's Y would be 2e-18),
//! * the reference is a piecewise-linear curve (a repeated time is a vertical jump) and the tube
//!   at time `t` is `[min − Y, max + Y]` of that curve over the window `[t − X, t + X]`.
//!
//! Every point of the tested signal must lie inside; a NaN never does. The width in time is what
//! lets an event found slightly earlier or later than in the reference still pass.

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::result::SimResult;

/// Why a comparison could not be made at all (as opposed to a signal failing it).
#[derive(Debug, Error)]
pub enum CompareError {
    /// A file (path, what is wrong): unreadable, or not names over rows of numbers.
    #[error("{path}: {1}", path = .0.display())]
    File(PathBuf, String),
    /// A trajectory (the reference file or "result", what is wrong) the tube cannot be built
    /// on: no time column, time running backward, no rows, a column of another length.
    #[error("{0}: {1}")]
    Trajectory(String, String),
    #[error("tolerance must be positive, got {0}")]
    Tolerance(f64),
}

/// Named columns over one time axis (`time`): a simulation result or a reference table.
pub trait Columns {
    fn column(&self, name: &str) -> Option<Vec<f64>>;
}

impl Columns for SimResult {
    fn column(&self, name: &str) -> Option<Vec<f64>> {
        SimResult::column(self, name)
    }
}

/// A reference trajectory table as MAP-LIB stores it: a header of (quoted) names, `time`
/// first, then one numeric row per output point, event instants written twice.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// The file it came from: every error about it names it.
    pub path: PathBuf,
    pub names: Vec<String>,
    /// One column per name (`compare` rejects columns of unequal length).
    pub columns: Vec<Vec<f64>>,
}

impl Reference {
    pub fn read(path: impl AsRef<Path>) -> Result<Self, CompareError> {
        let path = path.as_ref();
        Self::parse(&read_text(path)?, path)
    }

    /// Parses CSV text; `path` only names the source in errors. Blank lines and `#` comments
    /// are skipped, as `numpy.loadtxt` does for the Python reader.
    pub fn parse(text: &str, path: impl Into<PathBuf>) -> Result<Self, CompareError> {
        let path = path.into();
        let fail = |line, msg| CompareError::File(path.clone(), format!("line {line}: {msg}"));
        let mut lines = text.strip_prefix('\u{feff}').unwrap_or(text).lines();
        let header = lines.next().filter(|h| !h.trim().is_empty());
        let names = split_header(header.ok_or_else(|| fail(1, "empty file".into()))?);
        let mut columns = vec![Vec::new(); names.len()];
        for (line, text) in (2..).zip(lines) {
            let cells: Vec<&str> = text.split('#').next().unwrap_or("").split(',').collect();
            if cells.len() == 1 && cells[0].trim().is_empty() {
                continue;
            } else if cells.len() != names.len() {
                let msg = format!("{} values for {} names", cells.len(), names.len());
                return Err(fail(line, msg));
            }
            for (column, cell) in columns.iter_mut().zip(cells) {
                let value = cell.trim().parse();
                column.push(value.map_err(|_| fail(line, format!("'{cell}' is not a number")))?);
            }
        }
        Ok(Self {
            path,
            names,
            columns,
        })
    }
}

impl Columns for Reference {
    fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.names.iter().position(|n| n == name)?;
        self.columns.get(i).cloned()
    }
}

/// Reads an MSL `comparisonSignals.txt`: one name per line, `time` (first) left out.
pub fn read_signal_list(path: impl AsRef<Path>) -> Result<Vec<String>, CompareError> {
    let text = read_text(path.as_ref())?;
    let lines = text.trim_start_matches('\u{feff}').split(['\n', '\r']);
    let keep = |n: &&str| !n.is_empty() && !n.starts_with('#') && *n != "time";
    let names = lines.map(str::trim).filter(keep);
    Ok(names.map(String::from).collect())
}

/// Which side lacks a compared signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Result,
    Reference,
}

/// The verdict for one signal.
#[derive(Debug, Clone, Default, PartialEq)]
// Alike in shape only to other field lists (the duplicate finder pairs plain structs).
pub struct SignalReport {
    pub name: String,
    pub passed: bool,
    /// The largest distance of a point outside the tube, in tube half-heights Y: 0 when every
    /// point is inside, infinite for a NaN.
    pub max_excess: f64,
    /// When that worst point is (None when passed or missing).
    pub worst_time: Option<f64>,
    pub points_outside: usize,
    pub missing: Option<Side>,
    /// The tube half-width X in time and half-height Y.
    pub x_half: f64,
    pub y_half: f64,
}

/// The smallest tube half-height by default (Python's `DEFAULT_FLOOR`).
pub const FLOOR: f64 = 1e-9;

/// Checks `result` against `reference` on `signals` (`time` is skipped) with the tube method:
/// one verdict per signal, in order; the check passes if every one does. A signal missing on
/// either side fails; unusable input is an error.
pub fn compare<S: AsRef<str>>(
    result: &impl Columns,
    reference: &Reference,
    signals: &[S],
    tolerance: f64,
) -> Result<Vec<SignalReport>, CompareError> {
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(CompareError::Tolerance(tolerance));
    }
    let ref_what = reference.path.display().to_string();
    let t_ref = time_axis(reference, &ref_what)?;
    let t = time_axis(result, "result")?;
    let mut reports = Vec::new();
    for name in signals.iter().map(AsRef::as_ref).filter(|n| *n != "time") {
        let (y_ref, y) = match (reference.column(name), result.column(name)) {
            (Some(y_ref), Some(y)) => (y_ref, y),
            (y_ref, _) => {
                let missing = Some(y_ref.map_or(Side::Reference, |_| Side::Result));
                let name = name.to_string();
                reports.push(SignalReport {
                    name,
                    missing,
                    ..Default::default()
                });
                continue;
            }
        };
        for (what, y, t) in [(ref_what.as_str(), &y_ref, &t_ref), ("result", &y, &t)] {
            if y.len() != t.len() {
                let msg = format!("'{name}' has {} values for {} times", y.len(), t.len());
                return Err(trajectory(what, msg));
            }
        }
        if t_ref.is_empty() {
            return Err(trajectory(&ref_what, "the reference has no rows".into()));
        }
        let check = check_signal((&t_ref, &y_ref), (&t, &y), tolerance, FLOOR)?;
        reports.push(SignalReport {
            name: name.into(),
            passed: check.points_outside == 0,
            max_excess: check.max_excess,
            worst_time: check.worst_time,
            points_outside: check.points_outside,
            missing: None,
            x_half: check.x_half,
            y_half: check.y_half,
        });
    }
    Ok(reports)
}

/// The tube around a reference signal at given times: its lower and upper edges and its
/// half-sizes, X in time and Y in value (`comparison.py`'s `tube`).
#[derive(Debug, Clone, Default, PartialEq)]
// Alike in shape only to other field lists (the duplicate finder pairs plain structs).
pub struct Tube {
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    pub x_half: f64,
    pub y_half: f64,
}

/// One signal against its tube, as numbers (`comparison.py`'s per-signal check).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SignalCheck {
    /// The largest distance of a point outside the tube, in tube half-heights Y: 0 when every
    /// point is inside, infinite for a NaN.
    pub max_excess: f64,
    /// When that worst point is (None when every point is inside).
    pub worst_time: Option<f64>,
    pub points_outside: usize,
    pub x_half: f64,
    pub y_half: f64,
}

/// The tube half-sizes of a reference with rows: X = `tol`·(its time span), Y =
/// `tol`·max(y_max − y_min, 1e-15·max(1, |y|max)) over its finite values, at least `floor`.
fn half_sizes(t_ref: &[f64], y_ref: &[f64], tol: f64, floor: f64) -> (f64, f64) {
    let x_half = tol * (t_ref[t_ref.len() - 1] - t_ref[0]);
    let (lo, hi) = y_ref.iter().filter(|v| v.is_finite()).fold(EMPTY, extend);
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 0.0) };
    let y_half = (tol * (hi - lo).max(1e-15 * lo.abs().max(hi.abs()).max(1.0))).max(floor);
    (x_half, y_half)
}

/// (min, max) of the reference curve over the window `[ti − X, ti + X]`: the reference points
/// in it and the curve at its ends (interpolated); NaN if a NaN is among them.
fn window(reference: &mut Extrema, t_ref: &[f64], ti: f64, x_half: f64) -> (f64, f64) {
    let y_ref = reference.y;
    let (start, stop) = (ti - x_half, ti + x_half);
    let first = t_ref.partition_point(|&v| v < start);
    let end = t_ref.partition_point(|&v| v <= stop).max(first);
    let ends = [interp(start, t_ref, y_ref), interp(stop, t_ref, y_ref)];
    let inside = reference.of(first..end);
    ends.iter().fold(inside, extend)
}

/// (min, max) of runs of the reference values, NaN-propagating as `extend`. A window holds
/// about 2·tol of the rows: a short run is scanned; for long ones (a loose tolerance) the
/// extrema of every run of 2^k values are kept (a sparse table, levels built as far as a query
/// needs), so a run costs two lookups, as Python's sparse table did.
struct Extrema<'a> {
    y: &'a [f64],
    /// `levels[k - 1][i]`: (min, max) of `y[i..i + 2^k]`.
    levels: Vec<Vec<(f64, f64)>>,
}

impl<'a> Extrema<'a> {
    /// Runs up to this long are scanned.
    const SCAN: usize = 64;

    fn new(y: &'a [f64]) -> Self {
        Self {
            y,
            levels: Vec::new(),
        }
    }

    fn of(&mut self, run: std::ops::Range<usize>) -> (f64, f64) {
        let n = run.len();
        if n <= Self::SCAN {
            return self.y[run].iter().fold(EMPTY, extend);
        }
        let k = n.ilog2() as usize; // 2^k <= n < 2^(k+1)
        while self.levels.len() < k {
            let next = match self.levels.last() {
                None => (self.y.windows(2))
                    .map(|w| extend(extend(EMPTY, &w[0]), &w[1]))
                    .collect(),
                Some(below) => {
                    let half = 1 << self.levels.len();
                    let pairs = below.iter().zip(&below[half..]);
                    pairs.map(|(&a, &b)| both(a, b)).collect()
                }
            };
            self.levels.push(next);
        }
        let level = &self.levels[k - 1];
        both(level[run.start], level[run.end - (1 << k)])
    }
}

/// The extrema of two sets from theirs (a NaN in either wins).
fn both(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    extend(extend(a, &b.0), &b.1)
}

/// Checks that each side has as many values as times and the reference has rows.
fn check_lengths(t_ref: &[f64], sides: &[(&str, &[f64], &[f64])]) -> Result<(), CompareError> {
    for (what, t, y) in sides {
        if y.len() != t.len() {
            let msg = format!("{} values for {} times", y.len(), t.len());
            return Err(trajectory(what, msg));
        }
    }
    match t_ref.is_empty() {
        true => Err(trajectory("reference", "the reference has no rows".into())),
        false => Ok(()),
    }
}

/// The tube around the reference (`t_ref`, `y_ref`: time non-decreasing, a repeated time a
/// jump) at times `t`, with relative tolerance `tol` and smallest half-height `floor`: at each
/// time, `[min − Y, max + Y]` of the reference curve over `[t − X, t + X]` (NaN where a NaN of
/// the reference is in that window). An error if the reference has no rows.
pub fn tube(
    (t_ref, y_ref): (&[f64], &[f64]),
    t: &[f64],
    tol: f64,
    floor: f64,
) -> Result<Tube, CompareError> {
    check_lengths(t_ref, &[("reference", t_ref, y_ref)])?;
    let (x_half, y_half) = half_sizes(t_ref, y_ref, tol, floor);
    let (mut lower, mut upper) = (Vec::with_capacity(t.len()), Vec::with_capacity(t.len()));
    let mut reference = Extrema::new(y_ref);
    for &ti in t {
        let (lo, hi) = window(&mut reference, t_ref, ti, x_half);
        lower.push(lo - y_half);
        upper.push(hi + y_half);
    }
    Ok(Tube {
        lower,
        upper,
        x_half,
        y_half,
    })
}

/// One signal (`t`, `y`) against the tube around its reference (`t_ref`, `y_ref`; see
/// `tube`): how far outside its points are, in half-heights Y (a NaN point is infinitely
/// far), and the worst of them (the first if several are). An error if the reference has no
/// rows or a side has not as many values as times.
pub fn check_signal(
    (t_ref, y_ref): (&[f64], &[f64]),
    (t, y): (&[f64], &[f64]),
    tol: f64,
    floor: f64,
) -> Result<SignalCheck, CompareError> {
    let sides = [("reference", t_ref, y_ref), ("result", t, y)];
    check_lengths(t_ref, &sides)?;
    let (x_half, y_half) = half_sizes(t_ref, y_ref, tol, floor);
    let mut check = SignalCheck {
        x_half,
        y_half,
        ..Default::default()
    };
    let mut reference = Extrema::new(y_ref);
    for (&ti, &yi) in t.iter().zip(y) {
        let (lo, hi) = window(&mut reference, t_ref, ti, x_half);
        let (below, above) = ((lo - y_half) - yi, yi - (hi + y_half));
        let e = extend((below, below), &above).1 / y_half;
        let excess = if e.is_nan() { f64::INFINITY } else { e };
        if excess > 0.0 {
            check.points_outside += 1;
            if check.worst_time.is_none() || excess > check.max_excess {
                (check.max_excess, check.worst_time) = (excess, Some(ti));
            }
        }
    }
    Ok(check)
}

/// `numpy.interp` on a non-decreasing `xp`: at a repeated time (an event written twice) the
/// value after the jump; beyond either end, the end value.
fn interp(x: f64, xp: &[f64], fp: &[f64]) -> f64 {
    let (n, k) = (xp.len(), xp.partition_point(|&v| v <= x)); // k points at or before x
    if x.is_nan() {
        return x;
    } else if k == 0 || k == n || xp[k - 1] == x {
        return fp[k.saturating_sub(1)];
    }
    let slope = (fp[k] - fp[k - 1]) / (xp[k] - xp[k - 1]);
    let at = |i: usize| slope * (x - xp[i]) + fp[i];
    // numpy's fallbacks for infinite values: from the right end, then a flat infinite piece
    match (at(k - 1), at(k)) {
        (v, _) if !v.is_nan() => v,
        (_, v) if !v.is_nan() || fp[k - 1] != fp[k] => v,
        _ => fp[k - 1],
    }
}

/// No values yet: (min, max) of an empty set.
const EMPTY: (f64, f64) = (f64::INFINITY, f64::NEG_INFINITY);

/// Widens (min, max) by `v` as `numpy.minimum` / `maximum` do: a NaN wins, so a NaN in the
/// reference window makes the tube NaN and fails the point.
fn extend((lo, hi): (f64, f64), &v: &f64) -> (f64, f64) {
    if lo.is_nan() || v.is_nan() {
        (f64::NAN, f64::NAN)
    } else {
        (lo.min(v), hi.max(v))
    }
}

fn time_axis(source: &impl Columns, what: &str) -> Result<Vec<f64>, CompareError> {
    let t = source
        .column("time")
        .ok_or_else(|| trajectory(what, "no 'time' column".into()))?;
    match t.windows(2).position(|w| w[1] < w[0]) {
        Some(i) => Err(trajectory(what, format!("time decreases after row {i}"))),
        None => Ok(t),
    }
}

fn trajectory(what: &str, message: String) -> CompareError {
    CompareError::Trajectory(what.into(), message)
}

fn read_text(path: &Path) -> Result<String, CompareError> {
    let error = |e: std::io::Error| CompareError::File(path.into(), e.to_string());
    std::fs::read_to_string(path).map_err(error)
}

/// Splits a CSV header row into names: fields may be quoted, `""` is a quote inside quotes.
fn split_header(line: &str) -> Vec<String> {
    let (mut names, mut field) = (Vec::new(), String::new());
    let (mut quoted, mut at_start) = (false, true);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.next_if_eq(&'"').is_some() => field.push('"'),
            '"' if quoted || at_start => quoted = !quoted,
            ',' if !quoted => names.push(std::mem::take(&mut field).trim().to_string()),
            _ => field.push(c),
        }
        at_start = c == ',' && !quoted;
    }
    names.push(field.trim().to_string());
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step written twice at t = 1 (a jump): the tube spans both sides within X of it.
    #[test]
    fn the_tube_follows_jumps_floors_and_nans() {
        let (t_ref, y_ref) = ([0.0, 1.0, 1.0, 2.0], [0.0, 0.0, 1.0, 1.0]);
        let t = [0.0, 0.5, 0.999, 1.0, 1.5, 2.0];
        let step = tube((&t_ref, &y_ref), &t, 1e-2, 0.0).expect("a reference with rows");
        assert_eq!((step.x_half, step.y_half), (0.02, 0.01));
        assert_eq!(step.lower, [-0.01, -0.01, -0.01, -0.01, 0.99, 0.99]);
        assert_eq!(step.upper, [0.01, 0.01, 1.01, 1.01, 1.01, 1.01]);
        // a flat zero reference: Y is the floor
        let zero = tube((&t_ref, &[0.0; 4]), &t, 1e-2, 1e-9).unwrap();
        assert_eq!(zero.y_half, 1e-9);
        // a NaN in the reference makes the tube NaN where it is in the window
        let nan = tube((&t_ref, &[0.0, f64::NAN, 1.0, 1.0]), &[2.0], 1e-2, 0.0).unwrap();
        assert!(nan.lower[0] == 0.99 && nan.upper[0] == 1.01);
        let near = tube((&t_ref, &[0.0, f64::NAN, 1.0, 1.0]), &[1.0], 1e-2, 0.0).unwrap();
        assert!(near.lower[0].is_nan() && near.upper[0].is_nan());
        assert!(tube((&[], &[]), &t, 1e-2, 0.0).is_err());
    }

    #[test]
    fn a_signal_is_checked_against_its_tube() {
        let (t_ref, y_ref) = ([0.0, 1.0, 1.0, 2.0], [0.0, 0.0, 1.0, 1.0]);
        let t = [0.0, 0.5, 1.5, 2.0];
        let inside = check_signal((&t_ref, &y_ref), (&t, &[0.0, 0.005, 1.0, 1.0]), 1e-2, 0.0);
        let inside = inside.unwrap();
        assert_eq!((inside.points_outside, inside.worst_time), (0, None));
        assert_eq!(inside.max_excess, 0.0);
        // 0.03 at 0.5 is two half-heights out, a NaN infinitely: the NaN is the worst
        let y = [0.0, 0.03, f64::NAN, 1.0];
        let out = check_signal((&t_ref, &y_ref), (&t, &y), 1e-2, 0.0).unwrap();
        assert_eq!(out.points_outside, 2);
        assert_eq!((out.max_excess, out.worst_time), (f64::INFINITY, Some(1.5)));
        let short = check_signal((&t_ref, &y_ref), (&t, &y[..3]), 1e-2, 0.0);
        assert!(short.is_err());
    }

    /// Long runs through the sparse table give what a scan gives, NaN included.
    #[test]
    fn long_runs_equal_a_scan() {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut y: Vec<f64> = (0..700).map(|_| next() * 2.0 - 1.0).collect();
        y[500] = f64::NAN;
        let mut table = Extrema::new(&y);
        for _ in 0..2000 {
            let (a, b) = ((next() * 700.0) as usize, (next() * 701.0) as usize);
            let run = a.min(b)..a.max(b);
            let scan = y[run.clone()].iter().fold(EMPTY, extend);
            let got = table.of(run.clone());
            let same = |u: f64, v: f64| u.to_bits() == v.to_bits() || (u.is_nan() && v.is_nan());
            assert!(same(got.0, scan.0) && same(got.1, scan.1), "{run:?}");
        }
    }
}
