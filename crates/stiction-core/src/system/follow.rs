//! Shafts an ideal gear ties to a prescribed one. MSL's angles and speeds there are algebraic
//! (`phi_a = ratio·phi_b`), so a new input value of an AngleToTorqueAdaptor moves them at
//! once, through the ratio, as it moves the prescribed flange: the gears' rows hold at the
//! angle and speed level, not only in the accelerations the per-mode solve enforces.

use super::System;

impl System {
    /// The followers: (constraint, node) pairs, each node set from its gear's row once the
    /// node on the row's other side is set — the prescribed ones first, in that order.
    pub fn gear_followers(&self) -> Vec<(usize, usize)> {
        let mut set = vec![false; self.nodes];
        for p in self
            .constraints
            .iter()
            .filter_map(|c| c.prescribed.as_ref())
        {
            set[p.node] = true;
        }
        let mut followers = Vec::new();
        if !self.prescribes() {
            return followers;
        }
        loop {
            let before = followers.len();
            for (k, c) in self.constraints.iter().enumerate() {
                // a gear's row: two shafts, no work done (a speed source's row does work)
                if c.prescribed.is_some() || c.does_work || c.rel.terms.len() != 2 {
                    continue;
                }
                let (i, j) = (c.rel.terms[0].0, c.rel.terms[1].0);
                let next = match (set[i], set[j]) {
                    (true, false) => j,
                    (false, true) => i,
                    _ => continue,
                };
                set[next] = true;
                followers.push((k, next));
            }
            if followers.len() == before {
                return followers;
            }
        }
    }

    /// Sets the followers' angles and speeds so that their gears' rows hold (after the
    /// prescribed motions are set).
    #[inline]
    pub fn follow(&self, phi: &mut [f64], w: &mut [f64]) {
        for &(k, node) in &self.followers {
            let rel = &self.constraints[k].rel;
            let Some(&(_, c)) = rel.terms.iter().find(|t| t.0 == node) else {
                continue;
            };
            phi[node] -= rel.angle(phi) / c;
            w[node] -= rel.dot(w) / c;
        }
    }
}
