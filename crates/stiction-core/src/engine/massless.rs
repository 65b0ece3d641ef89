//! Shafts without inertia whose speed a damper determines (index reduction, as Modelica tools
//! do). In a mode, the directions `N` of node motion that carry no mass and that no row of G
//! holds leave the KKT matrix singular. Along them the torque balance has no `M·a` term: it is
//! the algebraic equation `Nᵀ·f(t, φ, w) = 0`, which the dampers (`f = … − D·w`) make solvable
//! for the speeds along `N` when `NᵀDN` is regular. So along `N` the angles stay states, the
//! speeds are algebraic (solved here at every evaluation), and the accelerations come from the
//! derivative of that equation. The mode's matrix gets the rows `Nᵀ·a = 0` (regular then); their
//! multipliers are `Nᵀ·f = 0` once the speeds are solved, so the other accelerations and all
//! constraint torques are those of the true system.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::system::{Rel, System};

/// Relative size below which an eigenvalue (of `GᵀG` on the massless nodes, or of `NᵀDN`)
/// counts as zero.
const RANK_TOL: f64 = 1e-10;

/// The massless directions of one mode and what solving along them needs.
pub struct Massless {
    /// The columns of `N`, each a row over the nodes (unit vectors when no row touches them).
    pub basis: Vec<Rel>,
    /// `(NᵀDN)⁻¹`.
    inv: DMatrix<f64>,
    /// Rows of `NᵀD` and `NᵀK` (damping and stiffness of the linear laws).
    nt_d: Vec<Rel>,
    nt_k: Vec<Rel>,
}

impl Massless {
    /// The massless directions left free by `rows` (the mode's rows of G). `Ok(None)`: none;
    /// `Err(nodes)`: directions no damper determines, on these nodes.
    pub fn of(sys: &System, rows: &[&Rel]) -> Result<Option<Self>, Vec<usize>> {
        let basis = free_directions(sys, rows);
        if basis.is_empty() {
            return Ok(None);
        }
        let (d, k) = linear_laws(sys);
        let nt_d: Vec<Rel> = basis.iter().map(|v| times(&d, v)).collect();
        let nt_k: Vec<Rel> = basis.iter().map(|v| times(&k, v)).collect();
        let dn = DMatrix::from_fn(basis.len(), basis.len(), |i, j| nt_d[i].dot_rel(&basis[j]));
        let eig = SymmetricEigen::new(dn.clone());
        let scale = eig.eigenvalues.amax();
        let undamped: Vec<usize> = (0..basis.len())
            .filter(|&j| eig.eigenvalues[j] <= RANK_TOL * scale || scale == 0.0)
            .collect();
        if !undamped.is_empty() {
            let mut nodes: Vec<usize> = Vec::new();
            for j in undamped {
                let v = eig.eigenvectors.column(j);
                for (b, &c) in basis.iter().zip(v.iter()) {
                    if c.abs() > RANK_TOL {
                        nodes.extend(b.terms.iter().map(|&(i, _)| i));
                    }
                }
            }
            nodes.sort_unstable();
            nodes.dedup();
            return Err(nodes);
        }
        let inv = dn.try_inverse().ok_or_else(|| support(&basis))?;
        Ok(Some(Self {
            basis,
            inv,
            nt_d,
            nt_k,
        }))
    }

    /// `Nᵀ·f`: the torque balances of the massless directions (zero once the speeds are solved).
    pub fn residual(&self, f: &[f64]) -> DVector<f64> {
        DVector::from_iterator(self.basis.len(), self.basis.iter().map(|v| v.dot(f)))
    }

    /// The step `s` along `N` (`w += N·s`) that zeroes the residual `r` if the forces are
    /// affine in the speeds: `(NᵀDN)⁻¹·r`.
    pub fn affine_step(&self, r: &DVector<f64>) -> DVector<f64> {
        &self.inv * r
    }

    /// The number of massless directions.
    pub fn dim(&self) -> usize {
        self.basis.len()
    }

    /// The accelerations along `N`: the derivative of `Nᵀ·f = 0` gives
    /// `NᵀDN·β = −Nᵀ(K·w + D·a)` for `a += N·β` (`a` solved with `Nᵀa = 0`). Time derivatives of
    /// sources acting along `N` are not included.
    pub fn accelerate(&self, w: &[f64], a: &mut [f64]) {
        let r = DVector::from_iterator(
            self.basis.len(),
            (self.nt_k.iter().zip(&self.nt_d)).map(|(k, d)| -(k.dot(w) + d.dot(a))),
        );
        let beta = &self.inv * r;
        self.add(&beta, a);
    }

    /// `x += N·s`.
    pub fn add(&self, s: &DVector<f64>, x: &mut [f64]) {
        for (v, &sj) in self.basis.iter().zip(s.iter()) {
            for &(i, c) in &v.terms {
                x[i] += c * sj;
            }
        }
    }
}

/// The nodes a set of directions moves.
fn support(basis: &[Rel]) -> Vec<usize> {
    let mut nodes: Vec<usize> = basis
        .iter()
        .flat_map(|v| v.terms.iter().map(|&(i, _)| i))
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// A basis of `{v : v = 0 on massive nodes, G·v = 0}`. Massless nodes no row touches are unit
/// vectors (exact); a row left with one free massless node holds that node (`peel`, so a
/// drivetrain's gears to inertias cost nothing); the null space of the rest of G comes from
/// an eigen-decomposition of its (small) Gram matrix.
fn free_directions(sys: &System, rows: &[&Rel]) -> Vec<Rel> {
    let mut free: Vec<bool> = sys.mass.iter().map(|&m| m == 0.0).collect();
    if !free.contains(&true) {
        return Vec::new();
    }
    let live = peel(rows, &mut free);
    let mut touched = vec![false; sys.nodes];
    live.iter()
        .for_each(|r| r.terms.iter().for_each(|&(i, _)| touched[i] = true));
    let mut basis: Vec<Rel> = Vec::new();
    let mut cols: Vec<usize> = Vec::new();
    for i in (0..sys.nodes).filter(|&i| free[i]) {
        if touched[i] {
            cols.push(i);
        } else {
            basis.push(unit(i));
        }
    }
    basis.extend(null_space(&live, &cols, sys.nodes));
    basis
}

/// Takes the free nodes that a row holds alone off `free` until none is left (a worklist, linear
/// in the rows' terms); returns the rows that still move two or more free nodes.
fn peel<'a>(rows: &[&'a Rel], free: &mut [bool]) -> Vec<&'a Rel> {
    let mut count: Vec<usize> = (rows.iter())
        .map(|r| r.terms.iter().filter(|&&(i, _)| free[i]).count())
        .collect();
    let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); free.len()];
    for (k, r) in rows.iter().enumerate() {
        r.terms
            .iter()
            .filter(|&&(i, _)| free[i])
            .for_each(|&(i, _)| rows_of[i].push(k));
    }
    let mut queue: Vec<usize> = (0..rows.len()).filter(|&k| count[k] == 1).collect();
    while let Some(k) = queue.pop() {
        let Some(&(i, _)) = rows[k].terms.iter().find(|&&(i, _)| free[i]) else {
            continue; // its last free node was taken by another row
        };
        free[i] = false;
        for &k2 in &rows_of[i] {
            count[k2] -= 1;
            if count[k2] == 1 {
                queue.push(k2);
            }
        }
    }
    (rows.iter().zip(&count))
        .filter(|(_, &c)| c >= 2)
        .map(|(r, _)| *r)
        .collect()
}

/// The null space of `rows` restricted to the nodes `cols`, each vector scaled to a largest
/// entry of 1 and cleaned of round-off.
fn null_space(rows: &[&Rel], cols: &[usize], nodes: usize) -> Vec<Rel> {
    if cols.is_empty() {
        return Vec::new();
    }
    let mut col_of = vec![usize::MAX; nodes];
    cols.iter().enumerate().for_each(|(j, &i)| col_of[i] = j);
    let mut g = DMatrix::<f64>::zeros(rows.len(), cols.len());
    for (r, row) in rows.iter().enumerate() {
        for &(i, c) in row.terms.iter().filter(|&&(i, _)| col_of[i] != usize::MAX) {
            g[(r, col_of[i])] += c;
        }
    }
    let eig = SymmetricEigen::new(g.transpose() * &g);
    let scale = eig.eigenvalues.amax().max(1.0);
    let mut out = Vec::new();
    for j in (0..cols.len()).filter(|&j| eig.eigenvalues[j] <= RANK_TOL * scale) {
        let v = eig.eigenvectors.column(j);
        let big = v
            .iter()
            .fold(0.0f64, |m, c| if c.abs() > m.abs() { *c } else { m });
        let terms = (cols.iter().zip(v.iter()))
            .filter(|(_, c)| c.abs() > 1e-13)
            .map(|(&i, &c)| (i, c / big))
            .collect();
        out.push(Rel { terms, offset: 0.0 });
    }
    out
}

fn unit(i: usize) -> Rel {
    Rel {
        terms: vec![(i, 1.0)],
        offset: 0.0,
    }
}

/// The linear laws as `(coefficient, row)`: damping `d·rowᵀrow` and stiffness `c·rowᵀrow`.
type Quadratic<'a> = Vec<(f64, &'a Rel)>;

fn linear_laws(sys: &System) -> (Quadratic<'_>, Quadratic<'_>) {
    let (mut d, mut k) = (Vec::new(), Vec::new());
    for law in &sys.laws {
        if let Some((c, dd)) = law.law.linear() {
            if dd != 0.0 {
                d.push((dd, &law.rel));
            }
            if c != 0.0 {
                k.push((c, &law.rel));
            }
        }
    }
    (d, k)
}

/// `vᵀ·Σ cₗ·rowₗᵀrowₗ` as a row over the nodes (only the laws `v` moves).
fn times(q: &Quadratic, v: &Rel) -> Rel {
    let mut out = Rel::default();
    for &(c, row) in q {
        let s = row.dot_rel(v);
        if s != 0.0 {
            for &(i, ci) in &row.terms {
                match out.terms.iter_mut().find(|(j, _)| *j == i) {
                    Some(t) => t.1 += c * s * ci,
                    None => out.terms.push((i, c * s * ci)),
                }
            }
        }
    }
    out
}
