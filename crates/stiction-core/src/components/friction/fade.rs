//! The fade parameters of Brake, Clutch, OneWayClutch and the translational Brake (beyond MSL,
//! `switching::fade`): read, checked by name, and none of them set means no fade at all.

use crate::error::ModelResult;
use crate::lookup_table::{Table1D, Table2D};
use crate::model::Params;
use crate::switching::fade::Fade;

const MU_T: &str = "mu_T [K, 1] Beyond MSL: factor over the heat port's temperature on the \
     whole friction coefficient (mu_pos and the static peak*mu(0)): rows [T, factor], linear \
     between rows, held beyond them; needs useHeatPort = true (default: no fade)";
const PEAK_T: &str = "peak_T [K, 1] Beyond MSL: factor over the heat port's temperature on \
     peak alone (peak*factor must stay >= 1): rows [T, factor], linear between rows, held \
     beyond them; needs useHeatPort = true (default: none)";
const MU_FN: &str = "mu_fn [N, 1] Beyond MSL: factor over the normal force fn on the whole \
     friction coefficient: rows [fn, factor], linear between rows, held beyond them (default: \
     none)";
const MU_TABLE: &str = "mu_table [rad/s, 1] Beyond MSL: friction coefficient over slip speed \
     and temperature, in place of mu_pos and mu_T; CombiTable2D's layout: first row [_, T1, \
     T2…] in K, then rows [w, mu(w, T1), mu(w, T2)…] for w >= 0; bilinear, held beyond the \
     edges (default: none)";
/// `mu_table` of the translational Brake: over the sliding speed in m/s.
const MU_TABLE_V: &str = "mu_table [m/s, 1] Beyond MSL: friction coefficient over sliding \
     speed and temperature, in place of mu_pos and mu_T; CombiTable2D's layout: first row [_, \
     T1, T2…] in K, then rows [v, mu(v, T1), mu(v, T2)…] for v >= 0; bilinear, held beyond the \
     edges (default: none)";

/// The parameters that read the heat port's temperature.
const THERMAL: [&str; 3] = ["mu_T", "peak_T", "mu_table"];

/// A factor table: values >= 0, abscissa increasing, held beyond its rows.
fn factor_table(p: &Params, decl: &'static str, default: f64) -> ModelResult<Table1D> {
    let rows = p.matrix(decl, 2, &[&[default, 1.0]])?;
    let name = crate::model::parse_decl(decl).0;
    p.table_at_least(name, &rows, 0.0, "factors")?;
    Ok(Table1D::from_rows(p, name, &rows, 1)?.holding())
}

/// `mu_table`: a rectangular CombiTable2D matrix, both abscissae increasing, values >= 0.
fn mu_table(p: &Params, decl: &'static str) -> ModelResult<Table2D> {
    let width = p.matrix_width("mu_table").unwrap_or(2).max(2);
    let rows = p.matrix(decl, width, &[&[0.0, 293.15], &[0.0, 0.5]])?;
    let values: Vec<Vec<f64>> = rows.iter().skip(1).cloned().collect();
    p.table_at_least("mu_table", &values, 0.0, "coefficients")?;
    if p.in_catalogue() {
        return Ok(Table2D::from_combi(&rows));
    }
    let malformed = |m: String| p.error("mu_table", m);
    if rows.len() < 2 {
        return Err(malformed(
            "needs a first row of temperatures [_, T1, T2…] and at least one row [w, mu…]".into(),
        ));
    }
    let temps = &rows[0][1..];
    if let Some(pair) = temps.windows(2).find(|w| w[1] <= w[0]) {
        let m = format!(
            "its first row (the temperatures) must be strictly increasing, but {} is followed \
             by {}",
            pair[0], pair[1]
        );
        return Err(malformed(m));
    }
    if let Some(t) = temps.iter().find(|&&t| t <= 0.0) {
        return Err(malformed(format!(
            "its first row holds temperatures in K, which must be > 0, got {t}"
        )));
    }
    Table1D::check_increasing(p, "mu_table", &values)?;
    Ok(Table2D::from_combi(&rows))
}

/// The fade of a friction element (`translational`: speeds in m/s), None when no fade parameter is given. `mu_pos` is refused
/// beside `mu_table` (which replaces it).
pub(crate) fn read_fade(
    p: &Params,
    use_heat_port: bool,
    peak: f64,
    translational: bool,
) -> ModelResult<Option<Fade>> {
    let table_decl = if translational { MU_TABLE_V } else { MU_TABLE };
    let given = ["mu_T", "peak_T", "mu_fn", "mu_table"];
    if !p.in_catalogue() && !given.iter().any(|n| p.has(n)) {
        // no fade: the default tables are not built (a sweep creates its clutches anew for
        // every variant), only declared
        for decl in [MU_T, PEAK_T, MU_FN, table_decl] {
            p.mark_used(decl);
        }
        return Ok(None);
    }
    let mu_t = factor_table(p, MU_T, 293.15)?;
    let peak_t = factor_table(p, PEAK_T, 293.15)?;
    let mu_fn = factor_table(p, MU_FN, 0.0)?;
    let table = mu_table(p, table_decl)?;
    if p.in_catalogue() {
        return Ok(None);
    }
    for other in ["mu_pos", "mu_T"] {
        if p.has("mu_table") && p.has(other) {
            let m =
                format!("mu_table replaces mu_pos and mu_T: give {other} or mu_table, not both");
            return Err(p.error("mu_table", m));
        }
    }
    if let Some(name) = THERMAL.iter().find(|n| p.has(n)).filter(|_| !use_heat_port) {
        return Err(p.error(
            name,
            "reads the heat port's temperature: set useHeatPort = true and connect heatPort to \
             a HeatCapacitor or a FixedTemperature",
        ));
    }
    if p.has("peak_T") {
        check_peak(p, peak)?;
    }
    let given = |name: &str, t: Table1D| p.has(name).then_some(t);
    Ok(Some(Fade {
        temperature: None,
        mu_t: given("mu_T", mu_t),
        peak_t: given("peak_T", peak_t),
        mu_fn: given("mu_fn", mu_fn),
        mu_table: p.has("mu_table").then_some(table),
    }))
}

/// `peak·peak_T` must stay >= 1 (MSL's `peak >= 1`: the static limit never below the
/// sliding one); a held, piecewise linear factor is smallest at one of its rows.
fn check_peak(p: &Params, peak: f64) -> ModelResult<()> {
    let rows = p.matrix(PEAK_T, 2, &[&[293.15, 1.0]])?;
    let low = rows.iter().map(|r| r[1]).fold(f64::INFINITY, f64::min);
    if peak * low < 1.0 {
        return Err(p.error(
            "peak_T",
            format!("peak*factor must stay >= 1, but peak = {peak} and a factor is {low}"),
        ));
    }
    Ok(())
}

/// The name of the first given parameter that reads the temperature (for the tap's messages).
pub(crate) fn thermal_param(f: &Fade) -> Option<&'static str> {
    [
        (f.mu_table.is_some(), "mu_table"),
        (f.mu_t.is_some(), "mu_T"),
        (f.peak_t.is_some(), "peak_T"),
    ]
    .into_iter()
    .find_map(|(on, name)| on.then_some(name))
}
