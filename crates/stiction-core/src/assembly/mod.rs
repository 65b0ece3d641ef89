//! Assembly: from the model's components and connections to the `System`. Validates every
//! connection, joins flanges into nodes (union–find), resolves signal and heat ports and model
//! inputs, and lets each component contribute through the `Builder`.

use std::collections::HashMap;

use crate::components::{self, Component, PortKind, Ports};
use crate::error::{ModelError, ModelResult};
use crate::model::{ModelSpec, PortRef};
use crate::signals::{BlockElem, SignalGraph};
use crate::system::flange::FlangeBuilder;
use crate::system::outputs::EnergyVar;
use crate::system::{Builder, ModelInput, NodeRef, Out, PortInfo, System};
use crate::thermal::{Capacity, NodeKind, ThermalNet};

/// Names no component may take: they hold system-wide outputs.
const RESERVED: &[&str] = &["system", "time"];

/// Union–find over port indices.
struct Sets(Vec<usize>);

impl Sets {
    fn new(n: usize) -> Self {
        Sets((0..n).collect())
    }
    fn find(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.0[r] != r {
            r = self.0[r];
        }
        let mut j = i;
        while self.0[j] != r {
            let next = self.0[j];
            self.0[j] = r;
            j = next;
        }
        r
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[rb] = ra;
        }
    }
}

pub fn assemble(spec: &ModelSpec) -> ModelResult<System> {
    let mut comps: Vec<Box<dyn Component>> = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for c in &spec.components {
        if RESERVED.contains(&c.name.as_str()) {
            return Err(ModelError::Component {
                component: c.name.clone(),
                message: "this name is reserved for system-wide results".into(),
            });
        }
        if names.contains(&c.name) {
            return Err(ModelError::Component {
                component: c.name.clone(),
                message: "defined twice".into(),
            });
        }
        comps.push(components::create(c, &spec.base_dir)?);
        names.push(c.name.clone());
    }
    let types: Vec<String> = spec
        .components
        .iter()
        .map(|c| c.type_name.clone())
        .collect();
    let port_decls: Vec<Ports> = comps.iter().map(|c| c.ports()).collect();

    let mut ports = Vec::new();
    let mut index = HashMap::new();
    for (ci, decl) in port_decls.iter().enumerate() {
        for name in decl.all() {
            let kind = decl.kind_of(name).expect("declared");
            index.insert((ci, name), ports.len());
            ports.push(PortInfo {
                component: ci,
                name,
                kind,
            });
        }
    }

    // Connections: check each end, then join flanges / heat ports, wire signals.
    let n = ports.len();
    let mut mech_sets = Sets::new(n);
    let mut cut_sets = Sets::new(n); // explicit connections only: the torque balances
    let mut heat_sets = Sets::new(n);
    let mut signal_source: Vec<Option<usize>> = vec![None; n];
    let resolve = |r: &PortRef, conn: &str| -> ModelResult<usize> {
        let ci = names
            .iter()
            .position(|nm| *nm == r.component)
            .ok_or_else(|| ModelError::Connection {
                connection: conn.to_string(),
                message: format!(
                    "unknown component '{}' (components: {})",
                    r.component,
                    names.join(", ")
                ),
            })?;
        let decl = &port_decls[ci];
        match decl.all().iter().find(|p| **p == r.port) {
            Some(p) => Ok(index[&(ci, *p)]),
            None => {
                let hint = match r.port.as_str() {
                    "support" => " (set useSupport = true to enable it)",
                    "heatPort" => " (set useHeatPort = true to enable it)",
                    _ => "",
                };
                Err(ModelError::Connection {
                    connection: conn.to_string(),
                    message: format!(
                        "component '{}' ({}) has no port '{}'{hint}; its ports: {}",
                        r.component,
                        types[ci],
                        r.port,
                        decl.all().join(", ")
                    ),
                })
            }
        }
    };
    for (a, b) in &spec.connections {
        let conn = format!("{a} — {b}");
        let (ia, ib) = (resolve(a, &conn)?, resolve(b, &conn)?);
        let (ka, kb) = (ports[ia].kind, ports[ib].kind);
        let err = |message: String| {
            Err(ModelError::Connection {
                connection: conn.clone(),
                message,
            })
        };
        match (ka, kb) {
            (PortKind::Mechanical, PortKind::Mechanical) => {
                mech_sets.union(ia, ib);
                cut_sets.union(ia, ib);
            }
            (PortKind::Heat, PortKind::Heat) => heat_sets.union(ia, ib),
            (PortKind::SignalOut, PortKind::SignalIn)
            | (PortKind::SignalIn, PortKind::SignalOut) => {
                let (out, inp) = if ka == PortKind::SignalOut {
                    (ia, ib)
                } else {
                    (ib, ia)
                };
                if signal_source[inp] == Some(out) {
                    continue; // the same connection twice
                }
                if signal_source[inp].is_some() {
                    return err(format!(
                        "signal input '{}.{}' is already connected to another output",
                        names[ports[inp].component], ports[inp].name
                    ));
                }
                signal_source[inp] = Some(out);
            }
            (PortKind::SignalIn, PortKind::SignalIn) => {
                return err("connects two signal inputs; one end must be an output (y)".into())
            }
            (PortKind::SignalOut, PortKind::SignalOut) => {
                return err("connects two signal outputs".into())
            }
            _ => {
                return err(format!(
                    "cannot connect {} ('{a}') to {} ('{b}')",
                    ka.describe(),
                    kb.describe()
                ))
            }
        }
    }
    for (ci, decl) in port_decls.iter().enumerate() {
        for (x, y) in &decl.joins {
            mech_sets.union(index[&(ci, *x)], index[&(ci, *y)]);
        }
    }

    // Nodes: one per rigid set of flanges, unless the set is held by a Fixed.
    let mut ground_of: HashMap<usize, (f64, String)> = HashMap::new();
    for (ci, decl) in port_decls.iter().enumerate() {
        for (p, phi0) in &decl.ground {
            let root = mech_sets.find(index[&(ci, *p)]);
            if let Some((other, by)) = ground_of.get(&root) {
                if other != phi0 {
                    return Err(ModelError::Parameter {
                        component: names[ci].clone(),
                        type_name: types[ci].clone(),
                        parameter: "phi0".into(),
                        message: format!("the flange is rigidly connected to '{by}', fixed at a different angle {other}"),
                    });
                }
            }
            ground_of.insert(root, (*phi0, names[ci].clone()));
        }
    }
    let mut node_of_root: HashMap<usize, usize> = HashMap::new();
    let mut node_ports: Vec<Vec<String>> = Vec::new();
    let mut mech_node = vec![None; n];
    for (i, p) in ports.iter().enumerate() {
        if p.kind != PortKind::Mechanical {
            continue;
        }
        let root = mech_sets.find(i);
        let label = format!("{}.{}", names[p.component], p.name);
        mech_node[i] = Some(match ground_of.get(&root) {
            Some((phi0, _)) => NodeRef::Ground(*phi0),
            None => {
                let node = *node_of_root.entry(root).or_insert_with(|| {
                    node_ports.push(Vec::new());
                    node_ports.len() - 1
                });
                node_ports[node].push(label);
                NodeRef::Node(node)
            }
        });
    }

    // Signal slots: one per output; inputs read their source's slot.
    let mut signal_slot = vec![None; n];
    let mut slots = 0;
    for (i, p) in ports.iter().enumerate() {
        if p.kind == PortKind::SignalOut {
            signal_slot[i] = Some(slots);
            slots += 1;
        }
    }
    for i in 0..n {
        if let Some(src) = signal_source[i] {
            signal_slot[i] = signal_slot[src];
        }
    }
    // Model inputs: unconnected signal inputs with a slot of their own, set by the simulation.
    let mut inputs: Vec<ModelInput> = Vec::new();
    for input in &spec.inputs {
        let what = format!("input {}", input.port);
        let i = resolve(&input.port, &what)?;
        let err = |message: String| ModelError::Connection {
            connection: what.clone(),
            message,
        };
        if ports[i].kind != PortKind::SignalIn {
            return Err(err(format!(
                "a model input must be a signal input port, not {}",
                ports[i].kind.describe()
            )));
        }
        if signal_slot[i].is_some() {
            return Err(err(
                "the port is connected (or declared an input twice); a model input is left unconnected".into(),
            ));
        }
        signal_slot[i] = Some(slots);
        inputs.push(ModelInput {
            name: input.port.to_string(),
            slot: slots,
            start: input.start,
        });
        slots += 1;
    }

    // Heat nodes.
    let mut heat_of_root: HashMap<usize, usize> = HashMap::new();
    let mut heat_node = vec![None; n];
    let mut heat_ports: Vec<Vec<String>> = Vec::new();
    for (i, p) in ports.iter().enumerate() {
        if p.kind != PortKind::Heat {
            continue;
        }
        let root = heat_sets.find(i);
        let node = *heat_of_root.entry(root).or_insert_with(|| {
            heat_ports.push(Vec::new());
            heat_ports.len() - 1
        });
        heat_ports[node].push(format!("{}.{}", names[p.component], p.name));
        heat_node[i] = Some(node);
    }

    let nodes = node_ports.len();
    let heat_nodes = heat_ports.len();
    let mut b = Builder {
        comp: 0,
        names: names.clone(),
        ports,
        index,
        mech_node,
        signal_slot,
        heat_node,
        sys: System {
            name: spec.name.clone(),
            experiment: spec.experiment.clone(),
            nodes,
            mass: vec![0.0; nodes],
            node_ports,
            laws: Vec::new(),
            relation_count: 0,
            constraints: Vec::new(),
            frictions: Vec::new(),
            lossy_gears: Vec::new(),
            signals: SignalGraph {
                slots,
                blocks: Vec::new(),
            },
            thermal: ThermalNet {
                nodes: heat_nodes,
                node_ports: heat_ports,
                ..ThermalNet::default()
            },
            init_phi: Vec::new(),
            init_w: Vec::new(),
            outputs: Vec::new(),
            flange_torques: Default::default(),
            time_events: Vec::new(),
            inputs,
        },
        flanges: FlangeBuilder::default(),
        fixed_temperature: vec![None; heat_nodes],
        capacitors: Vec::new(),
    };
    for (ci, comp) in comps.iter().enumerate() {
        b.comp = ci;
        comp.build(&mut b)?;
    }
    let exp = &spec.experiment;
    let mut events: Vec<f64> = Vec::new();
    for (ci, c) in comps.iter().enumerate() {
        let own = c.time_events(exp.start_time, exp.stop_time);
        if own.len() >= components::MAX_TIME_EVENTS {
            return Err(ModelError::Component {
                component: names[ci].clone(),
                message: format!(
                    "schedules more than {} time events before StopTime (a period far shorter than the run?)",
                    components::MAX_TIME_EVENTS
                ),
            });
        }
        events.extend(own);
    }
    b.sys.time_events = merge_time_events(events, exp.start_time, exp.stop_time);

    for (name, var) in [
        ("system.kineticEnergy", EnergyVar::Kinetic),
        ("system.potentialEnergy", EnergyVar::Potential),
        ("system.dissipatedEnergy", EnergyVar::Dissipated),
        ("system.sourceWork", EnergyVar::Work),
    ] {
        b.sys.outputs.push((name.to_string(), Out::Energy(var)));
    }
    order_signals(&mut b.sys.signals)?;
    finish_thermal(&mut b)?;
    let cut_roots: Vec<Option<usize>> = (0..n)
        .map(|i| (b.ports[i].kind == PortKind::Mechanical).then(|| cut_sets.find(i)))
        .collect();
    b.sys.flange_torques = b.flanges.finish(&cut_roots);
    Ok(b.sys)
}

/// Sorted time events strictly inside (start, stop). Events closer than the integrator can
/// separate (a Ramp's end computed as 0.1 + 0.2 next to a Step at 0.3) are one event, at the
/// latest of them, so every switch of the cluster has happened once it is handled.
fn merge_time_events(mut events: Vec<f64>, start: f64, stop: f64) -> Vec<f64> {
    let close = crate::signals::same_instant;
    events
        .retain(|&t| t.is_finite() && t > start && t < stop && !close(t, start) && !close(t, stop));
    events.sort_by(f64::total_cmp);
    let mut merged: Vec<f64> = Vec::with_capacity(events.len());
    for t in events {
        match merged.last_mut() {
            Some(last) if close(*last, t) => *last = t,
            _ => merged.push(t),
        }
    }
    merged
}

/// Orders blocks so that every block comes after the blocks it reads; a loop is an error.
fn order_signals(graph: &mut SignalGraph) -> ModelResult<()> {
    let mut pending: Vec<BlockElem> = std::mem::take(&mut graph.blocks);
    // A slot no block writes (a model input) is ready from the start.
    let mut ready = vec![true; graph.slots];
    for block in &pending {
        ready[block.output] = false;
    }
    let mut ordered = Vec::with_capacity(pending.len());
    while !pending.is_empty() {
        let before = pending.len();
        let mut k = 0;
        while k < pending.len() {
            if pending[k].inputs.iter().all(|&s| ready[s]) {
                let block = pending.remove(k);
                ready[block.output] = true;
                ordered.push(block);
            } else {
                k += 1;
            }
        }
        if pending.len() == before {
            return Err(ModelError::Component {
                component: pending[0].owner.clone(),
                message: "its inputs form an algebraic loop of signal blocks".into(),
            });
        }
    }
    graph.blocks = ordered;
    Ok(())
}

/// Decides what holds each heat node's temperature.
fn finish_thermal(b: &mut Builder) -> ModelResult<()> {
    let net = &mut b.sys.thermal;
    let mut cap_of_node: Vec<Option<usize>> = vec![None; net.nodes];
    for cap in &b.capacitors {
        match cap_of_node[cap.node] {
            Some(k) => {
                let merged: &mut Capacity = &mut net.capacities[k];
                merged.c += cap.c;
                if cap.init.fixed && !merged.init.fixed {
                    merged.init = cap.init;
                }
            }
            None => {
                cap_of_node[cap.node] = Some(net.capacities.len());
                net.capacities.push(cap.clone());
            }
        }
    }
    let mut linked = vec![false; net.nodes];
    for l in &net.links {
        linked[l.a] = true;
        linked[l.b] = true;
    }
    for node in 0..net.nodes {
        let kind = match (b.fixed_temperature[node], cap_of_node[node]) {
            (Some(t), _) => NodeKind::Fixed(t),
            (None, Some(k)) => NodeKind::Capacitive(k),
            (None, None) => {
                if !linked[node] {
                    return Err(ModelError::Component {
                        component: net.node_ports[node][0].split('.').next().unwrap_or("").to_string(),
                        message: format!(
                            "heat port '{}' has nowhere to send its heat: connect it to a HeatCapacitor, a conductor or a FixedTemperature (or set useHeatPort = false)",
                            net.node_ports[node].join(", ")
                        ),
                    });
                }
                net.algebraic.push(node);
                NodeKind::Algebraic(net.algebraic.len() - 1)
            }
        };
        net.kind.push(kind);
    }
    // A fixed temperature wins over capacitors on the same node: drop those capacities.
    net.capacities
        .retain(|c| b.fixed_temperature[c.node].is_none());
    for (k, cap) in net.capacities.iter().enumerate() {
        net.kind[cap.node] = NodeKind::Capacitive(k);
    }
    Ok(())
}
