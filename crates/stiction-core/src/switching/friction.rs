//! The friction element as the engine sees it (Brake, Clutch, BearingFriction, OneWayClutch):
//! its parameters, its discrete state between events, and MSL's `PartialFriction` rules applied
//! to it (the OneWayClutch's own one-directional rules included).

use super::logic::{self, Discrete};
use crate::rel::Rel;
use crate::table::Table1D;

/// One friction element as the engine sees it.
pub struct FrictionElem {
    pub name: String,
    /// `w_relfric = rel·w`.
    pub rel: Rel,
    pub mu_pos: Table1D,
    pub peak: f64,
    pub cgeo: f64,
    pub fn_max: f64,
    pub w_small: f64,
    /// `mu0 = T(0)`.
    pub mu0: f64,
    /// Signal slot of `f_normalized`; None for BearingFriction (fn ≡ 1, cgeo ≡ 1: the table is
    /// the friction torque itself and the element is never free).
    pub input: Option<usize>,
    /// Clutch reads the table at `+w_rel` while starting backward (spec §5.2).
    pub clutch_quirk: bool,
    pub heat_node: Option<usize>,
    /// OneWayClutch (spec §5.3): its own one-directional logic.
    pub one_way: Option<OneWay>,
    /// `pre()` of the discrete state at initialization.
    pub initial: Discrete,
}

/// What a OneWayClutch adds: the breakaway threshold while disengaged
/// (`tau0_max_low = 1e-4·mu0·cgeo·fn_max`). Its `peak` is already `max(peak, 1 + 1e-4)`.
#[derive(Debug, Clone, Copy)]
pub struct OneWay {
    pub tau0_max_low: f64,
}

/// The discrete state of a friction element between events (its relations frozen).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrictionState {
    pub pre: Discrete,
    pub locked: bool,
    pub free: bool,
    /// The values of its relations (they change only at events).
    pub rel: logic::Relations,
}

impl FrictionState {
    pub fn initial(elem: &FrictionElem) -> Self {
        FrictionState {
            pre: elem.initial,
            locked: false,
            free: true,
            rel: logic::Relations::default(),
        }
    }
}

impl FrictionElem {
    pub fn normal_force(&self, signals: &[f64]) -> f64 {
        match self.input {
            Some(slot) => self.fn_max * signals[slot],
            None => 1.0,
        }
    }

    /// The normal force MSL reports: a OneWayClutch has `fn = 0` while disengaged.
    pub fn reported_normal_force(&self, signals: &[f64], free: bool) -> f64 {
        match self.one_way {
            Some(_) if free => 0.0,
            _ => self.normal_force(signals),
        }
    }

    /// `(tau0, tau0_max)` for a normal force.
    pub fn limits(&self, fn_: f64, free: bool) -> (f64, f64) {
        let tau0 = self.mu0 * self.cgeo * fn_;
        match self.one_way {
            Some(ow) if free => (tau0, ow.tau0_max_low),
            _ => (tau0, self.peak * tau0),
        }
    }

    /// `mu` and the sliding torque `mu·cgeo·fn` with the sign pair of (sf, sb, pre(mode)).
    pub fn sliding(&self, w: f64, fn_: f64, pre_mode: i8, sf: bool, sb: bool) -> (f64, f64) {
        let mu = if self.one_way.is_some() {
            self.mu_pos.eval(w) // no sign handling: w_rel is assumed >= 0
        } else {
            let (s_w, s_mu) = logic::table_signs(sf, sb, pre_mode, self.clutch_quirk);
            s_mu * self.mu_pos.eval(s_w * w)
        };
        (mu, mu * self.cgeo * fn_)
    }

    /// (F1, F2), or the OneWayClutch's start condition (it never starts backward).
    pub fn start_flags(&self, pre: Discrete, r: logic::Relations, initial: bool) -> (bool, bool) {
        use logic::Relations as R;
        if self.one_way.is_none() {
            return logic::start_flags(pre, r, initial);
        }
        let pre_stuck = pre.mode == logic::STUCK;
        let forward = (pre_stuck
            && (r.get(R::SA_ABOVE_MAX)
                || (pre.start_forward && r.get(R::SA_ABOVE))
                || r.get(R::W_ABOVE_SMALL)))
            || (initial && r.get(R::W_POS));
        (forward, false)
    }

    /// (F3); a OneWayClutch locks whenever it was stuck and does not start, engaged or not.
    pub fn locked(&self, free: bool, pre: Discrete, sf: bool, sb: bool) -> bool {
        match self.one_way {
            Some(_) => pre.mode == logic::STUCK && !sf,
            None => logic::locked(free, pre.mode, sf, sb),
        }
    }

    /// (F5); a OneWayClutch's "mode" is Stuck while `stuck = locked ∨ w_rel ≤ 0`, else Forward.
    pub fn mode(&self, free: bool, pre: Discrete, sf: bool, sb: bool, r: logic::Relations) -> i8 {
        match self.one_way {
            Some(_) if self.locked(free, pre, sf, sb) || !r.get(logic::Relations::W_POS) => {
                logic::STUCK
            }
            Some(_) => logic::FORWARD,
            None => logic::mode(free, pre.mode, sf, sb, r),
        }
    }

    /// `sa` of an element that is not locked, from its relative acceleration (F4).
    pub fn sa_from_accel(
        &self,
        free: bool,
        pre: Discrete,
        a: f64,
        tau0: f64,
        tau0_max: f64,
    ) -> f64 {
        match self.one_way {
            Some(_) => a + tau0,
            None if free => a,
            None => {
                a + logic::accel_offset(
                    false,
                    pre.mode,
                    pre.start_forward,
                    pre.start_backward,
                    tau0_max,
                )
            }
        }
    }
}
