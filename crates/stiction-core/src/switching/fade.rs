//! Fade: friction that depends on the heat port's temperature and on the normal force, beyond
//! MSL (whose Brake leaves `heatPort.T` unused). `mu_T` (a factor over temperature on the whole
//! coefficient, `mu_pos` and the static `peak·mu(0)` alike), `peak_T` (a factor on `peak`),
//! `mu_fn` (a factor over the normal force) and `mu_table` (the coefficient over slip speed and
//! temperature, in place of `mu_pos` and `mu_T`). The factors scale the static and the sliding
//! values the same way, so they act as an effective normal force: `fn`, `lossPower` (= tau·w)
//! and the stick/slip logic are MSL's, evaluated with these limits.

use crate::lookup_table::{Table1D, Table2D};

/// What one friction element's fade reads; every table holds its end values beyond its rows.
#[derive(Debug, Clone, Default)]
pub struct Fade {
    /// The signal slot holding the heat port's temperature (a `TemperatureTap`).
    pub temperature: Option<usize>,
    pub mu_t: Option<Table1D>,
    pub peak_t: Option<Table1D>,
    pub mu_fn: Option<Table1D>,
    pub mu_table: Option<Table2D>,
}

/// The fade's values at one instant.
#[derive(Debug, Clone, Copy)]
pub struct FadeAt {
    /// The factor on the coefficient (`mu_T(T)·mu_fn(fn)`).
    pub factor: f64,
    /// The factor on `peak` (`peak_T(T)`).
    pub peak: f64,
    /// The temperature (NaN when no table reads it).
    pub temperature: f64,
}

impl Fade {
    /// The factors at the tapped temperature and normal force `fn_`.
    #[inline]
    pub fn at(&self, signals: &[f64], fn_: f64) -> FadeAt {
        let temperature = self.temperature.map_or(f64::NAN, |slot| signals[slot]);
        let of = |t: &Option<Table1D>, x: f64| t.as_ref().map_or(1.0, |t| t.eval(x));
        FadeAt {
            factor: of(&self.mu_t, temperature) * of(&self.mu_fn, fn_),
            peak: of(&self.peak_t, temperature),
            temperature,
        }
    }

    /// The base coefficient at slip speed `u` (>= 0 after the sign handling): `mu_table`'s at
    /// the temperature, else `mu_pos`'s.
    #[inline]
    pub fn base_mu(&self, mu_pos: &Table1D, u: f64, at: &FadeAt) -> f64 {
        match &self.mu_table {
            Some(table) => table.eval(u, at.temperature),
            None => mu_pos.eval(u),
        }
    }
}
