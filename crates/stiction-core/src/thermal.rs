//! The thermal network at run time: heat ports joined into nodes, links between them; friction
//! losses flow in as heat (`Q_flow = −lossPower`). The heat components are in `components`.
//! A node holds a capacity (its temperature is a state), a fixed temperature, or neither (its
//! temperature is algebraic: the heat flows into it balance).

use nalgebra::{DMatrix, DVector};

use crate::linalg::{BandLu, LinearSolver, Triplets, BAND_FROM};

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
        let mut m = Triplets::new(n);
        let mut rhs: Vec<f64> = self.algebraic.iter().map(|&node| heat_in[node]).collect();
        for link in &self.links {
            let g = link.conductance(signals);
            for (me, other) in [(link.a, link.b), (link.b, link.a)] {
                if let NodeKind::Algebraic(i) = self.kind[me] {
                    m.add(i, i, g);
                    match self.kind[other] {
                        NodeKind::Algebraic(j) => m.add(i, j, -g),
                        _ => rhs[i] += g * temps[other],
                    }
                }
            }
        }
        let solved = solve_heat_balance(&m, &mut rhs);
        for (k, &node) in self.algebraic.iter().enumerate() {
            temps[node] = if solved { rhs[k] } else { f64::NAN };
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

/// Solves in place: dense LU (nalgebra, no answer only at an exact zero pivot) for a few nodes,
/// the banded LU for many (a network of heat links is as sparse as the drivetrain).
fn solve_heat_balance(m: &Triplets, rhs: &mut [f64]) -> bool {
    let n = m.size;
    if n >= BAND_FROM {
        return match BandLu.factor(m) {
            Ok(f) => {
                f.solve_in_place(rhs);
                true
            }
            Err(_) => false,
        };
    }
    let mut dense = DMatrix::<f64>::zeros(n, n);
    for &(r, c, v) in &m.entries {
        dense[(r, c)] += v;
    }
    match dense.lu().solve(&DVector::from_column_slice(rhs)) {
        Some(x) => {
            rhs.copy_from_slice(x.as_slice());
            true
        }
        None => false,
    }
}
