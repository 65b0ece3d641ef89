//! Assembly: from the model's components and connections to the `System`, in three steps —
//! create the components (parameters validated), resolve the topology (`topology`: ports,
//! nodes, signals, heat), and build: each component contributes through the `Builder`. A
//! compiled model (`compiled`) keeps the first two and repeats only what parameters change.

mod compiled;
mod signals;
mod topology;

use std::sync::Arc;

pub use compiled::{CompiledModel, Recompiled};
pub use topology::Topology;

use crate::components::{self, Component};
use crate::error::{ModelError, ModelResult};
use crate::model::{check_prefixes, split_last, DerivedSpec, Experiment, ModelSpec, PortRef};
use crate::signals::SignalGraph;
use crate::system::flange::FlangeBuilder;
use crate::system::outputs::EnergyVar;
use crate::system::{Builder, Out, System};
use crate::thermal::{Capacity, NodeKind, ThermalNet};

/// Names no component may take: they hold system-wide outputs.
const RESERVED: &[&str] = &["system", "time"];

/// Assembles a model: its components, its topology, then the system they build.
pub fn assemble(spec: &ModelSpec) -> ModelResult<System> {
    let spec = canonical(spec);
    let comps = create_components(&spec)?;
    let topology = Topology::resolve(&spec, &comps)?;
    build(&spec, &topology, &comps)
}

/// The model in a canonical order — components sorted by name, each connection's ends and
/// then the connections sorted — so that the order of a model's lines, or the direction of a
/// `connect`, cannot change its result: node numbering, the order of sums and of the rows of
/// the linear system all follow from it. `written` keeps where each component was written, so
/// the result's variables stay in the order of the model.
pub fn canonical(spec: &ModelSpec) -> ModelSpec {
    canonical_owned(spec.clone())
}

/// `canonical` of a spec the caller gives up (a compile: no copy of every component's
/// parameters).
pub fn canonical_owned(spec: ModelSpec) -> ModelSpec {
    let mut out = spec;
    out.written = out.components.iter().map(|c| c.name.clone()).collect();
    out.components.sort_by(|a, b| a.name.cmp(&b.name));
    for (a, b) in &mut out.connections {
        if (&b.component, &b.port) < (&a.component, &a.port) {
            std::mem::swap(a, b);
        }
    }
    // ordered as the pair of "component.port" texts, compared without writing them out (a
    // stable sort, as the cached-key one of those texts was)
    out.connections
        .sort_by(|(a, b), (c, d)| dotted_cmp(a, c).then_with(|| dotted_cmp(b, d)));
    out.connections.dedup();
    out
}

/// The order of `a.to_string()` and `b.to_string()` ("component.port"), byte by byte as strings
/// compare, without allocating them.
fn dotted_cmp(a: &PortRef, b: &PortRef) -> std::cmp::Ordering {
    fn text(p: &PortRef) -> impl Iterator<Item = u8> + '_ {
        (p.component.bytes())
            .chain(std::iter::once(b'.'))
            .chain(p.port.bytes())
    }
    text(a).cmp(text(b))
}

/// Creates every component from its parameters (each validated), checking the names.
pub fn create_components(spec: &ModelSpec) -> ModelResult<Vec<Arc<dyn Component>>> {
    let mut comps: Vec<Arc<dyn Component>> = Vec::with_capacity(spec.components.len());
    // a set, not a search of the names so far: a ladder of 1000 elements (2 750 components)
    // spent a third of its compile comparing names
    let mut seen =
        rustc_hash::FxHashSet::with_capacity_and_hasher(spec.components.len(), Default::default());
    for c in &spec.components {
        // `system.…` names the system-wide results: no component's path starts there
        if RESERVED.contains(&c.name.split('.').next().unwrap_or_default()) {
            return Err(ModelError::Component {
                component: c.name.clone(),
                message: "this name is reserved for system-wide results".into(),
            });
        }
        if !seen.insert(c.name.as_str()) {
            return Err(ModelError::Component {
                component: c.name.clone(),
                message: "defined twice".into(),
            });
        }
        comps.push(components::create(c, &spec.base_dir)?.into());
    }
    check_prefixes(spec.components.iter().map(|c| c.name.as_str()))?;
    Ok(comps)
}

/// Builds the system of `comps` on a resolved topology: every component contributes through
/// the `Builder`; then time events, the system-wide outputs, the signal order, the heat network
/// and the flange torques are finished.
pub fn build(
    spec: &ModelSpec,
    topo: &Topology,
    comps: &[Arc<dyn Component>],
) -> ModelResult<System> {
    let view = SpecView {
        name: &spec.name,
        experiment: &spec.experiment,
        written: &spec.written,
        variables: &spec.variables,
        parameters: &spec.parameters,
    };
    build_with(&view, topo, comps)
}

/// What a build reads of the model description besides its components.
pub struct SpecView<'a> {
    pub name: &'a str,
    pub experiment: &'a Experiment,
    /// Component names in the order the model was written (empty: as built).
    pub written: &'a [String],
    /// The derived variables, appended to the outputs, and the numbers they may read.
    pub variables: &'a [DerivedSpec],
    pub parameters: &'a [(String, f64)],
}

/// `build` from the name and experiment alone.
pub fn build_with(
    spec: &SpecView,
    topo: &Topology,
    comps: &[Arc<dyn Component>],
) -> ModelResult<System> {
    let mut b = builder(spec, topo);
    let mut outputs_of = Vec::with_capacity(comps.len());
    for (ci, comp) in comps.iter().enumerate() {
        b.comp = ci;
        let first = b.sys.outputs.len();
        comp.build(&mut b)?;
        outputs_of.push(first..b.sys.outputs.len());
    }
    in_written_order(&mut b.sys.outputs, &outputs_of, &topo.names, spec.written);
    b.sys.time_events = time_events(spec, topo, comps)?;
    for (name, var) in [
        ("system.kineticEnergy", EnergyVar::Kinetic),
        ("system.potentialEnergy", EnergyVar::Potential),
        ("system.dissipatedEnergy", EnergyVar::Dissipated),
        ("system.sourceWork", EnergyVar::Work),
    ] {
        b.sys.outputs.push((name.to_string(), Out::Energy(var)));
    }
    crate::system::variables::append(&mut b.sys.outputs, spec.variables, spec.parameters)?;
    signals::stage(&mut b)?;
    derivatives_known(&b.sys)?;
    finish_thermal(&mut b)?;
    b.sys.flange_torques = b.flanges.finish(&topo.cut_roots);
    b.sys.followers = b.sys.gear_followers();
    Ok(b.sys)
}

/// Puts each component's outputs in the order the components were written.
fn in_written_order(
    outputs: &mut Vec<(String, Out)>,
    outputs_of: &[std::ops::Range<usize>],
    names: &[String],
    written: &[String],
) {
    if written.is_empty() {
        return;
    }
    let at: rustc_hash::FxHashMap<&str, usize> = (written.iter().enumerate())
        .map(|(k, w)| (w.as_str(), k))
        .rev()
        .collect();
    let position = |name: &String| at.get(name.as_str()).copied().unwrap_or(usize::MAX);
    let mut order: Vec<usize> = (0..names.len()).collect();
    // each key hashed once, not twice a comparison (a sweep builds a system per variant)
    order.sort_by_cached_key(|&ci| position(&names[ci]));
    let mut taken: Vec<Option<(String, Out)>> =
        std::mem::take(outputs).into_iter().map(Some).collect();
    for ci in order {
        outputs.extend(outputs_of[ci].clone().filter_map(|k| taken[k].take()));
    }
    outputs.extend(taken.into_iter().flatten());
}

/// A builder on the topology with an empty system.
fn builder(spec: &SpecView, topo: &Topology) -> Builder {
    let nodes = topo.node_ports.len();
    let heat_nodes = topo.heat_ports.len();
    Builder {
        comp: 0,
        names: topo.names.clone(),
        index: topo.index.clone(),
        mech_node: topo.mech_node.clone(),
        domain: topo.ports.iter().map(|p| p.domain).collect(),
        offset: topo.mech_offset.clone(),
        signal_slot: topo.signal_slot.clone(),
        heat_node: topo.heat_node.clone(),
        sys: System {
            name: spec.name.to_string(),
            experiment: spec.experiment.clone(),
            nodes,
            mass: vec![0.0; nodes],
            masses: Vec::new(),
            node_ports: topo.node_ports.clone(),
            laws: Vec::new(),
            relation_count: 0,
            constraints: Vec::new(),
            switching: Vec::new(),
            signals: SignalGraph {
                slots: topo.slots,
                ..SignalGraph::default()
            },
            thermal: ThermalNet {
                nodes: heat_nodes,
                node_ports: topo.heat_ports.clone(),
                ..ThermalNet::default()
            },
            init_phi: Vec::new(),
            init_w: Vec::new(),
            outputs: Vec::new(),
            flange_torques: Default::default(),
            time_events: Vec::new(),
            inputs: topo.inputs.clone(),
            followers: Vec::new(),
            derived: Default::default(),
            wear: Vec::new(),
        },
        flanges: FlangeBuilder::default(),
        fixed_temperature: vec![None; heat_nodes],
        capacitors: Vec::new(),
        signal_reads: Vec::new(),
        block_owners: Vec::new(),
        scope: None,
    }
}

/// Every component's time events in the run, merged.
fn time_events(
    spec: &SpecView,
    topo: &Topology,
    comps: &[Arc<dyn Component>],
) -> ModelResult<Vec<f64>> {
    let exp = &spec.experiment;
    let mut events: Vec<f64> = Vec::new();
    for (ci, c) in comps.iter().enumerate() {
        let own = c.time_events(exp.start_time, exp.stop_time);
        if own.len() >= components::MAX_TIME_EVENTS {
            return Err(ModelError::Component {
                component: topo.names[ci].clone(),
                message: format!(
                    "schedules more than {} time events before StopTime (a period far shorter than the run?)",
                    components::MAX_TIME_EVENTS
                ),
            });
        }
        events.extend(own);
    }
    Ok(merge_time_events(events, exp.start_time, exp.stop_time))
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

/// Refuses a source that follows an input exactly (`exact = true`) when the input's time
/// derivative is not known: MSL asks the tool to differentiate it, which a model input or a
/// measured signal does not allow.
fn derivatives_known(sys: &System) -> ModelResult<()> {
    let inputs: Vec<(usize, String)> = (sys.inputs.iter())
        .map(|i| (i.slot, i.name.clone()))
        .collect();
    match sys.signals.underivable(&inputs) {
        None => Ok(()),
        Some((d, why)) => Err(ModelError::Component {
            component: d.owner.clone(),
            message: format!(
                "exact = true follows input '{}' exactly and needs its time derivative, but the \
                 input comes from {why}; set exact = false (the filter, f_crit), or drive it \
                 with Modelica.Blocks sources and math blocks",
                d.port
            ),
        }),
    }
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
                let nominal = merged.init.nominal.min(cap.init.nominal);
                if cap.init.fixed && !merged.init.fixed {
                    merged.init = cap.init;
                }
                merged.init.nominal = nominal;
            }
            None => {
                cap_of_node[cap.node] = Some(net.capacities.len());
                net.capacities.push(cap.clone());
            }
        }
    }
    // a parameter that reads a temperature (a Brake's mu_T) needs a state or a fixed value
    for tap in net.taps.iter().filter(|t| t.param.is_some()) {
        if b.fixed_temperature[tap.node].is_none() && cap_of_node[tap.node].is_none() {
            let (owner, param) = (&tap.owner, tap.param.unwrap_or_default());
            return Err(ModelError::Component {
                component: owner.clone(),
                message: format!(
                    "{owner}.{param} needs {owner}.heatPort connected to a HeatCapacitor or a FixedTemperature; heat port '{}' has neither (a temperature set by conduction alone would depend on the element's own loss, an algebraic loop stiction does not solve)",
                    net.node_ports[tap.node].join(", ")
                ),
            });
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
                        component: split_last(&net.node_ports[node][0]).map_or("", |(c, _)| c).to_string(),
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
    for (k, owner) in &net.radiation {
        let link = &net.links[*k];
        if let Some(node) = [link.a, link.b]
            .into_iter()
            .find(|&n| matches!(net.kind[n], NodeKind::Algebraic(_)))
        {
            return Err(ModelError::Component {
                component: owner.clone(),
                message: format!(
                    "radiation to heat port '{}', whose temperature is neither a HeatCapacitor's nor fixed: its heat balance would be nonlinear in the temperature (T^4), which stiction's thermal network does not solve; connect a HeatCapacitor or a FixedTemperature there",
                    net.node_ports[node].join(", ")
                ),
            });
        }
    }
    for tap in &net.taps {
        if let NodeKind::Algebraic(_) = net.kind[tap.node] {
            return Err(ModelError::Component {
                component: tap.owner.clone(),
                message: format!(
                    "{} depends on the temperature of heat port '{}', which is neither a HeatCapacitor's nor fixed: it would depend on the component's own loss (an algebraic loop stiction does not solve); connect a HeatCapacitor or a FixedTemperature, or set useHeatPort = false",
                    tap.reader,
                    net.node_ports[tap.node].join(", ")
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::dotted_cmp;
    use crate::model::PortRef;

    #[test]
    fn ports_order_as_their_dotted_texts_do() {
        let names = ["J1", "J1x", "J1-", "a.b", "a", "", "J10", "Ä"];
        let ports: Vec<PortRef> = (names.iter())
            .flat_map(|c| {
                ["flange_a", "b.c", "", "y"].map(|p| PortRef {
                    component: c.to_string(),
                    port: p.to_string(),
                })
            })
            .collect();
        for a in &ports {
            for b in &ports {
                assert_eq!(
                    dotted_cmp(a, b),
                    a.to_string().cmp(&b.to_string()),
                    "{a} {b}"
                );
            }
        }
    }
}
