//! What an FMU made by `stiction fmu` carries in `resources/`: the model file (`model.toml`,
//! the engine's text) and the variable table (`variables.tsv`) that maps each value reference
//! to a model input, an output variable or a parameter by its MSL name. The Python side writes
//! both together with `modelDescription.xml`, so the three always agree.

use std::path::{Path, PathBuf};

/// What a value reference stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Input,
    Output,
    Parameter,
    /// Time (FMI 3.0 declares it).
    Independent,
    /// A state with a start value (`J1.w`): read as the state, set before the end of
    /// initialization as its start value, fixed (`initial="exact"`) or a guess (`"approx"`).
    Start {
        fixed: bool,
    },
    /// A Boolean parameter that leaves the model's structure alone (`TorqueDirection`).
    Flag,
    /// The start value of a Boolean discrete state (a OneWayClutch's `stuck`): read as the
    /// state, set before the end of initialization as its start (`pre()`) value.
    FlagStart,
    /// A table parameter (`brake.mu_pos`) as one array variable (FMI 3.0), row after row.
    Table {
        rows: usize,
        cols: usize,
    },
    /// One element of a table parameter (FMI 2.0: `brake.mu_pos[2,1]`, 1-based).
    Element {
        row: usize,
        col: usize,
    },
}

impl Kind {
    /// Whether the model compiles the value into the run (set only before initialization ends).
    pub fn is_setup(self) -> bool {
        !matches!(self, Kind::Input | Kind::Output | Kind::Independent)
    }

    /// Whether the variable is an FMI Boolean (else a Real / Float64).
    pub fn is_boolean(self) -> bool {
        matches!(self, Kind::Flag | Kind::FlagStart)
    }

    /// How many values the variable holds (a table: all its elements).
    pub fn size(self) -> usize {
        match self {
            Kind::Table { rows, cols } => rows * cols,
            _ => 1,
        }
    }
}

#[derive(Debug, Clone)]
pub struct VarSpec {
    pub kind: Kind,
    pub name: String,
    /// The start values of an input, a parameter or a table, row after row (outputs: unused;
    /// Booleans: 0 or 1).
    pub start: Vec<f64>,
}

/// The variable table: the GUID on its first line (`guid\t…`), then `vr kind name start`,
/// tab-separated, value references 0, 1, 2, … in order (a table's start: its values row after
/// row, separated by spaces).
#[derive(Debug, Clone)]
pub struct Layout {
    pub guid: String,
    pub vars: Vec<VarSpec>,
}

/// `rows`x`cols` (a table's shape).
fn parse_shape(shape: &str) -> Option<(usize, usize)> {
    let (rows, cols) = shape.split_once('x')?;
    Some((rows.parse().ok()?, cols.parse().ok()?))
}

/// `table.name[row,col]`: the table's name and the 1-based indices.
pub fn parse_element(name: &str) -> Option<(&str, usize, usize)> {
    let (table, index) = name.strip_suffix(']')?.rsplit_once('[')?;
    let (row, col) = index.split_once(',')?;
    let (row, col) = (row.trim().parse().ok()?, col.trim().parse().ok()?);
    (row >= 1 && col >= 1).then_some((table, row, col))
}

/// The kind word of a line (`table:3x2`: a table's shape follows its kind).
fn parse_kind(word: &str, name: &str) -> Result<Kind, String> {
    if let Some(shape) = word.strip_prefix("table:") {
        let (rows, cols) = parse_shape(shape).ok_or(format!("bad table shape '{shape}'"))?;
        return Ok(Kind::Table { rows, cols });
    }
    match word {
        "input" => Ok(Kind::Input),
        "output" => Ok(Kind::Output),
        "parameter" => Ok(Kind::Parameter),
        "independent" => Ok(Kind::Independent),
        "start" => Ok(Kind::Start { fixed: true }),
        "guess" => Ok(Kind::Start { fixed: false }),
        "boolean" => Ok(Kind::Flag),
        "boolean-start" => Ok(Kind::FlagStart),
        "element" => match parse_element(name) {
            Some((_, row, col)) => Ok(Kind::Element { row, col }),
            None => Err(format!("'{name}' is not a table element (name[row,col])")),
        },
        other => Err(format!("unknown variable kind '{other}'")),
    }
}

fn parse_var(k: usize, line: &str) -> Result<VarSpec, String> {
    let fields: Vec<&str> = line.split('\t').collect();
    let [vr, kind, name, start] = fields[..] else {
        return Err(format!("line {}: expected 4 tab-separated fields", k + 2));
    };
    if vr.parse::<usize>() != Ok(k) {
        return Err(format!(
            "line {}: value reference {vr}, expected {k}",
            k + 2
        ));
    }
    let kind = parse_kind(kind, name).map_err(|e| format!("line {}: {e}", k + 2))?;
    let start = (start.split(' '))
        .map(|v| v.parse::<f64>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|_| format!("line {}: start value '{start}' is not a number", k + 2))?;
    if start.len() != kind.size() {
        return Err(format!(
            "line {}: {} start values, expected {}",
            k + 2,
            start.len(),
            kind.size()
        ));
    }
    Ok(VarSpec {
        kind,
        name: name.to_string(),
        start,
    })
}

impl Layout {
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut lines = text.lines();
        let guid = lines
            .next()
            .and_then(|l| l.strip_prefix("guid\t"))
            .ok_or("variables.tsv: the first line must be 'guid<TAB>…'")?
            .to_string();
        let vars = lines
            .filter(|l| !l.is_empty())
            .enumerate()
            .map(|(k, l)| parse_var(k, l))
            .collect::<Result<_, _>>()
            .map_err(|e| format!("variables.tsv: {e}"))?;
        Ok(Layout { guid, vars })
    }
}

fn hex(b: u8) -> Option<u8> {
    (b as char).to_digit(16).map(|d| d as u8)
}

/// The folder a `file:` URI names (`file:///a/b`, `file:/a/b`, `file://localhost/a/b`), with
/// `%XX` escapes decoded; a plain path is taken as it is.
pub fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    let path = match uri.strip_prefix("file:") {
        None => uri,
        Some(rest) => match rest.strip_prefix("//") {
            Some(auth) => &auth[auth.find('/').ok_or(format!("bad file URI '{uri}'"))?..],
            None => rest,
        },
    };
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let escaped = (bytes[i] == b'%')
            .then(|| Some(hex(*bytes.get(i + 1)?)? * 16 + hex(*bytes.get(i + 2)?)?))
            .flatten();
        match escaped {
            Some(b) => {
                out.push(b);
                i += 3;
            }
            None => {
                out.push(bytes[i]);
                i += 1;
            }
        }
    }
    let decoded = String::from_utf8(out).map_err(|_| format!("bad file URI '{uri}'"))?;
    Ok(Path::new(&decoded).to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_uris_of_every_spelling_give_the_path() {
        for uri in [
            "file:///tmp/a%20b/res",
            "file:/tmp/a%20b/res",
            "file://localhost/tmp/a%20b/res",
        ] {
            assert_eq!(
                resource_dir(uri).unwrap(),
                Path::new("/tmp/a b/res"),
                "{uri}"
            );
        }
        assert_eq!(
            resource_dir("file:///x/100%").unwrap(),
            Path::new("/x/100%")
        );
    }

    #[test]
    fn the_variable_table_is_checked() {
        let ok = Layout::parse("guid\tabc\n0\tinput\tb.f\t0.5\n1\toutput\tJ.w\t0\n").unwrap();
        assert_eq!(ok.guid, "abc");
        assert_eq!(ok.vars[0].kind, Kind::Input);
        assert_eq!(ok.vars[0].start, [0.5]);
        assert!(Layout::parse("guid\tabc\n1\tinput\tb.f\t0\n").is_err());
        assert!(Layout::parse("0\tinput\tb.f\t0\n").is_err());
        assert!(Layout::parse("guid\tx\n0\tstate\tb.f\t0\n").is_err());
        let start = Layout::parse("guid\tx\n0\tstart\tJ.w\t1\n1\tguess\tJ.phi\t0\n").unwrap();
        assert_eq!(start.vars[0].kind, Kind::Start { fixed: true });
        assert_eq!(start.vars[1].kind, Kind::Start { fixed: false });
    }

    #[test]
    fn booleans_and_tables_are_read() {
        let text = "guid\tx\n0\tboolean\ts.TorqueDirection\t1\n\
                    1\ttable:2x2\tb.mu_pos\t0 0.4 10 0.3\n2\telement\tb.mu_pos[2,1]\t10\n";
        let l = Layout::parse(text).unwrap();
        assert_eq!(l.vars[0].kind, Kind::Flag);
        assert_eq!(l.vars[1].kind, Kind::Table { rows: 2, cols: 2 });
        assert_eq!(l.vars[1].start, [0.0, 0.4, 10.0, 0.3]);
        assert_eq!(l.vars[2].kind, Kind::Element { row: 2, col: 1 });
        assert_eq!(parse_element("b.mu_pos[2,1]"), Some(("b.mu_pos", 2, 1)));
        assert_eq!(parse_element("b.mu_pos[0,1]"), None);
        assert!(Layout::parse("guid\tx\n0\ttable:2x2\tb.t\t0 1 2\n").is_err());
        assert!(Layout::parse("guid\tx\n0\telement\tb.t\t0\n").is_err());
    }
}
