//! The friction element as the engine sees it (Brake, Clutch, BearingFriction, OneWayClutch):
//! its parameters, its discrete state between events, and MSL's `PartialFriction` rules applied
//! to it (the OneWayClutch's own one-directional rules included).

use super::element::{
    angle_and_speed, slip_rate_sign, BeforeSolve, ElementValues, Kinematics, Solved, SwitchState,
    SwitchVar, SwitchingElement, NEVER,
};
use super::fade::Fade;
use super::logic::{self, relation_index as R, Discrete, Relations};
use super::relation::flip_indicator;
use super::stop::StopFriction;
use crate::lookup_table::Table1D;
use crate::rel::Rel;

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
    /// The table parameter's name (`mu_pos`, a BearingFriction's `tau_pos`), for messages.
    pub table_name: &'static str,
    /// The table argument past which `mu_pos` extrapolates below 0 (infinite if it never
    /// does: a constant, rising or held table).
    pub negative_beyond: f64,
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
    /// MassWithStopAndFriction: the Stribeck law in place of the table, and the hard stops.
    pub stop: Option<Box<StopFriction>>,
    /// Beyond MSL: friction over temperature and normal force (`fade`); None: MSL's.
    pub fade: Option<Box<Fade>>,
}

/// What a OneWayClutch adds: the breakaway threshold while disengaged
/// (`tau0_max_low = 1e-4·mu0·cgeo·fn_max`). Its `peak` is already `max(peak, 1 + 1e-4)`.
#[derive(Debug, Clone, Copy)]
pub struct OneWay {
    pub tau0_max_low: f64,
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
    #[inline]
    pub fn sliding(&self, w: f64, fn_: f64, pre_mode: i8, sf: bool, sb: bool) -> (f64, f64) {
        let mu = if let Some(stop) = &self.stop {
            let (s_w, s_mu) = logic::table_signs(sf, sb, pre_mode, false);
            s_mu * stop.force(s_w * w, sf || sb)
        } else if self.one_way.is_some() {
            self.mu_pos.eval(w) // no sign handling: w_rel is assumed >= 0
        } else {
            let (s_w, s_mu) = logic::table_signs(sf, sb, pre_mode, self.clutch_quirk);
            s_mu * self.mu_pos.eval(s_w * w)
        };
        (mu, mu * self.cgeo * fn_)
    }

    /// `limits` and `sliding` with the fade's factors: `(mu, tau)`, `v.tau0` and `v.tau0_max`
    /// written. The factors scale the static and the sliding values alike. Out of line and
    /// cold: MSL's path in `forces` stays the code it was (inlined, it cost CoupledClutches
    /// 2.5 % of its core time without a fade anywhere).
    #[cold]
    #[inline(never)]
    fn faded(
        &self,
        fade: &Fade,
        st: &SwitchState,
        signals: &[f64],
        v: &mut ElementValues,
    ) -> (f64, f64) {
        let at = fade.at(signals, self.normal_force(signals));
        v.tau0 = fade.base_mu(&self.mu_pos, 0.0, &at) * at.factor * self.cgeo * v.fn_;
        v.tau0_max = match self.one_way {
            Some(ow) if st.free => ow.tau0_max_low,
            _ => self.peak * at.peak * v.tau0,
        };
        let (s_w, s_mu) = match self.one_way {
            Some(_) => (1.0, 1.0), // no sign handling: w_rel is assumed >= 0
            None => {
                let (sf, sb) = (st.pre.start_forward, st.pre.start_backward);
                logic::table_signs(sf, sb, st.pre.mode, self.clutch_quirk)
            }
        };
        let mu = s_mu * fade.base_mu(&self.mu_pos, s_w * v.w, &at) * at.factor;
        (mu, mu * self.cgeo * v.fn_)
    }

    /// (F1, F2), or the OneWayClutch's start condition (it never starts backward); a start
    /// held by its hysteresis ends when the element turns the other way (`logic::start_flags`).
    fn friction_start_flags(&self, pre: Discrete, r: Relations, initial: bool) -> (bool, bool) {
        if self.one_way.is_none() {
            return logic::start_flags(pre, r, initial);
        }
        let pre_stuck = pre.mode == logic::STUCK;
        let forward = (pre_stuck
            && (r.get(R::SA_ABOVE_MAX)
                || (pre.start_forward && r.get(R::SA_ABOVE) && !r.get(R::W_NEG))
                || r.get(R::W_ABOVE_SMALL)))
            || (initial && r.get(R::W_POS));
        (forward, false)
    }

    /// (F3); a OneWayClutch locks whenever it was stuck and does not start, engaged or not.
    fn friction_locked(&self, free: bool, pre: Discrete, sf: bool, sb: bool) -> bool {
        match self.one_way {
            Some(_) => pre.mode == logic::STUCK && !sf,
            None => logic::locked(free, pre.mode, sf, sb),
        }
    }

    /// (F5); a OneWayClutch's "mode" is Stuck while `stuck = locked ∨ w_rel ≤ 0`, else Forward.
    fn friction_mode(&self, free: bool, pre: Discrete, sf: bool, sb: bool, r: Relations) -> i8 {
        match self.one_way {
            Some(_) if self.friction_locked(free, pre, sf, sb) || !r.get(R::W_POS) => logic::STUCK,
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

impl SwitchingElement for FrictionElem {
    fn name(&self) -> &str {
        &self.name
    }

    fn initial_state(&self) -> SwitchState {
        SwitchState {
            pre: self.initial,
            locked: false,
            free: true,
            rel: Relations::default(),
        }
    }

    /// Every friction element's first mode is logged, from Unknown.
    fn log_start_mode(&self) -> i8 {
        logic::UNKNOWN
    }

    fn heat_node(&self) -> Option<usize> {
        self.heat_node
    }

    /// A freewheel cannot turn backward: MSL's equations would take it as stuck with a
    /// constant negative slip that transmits torque, reports no loss and makes energy.
    fn check_start(&self, phi: f64, w: f64) -> Result<(), String> {
        if let Some(stop) = &self.stop {
            return stop.check_start(phi, w);
        }
        if self.one_way.is_some() && w < -super::relation::EVENT_EPSILON {
            return Err(format!(
                "w_rel starts at {w} rad/s, but a one-way clutch cannot turn backward (w_rel < 0); \
                 start its flanges so that w_rel >= 0"
            ));
        }
        Ok(())
    }

    fn may_turn_negative(&self) -> bool {
        self.negative_beyond.is_finite()
    }

    /// Sliding (or starting), engaged, at a slip where its table is below 0: the friction
    /// would drive the motion and deliver energy (MSL extrapolates on, silently).
    fn negative_characteristic(&self, st: &SwitchState, v: &ElementValues) -> Option<String> {
        if st.locked || st.free {
            return None;
        }
        let (sf, sb) = (st.pre.start_forward, st.pre.start_backward);
        let u = if self.one_way.is_some() {
            v.w
        } else {
            logic::table_signs(sf, sb, st.pre.mode, self.clutch_quirk).0 * v.w
        };
        if u <= self.negative_beyond {
            return None;
        }
        let value = self.mu_pos.eval(u);
        if value >= 0.0 {
            return None;
        }
        let (x, y) = self.mu_pos.last_row();
        let what = if self.input.is_some() {
            "coefficient"
        } else {
            "torque"
        };
        Some(format!(
            "'{}' slips at {} rad/s, past {} rad/s where its table {} falls below 0 ({what} \
             {value:.3e}): beyond its last row [{x}, {y}] the table goes on linearly through its \
             last two rows (MSL's extrapolation), and a negative {what} would drive the motion; \
             extend {} to the speeds the run reaches, or set extrapolation = \"HoldLastPoint\" \
             to hold the last row's value",
            self.name,
            v.w.abs(),
            self.negative_beyond,
            self.table_name,
            self.table_name,
        ))
    }

    fn motion(&self) -> &Rel {
        &self.rel
    }

    fn forces(&self, st: &SwitchState, k: &Kinematics, v: &mut ElementValues, f: &mut [f64]) {
        (v.phi, v.w) = angle_and_speed(&self.rel, k.phi, k.w);
        v.fn_ = self.reported_normal_force(k.signals, st.free);
        let (mu, tau) = match &self.fade {
            None => {
                (v.tau0, v.tau0_max) = self.limits(v.fn_, st.free);
                let (sf, sb) = (st.pre.start_forward, st.pre.start_backward);
                self.sliding(v.w, v.fn_, st.pre.mode, sf, sb)
            }
            Some(fade) => self.faded(fade, st, k.signals, v),
        };
        v.mu = mu;
        v.tau = if st.free { 0.0 } else { tau };
        if !st.locked {
            self.rel.apply(v.tau, f);
        }
    }

    fn solved(&self, st: &SwitchState, s: &Solved, v: &mut ElementValues) {
        if st.locked {
            // a locked element whose row depends on others carries no torque
            v.tau = s.lock.unwrap_or(0.0);
        }
        v.a = self.rel.dot(s.a);
        v.held = s.held;
        v.sa = if st.locked {
            v.tau
        } else {
            self.sa_from_accel(st.free, st.pre, v.a, v.tau0, v.tau0_max)
        };
        // A OneWayClutch dissipates nothing while stuck (spec §10.8).
        let stuck_one_way = self.one_way.is_some() && st.pre.mode == logic::STUCK;
        let power = v.tau * v.w;
        v.loss = if stuck_one_way { 0.0 } else { power };
        v.withheld = power - v.loss;
    }

    /// Everything `forces` computes; the torque (0 while free) and the loss (`solved`'s
    /// product) too unless locked: its torque is then the lock row's multiplier. `a` and `sa`
    /// read the solve.
    fn before_solve(&self, st: &SwitchState, var: SwitchVar) -> BeforeSolve {
        use SwitchVar as V;
        match var {
            V::Tau if st.free && !st.locked => BeforeSolve::Constant(0.0),
            V::Phi | V::W | V::Fn | V::Mu | V::Tau0 | V::Tau0Max => BeforeSolve::Forces,
            V::Tau if !st.locked => BeforeSolve::Forces,
            V::LossPower if !st.locked => BeforeSolve::Solved,
            _ => BeforeSolve::Never,
        }
    }

    /// The normal force's input and the fade's temperature.
    fn signal_slots(&self) -> Option<Vec<usize>> {
        let temperature = self.fade.as_ref().and_then(|f| f.temperature);
        Some(self.input.into_iter().chain(temperature).collect())
    }

    fn is_free(&self, signals: &[f64]) -> bool {
        self.normal_force(signals) <= 0.0
    }

    fn relations(&self, previous: Relations, v: &ElementValues, initial: bool) -> Relations {
        let q = logic::Quantities {
            sa: v.sa,
            w: v.w,
            tau0: v.tau0,
            tau0_max: v.tau0_max,
            w_small: self.w_small,
        };
        let r = logic::relations(previous, &q, initial);
        match &self.stop {
            Some(stop) => stop.gate(r, v.phi),
            None => r,
        }
    }

    fn start_relations(&self) -> &'static [usize] {
        R::STARTS
    }

    fn start_flags(&self, pre: Discrete, r: Relations, initial: bool) -> (bool, bool) {
        self.friction_start_flags(pre, r, initial)
    }

    fn locked(&self, free: bool, pre: Discrete, sf: bool, sb: bool) -> bool {
        self.friction_locked(free, pre, sf, sb)
    }

    fn mode(&self, free: bool, pre: Discrete, sf: bool, sb: bool, r: Relations) -> i8 {
        self.friction_mode(free, pre, sf, sb, r)
    }

    /// Engagement (`free = fn <= 0`), and the relations that end the current state.
    fn indicators(&self, st: &SwitchState, v: &ElementValues, signals: &[f64], z: &mut [f64]) {
        let one_way = self.one_way.is_some();
        let normal_force = self.normal_force(signals);
        z[0] = if st.free { normal_force } else { -normal_force };
        let flip = |i: usize, g: f64| flip_indicator(st.rel.get(i), g);
        let (a, b) = if st.free && !one_way {
            (NEVER, NEVER)
        } else if st.locked && one_way {
            // a freewheel never breaks away backward
            (flip(R::SA_ABOVE_MAX, v.sa - v.tau0_max), NEVER)
        } else if st.locked {
            (
                flip(R::SA_ABOVE_MAX, v.sa - v.tau0_max),
                flip(R::SA_BELOW_MAX, -v.sa - v.tau0_max),
            )
        } else if let Some(slip) = self.slip_indicator(st, v.w) {
            // A start is held by sa beyond tau0_max, or by sa beyond tau0 while the element
            // has not turned the other way (`logic::start_flags`): any of the three relations
            // flipping may end it. Held by tau0_max alone (its speed already the other way),
            // it ends when sa comes back inside: unwatched, a brake went on starting backward
            // while its shaft turned forward to 1.2e-3 rad/s, and delivered energy.
            let end = if st.pre.mode != logic::STUCK {
                NEVER
            } else if st.pre.start_forward {
                flip(R::SA_ABOVE_MAX, v.sa - v.tau0_max)
                    .max(flip(R::SA_ABOVE, v.sa - v.tau0))
                    .max(flip(R::W_NEG, -v.w))
            } else {
                flip(R::SA_BELOW_MAX, -v.sa - v.tau0_max)
                    .max(flip(R::SA_BELOW, -v.sa - v.tau0))
                    .max(flip(R::W_POS, v.w))
            };
            (slip, end)
        } else {
            (NEVER, NEVER)
        };
        (z[1], z[2]) = match &self.stop {
            Some(stop) if st.locked => stop.breakaway(v.phi, a, b),
            _ => (a, b),
        };
        if let Some(stop) = &self.stop {
            z[0] = stop.indicator(st, v.phi); // never free: slot 0 watches the stops
        }
    }

    fn reset(&self, phi: &[f64], w: &[f64]) -> Option<super::element::NodeReset> {
        self.stop.as_ref()?.reset(&self.rel, phi, w)
    }

    /// Sliding, or starting to: its slip speed reaching zero (forward or backward).
    fn slip_indicator(&self, st: &SwitchState, w: f64) -> Option<f64> {
        if st.locked || (st.free && self.one_way.is_none()) {
            return None;
        }
        let flip = |i: usize, g: f64| flip_indicator(st.rel.get(i), g);
        let stuck = st.pre.mode == logic::STUCK;
        if st.pre.mode == logic::FORWARD || (stuck && st.pre.start_forward) {
            Some(flip(R::W_POS, w))
        } else if st.pre.mode == logic::BACKWARD || (stuck && st.pre.start_backward) {
            Some(flip(R::W_NEG, -w))
        } else {
            None
        }
    }

    fn speed_rate(&self, st: &SwitchState, v: &ElementValues) -> Option<f64> {
        let free = st.free && self.one_way.is_none();
        if st.locked || free || v.held {
            return None;
        }
        slip_rate_sign(st.pre).map(|s| s * v.a)
    }

    fn indicator_label(&self, st: &SwitchState, slot: usize) -> &'static str {
        match slot {
            0 if self.stop.is_some() => "the mass reached a hard stop (s = smax - L/2 or smin + L/2)",
            0 if st.free => "normal force became positive (engages)",
            0 => "normal force reached 0 (released)",
            1 if st.locked => "torque exceeded the static limit forward (sa > tau0_max)",
            2 if st.locked => "torque exceeded the static limit backward (sa < -tau0_max)",
            1 if st.pre.mode == logic::FORWARD => "forward slip speed reached 0",
            1 if st.pre.mode == logic::BACKWARD => "backward slip speed reached 0",
            1 if st.pre.start_forward => "started sliding forward (w > 0)",
            1 => "started sliding backward (w < 0)",
            _ => "the start's conditions changed: its torque against tau0 or tau0_max, or it turned the other way",
        }
    }
}
