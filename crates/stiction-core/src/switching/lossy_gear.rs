//! The LossyGear as the engine sees it (spec §5.5): efficiencies and bearing friction by
//! quadrant, its discrete state and relations, and its stick/roll rules.

pub use super::element::Losses;
use super::element::{
    angle_and_speed, common_variable, slip_rate_sign, Column, ElementValues, Kinematics, ModeKey,
    Solved, SwitchState, SwitchVar, SwitchingElement, NEVER,
};
use super::logic::{Discrete, BACKWARD, FORWARD, FREE, STUCK};
use super::relation::{flip_indicator, RelationSet};
use crate::lookup_table::Table1D;
use crate::rel::Rel;

/// One LossyGear as the engine sees it.
pub struct LossyGearElem {
    pub name: String,
    pub ratio: f64,
    /// `lossTable = [0, 1, 1, 0, 0]` exactly: an ideal gear (mode 2 for ever).
    pub ideal: bool,
    /// Columns 2..5 of lossTable against |w_a|: eta_mf1, eta_mf2, tau_bf1, tau_bf2 (one
    /// abscissa, lossTable's first column: `losses` reads them at once).
    pub table: [Table1D; 4],
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

/// The relations of the LossyGear's Boolean equations, each `g > 0` with hysteresis (see
/// `relation`): `sa > tauLossMax_p`, `sa < tauLossMin_m`, `w_a > 0`, `w_a < 0` and
/// `tau_eta ≥ 0` (`tau_etaPos`, the driving side). Their indices in a `RelationSet`:
// Alike in shape to the friction logic's `relation_index`: each element's own relations.
pub mod relation_index {
    pub const SA_ABOVE_MAX_P: usize = 0;
    pub const SA_BELOW_MIN_M: usize = 1;
    pub const W_POS: usize = 2;
    pub const W_NEG: usize = 3;
    pub const TAU_ETA_POS: usize = 4;
}
use relation_index as G;

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
        let [eta1, eta2, tbf1, tbf2] = Table1D::eval_columns(&self.table, u);
        let (tbf1, tbf2) = (tbf1.abs(), tbf2.abs());
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
    pub fn rolling_line(&self, st: &SwitchState, l: &Losses) -> (f64, f64) {
        let forward = st.pre.start_forward || (!st.pre.start_backward && st.pre.mode == FORWARD);
        match (forward, st.rel.get(G::TAU_ETA_POS)) {
            (true, true) => (1.0 - l.eta1, l.tbf1),         // quadrant 1
            (true, false) => (1.0 - 1.0 / l.eta2, l.tbf2),  // quadrant 2
            (false, true) => (1.0 - 1.0 / l.eta2, -l.tbf2), // quadrant 4
            (false, false) => (1.0 - l.eta1, -l.tbf1),      // quadrant 3
        }
    }

    /// How the gear enters the linear system at these losses: locked, or rolling with the
    /// loss slope `c1` in `τa`'s column `row + c1·ℓ`.
    pub fn mode_at(&self, st: &SwitchState, l: &Losses) -> ModeKey {
        let locked = !self.ideal && st.locked;
        let slope = if self.ideal || locked {
            0.0
        } else {
            self.rolling_line(st, l).0
        };
        ModeKey { locked, slope }
    }

    /// The losses at zero speed: the key of the factored mode (exact for a one-row table).
    pub fn losses_at_rest(&self) -> Losses {
        self.losses(0.0)
    }

    /// `tau_eta`: flange_a torque less the bearing friction share, deciding the driving side.
    pub fn tau_eta(&self, st: &SwitchState, tau_a: f64, tbf_a: f64) -> f64 {
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

    fn loss_torque(&self, st: &SwitchState, s: &Solved, v: &ElementValues) -> f64 {
        if self.ideal {
            0.0
        } else if st.locked {
            s.lock.unwrap_or(0.0)
        } else {
            let (c1, c0) = self.rolling_line(st, &v.losses);
            c1 * v.tau + c0
        }
    }
}

/// `tauLossMin_m` and `tauLossMax_p` are kept as the element's static limits `tau0`, `tau0_max`.
impl SwitchingElement for LossyGearElem {
    fn name(&self) -> &str {
        &self.name
    }

    /// `mode(start = 2, fixed = true)`, `tau_etaPos(start = true)`.
    fn initial_state(&self) -> SwitchState {
        let mut rel = RelationSet::default();
        rel.set(G::TAU_ETA_POS, true);
        SwitchState {
            pre: Discrete {
                mode: FREE,
                start_forward: false,
                start_backward: false,
            },
            locked: false,
            free: false,
            rel,
        }
    }

    fn heat_node(&self) -> Option<usize> {
        self.heat_node
    }

    fn motion(&self) -> &Rel {
        &self.lock_row
    }

    fn permanent_row(&self, key: ModeKey) -> Option<(&Rel, Column<'_>)> {
        let column = if !key.locked && key.slope != 0.0 {
            Column::Plus(&self.loss_col, key.slope)
        } else {
            Column::Same
        };
        Some((&self.row, column))
    }

    /// The stuck loss torque acts through ℓ.
    fn lock_column(&self) -> Column<'_> {
        Column::Only(&self.loss_col)
    }

    /// Locked friction elements come before locked gears, as in the reference results: a
    /// bearing stuck together with a gear carries the load first.
    fn lock_rank(&self) -> u8 {
        1
    }

    /// Keyed by the losses at rest: exact unless the loss table depends on the speed.
    fn mode_key(&self, st: &SwitchState) -> ModeKey {
        self.mode_at(st, &self.losses_at_rest())
    }

    fn slope_column(&self) -> Option<&Rel> {
        Some(&self.loss_col)
    }

    fn forces(&self, st: &SwitchState, k: &Kinematics, v: &mut ElementValues, f: &mut [f64]) {
        (v.phi, v.w) = angle_and_speed(&self.lock_row, k.phi, k.w);
        v.losses = self.losses(v.w);
        v.slope = self.mode_at(st, &v.losses).slope;
        if !self.ideal && !st.locked {
            // a rolling gear's constant loss part c0 acts through ℓ
            let (_, c0) = self.rolling_line(st, &v.losses);
            self.loss_col.apply(c0, f);
        }
    }

    fn solved(&self, st: &SwitchState, s: &Solved, v: &mut ElementValues) {
        v.tau = s.permanent.unwrap_or(0.0);
        v.held = s.held;
        v.a = self.lock_row.dot(s.a);
        v.tau_loss = self.loss_torque(st, s, v);
        v.sa = if st.locked {
            v.tau_loss
        } else {
            v.a + v.tau_loss
        };
        v.tau_b = -self.ratio * (v.tau - v.tau_loss);
        v.tau_support = -v.tau - v.tau_b;
        v.tau_eta = self.tau_eta(st, v.tau, v.losses.tbf_a);
        (v.tau0_max, v.tau0) = self.rest_limits(v.tau);
        v.loss = v.tau_loss * v.w;
    }

    fn relations(&self, previous: RelationSet, v: &ElementValues, initial: bool) -> RelationSet {
        let g = [v.sa - v.tau0_max, v.tau0 - v.sa, v.w, -v.w, v.tau_eta];
        let mut next = previous.update(&g, initial);
        // `tau_eta >= 0` holds at 0 itself
        if initial {
            next.set(G::TAU_ETA_POS, v.tau_eta >= 0.0);
        }
        next
    }

    fn start_relations(&self) -> &'static [usize] {
        &[G::SA_ABOVE_MAX_P, G::SA_BELOW_MIN_M]
    }

    /// Speeds do not change within an event; the driving side is the first candidate's.
    fn own_relations(&self) -> &'static [usize] {
        &[G::TAU_ETA_POS]
    }

    fn start_flags(&self, pre: Discrete, r: RelationSet, initial: bool) -> (bool, bool) {
        (
            (pre.mode == STUCK && r.get(G::SA_ABOVE_MAX_P)) || (initial && r.get(G::W_POS)),
            (pre.mode == STUCK && r.get(G::SA_BELOW_MIN_M)) || (initial && r.get(G::W_NEG)),
        )
    }

    fn locked(&self, _free: bool, pre: Discrete, sf: bool, sb: bool) -> bool {
        !(self.ideal || pre.mode == FORWARD || sf || pre.mode == BACKWARD || sb)
    }

    fn mode(&self, _free: bool, pre: Discrete, sf: bool, sb: bool, r: RelationSet) -> i8 {
        if self.ideal {
            FREE
        } else if (pre.mode == FORWARD || sf) && r.get(G::W_POS) {
            FORWARD
        } else if (pre.mode == BACKWARD || sb) && r.get(G::W_NEG) {
            BACKWARD
        } else {
            STUCK
        }
    }

    /// The driving side, and the relations that end the current state.
    fn indicators(&self, st: &SwitchState, v: &ElementValues, _signals: &[f64], z: &mut [f64]) {
        if self.ideal {
            z.fill(NEVER);
            return;
        }
        let flip = |i: usize, g: f64| flip_indicator(st.rel.get(i), g);
        z[0] = flip(G::TAU_ETA_POS, v.tau_eta);
        let (above, below) = (v.sa - v.tau0_max, v.tau0 - v.sa);
        let (a, b) = if st.locked {
            (
                flip(G::SA_ABOVE_MAX_P, above),
                flip(G::SA_BELOW_MIN_M, below),
            )
        } else if st.pre.mode == FORWARD {
            (flip(G::W_POS, v.w), NEVER)
        } else if st.pre.mode == BACKWARD {
            (flip(G::W_NEG, -v.w), NEVER)
        } else if st.pre.start_forward {
            (flip(G::W_POS, v.w), flip(G::SA_ABOVE_MAX_P, above))
        } else if st.pre.start_backward {
            (flip(G::W_NEG, -v.w), flip(G::SA_BELOW_MIN_M, below))
        } else {
            (NEVER, NEVER)
        };
        z[1] = a;
        z[2] = b;
    }

    fn speed_rate(&self, st: &SwitchState, v: &ElementValues) -> Option<f64> {
        if st.locked || self.ideal || v.held {
            return None;
        }
        slip_rate_sign(st.pre).map(|s| s * v.a)
    }

    fn indicator_label(&self, st: &SwitchState, slot: usize) -> &'static str {
        match slot {
            0 => "driving side changed (tau_eta crossed 0)",
            1 if st.locked => "loss torque exceeded tauLossMax_p (starts forward)",
            2 if st.locked => "loss torque fell below tauLossMin_m (starts backward)",
            1 if st.pre.mode == FORWARD => "forward speed reached 0",
            1 if st.pre.mode == BACKWARD => "backward speed reached 0",
            1 if st.pre.start_forward => "started rolling forward (w_a > 0)",
            1 => "started rolling backward (w_a < 0)",
            _ => "start condition lost",
        }
    }

    fn variable(&self, st: &SwitchState, v: &ElementValues, var: SwitchVar) -> f64 {
        match var {
            SwitchVar::TauEtaPos => {
                if st.rel.get(G::TAU_ETA_POS) {
                    1.0
                } else {
                    0.0
                }
            }
            _ => common_variable(st, v, var),
        }
    }
}
