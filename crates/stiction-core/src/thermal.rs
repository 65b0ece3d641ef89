//! The thermal network at run time: heat ports joined into nodes, links between them; friction
//! losses flow in as heat (`Q_flow = −lossPower`). The heat components are in `components`.
//! A node holds a capacity (its temperature is a state), a fixed temperature, or neither (its
//! temperature is algebraic: the heat flows into it balance).

use nalgebra::{DMatrix, DVectorViewMut, Dyn, LU};

use crate::linalg::{BandLu, Factorization, LinearSolver, Triplets, BAND_FROM};

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
    /// BodyRadiation's `Gr` [m2]: the flow is `Gr·σ·(T_a⁴ − T_b⁴)`, not linear in the
    /// temperatures, so the assembly allows it only between nodes whose temperature is a
    /// state or fixed (the flow is then explicit; the linear balance never sees it).
    Radiation(f64),
}

/// Modelica.Constants.sigma, the Stefan-Boltzmann constant [W/(m2.K4)].
pub const SIGMA: f64 = 5.670374419e-8;

#[derive(Debug, Clone)]
pub struct Link {
    pub a: usize,
    pub b: usize,
    pub g: Conductance,
}

impl Link {
    /// The linear conductance (0 for radiation, which joins no algebraic node).
    pub fn conductance(&self, signals: &[f64]) -> f64 {
        match self.g {
            Conductance::Constant(g) => g,
            Conductance::Signal(slot) => signals[slot],
            Conductance::Radiation(_) => 0.0,
        }
    }

    /// The heat flow from `a` to `b` at the node temperatures `temps`.
    #[inline]
    pub fn flow(&self, temps: &[f64], signals: &[f64]) -> f64 {
        let (ta, tb) = (temps[self.a], temps[self.b]);
        match self.g {
            Conductance::Radiation(gr) => gr * SIGMA * (ta.powi(4) - tb.powi(4)),
            _ => self.conductance(signals) * (ta - tb),
        }
    }

    pub fn is_radiation(&self) -> bool {
        matches!(self.g, Conductance::Radiation(_))
    }
}

#[derive(Debug, Clone)]
pub struct Capacity {
    pub node: usize,
    pub c: f64,
    pub init: InitValue,
}

/// What `temperatures` keeps between evaluations: the heat balance factored for the
/// conductances it was last called with (constant ones never change: one factorization per
/// run instead of one per evaluation), and scratch space.
#[derive(Default)]
pub struct HeatCache {
    g: Vec<f64>,
    factors: Option<HeatFactors>,
    rhs: Vec<f64>,
}

enum HeatFactors {
    /// One algebraic node (heat ports joined to a convection, the common case): the pivot of
    /// its 1×1 LU, by which `LU::solve_mut` divides (without a view and its checks per call).
    Scalar(f64),
    Dense(LU<f64, Dyn, Dyn>),
    Band(Box<dyn Factorization>),
    Singular,
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
    /// Heat-port temperatures a force law reads (EddyCurrentTorque's): copied into a signal
    /// slot before the laws are evaluated. Only nodes whose temperature is a state or fixed
    /// qualify (an algebraic one would depend on the law's own loss).
    pub taps: Vec<TemperatureTap>,
    /// The radiation links and their components (checked by the assembly).
    pub radiation: Vec<(usize, String)>,
}

#[derive(Debug, Clone)]
pub struct TemperatureTap {
    pub owner: String,
    /// What reads it, for messages ("its torque", "its wear").
    pub reader: &'static str,
    pub node: usize,
    pub slot: usize,
    /// The parameter that reads it (a Brake's `mu_T`), named when the port is not connected to
    /// a HeatCapacitor or a FixedTemperature; None: the component's torque law.
    pub param: Option<&'static str>,
}

impl ThermalNet {
    /// Writes the tapped temperatures into their signal slots, from the capacities' states.
    #[inline]
    pub fn tap(&self, cap_states: &[f64], signals: &mut [f64]) {
        for tap in &self.taps {
            signals[tap.slot] = match self.kind[tap.node] {
                NodeKind::Capacitive(i) => cap_states[i],
                NodeKind::Fixed(t) => t,
                NodeKind::Algebraic(_) => f64::NAN, // refused by the assembly
            };
        }
    }
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
        cache: &mut HeatCache,
    ) {
        for (temp, kind) in temps.iter_mut().zip(&self.kind) {
            *temp = match *kind {
                NodeKind::Capacitive(i) => states[i],
                NodeKind::Fixed(t) => t,
                NodeKind::Algebraic(_) => 0.0,
            };
        }
        if self.algebraic.is_empty() {
            return;
        }
        // Σ_links G·(T_other − T_i) + heat_in_i = 0 for every algebraic node i.
        // (a plain loop: `Iterator::eq` on the adaptors was a call of its own)
        let same = cache.factors.is_some()
            && cache.g.len() == self.links.len()
            && (self.links.iter().zip(&cache.g)).all(|(l, &g)| l.conductance(signals) == g);
        if !same {
            cache.g.clear();
            cache
                .g
                .extend(self.links.iter().map(|l| l.conductance(signals)));
            cache.factors = Some(self.factor_balance(&cache.g));
        }
        let rhs = &mut cache.rhs;
        rhs.clear();
        rhs.extend(self.algebraic.iter().map(|&node| heat_in[node]));
        for (link, &g) in self.links.iter().zip(&cache.g) {
            for (me, other) in [(link.a, link.b), (link.b, link.a)] {
                if let NodeKind::Algebraic(i) = self.kind[me] {
                    if !matches!(self.kind[other], NodeKind::Algebraic(_)) {
                        rhs[i] += g * temps[other];
                    }
                }
            }
        }
        let solved = match cache.factors.as_ref().expect("factored above") {
            // `solve_mut`'s arithmetic for one unknown: no permutation, no elimination, and
            // the division by the pivot unless it is zero
            &HeatFactors::Scalar(pivot) => {
                rhs[0] /= pivot;
                pivot != 0.0
            }
            HeatFactors::Dense(lu) => {
                // solved in place through a view: no vector allocated per evaluation
                let n = rhs.len();
                lu.solve_mut(&mut DVectorViewMut::from_slice(rhs, n))
            }
            HeatFactors::Band(f) => {
                f.solve_in_place(rhs);
                true
            }
            HeatFactors::Singular => false,
        };
        for (k, &node) in self.algebraic.iter().enumerate() {
            temps[node] = if solved { rhs[k] } else { f64::NAN };
        }
    }

    /// The heat-balance matrix of the algebraic nodes for the conductances `g`, factored.
    fn factor_balance(&self, g: &[f64]) -> HeatFactors {
        let n = self.algebraic.len();
        let mut m = Triplets::new(n);
        for (link, &g) in self.links.iter().zip(g) {
            for (me, other) in [(link.a, link.b), (link.b, link.a)] {
                if let NodeKind::Algebraic(i) = self.kind[me] {
                    m.add(i, i, g);
                    if let NodeKind::Algebraic(j) = self.kind[other] {
                        m.add(i, j, -g);
                    }
                }
            }
        }
        if n >= BAND_FROM {
            return match BandLu.factor(&m) {
                Ok(f) => HeatFactors::Band(f),
                Err(_) => HeatFactors::Singular,
            };
        }
        let mut dense = DMatrix::<f64>::zeros(n, n);
        for &(r, c, v) in &m.entries {
            dense[(r, c)] += v;
        }
        let lu = dense.lu();
        match n {
            1 => HeatFactors::Scalar(lu.u()[(0, 0)]),
            _ => HeatFactors::Dense(lu),
        }
    }

    /// Net heat flow into every node: losses plus conduction.
    pub fn net_inflow(&self, temps: &[f64], signals: &[f64], heat_in: &[f64], q: &mut [f64]) {
        q.copy_from_slice(heat_in);
        for link in &self.links {
            let flow = link.flow(temps, signals);
            q[link.a] -= flow;
            q[link.b] += flow;
        }
    }
}
