//! A deliberately chattering element, compiled for tests only: `ToyRelay` is Coulomb friction
//! without a stuck mode, `tau = tau_max·sign(w)` against the housing, as a naive friction law
//! or a bang-bang speed controller writes it. Driven by less torque than `tau_max`, the shaft
//! reaches rest and can neither stay there (no mode holds it) nor leave it: either direction of
//! slip turns it back. A Modelica tool chatters on such a model; the engine must stop it at
//! that instant after a handful of mode changes, naming the element (issue 13). MSL's friction
//! elements never do this: their stuck mode is what this toy lacks.

use super::OnFlange;
use crate::components::Component;
use crate::error::ModelResult;
use crate::model::Params;
use crate::rel::Rel;
use crate::switching::element::{
    ElementValues, Kinematics, Solved, SwitchState, SwitchVar, SwitchingElement, NEVER,
};
use crate::switching::logic::{Discrete, BACKWARD, FORWARD};
use crate::switching::relation::{flip_indicator, RelationSet};

/// Its one relation: `w > 0`.
const W_POS: usize = 0;

struct Relay {
    name: String,
    rel: Rel,
    tau_max: f64,
}

impl SwitchingElement for Relay {
    fn name(&self) -> &str {
        &self.name
    }
    fn motion(&self) -> &Rel {
        &self.rel
    }
    fn forces(&self, st: &SwitchState, k: &Kinematics, v: &mut ElementValues, f: &mut [f64]) {
        v.phi = self.rel.angle(k.phi);
        v.w = self.rel.dot(k.w);
        v.tau = if st.pre.mode == FORWARD {
            self.tau_max
        } else {
            -self.tau_max
        };
        self.rel.apply(v.tau, f);
    }
    fn solved(&self, _: &SwitchState, s: &Solved, v: &mut ElementValues) {
        v.a = self.rel.dot(s.a);
        v.held = s.held;
        v.sa = v.tau;
        v.loss = v.tau * v.w;
    }
    fn start_flags(&self, _pre: Discrete, _r: RelationSet, _initial: bool) -> (bool, bool) {
        (false, false)
    }
    fn locked(&self, _free: bool, _pre: Discrete, _sf: bool, _sb: bool) -> bool {
        false
    }
    fn mode(&self, _free: bool, _pre: Discrete, _sf: bool, _sb: bool, r: RelationSet) -> i8 {
        if r.get(W_POS) {
            FORWARD
        } else {
            BACKWARD
        }
    }
    fn indicators(&self, st: &SwitchState, v: &ElementValues, _: &[f64], z: &mut [f64]) {
        z.fill(NEVER);
        z[1] = flip_indicator(st.rel.get(W_POS), v.w);
    }
    fn speed_rate(&self, st: &SwitchState, v: &ElementValues) -> Option<f64> {
        Some(if st.rel.get(W_POS) { -v.a } else { v.a })
    }
    fn indicator_label(&self, _: &SwitchState, _: usize) -> &'static str {
        "w changed sign: the relay reverses its torque"
    }
}

pub(super) fn toy_relay(p: &Params) -> ModelResult<Box<dyn Component>> {
    let tau_max = p.real("tau_max", 1.0)?;
    Ok(Box::new(OnFlange {
        element: Box::new(move |name, rel| Box::new(Relay { name, rel, tau_max })),
        variables: &[
            ("w", SwitchVar::W),
            ("tau", SwitchVar::Tau),
            ("mode", SwitchVar::Mode),
        ],
    }))
}

#[cfg(test)]
mod tests {
    use crate::error::SimError;
    use crate::model::ModelSpec;
    use crate::simulation::chatter::CHANGES;
    use crate::simulation::simulate;

    /// J = 1, w(0) = 2, 5 N·m forward against a 10 N·m relay: w = 2 − 5t reaches 0 at t = 0.4,
    /// where the relay's torque flips at every ±1e-10 rad/s (the event epsilon): left alone,
    /// some 10¹⁰ events for the rest of the run.
    #[test]
    fn a_chattering_element_is_stopped_at_its_instant_after_a_handful_of_changes() {
        let text = r#"
            connect = [["shaft.flange_b", "relay.flange"], ["drive.flange", "shaft.flange_a"]]
            [experiment]
            StopTime = 1.0
            Interval = 0.01
            [components]
            shaft = { type = "Inertia", J = 1.0, phi = 0.0, w = 2.0 }
            drive = { type = "ConstantTorque", tau_constant = 5.0 }
            relay = { type = "ToyRelay", tau_max = 10.0 }
        "#;
        let spec = ModelSpec::from_toml(text, ".").expect("the model parses");
        let err = match simulate(&spec) {
            Err(err) => err,
            Ok(r) => panic!(
                "the run ended with {} events, chattering unseen",
                r.events.len()
            ),
        };
        let message = err.to_string();
        let SimError::Chattering {
            time,
            element,
            changes,
            window,
            ..
        } = err
        else {
            panic!("expected chattering of relay, got {message}");
        };
        assert_eq!(element, "relay");
        assert_eq!(changes, CHANGES, "stopped after {changes} changes");
        assert!((time - 0.4).abs() < 1e-8, "stopped at t = {time}");
        assert!(window <= 1e-9, "a window of {window} s");
        // the message names the element and the relation that flipped
        assert!(
            message.contains("'relay'") && message.contains("w changed sign"),
            "{message}"
        );
    }
}
