//! The assembled hybrid system: nodes (one angle per rigid connection set), force laws,
//! permanent constraints, switching elements, the signal graph, the thermal network, start-value
//! equations and the output variables. Built once per model; many runs share it.

mod builder;
pub(crate) mod flange;
pub mod law;
pub mod outputs;

pub use crate::rel::{NodeRef, Rel};
pub use builder::{Builder, PortInfo, PortKind};
pub use flange::FlangeTorques;
pub use law::{EnergyRole, ForceLaw, LawCtx};
pub use outputs::Out;

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
    pub heat_node: Option<usize>,
}

/// A permanent constraint `row·a = 0`; its multiplier is the element torque along the row.
pub struct Constraint {
    pub owner: String,
    pub rel: Rel,
    /// A speed source does work through its constraint; a gear does not.
    pub does_work: bool,
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
    /// Permanent acceleration constraints `row·a = 0` (gears, speed sources).
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
}

impl System {
    /// Number of continuous states: node angles and speeds, heat capacities, two energy integrals.
    pub fn state_len(&self) -> usize {
        2 * self.nodes + self.thermal.capacities.len() + 2
    }

    pub fn node_label(&self, node: usize) -> String {
        self.node_ports[node].join(", ")
    }
}
