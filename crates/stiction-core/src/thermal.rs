//! The thermal network: heat ports joined into nodes; HeatCapacitor, ThermalConductor,
//! Convection and FixedTemperature; friction losses flow in as heat (`Q_flow = −lossPower`).
//! A node holds a capacity (its temperature is a state), a fixed temperature, or neither (its
//! temperature is algebraic: the heat flows into it balance).

use nalgebra::{DMatrix, DVector};

use crate::components::{Component, Constructor, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, Out};

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeKind {
    /// Temperature is continuous state number `usize` among the capacities.
    Capacitive(usize),
    Fixed(f64),
    /// Temperature solved from the heat balance; index among the algebraic nodes.
    Algebraic(usize),
}

#[derive(Debug, Clone, Copy)]
pub enum Conductance {
    Constant(f64),
    /// Read from a signal slot (Convection's `Gc`).
    Signal(usize),
}

#[derive(Debug, Clone)]
pub struct Link {
    pub a: usize,
    pub b: usize,
    pub g: Conductance,
}

impl Link {
    pub fn conductance(&self, signals: &[f64]) -> f64 {
        match self.g {
            Conductance::Constant(g) => g,
            Conductance::Signal(slot) => signals[slot],
        }
    }
}

#[derive(Debug, Clone)]
pub struct Capacity {
    pub node: usize,
    pub c: f64,
    pub init: InitValue,
}

#[derive(Default)]
pub struct ThermalNet {
    pub nodes: usize,
    pub node_ports: Vec<Vec<String>>,
    pub kind: Vec<NodeKind>,
    /// One entry per capacitive node (capacitors on the same node are summed).
    pub capacities: Vec<Capacity>,
    pub links: Vec<Link>,
    pub algebraic: Vec<usize>,
}

impl ThermalNet {
    /// Node temperatures from the capacity states, the fixed values and the heat balance of the
    /// algebraic nodes; `heat_in` is the heat the mechanical losses put into each node.
    pub fn temperatures(
        &self,
        states: &[f64],
        signals: &[f64],
        heat_in: &[f64],
        temps: &mut [f64],
    ) {
        for (node, kind) in self.kind.iter().enumerate() {
            temps[node] = match *kind {
                NodeKind::Capacitive(i) => states[i],
                NodeKind::Fixed(t) => t,
                NodeKind::Algebraic(_) => 0.0,
            };
        }
        if self.algebraic.is_empty() {
            return;
        }
        // Σ_links G·(T_other − T_i) + heat_in_i = 0 for every algebraic node i.
        let n = self.algebraic.len();
        let mut m = DMatrix::<f64>::zeros(n, n);
        let mut rhs = DVector::<f64>::zeros(n);
        for (k, &node) in self.algebraic.iter().enumerate() {
            rhs[k] = heat_in[node];
        }
        for link in &self.links {
            let g = link.conductance(signals);
            for (me, other) in [(link.a, link.b), (link.b, link.a)] {
                if let NodeKind::Algebraic(i) = self.kind[me] {
                    m[(i, i)] += g;
                    match self.kind[other] {
                        NodeKind::Algebraic(j) => m[(i, j)] -= g,
                        _ => rhs[i] += g * temps[other],
                    }
                }
            }
        }
        if let Some(solution) = m.lu().solve(&rhs) {
            for (k, &node) in self.algebraic.iter().enumerate() {
                temps[node] = solution[k];
            }
        } else {
            for &node in &self.algebraic {
                temps[node] = f64::NAN;
            }
        }
    }

    /// Net heat flow into every node: losses plus conduction.
    pub fn net_inflow(&self, temps: &[f64], signals: &[f64], heat_in: &[f64], q: &mut [f64]) {
        q.copy_from_slice(heat_in);
        for link in &self.links {
            let flow = link.conductance(signals) * (temps[link.a] - temps[link.b]);
            q[link.a] -= flow;
            q[link.b] += flow;
        }
    }
}

struct HeatCapacitor {
    c: f64,
    t: InitValue,
}

impl Component for HeatCapacitor {
    fn ports(&self) -> Ports {
        Ports {
            heat: vec!["port"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.heat_node("port")?;
        b.add_heat_capacity(node, self.c, self.t);
        b.output("T", Out::HeatT(node));
        b.output("der_T", Out::HeatDerT(node));
        b.output("port.T", Out::HeatT(node));
        b.output("port.Q_flow", Out::HeatCapacitorFlow(node, self.c));
        Ok(())
    }
}

struct Conductor {
    g: Option<f64>,
    ports: (&'static str, &'static str),
}

impl Component for Conductor {
    fn ports(&self) -> Ports {
        Ports {
            heat: vec![self.ports.0, self.ports.1],
            signal_in: if self.g.is_none() { vec!["Gc"] } else { vec![] },
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (pa, pb) = self.ports;
        let a = b.heat_node(pa)?;
        let c = b.heat_node(pb)?;
        let g = match self.g {
            Some(g) => Conductance::Constant(g),
            None => {
                let slot = b.signal_in("Gc")?;
                b.output("Gc", Out::Signal(slot));
                Conductance::Signal(slot)
            }
        };
        let link = b.add_heat_link(Link { a, b: c, g });
        b.output("Q_flow", Out::HeatLinkFlow(link, 1.0));
        b.output("dT", Out::HeatDiff(a, c));
        b.output(&format!("{pa}.T"), Out::HeatT(a));
        b.output(&format!("{pa}.Q_flow"), Out::HeatLinkFlow(link, 1.0));
        b.output(&format!("{pb}.T"), Out::HeatT(c));
        b.output(&format!("{pb}.Q_flow"), Out::HeatLinkFlow(link, -1.0));
        Ok(())
    }
}

struct FixedTemperature {
    t: f64,
}

impl Component for FixedTemperature {
    fn ports(&self) -> Ports {
        Ports {
            heat: vec!["port"],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.heat_node("port")?;
        b.fix_temperature(node, self.t)?;
        b.output("port.T", Out::HeatT(node));
        // The source absorbs whatever flows into its node (Q_flow is positive into a component).
        b.output("port.Q_flow", Out::HeatNodeInflow(node, 1.0));
        Ok(())
    }
}

fn heat_capacitor(p: &Params) -> ModelResult<Box<dyn Component>> {
    let c = p.positive("C", p.required("C")?)?;
    // MSL HeatCapacitor: T(start = 293.15); the start value is the initial temperature.
    let t = p.init("T", 293.15)?;
    Ok(Box::new(HeatCapacitor { c, t }))
}

fn thermal_conductor(p: &Params) -> ModelResult<Box<dyn Component>> {
    let g = p.at_least("G", p.required("G")?, 0.0)?;
    Ok(Box::new(Conductor {
        g: Some(g),
        ports: ("port_a", "port_b"),
    }))
}

fn convection(_p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Conductor {
        g: None,
        ports: ("solid", "fluid"),
    }))
}

fn fixed_temperature(p: &Params) -> ModelResult<Box<dyn Component>> {
    let t = p.positive("T", p.required("T")?)?;
    Ok(Box::new(FixedTemperature { t }))
}

/// Thermal.HeatTransfer.Celsius.FixedTemperature: `T` in degrees Celsius.
fn fixed_temperature_celsius(p: &Params) -> ModelResult<Box<dyn Component>> {
    let t = p.at_least("T", p.required("T")?, -273.15)? + 273.15;
    Ok(Box::new(FixedTemperature { t }))
}

pub const REGISTRY: &[(&str, Constructor)] = &[
    ("HeatCapacitor", heat_capacitor),
    ("ThermalConductor", thermal_conductor),
    ("Convection", convection),
    ("FixedTemperature", fixed_temperature),
    ("Celsius.FixedTemperature", fixed_temperature_celsius),
];
