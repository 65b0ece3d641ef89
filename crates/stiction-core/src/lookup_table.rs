//! One-dimensional tables as MSL's CombiTable1D uses them for friction characteristics:
//! linear segments, linear extrapolation through the first/last two points (spec §4.1).
//! Written by hand because it is ten lines and must reproduce MSL's extrapolation exactly.

use crate::error::ModelResult;
use crate::model::Params;

#[derive(Debug, Clone)]
pub struct Table1D {
    x: Vec<f64>,
    y: Vec<f64>,
    /// CombiTable1D's `Extrapolation.HoldLastPoint`: the first/last row's value beyond the
    /// rows (MSL's friction tables use `LastTwoPoints`, the default: linear through the first
    /// or last two rows).
    hold: bool,
}

impl Table1D {
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
            hold: false,
        })
    }

    /// A table from validated `(x, y)` rows.
    pub fn from_points(rows: &[Vec<f64>]) -> Self {
        Self {
            x: rows.iter().map(|r| r[0]).collect(),
            y: rows.iter().map(|r| r[1]).collect(),
            hold: false,
        }
    }

    /// The table holding its first and last rows' values beyond them (`HoldLastPoint`).
    pub fn holding(mut self) -> Self {
        self.hold = true;
        self
    }

    /// Where, beyond its last row, the table's linear extrapolation reaches 0 from a
    /// nonnegative last value: the smallest `u` past the last row with `eval(u) < 0` is just
    /// above it. Infinite when it never does (a constant, rising or held table).
    pub fn zero_beyond_last(&self) -> f64 {
        let n = self.x.len();
        if n < 2 || self.hold {
            return f64::INFINITY;
        }
        let (x0, x1, y0, y1) = (self.x[n - 2], self.x[n - 1], self.y[n - 2], self.y[n - 1]);
        if y1 >= y0 {
            return f64::INFINITY;
        }
        x1 + y1 * (x1 - x0) / (y0 - y1)
    }

    /// The last row `(x, y)`.
    pub fn last_row(&self) -> (f64, f64) {
        (self.x[self.x.len() - 1], self.y[self.y.len() - 1])
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
        let u = if self.hold {
            u.clamp(self.x[0], self.x[self.x.len() - 1])
        } else {
            u
        };
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

/// A table over two arguments (a Brake's `mu_table` over slip speed and temperature), in MSL
/// CombiTable2D's layout: `table[0][1..]` the second argument (columns), `table[1..][0]` the
/// first (rows), `table[i][j]` the value at both; `table[0][0]` is ignored. Bilinear between
/// grid points, held at the edge values beyond them in both arguments.
#[derive(Debug, Clone)]
pub struct Table2D {
    u: Vec<f64>,
    v: Vec<f64>,
    /// Row-major values, `u.len()` rows of `v.len()`.
    y: Vec<f64>,
}

impl Table2D {
    /// From validated CombiTable2D rows (both abscissae strictly increasing, rectangular).
    pub fn from_combi(rows: &[Vec<f64>]) -> Self {
        Self {
            u: rows[1..].iter().map(|r| r[0]).collect(),
            v: rows[0][1..].to_vec(),
            y: rows[1..]
                .iter()
                .flat_map(|r| r[1..].iter().copied())
                .collect(),
        }
    }

    /// The held interval of `x` in `xs` and the fraction of the way across it.
    #[inline]
    fn locate(xs: &[f64], x: f64) -> (usize, f64) {
        let n = xs.len();
        if n == 1 {
            return (0, 0.0);
        }
        let x = x.clamp(xs[0], xs[n - 1]);
        let i = xs.partition_point(|&xi| xi <= x).clamp(1, n - 1) - 1;
        (i, (x - xs[i]) / (xs[i + 1] - xs[i]))
    }

    pub fn eval(&self, u: f64, v: f64) -> f64 {
        let (i, fu) = Self::locate(&self.u, u);
        let (j, fv) = Self::locate(&self.v, v);
        let m = self.v.len();
        let at = |i: usize, j: usize| self.y[i.min(self.u.len() - 1) * m + j.min(m - 1)];
        let lo = at(i, j) + (at(i, j + 1) - at(i, j)) * fv;
        let hi = at(i + 1, j) + (at(i + 1, j + 1) - at(i + 1, j)) * fv;
        lo + (hi - lo) * fu
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(rows: &[(f64, f64)]) -> Table1D {
        Table1D {
            x: rows.iter().map(|r| r.0).collect(),
            y: rows.iter().map(|r| r.1).collect(),
            hold: false,
        }
    }

    #[test]
    fn holding_tables_keep_their_end_values() {
        let t = table(&[(0.0, 0.35), (100.0, 0.3)]);
        assert!((t.eval(700.0) - 0.0).abs() < 1e-15);
        assert!((t.zero_beyond_last() - 700.0).abs() < 1e-9);
        let held = t.clone().holding();
        assert_eq!(held.eval(700.0), 0.3);
        assert_eq!(held.eval(-5.0), 0.35);
        assert_eq!(held.eval(50.0), t.eval(50.0));
        assert_eq!(held.zero_beyond_last(), f64::INFINITY);
        assert_eq!(
            table(&[(0.0, 0.3), (1.0, 0.4)]).zero_beyond_last(),
            f64::INFINITY
        );
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

    #[test]
    fn two_dimensional_tables_are_bilinear_and_held() {
        let rows = vec![
            vec![0.0, 300.0, 500.0],
            vec![0.0, 0.4, 0.2],
            vec![10.0, 0.3, 0.1],
        ];
        let t = Table2D::from_combi(&rows);
        assert!((t.eval(5.0, 400.0) - 0.25).abs() < 1e-15);
        assert_eq!(t.eval(0.0, 300.0), 0.4);
        assert_eq!(t.eval(-1.0, 200.0), 0.4); // held below both
        assert_eq!(t.eval(20.0, 900.0), 0.1); // held above both
        assert!((t.eval(10.0, 350.0) - 0.25).abs() < 1e-15);
        let one = Table2D::from_combi(&[vec![0.0, 300.0], vec![0.0, 0.5]]);
        assert_eq!(one.eval(3.0, 1000.0), 0.5);
    }
}
