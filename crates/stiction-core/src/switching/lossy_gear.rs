//! The LossyGear as the engine sees it (spec §5.5): efficiencies and bearing friction by
//! quadrant, its discrete state and relations, and its stick/roll rules.

use super::logic::{Discrete, BACKWARD, FORWARD, FREE, STUCK};
use super::relation;
use crate::rel::Rel;
use crate::table::Table1D;

/// One LossyGear as the engine sees it.
pub struct LossyGearElem {
    pub name: String,
    pub ratio: f64,
    /// `lossTable = [0, 1, 1, 0, 0]` exactly: an ideal gear (mode 2 for ever).
    pub ideal: bool,
    /// Columns 2..5 of lossTable against |w_a|: eta_mf1, eta_mf2, tau_bf1, tau_bf2.
    pub table: [Table1D; 4],
    /// Whether the losses depend on the speed (more than one table row).
    pub speed_dependent: bool,
    pub eta1_0: f64,
    pub eta2_0: f64,
    pub tbf1_0: f64,
    pub tbf2_0: f64,
    pub tbf_a_0: f64,
    /// `phi_a − ratio·phi_b − (1 − ratio)·phi_support`.
    pub row: Rel,
    /// `a_a = flange_a − support`: locked when stuck.
    pub lock_row: Rel,
    /// Where the loss torque acts: `[flange_b: ratio, support: −ratio]`.
    pub loss_col: Rel,
    pub heat_node: Option<usize>,
}

/// Discrete state between events: `pre()` of mode and start flags, `locked`, and the frozen
/// relation `tau_etaPos = tau_eta ≥ 0` that picks the driving side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GearState {
    pub pre: Discrete,
    pub locked: bool,
    /// The values of its relations (they change only at events).
    pub rel: GearRelations,
}

/// The relations of the LossyGear's Boolean equations, each `g > 0` with hysteresis (see
/// `events::relation`): `sa > tauLossMax_p`, `sa < tauLossMin_m`, `w_a > 0`, `w_a < 0` and
/// `tau_eta ≥ 0` (`tau_etaPos`, the driving side).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GearRelations(pub [bool; 5]);

impl GearRelations {
    pub const SA_ABOVE_MAX_P: usize = 0;
    pub const SA_BELOW_MIN_M: usize = 1;
    pub const W_POS: usize = 2;
    pub const W_NEG: usize = 3;
    pub const TAU_ETA_POS: usize = 4;

    /// `tau_etaPos(start = true)`; the others start false.
    pub const INITIAL: GearRelations = GearRelations([false, false, false, false, true]);

    /// The relations at the gear's current values, from their previous values (literal at
    /// initialization).
    pub fn update(
        self,
        sa: f64,
        max_p: f64,
        min_m: f64,
        w_a: f64,
        tau_eta: f64,
        initial: bool,
    ) -> Self {
        let g = [sa - max_p, min_m - sa, w_a, -w_a, tau_eta];
        let mut next = relation::update(self.0, g, initial);
        // `tau_eta >= 0` holds at 0 itself
        if initial {
            next[Self::TAU_ETA_POS] = tau_eta >= 0.0;
        }
        GearRelations(next)
    }

    pub fn get(&self, i: usize) -> bool {
        self.0[i]
    }
}

impl GearState {
    /// `tau_etaPos`: flange_a drives.
    pub fn tau_eta_pos(&self) -> bool {
        self.rel.get(GearRelations::TAU_ETA_POS)
    }
}

impl GearState {
    /// `mode(start = 2, fixed = true)`, `tau_etaPos(start = true)`.
    pub const INITIAL: GearState = GearState {
        pre: Discrete {
            mode: FREE,
            start_forward: false,
            start_backward: false,
        },
        locked: false,
        rel: GearRelations::INITIAL,
    };
}

/// Efficiencies and bearing friction at one speed.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Losses {
    pub eta1: f64,
    pub eta2: f64,
    pub tbf1: f64,
    pub tbf2: f64,
    pub tbf_a: f64,
}

/// How the gear enters the linear system in one mode: locked, or rolling with `τa`'s column
/// `row + c1·ℓ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearMode {
    pub locked: bool,
    pub c1: f64,
}

pub fn tbf_a(eta1: f64, eta2: f64, tbf1: f64, tbf2: f64) -> f64 {
    if (eta1 - 1.0).abs() <= 1e-15 && (eta2 - 1.0).abs() <= 1e-15 {
        tbf1 / 2.0
    } else {
        (tbf1 - tbf2) / (eta1 - 1.0 / eta2)
    }
}

impl LossyGearElem {
    pub fn losses(&self, w_a: f64) -> Losses {
        if self.ideal {
            return Losses {
                eta1: 1.0,
                eta2: 1.0,
                ..Losses::default()
            };
        }
        let u = w_a.abs();
        let (eta1, eta2) = (self.table[0].eval(u), self.table[1].eval(u));
        let (tbf1, tbf2) = (self.table[2].eval(u).abs(), self.table[3].eval(u).abs());
        Losses {
            eta1,
            eta2,
            tbf1,
            tbf2,
            tbf_a: tbf_a(eta1, eta2, tbf1, tbf2),
        }
    }

    /// The loss torque while rolling, `c1·τa + c0`, by quadrant: forward motion uses
    /// `tauLossMax`, backward `tauLossMin`; `tau_etaPos` says which flange drives.
    pub fn rolling_line(&self, st: &GearState, l: &Losses) -> (f64, f64) {
        let forward = st.pre.start_forward || (!st.pre.start_backward && st.pre.mode == FORWARD);
        match (forward, st.tau_eta_pos()) {
            (true, true) => (1.0 - l.eta1, l.tbf1),         // quadrant 1
            (true, false) => (1.0 - 1.0 / l.eta2, l.tbf2),  // quadrant 2
            (false, true) => (1.0 - 1.0 / l.eta2, -l.tbf2), // quadrant 4
            (false, false) => (1.0 - l.eta1, -l.tbf1),      // quadrant 3
        }
    }

    pub fn mode_in(&self, st: &GearState, l: &Losses) -> GearMode {
        if self.ideal {
            GearMode {
                locked: false,
                c1: 0.0,
            }
        } else if st.locked {
            GearMode {
                locked: true,
                c1: 0.0,
            }
        } else {
            GearMode {
                locked: false,
                c1: self.rolling_line(st, l).0,
            }
        }
    }

    /// The losses at zero speed: the key of the factored mode (exact for a one-row table).
    pub fn losses_at_rest(&self) -> Losses {
        self.losses(0.0)
    }

    /// `tau_eta`: flange_a torque less the bearing friction share, deciding the driving side.
    pub fn tau_eta(&self, st: &GearState, tau_a: f64, tbf_a: f64) -> f64 {
        if self.ideal || st.locked {
            tau_a
        } else if st.pre.start_forward || st.pre.mode == FORWARD {
            tau_a - tbf_a
        } else {
            tau_a + tbf_a
        }
    }

    /// `(tauLossMax_p, tauLossMin_m)`: the loss limits just off rest, for the breakaway test.
    pub fn rest_limits(&self, tau_a: f64) -> (f64, f64) {
        let max_p = if tau_a - self.tbf_a_0 > 0.0 {
            (1.0 - self.eta1_0) * tau_a + self.tbf1_0
        } else {
            (1.0 - 1.0 / self.eta2_0) * tau_a + self.tbf2_0
        };
        let min_m = if tau_a + self.tbf_a_0 > 0.0 {
            (1.0 - 1.0 / self.eta2_0) * tau_a - self.tbf2_0
        } else {
            (1.0 - self.eta1_0) * tau_a - self.tbf1_0
        };
        (max_p, min_m)
    }

    pub fn start_flags(&self, pre: Discrete, r: GearRelations, initial: bool) -> (bool, bool) {
        use GearRelations as R;
        (
            (pre.mode == STUCK && r.get(R::SA_ABOVE_MAX_P)) || (initial && r.get(R::W_POS)),
            (pre.mode == STUCK && r.get(R::SA_BELOW_MIN_M)) || (initial && r.get(R::W_NEG)),
        )
    }

    pub fn locked(&self, pre: Discrete, sf: bool, sb: bool) -> bool {
        !(self.ideal || pre.mode == FORWARD || sf || pre.mode == BACKWARD || sb)
    }

    pub fn mode(&self, pre: Discrete, sf: bool, sb: bool, r: GearRelations) -> i8 {
        if self.ideal {
            FREE
        } else if (pre.mode == FORWARD || sf) && r.get(GearRelations::W_POS) {
            FORWARD
        } else if (pre.mode == BACKWARD || sb) && r.get(GearRelations::W_NEG) {
            BACKWARD
        } else {
            STUCK
        }
    }
}
