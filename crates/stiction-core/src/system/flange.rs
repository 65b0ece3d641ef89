//! Cut torques of flanges (`J1.flange_a.tau`, …) for the results. Most are known from the
//! component's own law; the rest (an Inertia's or a Brake's two flanges, a Fixed flange) follow
//! from the torque balance of each connection set (`Σ tau = 0`) and the component's own sum.
//! The small linear system is solved once, as a pseudo-inverse, at assembly.

use std::collections::HashMap;

use nalgebra::DMatrix;

use super::Out;

#[derive(Default)]
pub struct FlangeBuilder {
    known: HashMap<usize, Out>,
    groups: Vec<(Vec<usize>, Option<Out>)>,
}

impl FlangeBuilder {
    pub fn known(&mut self, port: usize, tau: Out) {
        self.known.insert(port, tau);
    }

    pub fn group(&mut self, ports: Vec<usize>, total: Option<Out>) {
        self.groups.push((ports, total));
    }

    /// `cut_root[port]` is the connection set of each mechanical port (None for other ports).
    pub fn finish(self, cut_root: &[Option<usize>]) -> FlangeTorques {
        let mech: Vec<usize> = (0..cut_root.len())
            .filter(|&i| cut_root[i].is_some())
            .collect();
        let unknown: Vec<usize> = mech
            .iter()
            .copied()
            .filter(|p| !self.known.contains_key(p))
            .collect();
        let col: HashMap<usize, usize> = unknown.iter().enumerate().map(|(k, &p)| (p, k)).collect();
        let mut rows: Vec<Vec<usize>> = Vec::new(); // unknown columns of each equation
        let mut eq_known: Vec<Vec<usize>> = Vec::new();
        let mut eq_total: Vec<Option<Out>> = Vec::new();
        let mut sets: HashMap<usize, Vec<usize>> = HashMap::new();
        for &p in &mech {
            sets.entry(cut_root[p].expect("mechanical"))
                .or_default()
                .push(p);
        }
        let mut roots: Vec<usize> = sets.keys().copied().collect();
        roots.sort();
        for root in roots {
            let members = &sets[&root];
            let cols: Vec<usize> = members.iter().filter_map(|p| col.get(p).copied()).collect();
            if cols.is_empty() {
                continue;
            }
            rows.push(cols);
            eq_known.push(
                members
                    .iter()
                    .copied()
                    .filter(|p| self.known.contains_key(p))
                    .collect(),
            );
            eq_total.push(None);
        }
        for (ports, total) in self.groups {
            if let Some(total) = total {
                rows.push(ports.iter().filter_map(|p| col.get(p).copied()).collect());
                eq_known.push(Vec::new());
                eq_total.push(Some(total));
            }
        }
        let mut a = DMatrix::<f64>::zeros(rows.len(), unknown.len());
        for (r, cols) in rows.iter().enumerate() {
            for &c in cols {
                a[(r, c)] = 1.0;
            }
        }
        let pinv = if unknown.is_empty() || rows.is_empty() {
            DMatrix::zeros(unknown.len(), rows.len())
        } else {
            a.pseudo_inverse(1e-12)
                .unwrap_or_else(|_| DMatrix::zeros(unknown.len(), rows.len()))
        };
        let mut known: Vec<(usize, Out)> = self.known.into_iter().collect();
        known.sort_by_key(|(p, _)| *p);
        FlangeTorques {
            ports: cut_root.len(),
            known,
            unknown,
            eq_known,
            eq_total,
            pinv,
        }
    }
}

#[derive(Default)]
pub struct FlangeTorques {
    ports: usize,
    known: Vec<(usize, Out)>,
    unknown: Vec<usize>,
    eq_known: Vec<Vec<usize>>,
    eq_total: Vec<Option<Out>>,
    pinv: DMatrix<f64>,
}

impl FlangeTorques {
    pub fn ports(&self) -> usize {
        self.ports
    }

    /// Fills `tau[port]` for every mechanical port, given a way to evaluate outputs; `rhs` is
    /// scratch space, so a result row allocates nothing.
    pub fn solve(&self, eval: &dyn Fn(&Out) -> f64, tau: &mut [f64], rhs: &mut Vec<f64>) {
        for (p, out) in &self.known {
            tau[*p] = eval(out);
        }
        rhs.resize(self.eq_total.len(), 0.0);
        for (r, (known, total)) in self.eq_known.iter().zip(&self.eq_total).enumerate() {
            rhs[r] = match total {
                Some(out) => eval(out),
                None => -known.iter().map(|&p| tau[p]).sum::<f64>(),
            };
        }
        for (k, &p) in self.unknown.iter().enumerate() {
            tau[p] = (0..rhs.len()).map(|r| self.pinv[(k, r)] * rhs[r]).sum();
        }
    }
}
