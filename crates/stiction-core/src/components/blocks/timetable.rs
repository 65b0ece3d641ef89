//! A time table (MSL CombiTimeTable, linear interpolation): a measured normal-force or torque
//! profile given inline or as a CSV file. A table of several value columns outputs the chosen
//! `columns` as `y[1]`…`y[k]`; each output is the one-column table of its column (the same
//! block, the same numbers), so one output keeps the name `y`.

use crate::components::decl::START_TIME;
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

/// Names of the outputs of a table of several columns (port names are static).
pub(super) const Y: [&str; 32] = [
    "y[1]", "y[2]", "y[3]", "y[4]", "y[5]", "y[6]", "y[7]", "y[8]", "y[9]", "y[10]", "y[11]",
    "y[12]", "y[13]", "y[14]", "y[15]", "y[16]", "y[17]", "y[18]", "y[19]", "y[20]", "y[21]",
    "y[22]", "y[23]", "y[24]", "y[25]", "y[26]", "y[27]", "y[28]", "y[29]", "y[30]", "y[31]",
    "y[32]",
];

/// The component: one one-column table per output, all on the same abscissae.
struct TimeTables {
    outputs: Vec<TimeTable>,
}

impl TimeTables {
    fn names(&self) -> Vec<&'static str> {
        match self.outputs.len() {
            1 => vec!["y"],
            k => Y[..k].to_vec(),
        }
    }
}

impl Component for TimeTables {
    fn ports(&self) -> Ports {
        Ports {
            signal_out: self.names(),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        for (name, table) in self.names().into_iter().zip(&self.outputs) {
            let output = b.signal_out(name)?;
            b.output(name, Out::Signal(output));
            b.add_block(Box::new(table.clone()), vec![], output);
        }
        Ok(())
    }

    /// Breakpoints are kinks: restarting the integrator there keeps it accurate. All outputs
    /// share the abscissae, so the first one's are all of them.
    fn time_events(&self, _from: f64, _until: f64) -> Vec<f64> {
        let first = &self.outputs[0];
        let mut events = vec![first.start_time];
        events.extend(first.t.iter().map(|ti| ti + first.start_time));
        events
    }
}

pub fn time_table(p: &Params) -> ModelResult<Box<dyn Component>> {
    if p.has("file") && p.has("table") {
        return Err(p.error("table", "give either 'table' or 'file', not both"));
    }
    let file = p.string(
        "file CSV file of rows time, y1, y2… (relative to the model file); instead of table",
    )?;
    let width = p.matrix_width("table").unwrap_or(2).max(2);
    let rows = match file {
        Some(name) => {
            let path = p.base_dir.join(&name);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| p.error("file", format!("cannot read '{}': {e}", path.display())))?;
            parse_csv(&text).map_err(|m| p.error("file", format!("'{}': {m}", path.display())))?
        }
        None => p.matrix(
            "table [s, 1] Rows [time, y1, y2…]; a time given twice is a jump; linear between \
             rows, beyond the last row as `extrapolation` says",
            width,
            &[&[0.0, 0.0]],
        )?,
    };
    let which = if p.has("file") { "file" } else { "table" };
    check_times(p, which, &rows)?;
    let extrapolation = p.choice(
        "extrapolation Beyond the last point: LastTwoPoints (linearly through the last two \
         points) or HoldLastPoint (the last point's value)",
        &["LastTwoPoints", "HoldLastPoint"],
        "LastTwoPoints",
    )?;
    let columns = output_columns(p, rows[0].len(), TIME_COLUMNS)?;
    let offsets = p.vector(
        "offset [1] Offsets of the outputs: one per column, or one for all",
        &[0.0],
    )?;
    if offsets.len() != 1 && offsets.len() != columns.len() {
        return Err(p.error(
            "offset",
            format!(
                "has {} values for {} output columns; give one per column or one for all",
                offsets.len(),
                columns.len()
            ),
        ));
    }
    let t: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let start_time = p.real(START_TIME, 0.0)?;
    let hold = extrapolation == "HoldLastPoint";
    let outputs = (columns.iter().enumerate())
        .map(|(k, &c)| TimeTable {
            t: t.clone(),
            y: rows.iter().map(|r| r[c]).collect(),
            offset: offsets[if offsets.len() == 1 { 0 } else { k }],
            start_time,
            hold,
        })
        .collect();
    Ok(Box::new(TimeTables { outputs }))
}

/// Time must increase; one repeated time is a jump (as in MSL's CombiTimeTable).
fn check_times(p: &Params, which: &str, rows: &[Vec<f64>]) -> ModelResult<()> {
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
    Ok(())
}

/// `columns` of a TimeTable.
const TIME_COLUMNS: &str = "columns [1] Columns of the table to output, 1-based (column 1 is \
     time); default all the others";

/// The 0-based table columns of the outputs, from MSL's 1-based `columns` (default: all but
/// the first, time or the grid), declared as `decl` says.
pub(super) fn output_columns(
    p: &Params,
    width: usize,
    decl: &'static str,
) -> ModelResult<Vec<usize>> {
    let all: Vec<f64> = (2..=width).map(|c| c as f64).collect();
    let columns = p.vector(decl, &all)?;
    if columns.is_empty() || columns.len() > Y.len() {
        return Err(p.error(
            "columns",
            format!("give 1 to {} columns, got {}", Y.len(), columns.len()),
        ));
    }
    (columns.iter())
        .map(|&c| {
            if c.fract() == 0.0 && c >= 2.0 && c <= width as f64 {
                Ok(c as usize - 1)
            } else {
                Err(p.error(
                    "columns",
                    format!("column {c} is not a value column of the table (2 to {width})"),
                ))
            }
        })
        .collect()
}

/// Numeric columns (time, values…) separated by commas, semicolons or blanks; a non-numeric first line is a
/// header. Hand-written: the csv crate would bring serde for columns of numbers.
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
            Ok(v)
                if v.len() >= 2
                    && v.iter().all(|x| x.is_finite())
                    && rows.first().is_none_or(|r: &Vec<f64>| r.len() == v.len()) =>
            {
                rows.push(v)
            }
            Err(_) if rows.is_empty() => continue, // header
            _ => {
                return Err(format!(
                    "line {}: expected as many numbers as the first row (time, values…)",
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
