//! Zero-crossing indicators. Each is arranged so that the event happens when it goes from ≤ 0 to
//! above 0; for the friction relations that is where the relation's function clears the event
//! hysteresis band (`relation::flip_indicator`). Only the relations that can change something in
//! the current discrete state are watched, so a locked or free element never fires events from
//! noise in its relative speed.

use crate::engine::eval::{DiscreteState, Workspace};
use crate::switching::element::{INDICATORS, NEVER};
use crate::system::law::MAX_LAW_RELATIONS;
use crate::system::System;

/// `INDICATORS` per switching element (what each means is the element's business), then one
/// per law relation, then one per worn element (its pad reaching `thickness_min`).
pub fn indicator_count(sys: &System) -> usize {
    INDICATORS * sys.switching.len() + sys.relation_count + sys.wear.len()
}

/// The worn element whose limit indicator `i` is, if it is one.
pub fn wear_indicator(sys: &System, i: usize) -> Option<usize> {
    i.checked_sub(law_base(sys) + sys.relation_count)
}

fn law_base(sys: &System) -> usize {
    INDICATORS * sys.switching.len()
}

pub fn indicators(sys: &System, disc: &DiscreteState, ws: &Workspace, z: &mut [f64]) {
    let (elements, laws) = z.split_at_mut(law_base(sys));
    if !sys.wear.is_empty() {
        wear_limits(sys, ws, &mut laws[sys.relation_count..]);
    }
    for (((e, st), v), slot) in sys
        .switching
        .iter()
        .zip(&disc.switching)
        .zip(&ws.elements)
        .zip(elements.chunks_exact_mut(INDICATORS))
    {
        e.indicators(st, v, &ws.signals, slot);
    }
    let mut scratch = [0.0; MAX_LAW_RELATIONS];
    for (k, law) in sys.laws.iter().enumerate() {
        let count = law.relation_count;
        if count == 0 {
            continue;
        }
        law.law
            .relation_values(&ws.law_ctx(sys, disc, k), &mut scratch[..count]);
        for r in 0..count {
            let frozen = disc.relations[law.relation_base + r];
            laws[law.relation_base + r] = if frozen { -scratch[r] } else { scratch[r] };
        }
    }
}

/// The pads' limit indicators: worn volume − the volume at `thickness_min` (NEVER without one).
#[inline(never)]
fn wear_limits(sys: &System, ws: &Workspace, z: &mut [f64]) {
    for ((wear, z), volume) in sys.wear.iter().zip(z).zip(&ws.wear) {
        *z = wear.limit.map_or(NEVER, |(limit, _)| volume - limit);
    }
}

/// Rates of change of the speed indicators (±relative speed of a sliding or starting element:
/// the rate is ±its relative acceleration); NaN for the others. A speed that rises and falls
/// back within one step shows as a rate changing sign, which the driver then inspects.
pub fn speed_rates(sys: &System, disc: &DiscreteState, ws: &Workspace, dz: &mut [f64]) {
    dz.fill(f64::NAN);
    for (k, ((e, st), v)) in sys
        .switching
        .iter()
        .zip(&disc.switching)
        .zip(&ws.elements)
        .enumerate()
    {
        if let Some(rate) = e.speed_rate(st, v) {
            dz[INDICATORS * k + 1] = rate;
        }
    }
}

/// What crossing indicator `i` means, for the event log.
pub fn indicator_label(sys: &System, disc: &DiscreteState, i: usize) -> String {
    if i < law_base(sys) {
        let (k, slot) = (i / INDICATORS, i % INDICATORS);
        let e = &sys.switching[k];
        return format!(
            "{}: {}",
            e.name(),
            e.indicator_label(&disc.switching[k], slot)
        );
    }
    if let Some(k) = wear_indicator(sys, i) {
        return format!("{}: thickness_min reached", sys.wear[k].name);
    }
    let r = i - law_base(sys);
    for law in &sys.laws {
        let count = law.relation_count;
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
