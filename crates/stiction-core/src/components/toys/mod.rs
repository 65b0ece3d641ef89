//! Toy switching elements, compiled for tests only: each is one file (its element and its
//! constructor) plus a registry line here, driven by the engine through `SwitchingElement`
//! alone. What they share is written once: the component around an element between a flange
//! and the housing (`OnFlange`), and the trait's defaults (`initial_state`, `heat_node`,
//! `relations` on the speed, `start_relations`).

mod relay;
mod stop;

use super::{with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::rel::Rel;
use crate::switching::element::{SwitchVar, SwitchingElement};
use crate::system::{Builder, Out};

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "ToyStop",
        "stiction.Tests.ToyStop",
        "A frictionless pawl that holds its shaft once it stops (tests only)",
        stop::toy_stop,
    ),
    Entry::new(
        "ToyRelay",
        "stiction.Tests.ToyRelay",
        "Coulomb friction without a stuck mode, tau = tau_max·sign(w): it chatters (tests only)",
        relay::toy_relay,
    ),
];

/// Makes a toy's element from its name and its relative motion (flange − housing).
type MakeElement = Box<dyn Fn(String, Rel) -> Box<dyn SwitchingElement> + Send + Sync>;

/// A toy component: its element between `flange` and the housing, reporting `variables`.
struct OnFlange {
    element: MakeElement,
    variables: &'static [(&'static str, SwitchVar)],
}

impl Component for OnFlange {
    fn ports(&self) -> Ports {
        Ports {
            mech: with_support(&["flange"], false),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (n, ground) = (b.node("flange")?, b.node("support")?);
        let rel = Rel::of(&[(n, 1.0), (ground, -1.0)]);
        let k = b.add_switching((self.element)(b.name().to_string(), rel));
        for &(name, var) in self.variables {
            b.output(name, Out::Switch(k, var));
        }
        b.flange("flange", n, Some(Out::Switch(k, SwitchVar::Tau)))
    }
}
