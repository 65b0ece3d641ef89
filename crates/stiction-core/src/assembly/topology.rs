//! The structure of a model, resolved once: ports, flanges joined into nodes (union–find),
//! signal slots, model inputs and heat nodes. It depends on the component types, their
//! conditional ports and the connections — not on parameter values — so a compiled model keeps
//! it while parameters change.

use rustc_hash::FxHashMap as HashMap;
use std::sync::Arc;

use crate::components::{Component, Domain, PortKind, Ports};
use crate::error::{ModelError, ModelResult};
use crate::model::{ModelSpec, PortRef};
use crate::system::{ModelInput, NodeRef, PortInfo};

/// Union–find over port indices, with each port's coordinate relative to its set's root (a
/// Mass's flanges are L apart; every other join and every connection is at distance 0).
struct Sets {
    parent: Vec<usize>,
    /// Coordinate of a port minus its parent's (0 at a root).
    w: Vec<f64>,
}

impl Sets {
    fn new(n: usize) -> Self {
        Sets {
            parent: (0..n).collect(),
            w: vec![0.0; n],
        }
    }
    fn find(&mut self, i: usize) -> usize {
        let (mut r, mut total) = (i, 0.0);
        while self.parent[r] != r {
            total += self.w[r];
            r = self.parent[r];
        }
        // path compression, each port keeping its distance to the root
        let mut j = i;
        while j != r {
            let (next, wj) = (self.parent[j], self.w[j]);
            self.parent[j] = r;
            self.w[j] = total;
            total -= wj;
            j = next;
        }
        r
    }
    /// The coordinate of port `i` relative to its set's root.
    fn offset(&mut self, i: usize) -> f64 {
        let r = self.find(i);
        if r == i {
            0.0
        } else {
            self.w[i]
        }
    }
    fn union(&mut self, a: usize, b: usize) {
        self.union_at(a, b, 0.0)
            .expect("joins at distance 0 are always consistent");
    }
    /// Joins `b` to `a` at `x_b = x_a + d`; `Err(distance)` if they are already joined at
    /// another distance (a rigid loop that does not close).
    fn union_at(&mut self, a: usize, b: usize, d: f64) -> Result<(), f64> {
        let (wa, wb) = (self.offset(a), self.offset(b));
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            let have = wb - wa;
            return match (have - d).abs() <= 1e-12 * (1.0 + d.abs()) {
                true => Ok(()),
                false => Err(have),
            };
        }
        self.parent[rb] = ra;
        self.w[rb] = d + wa - wb;
        Ok(())
    }
}

/// What the connections join: rigid flange sets (connections and a component's own joins),
/// explicitly connected flanges (the torque balances), heat ports, and each signal input's
/// source.
struct Joins {
    mech: Sets,
    cut: Sets,
    heat: Sets,
    signal_source: Vec<Option<usize>>,
}

/// Where every port of a model sits.
#[derive(Debug, Clone)]
pub struct Topology {
    pub names: Vec<String>,
    pub types: Vec<String>,
    /// The ports each component declared (its conditional ones decided).
    pub port_decls: Vec<Ports>,
    pub ports: Vec<PortInfo>,
    pub index: HashMap<(usize, &'static str), usize>,
    component_of: HashMap<String, usize>,
    pub mech_node: Vec<Option<NodeRef>>,
    /// Each flange's coordinate minus its node's (a Mass's flanges sit ±L/2 from its center).
    pub mech_offset: Vec<f64>,
    pub node_ports: Vec<Vec<String>>,
    pub signal_slot: Vec<Option<usize>>,
    pub slots: usize,
    pub inputs: Vec<ModelInput>,
    pub heat_node: Vec<Option<usize>>,
    pub heat_ports: Vec<Vec<String>>,
    /// For each mechanical port, its set of explicitly connected flanges (torque balances).
    pub cut_roots: Vec<Option<usize>>,
}

impl Topology {
    /// Checks every connection and resolves the ports of `comps` (created from `spec`).
    pub fn resolve(spec: &ModelSpec, comps: &[Arc<dyn Component>]) -> ModelResult<Self> {
        let mut topo = Self::declare(spec, comps);
        let mut joins = topo.connect(spec)?;
        topo.mechanical_nodes(&mut joins.mech)?;
        topo.check_connected(&mut joins.mech)?;
        topo.signal_slots(&joins.signal_source);
        topo.model_inputs(spec)?;
        topo.heat_nodes(&mut joins.heat);
        topo.cut_roots = (0..topo.ports.len())
            .map(|i| (topo.ports[i].kind == PortKind::Mechanical).then(|| joins.cut.find(i)))
            .collect();
        Ok(topo)
    }

    /// Every port of every component, numbered.
    fn declare(spec: &ModelSpec, comps: &[Arc<dyn Component>]) -> Self {
        let port_decls: Vec<Ports> = comps.iter().map(|c| c.ports()).collect();
        let mut ports = Vec::new();
        let mut index = HashMap::default();
        for (ci, decl) in port_decls.iter().enumerate() {
            for name in decl.all() {
                let kind = decl.kind_of(name).expect("declared");
                index.insert((ci, name), ports.len());
                ports.push(PortInfo {
                    component: ci,
                    name,
                    kind,
                    domain: decl.domain_of(name),
                });
            }
            for &name in &decl.internal {
                index.insert((ci, name), ports.len());
                ports.push(PortInfo {
                    component: ci,
                    name,
                    kind: PortKind::Mechanical,
                    domain: decl.domain_of(name),
                });
            }
        }
        let names: Vec<String> = spec.components.iter().map(|c| c.name.clone()).collect();
        Topology {
            component_of: names
                .iter()
                .enumerate()
                .map(|(i, n)| (n.clone(), i))
                .collect(),
            names,
            types: spec
                .components
                .iter()
                .map(|c| c.type_name.clone())
                .collect(),
            port_decls,
            ports,
            index,
            mech_node: Vec::new(),
            mech_offset: Vec::new(),
            node_ports: Vec::new(),
            signal_slot: Vec::new(),
            slots: 0,
            inputs: Vec::new(),
            heat_node: Vec::new(),
            heat_ports: Vec::new(),
            cut_roots: Vec::new(),
        }
    }

    /// The index of a port written `component.port`; `what` names the connection for errors
    /// (written only for one: a model's hundreds of connections are written out for nothing).
    fn port_of(&self, r: &PortRef, what: impl Fn() -> String) -> ModelResult<usize> {
        let error = |message: String| ModelError::Connection {
            connection: what(),
            message,
        };
        let Some(&ci) = self.component_of.get(&r.component) else {
            return Err(error(format!(
                "unknown component '{}' (components: {})",
                r.component,
                self.names.join(", ")
            )));
        };
        let decl = &self.port_decls[ci];
        if let Some(p) = decl.all().iter().find(|p| **p == r.port) {
            return Ok(self.index[&(ci, *p)]);
        }
        let hint = match r.port.as_str() {
            "support" => " (set useSupport = true to enable it)",
            "heatPort" => " (set useHeatPort = true to enable it)",
            _ => "",
        };
        Err(error(format!(
            "component '{}' ({}) has no port '{}'{hint}; its ports: {}",
            r.component,
            self.types[ci],
            r.port,
            decl.all().join(", ")
        )))
    }

    /// Checks each connection's ends, then joins flanges and heat ports and wires signals.
    fn connect(&self, spec: &ModelSpec) -> ModelResult<Joins> {
        let n = self.ports.len();
        let mut j = Joins {
            mech: Sets::new(n),
            cut: Sets::new(n),
            heat: Sets::new(n),
            signal_source: vec![None; n],
        };
        for (a, b) in &spec.connections {
            let conn = || format!("{a} — {b}");
            let (ia, ib) = (self.port_of(a, conn)?, self.port_of(b, conn)?);
            let (ka, kb) = (self.ports[ia].kind, self.ports[ib].kind);
            let message = match (ka, kb) {
                (PortKind::Mechanical, PortKind::Mechanical)
                    if self.ports[ia].domain != self.ports[ib].domain =>
                {
                    Some(self.domains_differ(ia, ib))
                }
                (PortKind::Mechanical, PortKind::Mechanical) => {
                    j.mech.union(ia, ib);
                    j.cut.union(ia, ib);
                    continue;
                }
                (PortKind::Heat, PortKind::Heat) => {
                    j.heat.union(ia, ib);
                    continue;
                }
                (PortKind::SignalOut, PortKind::SignalIn) => self.wire(&mut j, ia, ib),
                (PortKind::SignalIn, PortKind::SignalOut) => self.wire(&mut j, ib, ia),
                (PortKind::SignalIn, PortKind::SignalIn) => {
                    Some("connects two signal inputs; one end must be an output (y)".into())
                }
                (PortKind::SignalOut, PortKind::SignalOut) => {
                    Some("connects two signal outputs".into())
                }
                _ => Some(format!(
                    "cannot connect {} ('{a}') to {} ('{b}')",
                    self.ports[ia].describe(),
                    self.ports[ib].describe()
                )),
            };
            if let Some(message) = message {
                return Err(ModelError::Connection {
                    connection: conn(),
                    message,
                });
            }
        }
        for (ci, decl) in self.port_decls.iter().enumerate() {
            for (x, y) in &decl.joins {
                let length = decl.offset_of(y) - decl.offset_of(x);
                let (ix, iy) = (self.index[&(ci, *x)], self.index[&(ci, *y)]);
                if let Err(have) = j.mech.union_at(ix, iy, length) {
                    return Err(ModelError::Component {
                        component: self.names[ci].clone(),
                        message: format!(
                            "{x} and {y} are {length} apart, but the connections outside join them rigidly {have} apart (a rigid loop that does not close)"
                        ),
                    });
                }
            }
        }
        Ok(j)
    }

    /// Why a rotational flange cannot join a translational one: their coordinates are an angle
    /// and a position, related only by a component that converts.
    fn domains_differ(&self, ia: usize, ib: usize) -> String {
        let name = |i: usize| {
            let p = &self.ports[i];
            format!(
                "{} flange '{}.{}'",
                p.domain.word(),
                self.names[p.component],
                p.name
            )
        };
        format!(
            "cannot connect the {} to the {}: an angle and a position are joined only through a \
             component that converts rotation into translation (IdealRollingWheel, IdealGearR2T)",
            name(ia),
            name(ib)
        )
    }

    /// Wires a signal output to an input; the reason it cannot, if it cannot.
    fn wire(&self, j: &mut Joins, out: usize, inp: usize) -> Option<String> {
        match j.signal_source[inp] {
            Some(src) if src == out => None, // the same connection twice
            Some(_) => Some(format!(
                "signal input '{}.{}' is already connected to another output",
                self.names[self.ports[inp].component], self.ports[inp].name
            )),
            None => {
                j.signal_source[inp] = Some(out);
                None
            }
        }
    }

    /// One node per rigid set of flanges, unless the set is held by a Fixed; a node's
    /// coordinate is its root port's, each port sits at its offset from it (`mech_offset`).
    fn mechanical_nodes(&mut self, sets: &mut Sets) -> ModelResult<()> {
        // per set held by a Fixed: the root's coordinate, and who holds it
        let mut ground_of: HashMap<usize, (f64, usize)> = HashMap::default();
        for (ci, decl) in self.port_decls.iter().enumerate() {
            for (p, phi0) in &decl.ground {
                let i = self.index[&(ci, *p)];
                let (root, at) = (sets.find(i), *phi0 - sets.offset(i));
                if let Some(&(other, by)) = ground_of.get(&root) {
                    if (other - at).abs() > 1e-12 * (1.0 + at.abs()) {
                        let (parameter, what) = match decl.domain_of(p) {
                            Domain::Rotational => ("phi0", "angle"),
                            Domain::Translational => ("s0", "position"),
                        };
                        return Err(ModelError::Parameter {
                            component: self.names[ci].clone(),
                            type_name: self.types[ci].clone(),
                            parameter: parameter.into(),
                            message: format!("the flange is rigidly connected to '{}', fixed at a different {what} {}", self.names[by], other + sets.offset(i)),
                        });
                    }
                }
                ground_of.insert(root, (at, ci));
            }
        }
        let mut node_of_root: HashMap<usize, usize> = HashMap::default();
        self.mech_node = vec![None; self.ports.len()];
        self.mech_offset = vec![0.0; self.ports.len()];
        for (i, p) in self.ports.iter().enumerate() {
            if p.kind != PortKind::Mechanical {
                continue;
            }
            let (root, offset) = (sets.find(i), sets.offset(i));
            self.mech_node[i] = Some(match ground_of.get(&root) {
                Some((at, _)) => NodeRef::Ground(at + offset),
                None => {
                    let node = *node_of_root.entry(root).or_insert_with(|| {
                        self.node_ports.push(Vec::new());
                        self.node_ports.len() - 1
                    });
                    let label = format!("{}.{}", self.names[p.component], p.name);
                    self.node_ports[node].push(label);
                    self.mech_offset[i] = offset;
                    NodeRef::Node(node)
                }
            });
        }
        Ok(())
    }

    /// Every port a component says must be connected (`Ports::must_connect`, a friction
    /// element's flanges) shares its rigid set with another component's port. A Brake whose
    /// shaft nothing else touches has no inertia there, and once it slips nothing determines
    /// its motion: said here, by port, not as a singular system in the middle of a run.
    fn check_connected(&self, sets: &mut Sets) -> ModelResult<()> {
        // per rigid set: the first component with a port in it, and whether there are others
        let mut owners: HashMap<usize, (usize, bool)> = HashMap::default();
        for (i, p) in self.ports.iter().enumerate() {
            if p.kind != PortKind::Mechanical {
                continue;
            }
            let entry = owners.entry(sets.find(i)).or_insert((p.component, false));
            entry.1 |= entry.0 != p.component;
        }
        for (ci, decl) in self.port_decls.iter().enumerate() {
            let alone: Vec<String> = (decl.must_connect.iter())
                .filter(|p| !owners[&sets.find(self.index[&(ci, **p)])].1)
                .map(|p| format!("{}.{p}", self.names[ci]))
                .collect();
            if alone.is_empty() {
                continue;
            }
            let (ports, verb) = match alone.len() {
                1 => (alone[0].clone(), "is"),
                _ => (alone.join(" and "), "are"),
            };
            return Err(ModelError::Component {
                component: self.names[ci].clone(),
                message: format!(
                    "{ports} {verb} not connected: a {} acts on the shafts connected to its \
                     flanges, and alone a flange's shaft has no inertia, so nothing determines \
                     its motion once it slips (MSL refuses it too); connect {} to the shaft it \
                     acts on",
                    self.types[ci],
                    if alone.len() == 1 {
                        "it".to_string()
                    } else {
                        "one of them".to_string()
                    },
                ),
            });
        }
        Ok(())
    }

    /// One slot per signal output; inputs read their source's slot.
    fn signal_slots(&mut self, signal_source: &[Option<usize>]) {
        self.signal_slot = vec![None; self.ports.len()];
        for (i, p) in self.ports.iter().enumerate() {
            if p.kind == PortKind::SignalOut {
                self.signal_slot[i] = Some(self.slots);
                self.slots += 1;
            }
        }
        for (i, src) in signal_source.iter().enumerate() {
            if let Some(src) = src {
                self.signal_slot[i] = self.signal_slot[*src];
            }
        }
    }

    /// Model inputs: unconnected signal inputs with a slot of their own, set by the simulation.
    fn model_inputs(&mut self, spec: &ModelSpec) -> ModelResult<()> {
        for input in &spec.inputs {
            let what = format!("input {}", input.port);
            let i = self.port_of(&input.port, || what.clone())?;
            let err = |message: String| ModelError::Connection {
                connection: what.clone(),
                message,
            };
            if self.ports[i].kind != PortKind::SignalIn {
                return Err(err(format!(
                    "a model input must be a signal input port, not {}",
                    self.ports[i].describe()
                )));
            }
            if self.signal_slot[i].is_some() {
                return Err(err(
                    "the port is connected (or declared an input twice); a model input is left unconnected".into(),
                ));
            }
            self.signal_slot[i] = Some(self.slots);
            self.inputs.push(ModelInput {
                name: input.port.to_string(),
                slot: self.slots,
                start: input.start,
            });
            self.slots += 1;
        }
        Ok(())
    }

    /// One heat node per set of connected heat ports.
    // Not merged with the mechanical nodes above: those also join rigid pairs, fix grounds and
    // resolve supports; heat nodes only number the sets.
    fn heat_nodes(&mut self, sets: &mut Sets) {
        let mut heat_of_root: HashMap<usize, usize> = HashMap::default();
        self.heat_node = vec![None; self.ports.len()];
        for (i, p) in self.ports.iter().enumerate() {
            if p.kind != PortKind::Heat {
                continue;
            }
            let root = sets.find(i);
            let node = *heat_of_root.entry(root).or_insert_with(|| {
                self.heat_ports.push(Vec::new());
                self.heat_ports.len() - 1
            });
            let label = format!("{}.{}", self.names[p.component], p.name);
            self.heat_ports[node].push(label);
            self.heat_node[i] = Some(node);
        }
    }
}
