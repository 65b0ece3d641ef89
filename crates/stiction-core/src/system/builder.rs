//! What a component sees while it contributes to the system: its resolved ports (nodes, signal
//! slots, heat nodes) and the calls that add masses, force laws, constraints, switching
//! elements, start values and output variables. The assembly (`crate::assembly`) drives it.

use rustc_hash::FxHashMap as HashMap;

use super::flange::FlangeBuilder;
use super::{Constraint, ForceLaw, InitEq, LawElem, NodeRef, Out, Prescribed, Rel, System};
use crate::error::{ModelError, ModelResult};
use crate::model::InitValue;
use crate::signals::{Block, BlockElem, Derivative, Measure, Sensor, Stage};
use crate::switching::element::SwitchingElement;
use crate::thermal::{Capacity, Link};

/// The placeholder of a start value a signal gives (`InitEq::signal`).
const FROM_SIGNAL: InitValue = InitValue {
    start: 0.0,
    fixed: true,
    nominal: 1.0,
};

/// What a port carries, for connection checks and messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PortKind {
    Mechanical,
    SignalIn,
    SignalOut,
    Heat,
}

impl PortKind {
    pub fn describe(self) -> &'static str {
        match self {
            PortKind::Mechanical => "a flange",
            PortKind::SignalIn => "a signal input",
            PortKind::SignalOut => "a signal output",
            PortKind::Heat => "a heat port",
        }
    }
}

/// The mechanical domain of a flange: a property of the port, not a copy of the engine. Nodes,
/// constraint rows, laws, switching elements, events, the energy audit and shafts without
/// inertia serve both; only the names and units of what a flange reports differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Domain {
    /// `phi` [rad], `w` [rad/s], `a` [rad/s2], `tau` [N.m].
    #[default]
    Rotational,
    /// `s` [m], `v` [m/s], `a` [m/s2], `f` [N].
    Translational,
}

impl Domain {
    /// The name of a flange's position (`flange_a.phi`, `flange_a.s`).
    pub fn position(self) -> &'static str {
        match self {
            Domain::Rotational => "phi",
            Domain::Translational => "s",
        }
    }

    /// The name of a flange's cut force (`flange_a.tau`, `flange_a.f`).
    pub fn force(self) -> &'static str {
        match self {
            Domain::Rotational => "tau",
            Domain::Translational => "f",
        }
    }

    pub fn word(self) -> &'static str {
        match self {
            Domain::Rotational => "rotational",
            Domain::Translational => "translational",
        }
    }
}

/// One port of one component, as the assembly resolved it.
#[derive(Debug, Clone)]
pub struct PortInfo {
    pub component: usize,
    pub name: &'static str,
    pub kind: PortKind,
    /// For a flange, its domain (Rotational for every other port).
    pub domain: Domain,
}

impl PortInfo {
    /// `a flange`, `a translational flange`, `a signal input` … for messages.
    pub fn describe(&self) -> &'static str {
        match (self.kind, self.domain) {
            (PortKind::Mechanical, Domain::Translational) => "a translational flange",
            (kind, _) => kind.describe(),
        }
    }
}

/// What a component sees while it contributes to the system.
pub struct Builder {
    pub(crate) comp: usize,
    pub(crate) names: Vec<String>,
    pub(crate) index: HashMap<(usize, &'static str), usize>,
    pub(crate) mech_node: Vec<Option<NodeRef>>,
    /// The domain of every port (by global index): what its flange outputs are called.
    pub(crate) domain: Vec<Domain>,
    /// Each flange's coordinate minus its node's (0 but for a Mass with a length).
    pub(crate) offset: Vec<f64>,
    pub(crate) signal_slot: Vec<Option<usize>>,
    pub(crate) heat_node: Vec<Option<usize>>,
    pub(crate) sys: System,
    pub(crate) flanges: FlangeBuilder,
    pub(crate) fixed_temperature: Vec<Option<f64>>,
    pub(crate) capacitors: Vec<Capacity>,
    /// Every signal input read, as (component, port, slot): the assembly checks what reaches
    /// a mechanical component's input (`assembly::signals`).
    pub(crate) signal_reads: Vec<(usize, String, usize)>,
    /// The components that added blocks (their inputs feed only other signals).
    pub(crate) block_owners: Vec<usize>,
    /// While a composite builds one of its parts (`within`): the part's name and ports.
    pub(crate) scope: Option<Scope>,
}

/// A part of a composite component (MSL's `Gearbox.lossyGear`): its outputs and messages go
/// under `composite.part`, and its port names map onto the composite's ports.
pub(crate) struct Scope {
    name: String,
    /// (the part's port, the composite's port it is)
    ports: Vec<(&'static str, &'static str)>,
}

impl Builder {
    pub fn name(&self) -> &str {
        match &self.scope {
            Some(scope) => &scope.name,
            None => &self.names[self.comp],
        }
    }

    /// Builds `part` of a composite component (its `build`) as a component named `composite.name`,
    /// whose ports are the composite's as `ports` maps them (`(part's, composite's)`); a
    /// port left out is undeclared (an unmapped `support` is the implicit ground).
    pub fn within(
        &mut self,
        name: &str,
        ports: &[(&'static str, &'static str)],
        part: impl FnOnce(&mut Builder) -> ModelResult<()>,
    ) -> ModelResult<()> {
        let scope = Scope {
            name: format!("{}.{name}", self.names[self.comp]),
            ports: ports.to_vec(),
        };
        let outer = self.scope.replace(scope);
        let built = part(self);
        self.scope = outer;
        built
    }

    /// The expression of an output this component (or one of its parts) reported as
    /// `name` (relative to the component).
    pub fn reported(&self, name: &str) -> Option<Out> {
        let full = format!("{}.{name}", self.names[self.comp]);
        (self.sys.outputs.iter().rev())
            .find(|(n, _)| *n == full)
            .map(|(_, out)| out.clone())
    }

    pub fn error(&self, message: impl Into<String>) -> ModelError {
        ModelError::Component {
            component: self.names[self.comp].clone(),
            message: message.into(),
        }
    }

    fn port(&self, port: &str) -> Option<usize> {
        let port = match &self.scope {
            Some(scope) => scope.ports.iter().find(|(p, _)| *p == port)?.1,
            None => port,
        };
        // the map is covariant in its key, so a shorter-lived name looks it up directly
        let index: &HashMap<(usize, &str), usize> = &self.index;
        index.get(&(self.comp, port)).copied()
    }

    fn port_index(&self, port: &str) -> ModelResult<usize> {
        self.port(port)
            .ok_or_else(|| self.error(format!("internal: port '{port}' not declared")))
    }

    /// The node of a mechanical port; an undeclared `support` (`supportR`, `supportT`) is the
    /// implicit ground (MSL `useSupport = false`: `phi_support = 0`).
    pub fn node(&self, port: &str) -> ModelResult<NodeRef> {
        match self.port(port) {
            Some(i) => Ok(self.mech_node[i].expect("mechanical port has a node")),
            None if port.starts_with("support") => Ok(NodeRef::Ground(0.0)),
            None => Err(self.error(format!("internal: flange '{port}' not declared"))),
        }
    }

    /// `Σ coef·position(port)`: a row over the flanges' own coordinates, with the offsets of
    /// flanges that sit apart from their node (a Mass's of length L) and the implicit ground of
    /// an undeclared support.
    pub fn rel(&self, parts: &[(&str, f64)]) -> ModelResult<Rel> {
        let mut nodes = Vec::with_capacity(parts.len());
        let mut offset = 0.0;
        for &(port, coef) in parts {
            nodes.push((self.node(port)?, coef));
            if let Some(i) = self.port(port) {
                offset += coef * self.offset[i];
            }
        }
        let mut rel = Rel::of(&nodes);
        rel.offset += offset;
        Ok(rel)
    }

    pub fn add_mass(&mut self, node: NodeRef, j: f64) {
        if let NodeRef::Node(i) = node {
            self.sys.mass[i] += j;
            let owner = self.name().to_string();
            self.sys.masses.push((owner, i, j));
        }
    }

    pub fn add_law(&mut self, rel: Rel, law: Box<dyn ForceLaw>) -> usize {
        let relation_base = self.sys.relation_count;
        let relation_count = law.relation_count();
        debug_assert!(relation_count <= super::law::MAX_LAW_RELATIONS);
        self.sys.relation_count += relation_count;
        let role = law.role();
        self.sys.laws.push(LawElem {
            owner: self.name().to_string(),
            rel,
            law,
            relation_base,
            relation_count,
            role,
            heat_node: None,
            relative_states: false,
        });
        self.sys.laws.len() - 1
    }

    /// Law `law`'s relative position and speed are states (MSL's
    /// `PartialCompliantWithRelativeStates`, `stateSelect = prefer`): a reset at an event keeps
    /// them, so it moves the flanges on its other side too.
    pub fn keep_relative_states(&mut self, law: usize) {
        self.sys.laws[law].relative_states = true;
    }

    pub fn set_law_heat(&mut self, law: usize, node: usize) {
        self.sys.laws[law].heat_node = Some(node);
    }

    pub fn add_constraint(&mut self, rel: Rel, does_work: bool) -> ModelResult<usize> {
        if rel.is_zero() {
            return Err(self.error(
                "its flanges are rigidly connected to each other or to ground on both sides",
            ));
        }
        self.sys.constraints.push(Constraint {
            owner: self.name().to_string(),
            rel,
            does_work,
            prescribed: None,
        });
        Ok(self.sys.constraints.len() - 1)
    }

    /// A motion prescribed by signals along `rel` (see `Prescribed`); it does work.
    pub fn add_prescribed(&mut self, rel: Rel, prescribed: Prescribed) -> ModelResult<usize> {
        let k = self.add_constraint(rel, true)?;
        self.sys.constraints[k].prescribed = Some(prescribed);
        Ok(k)
    }

    /// Adds a switching element; returns its index (for its result variables).
    pub fn add_switching(&mut self, element: Box<dyn SwitchingElement>) -> usize {
        self.sys.switching.push(element);
        self.sys.switching.len() - 1
    }

    pub fn signal_in(&mut self, port: &str) -> ModelResult<usize> {
        let i = self.port_index(port)?;
        let slot = self.signal_slot[i].ok_or_else(|| ModelError::Component {
            component: self.name().to_string(),
            message: format!(
                "port '{port}': signal input is not connected (connect a signal source to it)"
            ),
        })?;
        self.signal_reads.push((self.comp, port.to_string(), slot));
        Ok(slot)
    }

    pub fn signal_out(&self, port: &str) -> ModelResult<usize> {
        let i = self.port_index(port)?;
        Ok(self.signal_slot[i].expect("outputs have slots"))
    }

    pub fn add_block(&mut self, block: Box<dyn Block>, inputs: Vec<usize>, output: usize) {
        self.block_owners.push(self.comp);
        self.sys.signals.blocks.push(BlockElem {
            owner: self.name().to_string(),
            block,
            inputs,
            output,
        });
    }

    /// A sensor writing what it measures into its output `port`, reported as a variable
    /// `component.port`.
    pub fn add_sensor(&mut self, port: &'static str, measure: Measure) -> ModelResult<()> {
        let slot = self.signal_out(port)?;
        self.output(port, Out::Signal(slot));
        let part = match measure.stage() {
            Stage::Solved => &mut self.sys.signals.solved,
            _ => &mut self.sys.signals.state,
        };
        part.sensors.push(Sensor {
            owner: self.names[self.comp].clone(),
            port,
            measure,
            slot,
        });
        Ok(())
    }

    pub fn heat_node(&self, port: &str) -> ModelResult<usize> {
        let i = self.port_index(port)?;
        Ok(self.heat_node[i].expect("heat port has a node"))
    }

    /// A signal slot that holds the temperature of heat node `node` (a law's input).
    pub fn temperature_tap(&mut self, node: usize) -> usize {
        self.temperature_tap_for(node, "its torque", None)
    }

    /// `temperature_tap` for `reader` (named in messages: "its wear"), or for a parameter that
    /// reads it (a Brake's `mu_T`), which the messages about its heat port then name.
    pub fn temperature_tap_for(
        &mut self,
        node: usize,
        reader: &'static str,
        param: Option<&'static str>,
    ) -> usize {
        let slot = self.sys.signals.slots;
        self.sys.signals.slots += 1;
        let owner = self.name().to_string();
        let tap = crate::thermal::TemperatureTap {
            owner,
            reader,
            node,
            slot,
            param,
        };
        self.sys.thermal.taps.push(tap);
        slot
    }

    /// Adds a worn element's wear state; gives its index among the worn elements.
    pub fn add_wear(&mut self, wear: crate::wear::Wear) -> usize {
        self.sys.wear.push(wear);
        self.sys.wear.len() - 1
    }

    pub fn add_heat_capacity(&mut self, node: usize, c: f64, init: InitValue) {
        self.capacitors.push(Capacity { node, c, init });
    }

    pub fn fix_temperature(&mut self, node: usize, t: f64) -> ModelResult<()> {
        match self.fixed_temperature[node] {
            Some(other) if other != t => Err(self.error(format!(
                "port 'port': connected to another FixedTemperature of {other} K"
            ))),
            _ => {
                self.fixed_temperature[node] = Some(t);
                Ok(())
            }
        }
    }

    /// A heat link; a radiation link is recorded with its component too: the assembly refuses
    /// it by name where it touches a node whose temperature is algebraic.
    pub fn add_heat_link(&mut self, link: Link) -> usize {
        let radiation = link.is_radiation();
        self.sys.thermal.links.push(link);
        let k = self.sys.thermal.links.len() - 1;
        if radiation {
            let owner = self.name().to_string();
            self.sys.thermal.radiation.push((k, owner));
        }
        k
    }

    pub fn init_angle(&mut self, rel: Rel, value: InitValue, variable: &str) {
        let eq = self.start_value(rel, value, variable);
        self.sys.init_phi.push(eq);
    }

    pub fn init_speed(&mut self, mut rel: Rel, value: InitValue, variable: &str) {
        // a coordinate's constant offset (a ground's angle, a flange's place) has no speed
        rel.offset = 0.0;
        let eq = self.start_value(rel, value, variable);
        self.sys.init_w.push(eq);
    }

    /// A fixed start value `rel(phi) = signal(t0)`: the value of a signal slot at the start.
    pub fn init_angle_from(&mut self, rel: Rel, slot: usize, variable: &str) {
        let mut eq = self.start_value(rel, FROM_SIGNAL, variable);
        eq.signal = Some(slot);
        self.sys.init_phi.push(eq);
    }

    /// A fixed start value `rel(w) = signal(t0)`.
    pub fn init_speed_from(&mut self, rel: Rel, slot: usize, variable: &str) {
        let mut eq = self.start_value(rel, FROM_SIGNAL, variable);
        eq.signal = Some(slot);
        self.sys.init_w.push(eq);
    }

    /// A slot holding the `order`-th time derivative (1 or 2) of signal input `port`, for a
    /// source that follows it exactly; the assembly refuses an input whose derivative is not
    /// known (`SignalGraph::underivable`).
    pub fn signal_derivative(&mut self, port: &'static str, order: usize) -> ModelResult<usize> {
        let of = self.signal_in(port)?;
        let slot = self.sys.signals.slots;
        self.sys.signals.slots += 1;
        self.sys.signals.derivatives.push(Derivative {
            of,
            order,
            slot,
            owner: self.name().to_string(),
            port,
        });
        Ok(slot)
    }

    /// The start-value equation of this component's `variable`.
    fn start_value(&self, rel: Rel, value: InitValue, variable: &str) -> InitEq {
        InitEq {
            rel,
            value,
            variable: dotted(self.name(), variable),
            constraint: false,
            signal: None,
        }
    }

    /// A gear's kinematic row `row = 0` holds from the start, for angles and speeds.
    pub fn init_constraint(&mut self, row: Rel) {
        let value = InitValue::fixed(0.0);
        let variable = format!("{} (gear constraint)", self.name());
        let speeds = Rel {
            offset: 0.0, // the row's constant has no speed
            ..row.clone()
        };
        for (list, rel) in [
            (&mut self.sys.init_phi, row),
            (&mut self.sys.init_w, speeds),
        ] {
            list.push(InitEq {
                rel,
                value,
                variable: variable.clone(),
                constraint: true,
                signal: None,
            });
        }
    }

    /// Reports a variable under `component.name`.
    pub fn output(&mut self, name: &str, out: Out) {
        let full = dotted(self.name(), name);
        self.sys.outputs.push((full, out));
    }

    /// Reports the position and cut force of a flange (`.phi`/`.tau` or, translational,
    /// `.s`/`.f`), and says how its force is known. `node` is the port's own (`node(port)`):
    /// the flange's offset from it is added.
    pub fn flange(&mut self, port: &str, node: NodeRef, tau: Option<Out>) -> ModelResult<()> {
        let i = self.port_index(port)?;
        let d = self.domain[i];
        let position = dotted(port, d.position());
        let mut at = Rel::of(&[(node, 1.0)]);
        at.offset += self.offset[i];
        self.output(&position, Out::Angle(at));
        self.output(&dotted(port, d.force()), Out::FlangeTau(i));
        if let Some(tau) = tau {
            self.flanges.known(i, tau);
        }
        Ok(())
    }

    /// Flanges whose torques add up to `total` (an Inertia: `J·a`; a Brake: `tau`), or are free
    /// (a Fixed flange takes whatever the connection needs).
    pub fn flange_group(&mut self, ports: &[&str], total: Option<Out>) -> ModelResult<()> {
        let idx = ports
            .iter()
            .map(|p| self.port_index(p))
            .collect::<ModelResult<Vec<_>>>()?;
        self.flanges.group(idx, total);
        Ok(())
    }
}

/// `a.b`, allocated once at its length: a sweep builds every variant's hundred output names,
/// and `format!` took a tenth of the build.
fn dotted(a: &str, b: &str) -> String {
    let mut s = String::with_capacity(a.len() + 1 + b.len());
    s.push_str(a);
    s.push('.');
    s.push_str(b);
    s
}
