//! The result file of Dymola and OpenModelica: MATLAB v4, "binTrans" layout.
//!
//! Six matrices: `Aclass` (file kind), `name` and `description` (one column of characters per
//! variable), `dataInfo` (per variable: data matrix, 1-based column with sign, interpolation,
//! extrapolation), `data_1` (parameters and constants: one row per variable, values at start
//! and stop time) and `data_2` (trajectories: one row per variable, `time` first, one column
//! per output row — so a row-major result table is written as it is). Event instants appear
//! twice, left and right value, as the tools write them.

use std::io::{self, Write};

use super::check_shape;

const TEXT: i32 = 51; // little-endian IEEE, uint8 characters, text matrix
const INT32: i32 = 20;
const DOUBLE: i32 = 0;

/// A parameter for `data_1`: name, description, value.
pub struct Parameter {
    pub name: String,
    pub description: String,
    pub value: f64,
}

/// Writes a result: `names[0]` must be `time`; `table` is row-major `rows × names.len()`.
// Alike in shape to `write_csv` (a file writer's arguments); the shape check is shared.
pub fn write_mat<W: Write>(
    out: W,
    names: &[String],
    descriptions: &[String],
    table: &[f64],
    parameters: &[Parameter],
) -> io::Result<()> {
    let width = names.len();
    check_shape(width, descriptions.len(), table.len())?;
    let rows = table.len() / width;
    let mut out = io::BufWriter::with_capacity(1 << 20, out);
    let aclass = ["Atrajectory", "1.1", "", "binTrans"];
    write_text_rows(&mut out, "Aclass", &aclass)?;
    let all_names: Vec<&str> = names
        .iter()
        .map(String::as_str)
        .chain(parameters.iter().map(|p| p.name.as_str()))
        .collect();
    let all_descriptions: Vec<&str> = descriptions
        .iter()
        .map(String::as_str)
        .chain(parameters.iter().map(|p| p.description.as_str()))
        .collect();
    write_text_columns(&mut out, "name", &all_names)?;
    write_text_columns(&mut out, "description", &all_descriptions)?;
    let mut info: Vec<i32> = vec![0, 1, 0, -1];
    for c in 1..width {
        info.extend([2, c as i32 + 1, 0, -1]);
    }
    for k in 0..parameters.len() {
        info.extend([1, k as i32 + 2, 0, 0]);
    }
    header(&mut out, INT32, 4, all_names.len(), "dataInfo")?;
    for v in info {
        out.write_all(&v.to_le_bytes())?;
    }
    let (t0, t1) = match rows {
        0 => (0.0, 0.0),
        _ => (table[0], table[(rows - 1) * width]),
    };
    header(&mut out, DOUBLE, parameters.len() + 1, 2, "data_1")?;
    for t in [t0, t1] {
        write_doubles(&mut out, std::iter::once(t))?;
        write_doubles(&mut out, parameters.iter().map(|p| p.value))?;
    }
    header(&mut out, DOUBLE, width, rows, "data_2")?;
    write_doubles(&mut out, table.iter().copied())?;
    out.flush()
}

fn header<W: Write>(
    out: &mut W,
    kind: i32,
    rows: usize,
    cols: usize,
    name: &str,
) -> io::Result<()> {
    for v in [kind, rows as i32, cols as i32, 0, name.len() as i32 + 1] {
        out.write_all(&v.to_le_bytes())?;
    }
    out.write_all(name.as_bytes())?;
    out.write_all(&[0])
}

fn write_doubles<W: Write>(out: &mut W, values: impl Iterator<Item = f64>) -> io::Result<()> {
    for v in values {
        out.write_all(&v.to_le_bytes())?;
    }
    Ok(())
}

/// Strings as the rows of a character matrix (column-major on disk), padded with blanks.
fn write_text_rows<W: Write>(out: &mut W, name: &str, rows: &[&str]) -> io::Result<()> {
    let len = rows.iter().map(|s| s.len()).max().unwrap_or(0);
    header(out, TEXT, rows.len(), len, name)?;
    for c in 0..len {
        for s in rows {
            out.write_all(&[*s.as_bytes().get(c).unwrap_or(&b' ')])?;
        }
    }
    Ok(())
}

/// Strings as the columns of a character matrix ("binTrans"), padded with blanks.
fn write_text_columns<W: Write>(out: &mut W, name: &str, cols: &[&str]) -> io::Result<()> {
    let len = cols.iter().map(|s| s.len()).max().unwrap_or(0).max(1);
    header(out, TEXT, len, cols.len(), name)?;
    let mut column = vec![b' '; len];
    for s in cols {
        column.fill(b' ');
        column[..s.len()].copy_from_slice(s.as_bytes());
        out.write_all(&column)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_of_a_small_result() {
        let names = vec!["time".to_string(), "J.w".to_string()];
        let descriptions = vec!["Time".to_string(), String::new()];
        let table = [0.0, 1.0, 0.5, 2.0];
        let p = Parameter {
            name: "J.J".into(),
            description: String::new(),
            value: 3.0,
        };
        let mut buf = Vec::new();
        write_mat(&mut buf, &names, &descriptions, &table, &[p]).unwrap();
        let aclass = 20 + 7 + 4 * 11;
        let name = 20 + 5 + 4 * 3;
        let description = 20 + 12 + 4 * 3;
        let data_info = 20 + 9 + 4 * 3 * 4;
        let data_1 = 20 + 7 + 8 * 2 * 2;
        let data_2 = 20 + 7 + 8 * 4;
        assert_eq!(
            buf.len(),
            aclass + name + description + data_info + data_1 + data_2
        );
        let tail = &buf[buf.len() - 8..];
        assert_eq!(f64::from_le_bytes(tail.try_into().unwrap()), 2.0);
    }
}
