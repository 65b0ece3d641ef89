//! Which nodes a reset at an event moves (MSL's `reinit` of a mass's position and speed): the
//! node itself and every node joined to it through a law whose relative position and speed are
//! states (a SpringDamper, Damper, ElastoGap: MSL's `PartialCompliantWithRelativeStates` with
//! `stateSelect = prefer`). A reinit keeps every other state, so those relative states stay and
//! the flanges beyond them move with the reset mass (Dymola: `springDamper1.v_rel` is the same
//! on both sides of the stop's event in MSL's Translational HeatLosses).

use crate::system::System;

/// The nodes a reset of `node` moves, `node` first.
pub fn carried(sys: &System, node: usize) -> Vec<usize> {
    let mut moved = vec![node];
    let mut k = 0;
    while k < moved.len() {
        let at = moved[k];
        for law in sys.laws.iter().filter(|l| l.relative_states) {
            // a relative state to the ground (one node) holds nothing that moves
            if let [(a, _), (b, _)] = law.rel.terms.as_slice() {
                let other = if *a == at {
                    *b
                } else if *b == at {
                    *a
                } else {
                    continue;
                };
                if !moved.contains(&other) {
                    moved.push(other);
                }
            }
        }
        k += 1;
    }
    moved
}
