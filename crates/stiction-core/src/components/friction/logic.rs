//! MSL `PartialFriction` (spec §3.2): the start conditions, `locked`, the acceleration branch and
//! the mode, as pure functions of the pre-values and the current continuous values. Brake and
//! Clutch share them; the event iteration in `events/` drives them to a fixed point.

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
pub struct Relations {
    pub sa: f64,
    pub w: f64,
    pub tau0: f64,
    pub tau0_max: f64,
    pub w_small: f64,
    pub initial: bool,
}

/// (F1) and (F2).
pub fn start_flags(pre: Discrete, r: Relations) -> (bool, bool) {
    let forward = (pre.mode == STUCK
        && (r.sa > r.tau0_max || (pre.start_forward && r.sa > r.tau0)))
        || (pre.mode == BACKWARD && r.w > r.w_small)
        || (r.initial && r.w > 0.0);
    let backward = (pre.mode == STUCK
        && (r.sa < -r.tau0_max || (pre.start_backward && r.sa < -r.tau0)))
        || (pre.mode == FORWARD && r.w < -r.w_small)
        || (r.initial && r.w < 0.0);
    (forward, backward)
}

/// (F3).
pub fn locked(free: bool, pre_mode: i8, start_forward: bool, start_backward: bool) -> bool {
    !(free || pre_mode == FORWARD || start_forward || pre_mode == BACKWARD || start_backward)
}

/// (F5).
pub fn mode(free: bool, pre_mode: i8, start_forward: bool, start_backward: bool, w: f64) -> i8 {
    if free {
        FREE
    } else if (pre_mode == FORWARD || pre_mode == FREE || start_forward) && w > 0.0 {
        FORWARD
    } else if (pre_mode == BACKWARD || pre_mode == FREE || start_backward) && w < 0.0 {
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
        Relations {
            sa,
            w,
            tau0: 10.0,
            tau0_max: 11.0,
            w_small: 1e10,
            initial: false,
        }
    }

    #[test]
    fn breakaway_needs_peak_then_hysteresis_holds_down_to_tau0() {
        let stuck = Discrete {
            mode: STUCK,
            start_forward: false,
            start_backward: false,
        };
        assert_eq!(start_flags(stuck, rel(10.5, 0.0)), (false, false));
        assert_eq!(start_flags(stuck, rel(11.5, 0.0)), (true, false));
        let starting = Discrete {
            start_forward: true,
            ..stuck
        };
        assert_eq!(start_flags(starting, rel(10.5, 0.0)), (true, false));
        assert_eq!(start_flags(starting, rel(9.5, 0.0)), (false, false));
        assert_eq!(start_flags(stuck, rel(-11.5, 0.0)), (false, true));
    }

    #[test]
    fn initialization_starts_in_the_direction_of_motion() {
        let r = Relations {
            initial: true,
            ..rel(0.0, -10.0)
        };
        let (sf, sb) = start_flags(Discrete::INITIAL, r);
        assert!(!sf && sb);
        assert!(!locked(false, UNKNOWN, sf, sb));
        assert_eq!(mode(false, UNKNOWN, sf, sb, -10.0), BACKWARD);
        // at rest and engaged: locked and stuck
        assert!(locked(false, UNKNOWN, false, false));
        assert_eq!(mode(false, UNKNOWN, false, false, 0.0), STUCK);
    }

    #[test]
    fn leaving_free_takes_one_locked_pass() {
        assert!(locked(false, FREE, false, false));
        assert_eq!(mode(false, FREE, false, false, 2.0), FORWARD);
        assert!(!locked(false, FORWARD, false, false));
    }
}
