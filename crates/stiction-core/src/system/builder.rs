//! What a component sees while it contributes to the system: its resolved ports (nodes, signal
//! slots, heat nodes) and the calls that add masses, force laws, constraints, switching
//! elements, start values and output variables. The assembly (`crate::assembly`) drives it.

use std::collections::HashMap;

use super::flange::FlangeBuilder;
use super::{Constraint, ForceLaw, InitEq, LawElem, NodeRef, Out, Prescribed, Rel, System};
use crate::error::{ModelError, ModelResult};
use crate::model::InitValue;
use crate::signals::{Block, BlockElem};
use crate::switching::element::SwitchingElement;
use crate::thermal::{Capacity, Link};

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

/// One port of one component, as the assembly resolved it.
#[derive(Debug, Clone)]
pub struct PortInfo {
    pub component: usize,
    pub name: &'static str,
    pub kind: PortKind,
}

/// What a component sees while it contributes to the system.
pub struct Builder {
    pub(crate) comp: usize,
    pub(crate) names: Vec<String>,
    pub(crate) index: HashMap<(usize, &'static str), usize>,
    pub(crate) mech_node: Vec<Option<NodeRef>>,
    pub(crate) signal_slot: Vec<Option<usize>>,
    pub(crate) heat_node: Vec<Option<usize>>,
    pub(crate) sys: System,
    pub(crate) flanges: FlangeBuilder,
    pub(crate) fixed_temperature: Vec<Option<f64>>,
    pub(crate) capacitors: Vec<Capacity>,
}

impl Builder {
    pub fn name(&self) -> &str {
        &self.names[self.comp]
    }

    pub fn error(&self, message: impl Into<String>) -> ModelError {
        ModelError::Component {
            component: self.names[self.comp].clone(),
            message: message.into(),
        }
    }

    fn port(&self, port: &str) -> Option<usize> {
        // the map is covariant in its key, so a shorter-lived name looks it up directly
        let index: &HashMap<(usize, &str), usize> = &self.index;
        index.get(&(self.comp, port)).copied()
    }

    fn port_index(&self, port: &str) -> ModelResult<usize> {
        self.port(port)
            .ok_or_else(|| self.error(format!("internal: port '{port}' not declared")))
    }

    /// The node of a mechanical port; an undeclared `support` is the implicit ground (MSL
    /// `useSupport = false`: `phi_support = 0`).
    pub fn node(&self, port: &str) -> ModelResult<NodeRef> {
        match self.port(port) {
            Some(i) => Ok(self.mech_node[i].expect("mechanical port has a node")),
            None if port == "support" => Ok(NodeRef::Ground(0.0)),
            None => Err(self.error(format!("internal: flange '{port}' not declared"))),
        }
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
        });
        self.sys.laws.len() - 1
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

    pub fn signal_in(&self, port: &str) -> ModelResult<usize> {
        let i = self.port_index(port)?;
        self.signal_slot[i].ok_or_else(|| ModelError::Component {
            component: self.name().to_string(),
            message: format!(
                "port '{port}': signal input is not connected (connect a signal source to it)"
            ),
        })
    }

    pub fn signal_out(&self, port: &str) -> ModelResult<usize> {
        let i = self.port_index(port)?;
        Ok(self.signal_slot[i].expect("outputs have slots"))
    }

    pub fn add_block(&mut self, block: Box<dyn Block>, inputs: Vec<usize>, output: usize) {
        self.sys.signals.blocks.push(BlockElem {
            owner: self.name().to_string(),
            block,
            inputs,
            output,
        });
    }

    pub fn heat_node(&self, port: &str) -> ModelResult<usize> {
        let i = self.port_index(port)?;
        Ok(self.heat_node[i].expect("heat port has a node"))
    }

    /// A signal slot that holds the temperature of heat node `node` (a law's input).
    pub fn temperature_tap(&mut self, node: usize) -> usize {
        let slot = self.sys.signals.slots;
        self.sys.signals.slots += 1;
        let owner = self.name().to_string();
        (self.sys.thermal.taps).push(crate::thermal::TemperatureTap { owner, node, slot });
        slot
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

    pub fn add_heat_link(&mut self, link: Link) -> usize {
        self.sys.thermal.links.push(link);
        self.sys.thermal.links.len() - 1
    }

    pub fn init_angle(&mut self, rel: Rel, value: InitValue, variable: &str) {
        let eq = self.start_value(rel, value, variable);
        self.sys.init_phi.push(eq);
    }

    pub fn init_speed(&mut self, rel: Rel, value: InitValue, variable: &str) {
        let eq = self.start_value(rel, value, variable);
        self.sys.init_w.push(eq);
    }

    /// The start-value equation of this component's `variable`.
    fn start_value(&self, rel: Rel, value: InitValue, variable: &str) -> InitEq {
        InitEq {
            rel,
            value,
            variable: format!("{}.{variable}", self.name()),
            constraint: false,
        }
    }

    /// A gear's kinematic row `row = 0` holds from the start, for angles and speeds.
    pub fn init_constraint(&mut self, row: Rel) {
        let value = InitValue {
            start: 0.0,
            fixed: true,
        };
        let variable = format!("{} (gear constraint)", self.name());
        for list in [&mut self.sys.init_phi, &mut self.sys.init_w] {
            list.push(InitEq {
                rel: row.clone(),
                value,
                variable: variable.clone(),
                constraint: true,
            });
        }
    }

    /// Reports a variable under `component.name`.
    pub fn output(&mut self, name: &str, out: Out) {
        let full = format!("{}.{name}", self.name());
        self.sys.outputs.push((full, out));
    }

    /// Reports the angle and cut torque of a flange, and says how its torque is known.
    pub fn flange(&mut self, port: &str, node: NodeRef, tau: Option<Out>) -> ModelResult<()> {
        let i = self.port_index(port)?;
        self.output(&format!("{port}.phi"), Out::Angle(Rel::of(&[(node, 1.0)])));
        self.output(&format!("{port}.tau"), Out::FlangeTau(i));
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
