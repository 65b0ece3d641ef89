//! Trajectory CSV in the MSL reference style, written at disk speed: a quoted header, `time`
//! first, one line per row, every value in the shortest text that reads back to the same double
//! (Ryū, about five times faster than `{:?}` on millions of cells), integer modes and flags
//! without ".0".

use std::io::{self, Write};

use super::check_shape;

/// Writes `rows × names.len()` values (row-major `table`) as CSV; `integer[c]` marks columns
/// written as integers when a value is integral (modes, Boolean flags).
pub fn write_csv<W: Write>(
    out: W,
    names: &[String],
    integer: &[bool],
    table: &[f64],
) -> io::Result<()> {
    let width = names.len();
    check_shape(width, integer.len(), table.len())?;
    let mut out = io::BufWriter::with_capacity(1 << 20, out);
    let header: Vec<String> = names
        .iter()
        .map(|n| format!("\"{}\"", n.replace('"', "\"\"")))
        .collect();
    writeln!(out, "{}", header.join(","))?;
    let mut line: Vec<u8> = Vec::with_capacity(width * 24);
    let mut ryu = ryu::Buffer::new();
    let mut itoa = String::new();
    for row in table.chunks_exact(width) {
        line.clear();
        for (c, &v) in row.iter().enumerate() {
            if c > 0 {
                line.push(b',');
            }
            if integer[c] && v.fract() == 0.0 && v.abs() < 1e15 {
                use std::fmt::Write as _;
                itoa.clear();
                let _ = write!(itoa, "{}", v as i64);
                line.extend_from_slice(itoa.as_bytes());
            } else if v.is_nan() {
                line.extend_from_slice(b"nan");
            } else {
                line.extend_from_slice(ryu.format(v).as_bytes());
            }
        }
        line.push(b'\n');
        out.write_all(&line)?;
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_read_back_exactly() {
        let names = vec!["time".to_string(), "J.w".into(), "c.mode".into()];
        let table = [0.0, 0.1, -1.0, 1e-300, 1.0 / 3.0, 2.0];
        let mut buf = Vec::new();
        write_csv(&mut buf, &names, &[false, false, true], &table).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("\"time\",\"J.w\",\"c.mode\""));
        let values: Vec<f64> = lines
            .flat_map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect();
        assert_eq!(values, table);
        assert!(text.contains(",-1\n") && text.contains(",2\n"));
    }
}
