//! Relations with hysteresis, as Modelica tools evaluate them at events (Dymola's event
//! epsilon). A relation `g > 0` that is false becomes true only once `g > ε`; one that is true
//! becomes false only once `g < −ε`. Within the band it keeps its previous value.
//!
//! Why: a stick/slip decision taken on round-off is arbitrary. After a stop the relative speed is
//! zero to within 1e-17, and a stuck element's `sa` sits exactly on its threshold while another
//! element holds the motion; comparing such values literally makes the mode depend on the last
//! bit. With the band, the crossing is located where `g` clears ε, and the relations keep the
//! value they had until then — the reference results show exactly this: after every stop in
//! MSL LossyGearDemo2 the shaft drifts at ±1.0e-10 rad/s.

/// The hysteresis band (absolute).
pub const EVENT_EPSILON: f64 = 1.0e-10;

/// The value of `g > 0` given its previous value.
pub fn hysteresis(previous: bool, g: f64) -> bool {
    if previous {
        g > -EVENT_EPSILON
    } else {
        g > EVENT_EPSILON
    }
}

/// Zero-crossing indicator of `g > 0` while it has the value `current`: it goes from ≤ 0 to
/// above 0 where the relation flips.
pub fn flip_indicator(current: bool, g: f64) -> f64 {
    if current {
        -g - EVENT_EPSILON
    } else {
        g - EVENT_EPSILON
    }
}

/// The most relations one switching element has.
pub const MAX_RELATIONS: usize = 8;

/// The values of one element's relations, indexed by the element's own constants.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct RelationSet(pub [bool; MAX_RELATIONS]);

impl RelationSet {
    pub fn get(&self, i: usize) -> bool {
        self.0[i]
    }

    pub fn set(&mut self, i: usize, value: bool) {
        self.0[i] = value;
    }

    /// The relations `g[i] > 0` from these previous values (see `update`); the others keep theirs.
    /// At initialization there is no previous value: a relation starts false and is true only
    /// once `g` clears the band, as it would become true afterwards. A `g` within the band is
    /// round-off of a quantity that is zero exactly (a relative position computed from absolute
    /// ones), and comparing it literally made the sign of the last bit a start condition.
    pub fn update(self, g: &[f64], initial: bool) -> Self {
        let mut next = self;
        for (i, &g) in g.iter().enumerate() {
            next.0[i] = hysteresis(!initial && self.0[i], g);
        }
        next
    }

    /// Every relation true in either, except `own`, which keep this set's values.
    pub fn union_keeping(self, other: RelationSet, own: &[usize]) -> Self {
        let mut union = RelationSet(std::array::from_fn(|i| self.0[i] || other.0[i]));
        for &i in own {
            union.0[i] = self.0[i];
        }
        union
    }

    /// The same with `which` false.
    pub fn cleared(mut self, which: &[usize]) -> Self {
        for &i in which {
            self.0[i] = false;
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_relation_flips_only_outside_the_band() {
        assert!(!hysteresis(false, 0.5 * EVENT_EPSILON));
        assert!(hysteresis(false, 2.0 * EVENT_EPSILON));
        assert!(hysteresis(true, -0.5 * EVENT_EPSILON));
        assert!(!hysteresis(true, -2.0 * EVENT_EPSILON));
        // the indicator turns positive exactly where the value flips
        for (current, g) in [
            (false, 2e-10),
            (false, 5e-11),
            (true, -2e-10),
            (true, -5e-11),
        ] {
            assert_eq!(
                flip_indicator(current, g) > 0.0,
                hysteresis(current, g) != current
            );
        }
        let previous = RelationSet([false, true, false, false, false, false, false, false]);
        assert_eq!(previous.update(&[0.0, 0.0], true), RelationSet::default());
        // at initialization a round-off g is no start condition, a real one is
        let start = previous.update(&[0.5 * EVENT_EPSILON, 2.0 * EVENT_EPSILON], true);
        assert!(!start.get(0) && start.get(1));
        assert_eq!(previous.update(&[0.0, 0.0], false), previous);
    }
}
