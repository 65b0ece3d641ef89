//! One-dimensional tables as MSL's CombiTable1D uses them for friction characteristics:
//! linear segments, linear extrapolation through the first/last two points (spec §4.1).
//! Written by hand because it is ten lines and must reproduce MSL's extrapolation exactly.

use crate::error::ModelResult;
use crate::model::{parse_decl, Params};

#[derive(Debug, Clone)]
pub struct Table1D {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl Table1D {
    /// Reads a `[:, 2]` table parameter (its declaration `"name [unit] description"`) and
    /// checks that its abscissa strictly increases.
    pub fn from_param(p: &Params, decl: &'static str, default: &[&[f64]]) -> ModelResult<Self> {
        let rows = p.matrix(decl, 2, default)?;
        Self::from_rows(p, parse_decl(decl).0, &rows, 1)
    }

    /// Builds a table from `rows[:, 0]` against `rows[:, column]`.
    pub fn from_rows(
        p: &Params,
        name: &str,
        rows: &[Vec<f64>],
        column: usize,
    ) -> ModelResult<Self> {
        Self::check_increasing(p, name, rows)?;
        Ok(Self {
            x: rows.iter().map(|r| r[0]).collect(),
            y: rows.iter().map(|r| r[column]).collect(),
        })
    }

    /// A table from validated `(x, y)` rows.
    pub fn from_points(rows: &[Vec<f64>]) -> Self {
        Self {
            x: rows.iter().map(|r| r[0]).collect(),
            y: rows.iter().map(|r| r[1]).collect(),
        }
    }

    /// The first column must be strictly increasing (CombiTable1D's rule).
    pub fn check_increasing(p: &Params, name: &str, rows: &[Vec<f64>]) -> ModelResult<()> {
        for pair in rows.windows(2) {
            if pair[1][0] <= pair[0][0] {
                return Err(p.error(
                    name,
                    format!(
                        "first column must be strictly increasing, but {} is followed by {}",
                        pair[0][0], pair[1][0]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Inline for a one-row table (a friction characteristic's usual constant: no call).
    #[inline]
    pub fn eval(&self, u: f64) -> f64 {
        if self.x.len() == 1 {
            return self.y[0];
        }
        self.interpolate(u)
    }

    /// `eval(u)` of a table of two rows or more.
    #[inline(never)]
    fn interpolate(&self, u: f64) -> f64 {
        let i = self.interval(u);
        let (x, y) = (&self.x[i..i + 2], &self.y[i..i + 2]);
        y[0] + (y[1] - y[0]) * (u - x[0]) / (x[1] - x[0])
    }

    /// The interval `eval(u)` interpolates in: i with x[i] <= u < x[i+1], the first/last
    /// interval extrapolating (0 for a one-row table).
    #[inline]
    fn interval(&self, u: f64) -> usize {
        let n = self.x.len();
        if n == 1 {
            return 0;
        }
        match self.x.partition_point(|&xi| xi <= u) {
            0 => 0,
            k if k >= n => n - 2,
            k => k - 1,
        }
    }

    /// `eval(u)` of each of tables with one abscissa (a LossyGear's loss columns): the
    /// interval, `u − x[i]` and `x[i+1] − x[i]` found once, each value `eval`'s.
    #[inline]
    pub fn eval_columns<const K: usize>(tables: &[Table1D; K], u: f64) -> [f64; K] {
        let x = &tables[0].x;
        if x.len() == 1 {
            return tables.each_ref().map(|t| t.y[0]);
        }
        let i = tables[0].interval(u);
        let (du, dx) = (u - x[i], x[i + 1] - x[i]);
        tables.each_ref().map(|t| {
            let y = &t.y[i..i + 2];
            y[0] + (y[1] - y[0]) * du / dx
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(rows: &[(f64, f64)]) -> Table1D {
        Table1D {
            x: rows.iter().map(|r| r.0).collect(),
            y: rows.iter().map(|r| r.1).collect(),
        }
    }

    #[test]
    fn single_row_is_constant() {
        let t = table(&[(0.0, 0.5)]);
        assert_eq!(t.eval(-3.0), 0.5);
        assert_eq!(t.eval(7.0), 0.5);
    }

    #[test]
    fn interpolates_and_extrapolates_linearly() {
        let t = table(&[(0.0, 0.8), (1.0, 0.7)]);
        assert!((t.eval(0.5) - 0.75).abs() < 1e-15);
        assert!((t.eval(3.0) - 0.5).abs() < 1e-15); // beyond the last point, no clamping
        assert!((t.eval(-1.0) - 0.9).abs() < 1e-15);
        let t = table(&[(0.0, 1.0), (1.0, 2.0), (3.0, 0.0)]);
        assert!((t.eval(1.0) - 2.0).abs() < 1e-15);
        assert!((t.eval(2.0) - 1.0).abs() < 1e-15);
        assert!((t.eval(4.0) + 1.0).abs() < 1e-15);
    }
}
