//! What MSL's `MassWithStopAndFriction` adds to the friction element: the Stribeck law in
//! place of a table, and the two hard stops that gate its start and sliding rules
//! (`PartialFrictionWithStop`) and reset its position and speed when the mass reaches one
//! (`reinit(s, ...)`, `reinit(v, 0)`). The stick/slip logic stays `FrictionElem`'s.

use super::element::{NodeReset, SwitchState, NEVER};
use super::logic::{self, relation_index as R, Relations};
use crate::rel::Rel;

/// `f = F_prop·v + F_Coulomb + F_Stribeck·exp(−fexp·|v|)` (v ≥ 0) and the stops, on the
/// element's motion (the position of the mass's `flange_a`, so that a reset sets it exactly).
#[derive(Debug, Clone)]
pub struct StopFriction {
    pub f_prop: f64,
    pub f_coulomb: f64,
    pub f_stribeck: f64,
    pub fexp: f64,
    /// `smin + L/2` and `smax − L/2` as positions of `flange_a` (`smin`, `smax − L`).
    pub lower: f64,
    pub upper: f64,
    /// The node the motion is (its coefficient 1, no offset).
    pub node: usize,
    /// `L`, for messages in MSL's terms.
    pub length: f64,
}

impl StopFriction {
    /// The positive sliding force at `u = ±v ≥ 0`; a start uses `exp(0)` (MSL: `f0` while
    /// `startForward` or `startBackward`).
    #[inline]
    pub fn force(&self, u: f64, starting: bool) -> f64 {
        let decay = if starting {
            1.0
        } else {
            (-self.fexp * u.abs()).exp()
        };
        self.f_prop * u + self.f_coulomb + self.f_stribeck * decay
    }

    pub fn at_upper(&self, s: f64) -> bool {
        s >= self.upper
    }

    pub fn at_lower(&self, s: f64) -> bool {
        s <= self.lower
    }

    /// MSL gates `startForward` and `Forward` by `s < smax − L/2`, and the backward ones by
    /// `s > smin + L/2`: at a stop the relations that would start or keep the mass moving into
    /// it are false (a speed reset to exactly 0 there must not keep `w > 0` by hysteresis).
    pub fn gate(&self, mut r: Relations, s: f64) -> Relations {
        if self.at_upper(s) {
            r = r.cleared(&[R::SA_ABOVE_MAX, R::SA_ABOVE, R::W_POS]);
        }
        if self.at_lower(s) {
            r = r.cleared(&[R::SA_BELOW_MAX, R::SA_BELOW, R::W_NEG]);
        }
        r
    }

    /// MSL's initial asserts: `s − L/2 ≥ smin` (equal only at rest or leaving the stop) and
    /// `s + L/2 ≤ smax` likewise; `a` is `flange_a`'s position, `v` the speed.
    pub fn check_start(&self, a: f64, v: f64) -> Result<(), String> {
        let (lo, hi) = (a, a + self.length);
        let smax = self.upper + self.length;
        if a < self.lower || (a == self.lower && v < 0.0) {
            return Err(format!(
                "its left end starts at s - L/2 = {lo} m (v = {v} m/s), below or into its stop \
                 smin = {} m: start it between its stops",
                self.lower
            ));
        }
        if a > self.upper || (a == self.upper && v > 0.0) {
            return Err(format!(
                "its right end starts at s + L/2 = {hi} m (v = {v} m/s), beyond or into its stop \
                 smax = {smax} m: start it between its stops"
            ));
        }
        Ok(())
    }

    /// The stop indicator (slot 0): the mass passing the stop it moves towards.
    pub fn indicator(&self, st: &SwitchState, s: f64) -> f64 {
        if st.locked {
            return NEVER;
        }
        let stuck = st.pre.mode == logic::STUCK;
        if st.pre.mode == logic::FORWARD || (stuck && st.pre.start_forward) {
            s - self.upper
        } else if st.pre.mode == logic::BACKWARD || (stuck && st.pre.start_backward) {
            self.lower - s
        } else {
            NEVER
        }
    }

    /// A locked mass held at a stop cannot break away into it: that breakaway indicator
    /// never fires (its relation is gated false, and would flip at once).
    pub fn breakaway(&self, s: f64, forward: f64, backward: f64) -> (f64, f64) {
        let f = if self.at_upper(s) { NEVER } else { forward };
        let b = if self.at_lower(s) { NEVER } else { backward };
        (f, b)
    }

    /// `when stopped <> 0 then reinit(s, stop); reinit(v, 0)`: past a stop, or on it and
    /// moving into it, the mass is put on the stop at rest (on it at rest: nothing to do).
    pub fn reset(&self, rel: &Rel, phi: &[f64], w: &[f64]) -> Option<NodeReset> {
        let s = rel.angle(phi);
        let v = rel.dot(w);
        let to = if s > self.upper || (s == self.upper && v > 0.0) {
            self.upper
        } else if s < self.lower || (s == self.lower && v < 0.0) {
            self.lower
        } else {
            return None;
        };
        Some(NodeReset {
            node: self.node,
            phi: to,
            w: 0.0,
        })
    }
}
