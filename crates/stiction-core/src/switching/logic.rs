//! MSL `PartialFriction` (spec §3.2): the start conditions, `locked`, the acceleration branch and
//! the mode, as pure functions of the pre-values and the current continuous values. Brake and
//! Clutch share them; the event iteration in `events/` drives them to a fixed point.

pub use super::relation::RelationSet as Relations;

pub const BACKWARD: i8 = -1;
pub const STUCK: i8 = 0;
pub const FORWARD: i8 = 1;
pub const FREE: i8 = 2;
pub const UNKNOWN: i8 = 3;

/// The discrete state MSL keeps with `pre()`: mode and the two start flags.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Discrete {
    pub mode: i8,
    pub start_forward: bool,
    pub start_backward: bool,
}

impl Discrete {
    /// `mode(start = 3, fixed = true)`, `startForward/Backward(start = false, fixed = true)`.
    pub const INITIAL: Discrete = Discrete {
        mode: UNKNOWN,
        start_forward: false,
        start_backward: false,
    };
}

/// The continuous quantities the Boolean equations compare.
#[derive(Debug, Clone, Copy)]
pub struct Quantities {
    pub sa: f64,
    pub w: f64,
    pub tau0: f64,
    pub tau0_max: f64,
    pub w_small: f64,
}

/// The relations (F1), (F2) and (F5) compare, each `g > 0` with hysteresis (see
/// `relation`): `sa > tau0_max`, `sa > tau0`, `sa < −tau0_max`, `sa < −tau0`,
/// `w > 0`, `w < 0`, `w > w_small`, `w < −w_small`. Their indices in a `RelationSet`:
pub mod relation_index {
    pub const SA_ABOVE_MAX: usize = 0;
    pub const SA_ABOVE: usize = 1;
    pub const SA_BELOW_MAX: usize = 2;
    pub const SA_BELOW: usize = 3;
    pub const W_POS: usize = 4;
    pub const W_NEG: usize = 5;
    pub const W_ABOVE_SMALL: usize = 6;
    pub const W_BELOW_SMALL: usize = 7;
    /// The start conditions on `sa`.
    pub const STARTS: &[usize] = &[SA_ABOVE_MAX, SA_ABOVE, SA_BELOW_MAX, SA_BELOW];
}
use relation_index as R;

/// The functions `g` of the relations, in the order of `relation_index`.
pub fn relation_functions(q: &Quantities) -> [f64; 8] {
    [
        q.sa - q.tau0_max,
        q.sa - q.tau0,
        -q.sa - q.tau0_max,
        -q.sa - q.tau0,
        q.w,
        -q.w,
        q.w - q.w_small,
        -q.w - q.w_small,
    ]
}

/// The relations at `q`, from their previous values (from none at initialization).
pub fn relations(previous: Relations, q: &Quantities, initial: bool) -> Relations {
    previous.update(&relation_functions(q), initial)
}

/// (F1) and (F2), with one departure from MSL: a start held by its hysteresis (`sa` between
/// `tau0` and `tau0_max`) ends when the element moves the other way. MSL keeps it, its
/// friction torque then drives the motion instead of opposing it, and when the start ends the
/// element "locks" at the slip it gained and creeps at it (found by the property tests: a brake
/// starting backward while a lossy gear drove its shaft forward, stuck at 5e-3 rad/s). Ended
/// there, it locks where its speed leaves zero, inside the relation band.
pub fn start_flags(pre: Discrete, r: Relations, initial: bool) -> (bool, bool) {
    let keeps_forward = pre.start_forward && r.get(R::SA_ABOVE) && !r.get(R::W_NEG);
    let keeps_backward = pre.start_backward && r.get(R::SA_BELOW) && !r.get(R::W_POS);
    let forward = (pre.mode == STUCK && (r.get(R::SA_ABOVE_MAX) || keeps_forward))
        || (pre.mode == BACKWARD && r.get(R::W_ABOVE_SMALL))
        || (initial && r.get(R::W_POS));
    let backward = (pre.mode == STUCK && (r.get(R::SA_BELOW_MAX) || keeps_backward))
        || (pre.mode == FORWARD && r.get(R::W_BELOW_SMALL))
        || (initial && r.get(R::W_NEG));
    (forward, backward)
}

/// (F3).
pub fn locked(free: bool, pre_mode: i8, start_forward: bool, start_backward: bool) -> bool {
    !(free || pre_mode == FORWARD || start_forward || pre_mode == BACKWARD || start_backward)
}

/// (F5).
pub fn mode(
    free: bool,
    pre_mode: i8,
    start_forward: bool,
    start_backward: bool,
    r: Relations,
) -> i8 {
    if free {
        FREE
    } else if (pre_mode == FORWARD || pre_mode == FREE || start_forward) && r.get(R::W_POS) {
        FORWARD
    } else if (pre_mode == BACKWARD || pre_mode == FREE || start_backward) && r.get(R::W_NEG) {
        BACKWARD
    } else {
        STUCK
    }
}

/// The offset of (F4) for an element that is not locked: `a_relfric = sa − offset`.
pub fn accel_offset(free: bool, pre_mode: i8, sf: bool, sb: bool, tau0_max: f64) -> f64 {
    if free {
        0.0
    } else if sf {
        tau0_max
    } else if sb {
        -tau0_max
    } else if pre_mode == FORWARD {
        tau0_max
    } else if pre_mode == BACKWARD {
        -tau0_max
    } else {
        // Unreachable per spec §3.2 (such an element is locked); MSL 4.1.0 writes this branch.
        tau0_max
    }
}

/// `(s_w, s_mu)` of Brake and BearingFriction: `mu = s_mu·T(s_w·w)`.
pub fn table_signs(sf: bool, sb: bool, pre_mode: i8, clutch_quirk: bool) -> (f64, f64) {
    if sf {
        (1.0, 1.0)
    } else if sb {
        // Clutch reads the table at +w_rel here (spec §5.2 quirk).
        if clutch_quirk {
            (1.0, -1.0)
        } else {
            (-1.0, -1.0)
        }
    } else if pre_mode == FORWARD {
        (1.0, 1.0)
    } else {
        (-1.0, -1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(sa: f64, w: f64) -> Relations {
        let q = Quantities {
            sa,
            w,
            tau0: 10.0,
            tau0_max: 11.0,
            w_small: 1e10,
        };
        relations(Relations::default(), &q, true)
    }

    #[test]
    fn breakaway_needs_peak_then_hysteresis_holds_down_to_tau0() {
        let stuck = Discrete {
            mode: STUCK,
            start_forward: false,
            start_backward: false,
        };
        assert_eq!(start_flags(stuck, rel(10.5, 0.0), false), (false, false));
        assert_eq!(start_flags(stuck, rel(11.5, 0.0), false), (true, false));
        let starting = Discrete {
            start_forward: true,
            ..stuck
        };
        assert_eq!(start_flags(starting, rel(10.5, 0.0), false), (true, false));
        assert_eq!(start_flags(starting, rel(9.5, 0.0), false), (false, false));
        assert_eq!(start_flags(stuck, rel(-11.5, 0.0), false), (false, true));
    }

    #[test]
    fn a_start_held_by_its_hysteresis_ends_when_the_element_moves_the_other_way() {
        let starting_backward = Discrete {
            mode: STUCK,
            start_forward: false,
            start_backward: true,
        };
        // sa between -tau0_max and -tau0: the start holds while the element has not moved ...
        assert_eq!(
            start_flags(starting_backward, rel(-10.5, 0.0), false),
            (false, true)
        );
        // ... and ends once it turns forward, so the element locks (MSL would keep starting)
        assert_eq!(
            start_flags(starting_backward, rel(-10.5, 1e-9), false),
            (false, false)
        );
        // beyond tau0_max it starts again whatever the speed: the torque now opposes the motion
        assert_eq!(
            start_flags(starting_backward, rel(-11.5, 1e-9), false),
            (false, true)
        );
        let starting_forward = Discrete {
            start_forward: true,
            start_backward: false,
            ..starting_backward
        };
        assert_eq!(
            start_flags(starting_forward, rel(10.5, -1e-9), false),
            (false, false)
        );
        assert_eq!(
            start_flags(starting_forward, rel(10.5, 1e-9), false),
            (true, false)
        );
    }

    #[test]
    fn a_threshold_met_exactly_keeps_the_previous_decision() {
        let q = |sa| Quantities {
            sa,
            w: 0.0,
            tau0: 0.5,
            tau0_max: 0.5,
            w_small: 1e10,
        };
        let started = relations(Relations::default(), &q(0.7), false);
        assert!(started.get(R::SA_ABOVE_MAX));
        // another element now holds the motion: sa sits on the limit, within round-off
        assert!(relations(started, &q(0.5 - 1e-16), false).get(R::SA_ABOVE_MAX));
        assert!(!relations(started, &q(0.4), false).get(R::SA_ABOVE_MAX));
    }

    #[test]
    fn initialization_starts_in_the_direction_of_motion() {
        let r = rel(0.0, -10.0);
        let (sf, sb) = start_flags(Discrete::INITIAL, r, true);
        assert!(!sf && sb);
        assert!(!locked(false, UNKNOWN, sf, sb));
        assert_eq!(mode(false, UNKNOWN, sf, sb, r), BACKWARD);
        // at rest and engaged: locked and stuck
        assert!(locked(false, UNKNOWN, false, false));
        assert_eq!(mode(false, UNKNOWN, false, false, rel(0.0, 0.0)), STUCK);
    }

    #[test]
    fn leaving_free_takes_one_locked_pass() {
        assert!(locked(false, FREE, false, false));
        assert_eq!(mode(false, FREE, false, false, rel(0.0, 2.0)), FORWARD);
        assert!(!locked(false, FORWARD, false, false));
    }
}
