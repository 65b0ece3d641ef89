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
    /// Its relative motion is a state a reset keeps (`Builder::keep_relative_states`).
    pub relative_states: bool,
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

/// A motion prescribed by signals along a constraint's row (MSL's `Sources.Move`, `Speed`,
/// `Position`, `Accelerate`): what the signals hold at every evaluation (`Held`) and the row's
/// acceleration (`Accel`); the rest of the row's motion is the node's state. Held values are
/// algebraic, as in MSL (`flange.phi = phi`), so a new input value moves the flange at once:
/// the state entries of `node` are overwritten wherever the state is evaluated or recorded —
/// the reset of the flange's angle and speed at an input event.
#[derive(Debug, Clone, Copy)]
pub struct Prescribed {
    /// The node set to satisfy the row (the flange's; the support keeps its own motion).
    pub node: usize,
    pub held: Held,
    pub accel: Accel,
}

impl Prescribed {
    /// The signal slots the row holds its angle and speed to (set before any sensor reads the
    /// shafts), and the slot its acceleration reads (read after the angle and speed sensors).
    pub fn slots(&self) -> ([Option<usize>; 2], Option<usize>) {
        let held = match self.held {
            Held::Angle { phi, w } => [Some(phi), w],
            Held::Speed(w) => [Some(w), None],
            Held::Nothing => [None, None],
        };
        let accel = match self.accel {
            Accel::Zero => None,
            Accel::Signal(slot) => Some(slot),
            Accel::FirstOrder { w_ref, .. } => Some(w_ref),
            Accel::SecondOrder { phi_ref, .. } => Some(phi_ref),
        };
        (held, accel)
    }
}

/// What the signals hold of a prescribed row's angle and speed (signal slots).
#[derive(Debug, Clone, Copy)]
pub enum Held {
    /// The angle, and the speed (0 without a slot): `Move`, `Position(exact = true)`.
    Angle { phi: usize, w: Option<usize> },
    /// The speed; the angle is a state: `Speed(exact = true)`.
    Speed(usize),
    /// Nothing: angle and speed are states (the filters, `Accelerate`).
    Nothing,
}

/// The right-hand side of a prescribed row's acceleration.
#[derive(Debug, Clone, Copy)]
pub enum Accel {
    Zero,
    /// A signal slot (an input, or an input's time derivative).
    Signal(usize),
    /// MSL `Speed`'s first-order filter: `a = (w_ref − w)·w_crit`.
    FirstOrder {
        w_ref: usize,
        w_crit: f64,
    },
    /// MSL `Position`'s critically damped filter: `a = ((phi_ref − phi)·w_crit − af·w)·w_crit/bf`.
    SecondOrder {
        phi_ref: usize,
        w_crit: f64,
        af: f64,
        bf: f64,
    },
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
    /// Sets `phi[node]` and `w[node]` so that the row's angle and speed are what the signals
    /// hold (`Held`); the entries a signal does not hold are left as they are.
    pub fn prescribe(&self, signals: &[f64], phi: &mut [f64], w: &mut [f64]) {
        let Some(p) = &self.prescribed else {
            return;
        };
        let c = (self.rel.terms.iter())
            .find(|(i, _)| *i == p.node)
            .map_or(1.0, |t| t.1);
        let (target_phi, target_w) = match p.held {
            Held::Angle { phi, w } => (Some(signals[phi]), Some(w.map_or(0.0, |s| signals[s]))),
            Held::Speed(w) => (None, Some(signals[w])),
            Held::Nothing => return,
        };
        if let Some(target) = target_phi {
            let rest_phi = self.rel.angle(phi) - c * phi[p.node];
            phi[p.node] = (target - rest_phi) / c;
        }
        if let Some(target) = target_w {
            let rest_w = self.rel.dot(w) - c * w[p.node];
            w[p.node] = (target - rest_w) / c;
        }
    }

    /// The right-hand side of the acceleration row at the angles and speeds `phi`, `w`.
    #[inline]
    pub fn accel(&self, signals: &[f64], phi: &[f64], w: &[f64]) -> f64 {
        let Some(p) = &self.prescribed else {
            return 0.0;
        };
        match p.accel {
            Accel::Zero => 0.0,
            Accel::Signal(slot) => signals[slot],
            Accel::FirstOrder { w_ref, w_crit } => (signals[w_ref] - self.rel.dot(w)) * w_crit,
            Accel::SecondOrder {
                phi_ref,
                w_crit,
                af,
                bf,
            } => {
                let (phi_rel, w_rel) = (self.rel.angle(phi), self.rel.dot(w));
                ((signals[phi_ref] - phi_rel) * w_crit - af * w_rel) * (w_crit / bf)
            }
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
    /// The start value is this signal slot's value at the start time (a prescribed motion's
    /// `w = w_ref` at initialization); `value.start` is then a placeholder.
    pub signal: Option<usize>,
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
    /// The worn friction elements: one state each, after the energy integrals.
    pub wear: Vec<crate::wear::Wear>,
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
    /// Number of continuous states: node angles and speeds, heat capacities, two energy
    /// integrals, worn volumes.
    pub fn state_len(&self) -> usize {
        2 * self.nodes + self.thermal.capacities.len() + 2 + self.wear.len()
    }

    /// The signals at the start time with the inputs' start values (what start values taken
    /// from signals read).
    pub fn start_signals(&self) -> Vec<f64> {
        let mut values = vec![0.0; self.signals.slots];
        for input in &self.inputs {
            values[input.slot] = input.start;
        }
        let t0 = self.experiment.start_time;
        let horizon = (self.time_events.first().copied()).unwrap_or(self.experiment.stop_time);
        self.signals.eval(t0, horizon, &mut values);
        values
    }

    /// Whether some constraint prescribes a motion from signals (its node's state is algebraic).
    pub fn prescribes(&self) -> bool {
        self.constraints.iter().any(|c| c.prescribed.is_some())
    }

    pub fn node_label(&self, node: usize) -> String {
        self.node_ports[node].join(", ")
    }
}
