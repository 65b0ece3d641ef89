//! Pad wear of friction elements at run time: one continuous state per worn element, the worn
//! volume [m³], integrated with the run (after the energy integrals in the state vector). Its
//! rate reads the element's values of the evaluation — slip speed, normal force, friction power
//! — and so is exactly 0 while the element is stuck (its relative speed is then 0). Nothing
//! reads the wear back: it changes no trajectory, only adds its own states.

use crate::switching::element::{ElementValues, SwitchState};

/// The wear rates of `wear` at an evaluation (the elements' discrete states, values and the
/// signals), 0 while an element is locked. Out of line: a model without wear pays one branch.
#[inline(never)]
pub fn rates(
    wear: &[Wear],
    states: &[SwitchState],
    elements: &[ElementValues],
    signals: &[f64],
    rates: &mut [f64],
) {
    for (w, rate) in wear.iter().zip(rates) {
        *rate = match states[w.element].locked {
            true => 0.0,
            false => w.model.rate(&elements[w.element], signals),
        };
    }
}

/// The molar gas constant R [J/(mol·K)] of the Arrhenius law.
pub const GAS_CONSTANT: f64 = 8.314_462_618;

/// How the worn volume grows.
#[derive(Debug, Clone, PartialEq)]
pub enum WearModel {
    /// Archard: `k·fn·v_slide/H`, `v_slide = r_eff·|w_rel|` (translational: `|v_rel|`, r_eff 1).
    Archard { k: f64, h: f64, r_eff: f64 },
    /// Energy (frictional work) wear: `alpha·lossPower`.
    Energy { alpha: f64 },
    /// `lossPower·(alpha0 + k0·max(0, exp(−E/(R·T)) − exp(−E/(R·T_threshold))))`: the energy
    /// law below the threshold temperature, an Arrhenius term growing above it (continuous at
    /// it). `slot` is the signal slot the heat port's temperature is tapped into.
    Arrhenius {
        alpha0: f64,
        k0: f64,
        e_a: f64,
        t_threshold: f64,
        slot: usize,
    },
}

/// A worn friction element.
#[derive(Debug, Clone)]
pub struct Wear {
    /// The switching element worn.
    pub element: usize,
    pub name: String,
    pub model: WearModel,
    /// The volume scale of the error control: absolute tolerance = Tolerance·nominal.
    pub nominal: f64,
    /// The worn volume at which the pad reaches `thickness_min`, and that thickness (m).
    pub limit: Option<(f64, f64)>,
}

impl WearModel {
    /// The wear rate [m³/s] at an evaluation's element values and signals.
    #[inline]
    pub fn rate(&self, v: &ElementValues, signals: &[f64]) -> f64 {
        match *self {
            WearModel::Archard { k, h, r_eff } => k * v.fn_.max(0.0) * r_eff * slide(v) / h,
            WearModel::Energy { alpha } => alpha * v.loss,
            WearModel::Arrhenius {
                alpha0,
                k0,
                e_a,
                t_threshold,
                slot,
            } => v.loss * arrhenius_factor(alpha0, k0, e_a, t_threshold, signals[slot]),
        }
    }
}

/// The sliding speed `|w_rel|`, as the slip in the direction the friction torque opposes while
/// there is one: smooth within a mode, so that a step that overshoots a stop (then located and
/// interpolated back) integrates a line, not a kink.
#[inline]
fn slide(v: &ElementValues) -> f64 {
    if v.tau != 0.0 {
        v.w * v.tau.signum()
    } else {
        v.w.abs()
    }
}

/// The volume per dissipated energy [m³/J] of the Arrhenius model at temperature `t`.
pub fn arrhenius_factor(alpha0: f64, k0: f64, e_a: f64, t_threshold: f64, t: f64) -> f64 {
    let above = (-e_a / (GAS_CONSTANT * t)).exp() - (-e_a / (GAS_CONSTANT * t_threshold)).exp();
    alpha0 + k0 * above.max(0.0)
}
