//! A level a run waits for (`Simulation::advance_until`, `redrive.rs`), and the search for its
//! crossing inside a step: regula falsi with the Illinois modification on the dense output.

use crate::error::SimError;
use crate::result::Probe;

/// The variable `probe` reads, minus `level`, times `side`, falls to 0 or below: the crossing.
/// `hit` is the instant found. Its own probe (workspace, or the state alone for a speed) and
/// state buffer, so that the search leaves the run's evaluations alone.
pub(super) struct Watch {
    pub(super) probe: Probe,
    pub(super) level: f64,
    pub(super) side: f64,
    pub(super) hit: Option<f64>,
    pub(super) x: Vec<f64>,
}

/// The first instant in [start, end] where `g` (positive before the crossing) is at or below
/// 0, to round-off: `None` when `g(end) > 0`, `start` when `g(start) <= 0`.
pub(super) fn first_crossing(
    mut g: impl FnMut(f64) -> Result<f64, SimError>,
    start: f64,
    end: f64,
) -> Result<Option<f64>, SimError> {
    let (mut b, mut gb) = (end, g(end)?);
    if gb > 0.0 {
        return Ok(None);
    }
    let (mut a, mut ga) = (start, g(start)?);
    if ga <= 0.0 {
        return Ok(Some(start));
    }
    // ga > 0 >= gb: keep the bracket, halving the weight of an end kept twice (Illinois)
    let mut kept = 0i8;
    for _ in 0..200 {
        if b - a <= 4.0 * f64::EPSILON * b.abs().max(1e-300) {
            break;
        }
        let mut t = b - gb * (b - a) / (gb - ga);
        if !(t > a && t < b) {
            t = 0.5 * (a + b);
        }
        let gt = g(t)?;
        if gt > 0.0 {
            (a, ga) = (t, gt);
            if kept == 1 {
                gb *= 0.5;
            }
            kept = 1;
        } else {
            (b, gb) = (t, gt);
            if kept == -1 {
                ga *= 0.5;
            }
            kept = -1;
        }
    }
    Ok(Some(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_crossing_of_a_line_and_of_an_exponential_is_found_to_round_off() {
        let t = first_crossing(|t| Ok(3.0 - 2.0 * t), 0.0, 4.0)
            .unwrap()
            .unwrap();
        assert!((t - 1.5).abs() <= 4.0 * f64::EPSILON * 1.5);
        let g = |t: f64| Ok((-t / 7.0).exp() - 0.25);
        let t = first_crossing(g, 1.0, 20.0).unwrap().unwrap();
        assert!((t - 7.0 * 4f64.ln()).abs() <= 1e-14 * t, "{t}");
        assert_eq!(first_crossing(|t| Ok(1.0 + t), 0.0, 1.0).unwrap(), None);
        assert_eq!(first_crossing(|t| Ok(-t), 0.5, 1.0).unwrap(), Some(0.5));
    }
}
