//! A toy switching element, compiled for tests only: it shows that a new element with stick
//! logic is one file (element + constructor) plus one registry line, and that the engine drives
//! it through `SwitchingElement` alone. `ToyStop` is a frictionless pawl between its flange and
//! the housing: the shaft turns freely forward; the first time its speed reaches 0 the pawl
//! drops and holds it for ever, whatever the torque.

use super::OnFlange;
use crate::components::Component;
use crate::error::ModelResult;
use crate::model::Params;
use crate::rel::Rel;
use crate::switching::element::{
    ElementValues, Kinematics, Solved, SwitchState, SwitchVar, SwitchingElement, NEVER,
};
use crate::switching::logic::{Discrete, FORWARD, STUCK};
use crate::switching::relation::{flip_indicator, RelationSet};

/// Its one relation: `w > 0`.
const W_POS: usize = 0;

struct Pawl {
    name: String,
    rel: Rel,
}

impl SwitchingElement for Pawl {
    fn name(&self) -> &str {
        &self.name
    }
    fn motion(&self) -> &Rel {
        &self.rel
    }
    fn forces(&self, _: &SwitchState, k: &Kinematics, v: &mut ElementValues, _: &mut [f64]) {
        v.phi = self.rel.angle(k.phi);
        v.w = self.rel.dot(k.w);
        v.tau = 0.0;
    }
    fn solved(&self, st: &SwitchState, s: &Solved, v: &mut ElementValues) {
        v.tau = if st.locked {
            s.lock.unwrap_or(0.0)
        } else {
            0.0
        };
        v.a = self.rel.dot(s.a);
        v.held = s.held;
        v.sa = v.tau;
        v.loss = v.tau * v.w;
    }
    fn start_flags(&self, _pre: Discrete, r: RelationSet, initial: bool) -> (bool, bool) {
        (initial && r.get(W_POS), false)
    }
    fn locked(&self, _free: bool, pre: Discrete, sf: bool, _sb: bool) -> bool {
        !(sf || pre.mode == FORWARD)
    }
    fn mode(&self, _free: bool, pre: Discrete, sf: bool, _sb: bool, r: RelationSet) -> i8 {
        if (pre.mode == FORWARD || sf) && r.get(W_POS) {
            FORWARD
        } else {
            STUCK
        }
    }
    fn indicators(&self, st: &SwitchState, v: &ElementValues, _: &[f64], z: &mut [f64]) {
        z.fill(NEVER);
        if !st.locked && st.pre.mode == FORWARD {
            z[1] = flip_indicator(st.rel.get(W_POS), v.w);
        }
    }
    fn speed_rate(&self, st: &SwitchState, v: &ElementValues) -> Option<f64> {
        (!st.locked && !v.held && st.pre.mode == FORWARD).then_some(-v.a)
    }
    fn indicator_label(&self, _: &SwitchState, _: usize) -> &'static str {
        "the shaft stopped: the pawl drops"
    }
}

pub(super) fn toy_stop(_: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(OnFlange {
        element: Box::new(|name, rel| Box::new(Pawl { name, rel })),
        variables: &[
            ("w", SwitchVar::W),
            ("tau", SwitchVar::Tau),
            ("mode", SwitchVar::Mode),
            ("locked", SwitchVar::Locked),
        ],
    }))
}

#[cfg(test)]
mod tests {
    use crate::model::ModelSpec;
    use crate::simulation::simulate;

    /// J = 2, w(0) = 3, driven backward by 1 N·m: w = 3 − t/2 reaches 0 at t = 6, where the
    /// pawl holds the shaft at phi = 3·6 − 6²/4 = 9 and carries the 1 N·m.
    #[test]
    fn a_toy_element_in_one_file_stops_the_shaft_exactly_when_it_reaches_rest() {
        let text = r#"
            connect = [["shaft.flange_b", "pawl.flange"], ["drive.flange", "shaft.flange_a"]]
            [experiment]
            StopTime = 10.0
            Interval = 0.5
            [components]
            shaft = { type = "Inertia", J = 2.0, phi = 0.0, w = 3.0 }
            drive = { type = "ConstantTorque", tau_constant = -1.0 }
            pawl = { type = "ToyStop" }
        "#;
        let spec = ModelSpec::from_toml(text, ".").expect("the model parses");
        let r = simulate(&spec).expect("it runs");
        let locks: Vec<_> = r.events.iter().filter(|e| e.component == "pawl").collect();
        assert_eq!(locks.len(), 2, "initialization and the stop: {locks:?}");
        assert!((locks[1].time - 6.0).abs() < 1e-9, "{:?}", locks[1]);
        assert_eq!(locks[1].new_mode, super::STUCK);
        let (t, phi, w) = (
            r.column("time").unwrap(),
            r.column("shaft.phi").unwrap(),
            r.column("shaft.w").unwrap(),
        );
        let tau = r.column("pawl.tau").unwrap();
        for row in 0..t.len() {
            let (t, phi, w) = (t[row], phi[row], w[row]);
            if t < 6.0 - 1e-9 {
                assert!((w - (3.0 - t / 2.0)).abs() < 1e-9, "w({t}) = {w}");
                assert_eq!(tau[row], 0.0);
            } else if t > 6.0 + 1e-9 {
                assert!(
                    w.abs() < 1e-9 && (phi - 9.0).abs() < 1e-8,
                    "t {t}: {phi} {w}"
                );
                assert!(
                    (tau[row].abs() - 1.0).abs() < 1e-9,
                    "the pawl carries 1 N·m"
                );
            }
        }
    }
}
