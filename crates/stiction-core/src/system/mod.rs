//! The assembled hybrid system: nodes (one angle per rigid connection set), force laws,
//! permanent constraints, switching elements, the signal graph, the thermal network, start-value
//! equations and the output variables. Built once per model; many runs share it.

mod builder;
pub(crate) mod flange;
mod follow;
pub mod formula;
pub mod law;
pub mod outputs;
pub mod variables;

pub use crate::rel::{NodeRef, Rel};
pub use builder::{Builder, Domain, PortInfo, PortKind};
pub use flange::FlangeTorques;
pub use law::{EnergyRole, ForceLaw, LawCtx};
pub use outputs::Out;

use std::any::Any;
use std::sync::OnceLock;

use crate::model::{Experiment, InitValue};
use crate::signals::SignalGraph;
use crate::switching::element::SwitchingElement;
use crate::thermal::ThermalNet;

pub struct LawElem {
    pub owner: String,
    pub rel: Rel,
    pub law: Box<dyn ForceLaw>,
    /// Index of this law's first frozen relation in the discrete state.
    pub relation_base: usize,
    /// `law.relation_count()`, kept so that an evaluation need not ask the law each time.
    pub relation_count: usize,
    /// `law.role()`, kept likewise (every evaluation's energy balance asks it of each law).
    pub role: EnergyRole,
    pub heat_node: Option<usize>,
}

/// A permanent constraint `row·a = 0` (or `= a(t)` for a prescribed motion); its multiplier is
/// the element torque along the row.
pub struct Constraint {
    pub owner: String,
    pub rel: Rel,
    /// A speed source does work through its constraint; a gear does not.
    pub does_work: bool,
    /// The row's angle and speed follow input signals (an AngleToTorqueAdaptor).
    pub prescribed: Option<Prescribed>,
}

/// A motion prescribed by signals, as MSL's `Sources.Move` with exact motion: the row's angle is
/// the `phi` signal and its speed the `w` signal (0 without one) at every evaluation, its
/// acceleration the `a` signal (0 without one). The angle and speed are algebraic, as in MSL
/// (`flange.phi = phi`), so a new input value moves the flange at once: the state entries of
/// `node` are overwritten wherever the state is evaluated or recorded — the reset of the
/// flange's angle and speed at an input event.
#[derive(Debug, Clone, Copy)]
pub struct Prescribed {
    /// The node set to satisfy the row (the flange's; the support keeps its own motion).
    pub node: usize,
    /// Signal slots of the inputs.
    pub phi: usize,
    pub w: Option<usize>,
    pub a: Option<usize>,
}

impl LawElem {
    /// What the law sees at (t, horizon) with its relative angle and speed, given the signals
    /// and all frozen relations (it takes its own): the evaluation's loops zip the laws with
    /// their values instead of indexing them.
    #[inline]
    pub fn view<'a>(
        &self,
        (t, horizon): (f64, f64),
        (phi_rel, w_rel): (f64, f64),
        signals: &'a [f64],
        relations: &'a [bool],
    ) -> LawCtx<'a> {
        let base = self.relation_base;
        LawCtx {
            t,
            horizon,
            phi_rel,
            w_rel,
            signals,
            relations: &relations[base..base + self.relation_count],
        }
    }
}

impl Constraint {
    /// Sets `phi[node]` and `w[node]` so that the row's angle and speed are the inputs'.
    pub fn prescribe(&self, signals: &[f64], phi: &mut [f64], w: &mut [f64]) {
        let Some(p) = &self.prescribed else {
            return;
        };
        let c = (self.rel.terms.iter())
            .find(|(i, _)| *i == p.node)
            .map_or(1.0, |t| t.1);
        let target_w = p.w.map_or(0.0, |slot| signals[slot]);
        let rest_phi = self.rel.angle(phi) - c * phi[p.node];
        let rest_w = self.rel.dot(w) - c * w[p.node];
        phi[p.node] = (signals[p.phi] - rest_phi) / c;
        w[p.node] = (target_w - rest_w) / c;
    }

    /// The right-hand side of the acceleration row: the `a` input, or 0.
    pub fn accel(&self, signals: &[f64]) -> f64 {
        match self.prescribed {
            Some(Prescribed { a: Some(slot), .. }) => signals[slot],
            _ => 0.0,
        }
    }
}

/// A start-value equation `rel(phi or w) = value`, fixed or a guess.
#[derive(Debug, Clone)]
pub struct InitEq {
    pub rel: Rel,
    pub value: InitValue,
    pub variable: String,
    /// A holonomic constraint holding at the start (a gear), not a user's start value.
    pub constraint: bool,
}

/// A signal input of a component declared an input of the model: its value comes from the
/// simulation (`Simulation::set_input`, an FMU host) instead of a connection.
#[derive(Debug, Clone)]
pub struct ModelInput {
    /// `component.port`, e.g. `brake.f_normalized`.
    pub name: String,
    pub slot: usize,
    pub start: f64,
}

pub struct System {
    pub name: String,
    pub experiment: Experiment,
    pub nodes: usize,
    pub mass: Vec<f64>,
    /// Who gave each node its mass: (component, node, J), for the per-element energy audit.
    pub masses: Vec<(String, usize, f64)>,
    /// Ports on each node, for messages.
    pub node_ports: Vec<Vec<String>>,
    pub laws: Vec<LawElem>,
    pub relation_count: usize,
    /// Permanent acceleration constraints `row·a = 0` (gears, speed sources) or `row·a = a(t)`
    /// (prescribed motions).
    pub constraints: Vec<Constraint>,
    /// Every element with stick/slip or quadrant logic, in one list.
    pub switching: Vec<Box<dyn SwitchingElement>>,
    pub signals: SignalGraph,
    pub thermal: ThermalNet,
    pub init_phi: Vec<InitEq>,
    pub init_w: Vec<InitEq>,
    pub outputs: Vec<(String, Out)>,
    pub flange_torques: FlangeTorques,
    pub time_events: Vec<f64>,
    pub inputs: Vec<ModelInput>,
    /// Shafts ideal gears tie to prescribed ones (`follow`).
    pub followers: Vec<(usize, usize)>,
    /// What a layer above derives from this system once and keeps with it (`Derived`).
    pub derived: Derived,
}

/// A value derived from a system on first use and kept with it: the result table's layout of
/// every variable, built in about 20 µs for CoupledClutches, once per compiled model rather
/// than once per run. A system never changes once built (its values change by building
/// another), so neither does what is derived from it. Type-erased so that this layer does not
/// name the types of the layers that use it.
#[derive(Default)]
pub struct Derived(OnceLock<Box<dyn Any + Send + Sync>>);

impl Derived {
    /// The kept value, made by `make` on first use; `None` if a value of another type was kept.
    pub fn get_or_init<T: Any + Send + Sync>(&self, make: impl FnOnce() -> T) -> Option<&T> {
        self.0.get_or_init(|| Box::new(make())).downcast_ref()
    }

    /// The kept value, if one of type `T` was kept.
    pub fn get<T: Any + Send + Sync>(&self) -> Option<&T> {
        self.0.get()?.downcast_ref()
    }
}

impl System {
    /// Number of continuous states: node angles and speeds, heat capacities, two energy integrals.
    pub fn state_len(&self) -> usize {
        2 * self.nodes + self.thermal.capacities.len() + 2
    }

    /// Whether some constraint prescribes a motion from signals (its node's state is algebraic).
    pub fn prescribes(&self) -> bool {
        self.constraints.iter().any(|c| c.prescribed.is_some())
    }

    pub fn node_label(&self, node: usize) -> String {
        self.node_ports[node].join(", ")
    }
}
