//! Zero-crossing indicators. Each is arranged so that the event happens when it goes from ≤ 0 to
//! above 0; for the friction relations that is where the relation's function clears the event
//! hysteresis band (`relation::flip_indicator`). Only the relations that can change something in
//! the current discrete state are watched, so a locked or free element never fires events from
//! noise in its relative speed.

use crate::engine::eval::{DiscreteState, Workspace};
use crate::switching::logic::{Relations as R, BACKWARD, FORWARD, STUCK};
use crate::switching::lossy_gear::GearRelations as G;
use crate::switching::relation::flip_indicator;
use crate::system::System;

/// Three per friction element (engagement, and two mode-dependent ones), three per LossyGear
/// (driving side, and two mode-dependent ones), one per law relation.
pub fn indicator_count(sys: &System) -> usize {
    3 * sys.frictions.len() + 3 * sys.lossy_gears.len() + sys.relation_count
}

fn gear_base(sys: &System) -> usize {
    3 * sys.frictions.len()
}

fn law_base(sys: &System) -> usize {
    3 * (sys.frictions.len() + sys.lossy_gears.len())
}

const NEVER: f64 = -1.0;

pub fn indicators(sys: &System, disc: &DiscreteState, ws: &Workspace, z: &mut [f64]) {
    for (k, st) in disc.friction.iter().enumerate() {
        let v = &ws.friction[k];
        let fe = &sys.frictions[k];
        let one_way = fe.one_way.is_some();
        let slot = &mut z[3 * k..3 * k + 3];
        // free = (fn <= 0)
        let normal_force = fe.normal_force(&ws.signals);
        slot[0] = if st.free { normal_force } else { -normal_force };
        // where the relation that ends the current state flips (with hysteresis)
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
        } else if st.pre.mode == FORWARD {
            (flip(R::W_POS, v.w), NEVER)
        } else if st.pre.mode == BACKWARD {
            (flip(R::W_NEG, -v.w), NEVER)
        } else if st.pre.mode == STUCK && st.pre.start_forward {
            (flip(R::W_POS, v.w), flip(R::SA_ABOVE, v.sa - v.tau0))
        } else if st.pre.mode == STUCK && st.pre.start_backward {
            (flip(R::W_NEG, -v.w), flip(R::SA_BELOW, -v.sa - v.tau0))
        } else {
            (NEVER, NEVER)
        };
        slot[1] = a;
        slot[2] = b;
    }
    for (k, (g, st)) in sys.lossy_gears.iter().zip(&disc.gears).enumerate() {
        let v = &ws.gears[k];
        let slot = &mut z[gear_base(sys) + 3 * k..gear_base(sys) + 3 * k + 3];
        if g.ideal {
            slot.fill(NEVER);
            continue;
        }
        let flip = |i: usize, g: f64| flip_indicator(st.rel.get(i), g);
        // tau_etaPos = (tau_eta >= 0)
        slot[0] = flip(G::TAU_ETA_POS, v.tau_eta);
        let (above, below) = (v.sa - v.loss_max_p, v.loss_min_m - v.sa);
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
        slot[1] = a;
        slot[2] = b;
    }
    let base = law_base(sys);
    let mut scratch = [0.0; 4];
    for (k, law) in sys.laws.iter().enumerate() {
        let count = law.law.relation_count();
        if count == 0 {
            continue;
        }
        law.law
            .relation_values(&ws.law_ctx(sys, disc, k), &mut scratch[..count]);
        for r in 0..count {
            let frozen = disc.relations[law.relation_base + r];
            z[base + law.relation_base + r] = if frozen { -scratch[r] } else { scratch[r] };
        }
    }
}

/// Rates of change of the speed indicators (±relative speed of a sliding or starting element:
/// the rate is ±its relative acceleration); NaN for the others. A speed that rises and falls
/// back within one step shows as a rate changing sign, which the driver then inspects.
pub fn speed_rates(sys: &System, disc: &DiscreteState, ws: &Workspace, dz: &mut [f64]) {
    dz.fill(f64::NAN);
    let sign = |locked: bool, free: bool, held: bool, pre: crate::switching::logic::Discrete| {
        if locked || free || held {
            None
        } else if pre.mode == FORWARD || (pre.mode == STUCK && pre.start_backward) {
            Some(-1.0)
        } else if pre.mode == BACKWARD || (pre.mode == STUCK && pre.start_forward) {
            Some(1.0)
        } else {
            None
        }
    };
    for (k, st) in disc.friction.iter().enumerate() {
        let v = &ws.friction[k];
        let free = st.free && sys.frictions[k].one_way.is_none();
        if let Some(s) = sign(st.locked, free, v.held, st.pre) {
            dz[3 * k + 1] = s * v.a;
        }
    }
    for (k, (g, st)) in sys.lossy_gears.iter().zip(&disc.gears).enumerate() {
        let v = &ws.gears[k];
        if let Some(s) = sign(st.locked || g.ideal, false, v.held, st.pre) {
            dz[gear_base(sys) + 3 * k + 1] = s * v.a;
        }
    }
}

/// What crossing indicator `i` means, for the event log.
pub fn indicator_label(sys: &System, disc: &DiscreteState, i: usize) -> String {
    let nf = sys.frictions.len();
    if i < 3 * nf {
        let (k, slot) = (i / 3, i % 3);
        let st = &disc.friction[k];
        let name = &sys.frictions[k].name;
        let what = match slot {
            0 if st.free => "normal force became positive (engages)",
            0 => "normal force reached 0 (released)",
            1 if st.locked => "torque exceeded the static limit forward (sa > tau0_max)",
            2 if st.locked => "torque exceeded the static limit backward (sa < -tau0_max)",
            1 if st.pre.mode == FORWARD => "forward slip speed reached 0",
            1 if st.pre.mode == BACKWARD => "backward slip speed reached 0",
            1 if st.pre.start_forward => "started sliding forward (w > 0)",
            1 => "started sliding backward (w < 0)",
            _ => "start torque fell below the sliding torque (hysteresis)",
        };
        return format!("{name}: {what}");
    }
    if i < law_base(sys) {
        let (k, slot) = ((i - gear_base(sys)) / 3, (i - gear_base(sys)) % 3);
        let st = &disc.gears[k];
        let what = match slot {
            0 => "driving side changed (tau_eta crossed 0)",
            1 if st.locked => "loss torque exceeded tauLossMax_p (starts forward)",
            2 if st.locked => "loss torque fell below tauLossMin_m (starts backward)",
            1 if st.pre.mode == FORWARD => "forward speed reached 0",
            1 if st.pre.mode == BACKWARD => "backward speed reached 0",
            1 if st.pre.start_forward => "started rolling forward (w_a > 0)",
            1 => "started rolling backward (w_a < 0)",
            _ => "start condition lost",
        };
        return format!("{}: {what}", sys.lossy_gears[k].name);
    }
    let r = i - law_base(sys);
    for law in &sys.laws {
        let count = law.law.relation_count();
        if r >= law.relation_base && r < law.relation_base + count {
            return format!(
                "{}: {}",
                law.owner,
                law.law.relation_label(r - law.relation_base)
            );
        }
    }
    "relation".into()
}
