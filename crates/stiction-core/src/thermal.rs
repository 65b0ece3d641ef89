//! The thermal network at run time: heat ports joined into nodes, links between them; friction
//! losses flow in as heat (`Q_flow = −lossPower`). The heat components are in `components`.
//! A node holds a capacity (its temperature is a state), a fixed temperature, or neither (its
//! temperature is algebraic: the heat flows into it balance).

use nalgebra::{DMatrix, DVector};

use crate::model::InitValue;

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
