//! A time table (MSL CombiTimeTable, one output column, linear interpolation): a measured
//! normal-force or torque profile given inline or as a two-column CSV file.

use crate::components::decl::{OFFSET, START_TIME};
use crate::components::{Component, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::signals::{Block, Jet};
use crate::system::{Builder, Out};

#[derive(Clone)]
struct TimeTable {
    t: Vec<f64>,
    y: Vec<f64>,
    offset: f64,
    start_time: f64,
    hold: bool,
}

impl Block for TimeTable {
    fn eval(&self, t: f64, horizon: f64, _u: &[f64]) -> f64 {
        self.piece(t, horizon).0
    }

    /// Piecewise linear: the segment's slope, no curvature (breakpoints are time events).
    fn jet(&self, t: f64, horizon: f64, _u: &[Jet]) -> Option<Jet> {
        let (y, slope) = self.piece(t, horizon);
        Some([y, slope, 0.0])
    }
}

impl TimeTable {
    /// The output and the slope of the segment in force.
    #[inline]
    fn piece(&self, t: f64, horizon: f64) -> (f64, f64) {
        // MSL CombiTimeTable: the output is `offset` before startTime.
        if !crate::signals::reached(t, self.start_time, horizon) {
            return (self.offset, 0.0);
        }
        let n = self.t.len();
        if n == 1 {
            return (self.offset + self.y[0], 0.0);
        }
        let s = t - self.start_time;
        // Breakpoints are time events: the segment in force is the last one whose start has
        // been reached (its absolute time lies before the horizon of unhandled events).
        let started = |i: usize| crate::signals::reached(t, self.t[i] + self.start_time, horizon);
        let mut k = self.t.partition_point(|&ti| ti <= s).max(1);
        while k > 1 && !started(k - 1) {
            k -= 1;
        }
        if self.hold && k >= n && started(n - 1) {
            return (self.offset + self.y[n - 1], 0.0);
        }
        if self.hold && !started(0) {
            return (self.offset + self.y[0], 0.0);
        }
        let i = k.min(n - 1) - 1;
        let (t0, t1, y0, y1) = (self.t[i], self.t[i + 1], self.y[i], self.y[i + 1]);
        if t1 == t0 {
            // a jump at the table's last point: its right value once it has happened
            return (self.offset + if started(i + 1) { y1 } else { y0 }, 0.0);
        }
        (
            self.offset + y0 + (y1 - y0) * (s - t0) / (t1 - t0),
            (y1 - y0) / (t1 - t0),
        )
    }
}

impl Component for TimeTable {
    fn ports(&self) -> Ports {
        Ports {
            signal_out: vec!["y"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let output = b.signal_out("y")?;
        b.output("y", Out::Signal(output));
        b.add_block(Box::new(self.clone()), vec![], output);
        Ok(())
    }

    /// Breakpoints are kinks: restarting the integrator there keeps it accurate.
    fn time_events(&self, _from: f64, _until: f64) -> Vec<f64> {
        let mut events = vec![self.start_time];
        events.extend(self.t.iter().map(|ti| ti + self.start_time));
        events
    }
}

pub fn time_table(p: &Params) -> ModelResult<Box<dyn Component>> {
    if p.has("file") && p.has("table") {
        return Err(p.error("table", "give either 'table' or 'file', not both"));
    }
    let file =
        p.string("file CSV file of rows time, y (relative to the model file); instead of table")?;
    let rows = match file {
        Some(name) => {
            let path = p.base_dir.join(&name);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| p.error("file", format!("cannot read '{}': {e}", path.display())))?;
            parse_csv(&text).map_err(|m| p.error("file", format!("'{}': {m}", path.display())))?
        }
        None => p.matrix(
            "table [s, 1] Rows [time, y]; a time given twice is a jump; linear between rows, \
             beyond the last row as `extrapolation` says",
            2,
            &[&[0.0, 0.0]],
        )?,
    };
    // Time must increase; one repeated time is a jump (as in MSL's CombiTimeTable).
    let which = if p.has("file") { "file" } else { "table" };
    for (k, pair) in rows.windows(2).enumerate() {
        let (a, b) = (pair[0][0], pair[1][0]);
        if b < a {
            return Err(p.error(
                which,
                format!("time must not decrease, but {a} is followed by {b}"),
            ));
        }
        if b == a && k > 0 && rows[k - 1][0] == a {
            return Err(p.error(
                which,
                format!("time {a} appears three times; a jump repeats a time once"),
            ));
        }
    }
    let extrapolation = p.choice(
        "extrapolation Beyond the last point: LastTwoPoints (linearly through the last two \
         points) or HoldLastPoint (the last point's value)",
        &["LastTwoPoints", "HoldLastPoint"],
        "LastTwoPoints",
    )?;
    Ok(Box::new(TimeTable {
        t: rows.iter().map(|r| r[0]).collect(),
        y: rows.iter().map(|r| r[1]).collect(),
        offset: p.real(OFFSET, 0.0)?,
        start_time: p.real(START_TIME, 0.0)?,
        hold: extrapolation == "HoldLastPoint",
    }))
}

/// Two numeric columns separated by commas, semicolons or blanks; a non-numeric first line is a
/// header. Hand-written: the csv crate would bring serde for two columns of numbers.
fn parse_csv(text: &str) -> Result<Vec<Vec<f64>>, String> {
    let mut rows = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|c| !c.is_empty())
            .collect();
        let values: Result<Vec<f64>, _> = cells
            .iter()
            .map(|c| c.trim_matches('"').parse::<f64>())
            .collect();
        match values {
            Ok(v) if v.len() >= 2 && v.iter().all(|x| x.is_finite()) => rows.push(vec![v[0], v[1]]),
            Err(_) if rows.is_empty() => continue, // header
            _ => {
                return Err(format!(
                    "line {}: expected two numbers (time, value)",
                    number + 1
                ))
            }
        }
    }
    if rows.is_empty() {
        return Err("no data rows".into());
    }
    Ok(rows)
}
