//! Cut torques of flanges (`J1.flange_a.tau`, …) for the results. Most are known from the
//! component's own law; the rest (an Inertia's or a Brake's two flanges, a Fixed flange) follow
//! from the torque balance of each connection set (`Σ tau = 0`) and the component's own sum.
//! The linear system is solved once, as a pseudo-inverse, at assembly. Each unknown appears in
//! at most two equations (its connection set and its component's sum), so the matrix falls apart
//! into small independent blocks (equations sharing an unknown); the pseudo-inverse of the whole
//! is that of each block, which keeps assembly and each result row linear in the model's size.

use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

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
    pub fn finish(mut self, cut_root: &[Option<usize>]) -> FlangeTorques {
        let mech: Vec<usize> = (0..cut_root.len())
            .filter(|&i| cut_root[i].is_some())
            .collect();
        let mut sets: HashMap<usize, Vec<usize>> = HashMap::default();
        for &p in &mech {
            sets.entry(cut_root[p].expect("mechanical"))
                .or_default()
                .push(p);
        }
        // A flange alone in its connection set has torque 0 by definition: exactly 0, not the
        // round-off of a least-squares solution through its component's sum.
        for members in sets.values() {
            if let [p] = members[..] {
                self.known.entry(p).or_insert(Out::Const(0.0));
            }
        }
        let unknown: Vec<usize> = mech
            .iter()
            .copied()
            .filter(|p| !self.known.contains_key(p))
            .collect();
        let col: HashMap<usize, usize> = unknown.iter().enumerate().map(|(k, &p)| (p, k)).collect();
        let mut rows: Vec<Vec<usize>> = Vec::new(); // unknown columns of each equation
        let mut eq_known: Vec<Vec<usize>> = Vec::new();
        let mut eq_total: Vec<Option<Out>> = Vec::new();
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
                eq_known.push(
                    ports
                        .iter()
                        .copied()
                        .filter(|p| !col.contains_key(p))
                        .collect(),
                );
                eq_total.push(Some(total));
            }
        }
        let blocks = blocks(&rows, unknown.len());
        let solved: HashSet<usize> = (blocks.iter())
            .flat_map(|b| b.cols.iter().copied())
            .collect();
        let unsolved = (unknown.iter().enumerate())
            .filter(|(c, _)| !solved.contains(c))
            .map(|(_, &p)| p)
            .collect();
        let mut known: Vec<(usize, Out)> = self.known.into_iter().collect();
        known.sort_by_key(|(p, _)| *p);
        FlangeTorques {
            ports: cut_root.len(),
            known,
            unknown,
            unsolved,
            eq_known,
            eq_total,
            blocks,
        }
    }
}

#[derive(Default)]
pub struct FlangeTorques {
    ports: usize,
    known: Vec<(usize, Out)>,
    unknown: Vec<usize>,
    /// The unknown ports in no block (0); the blocks' sums set the others.
    unsolved: Vec<usize>,
    eq_known: Vec<Vec<usize>>,
    eq_total: Vec<Option<Out>>,
    blocks: Vec<Block>,
}

impl FlangeTorques {
    pub fn ports(&self) -> usize {
        self.ports
    }

    /// The expressions of the known torques, in the order `solve_rows` takes their values.
    pub fn known_outs(&self) -> impl Iterator<Item = &Out> {
        self.known.iter().map(|(_, out)| out)
    }

    /// The known torques with their ports (a port's torque is its expression's value).
    pub fn known_ports(&self) -> impl Iterator<Item = (usize, &Out)> {
        self.known.iter().map(|(p, out)| (*p, out))
    }

    /// The ports whose torques the balance equations give.
    pub fn unknown_ports(&self) -> &[usize] {
        &self.unknown
    }

    /// The expressions of the component sums (an Inertia's `J·a`), in `solve_rows`' order.
    pub fn total_outs(&self) -> impl Iterator<Item = &Out> {
        self.eq_total.iter().flatten()
    }

    /// Fills `tau[port]` for every mechanical port, given a way to evaluate outputs; `rhs` is
    /// scratch space, so a result row allocates nothing.
    pub fn solve(&self, eval: impl Fn(&Out) -> f64, tau: &mut [f64], rhs: &mut Vec<f64>) {
        for (p, out) in &self.known {
            tau[*p] = eval(out);
        }
        rhs.resize(self.eq_total.len(), 0.0);
        for (r, (known, total)) in self.eq_known.iter().zip(&self.eq_total).enumerate() {
            let known: f64 = known.iter().map(|&p| tau[p]).sum();
            rhs[r] = match total {
                Some(out) => eval(out) - known,
                None => -known,
            };
        }
        for &p in &self.unknown {
            tau[p] = 0.0;
        }
        for b in &self.blocks {
            for (&c, pinv) in b.cols.iter().zip(b.pinv.chunks_exact(b.rows.len())) {
                tau[self.unknown[c]] = (b.rows.iter().zip(pinv)).map(|(&r, p)| p * rhs[r]).sum();
            }
        }
    }

    /// `solve` for `n` rows at once, every quantity a plane of `n` values (row after
    /// row): the known torques `known[i·n..]`, the sums `totals[j·n..]`, the torques into
    /// `tau[port·n..]`. Each row's arithmetic is `solve`'s (each sum from the neutral element
    /// `sum` starts with, the terms in the same order); a loop runs over rows in each step.
    pub fn solve_rows(
        &self,
        n: usize,
        known: &[f64],
        totals: &[f64],
        tau: &mut [f64],
        rhs: &mut Vec<f64>,
    ) {
        let zero: f64 = std::iter::empty::<f64>().sum();
        let plane = |i: usize| i * n..(i + 1) * n;
        for (i, (p, _)) in self.known.iter().enumerate() {
            tau[plane(*p)].copy_from_slice(&known[plane(i)]);
        }
        rhs.clear();
        rhs.resize(self.eq_total.len() * n, zero);
        let mut totals = totals.chunks_exact(n.max(1));
        for (r, (ports, t)) in self.eq_known.iter().zip(&self.eq_total).enumerate() {
            let out = &mut rhs[plane(r)];
            for &p in ports {
                out.iter_mut()
                    .zip(&tau[plane(p)])
                    .for_each(|(o, x)| *o += x);
            }
            match t {
                Some(_) => {
                    let total = totals.next().expect("one plane per total");
                    out.iter_mut().zip(total).for_each(|(o, t)| *o = t - *o);
                }
                None => out.iter_mut().for_each(|o| *o = -*o),
            }
        }
        // (the blocks' sums start from their own zero: no plane filled twice)
        for &p in &self.unsolved {
            tau[plane(p)].fill(0.0);
        }
        for b in &self.blocks {
            for (&c, pinv) in b.cols.iter().zip(b.pinv.chunks_exact(b.rows.len())) {
                let out = &mut tau[plane(self.unknown[c])];
                out.fill(zero);
                for (&r, p) in b.rows.iter().zip(pinv) {
                    out.iter_mut()
                        .zip(&rhs[plane(r)])
                        .for_each(|(o, x)| *o += p * x);
                }
            }
        }
    }
}

/// Equations linked through shared unknowns, with the pseudo-inverse of their sub-matrix
/// (row-major: one row of `rows.len()` per unknown, read per result row without indexing
/// through nalgebra).
struct Block {
    rows: Vec<usize>,
    cols: Vec<usize>,
    pinv: Vec<f64>,
}

/// Splits the 0/1 matrix whose row `r` has ones in `rows[r]` into independent blocks.
fn blocks(rows: &[Vec<usize>], ncols: usize) -> Vec<Block> {
    let mut parent: Vec<usize> = (0..rows.len()).collect();
    let mut owner: Vec<Option<usize>> = vec![None; ncols];
    for (r, cols) in rows.iter().enumerate() {
        for &c in cols {
            match owner[c] {
                Some(o) => union(&mut parent, o, r),
                None => owner[c] = Some(r),
            }
        }
    }
    let mut index: HashMap<usize, usize> = HashMap::default();
    let mut out: Vec<Block> = Vec::new();
    for r in 0..rows.len() {
        let root = find(&mut parent, r);
        let b = *index.entry(root).or_insert_with(|| {
            out.push(Block {
                rows: Vec::new(),
                cols: Vec::new(),
                pinv: Vec::new(),
            });
            out.len() - 1
        });
        out[b].rows.push(r);
    }
    for (c, o) in owner.iter().enumerate() {
        if let Some(o) = o {
            let b = index[&find(&mut parent, *o)];
            out[b].cols.push(c);
        }
    }
    out.retain(|b| !b.cols.is_empty());
    out.iter_mut().for_each(|b| b.pinv = block_pinv(rows, b));
    out
}

fn block_pinv(rows: &[Vec<usize>], b: &Block) -> Vec<f64> {
    let col: HashMap<usize, usize> = b.cols.iter().enumerate().map(|(k, &c)| (c, k)).collect();
    let mut a = DMatrix::<f64>::zeros(b.rows.len(), b.cols.len());
    for (j, &r) in b.rows.iter().enumerate() {
        for c in &rows[r] {
            a[(j, col[c])] = 1.0;
        }
    }
    let (m, n) = (b.cols.len(), b.rows.len());
    let pinv = a
        .pseudo_inverse(1e-12)
        .unwrap_or_else(|_| DMatrix::zeros(m, n));
    pinv.transpose().as_slice().to_vec()
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb);
    }
}
