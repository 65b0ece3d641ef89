//! Initial values (design §3): the fixed start values of absolute and relative variables are
//! linear equations on the node angles (and, separately, speeds). They must be independent; the
//! freedom they leave is filled with start-value guesses, in model order, as Modelica tools do.

use nalgebra::{DMatrix, DVector};

use crate::engine::eval::Layout;
use crate::error::ModelError;
use crate::system::{InitEq, System};

pub fn initial_state(sys: &System) -> Result<Vec<f64>, ModelError> {
    let n = sys.nodes;
    let lay = Layout::of(sys);
    let mut x = vec![0.0; sys.state_len()];
    let phi = solve(&sys.init_phi, sys, "angle")?;
    let w = solve(&sys.init_w, sys, "speed")?;
    x[..n].copy_from_slice(&phi);
    x[n..2 * n].copy_from_slice(&w);
    for (k, cap) in sys.thermal.capacities.iter().enumerate() {
        x[lay.temps() + k] = cap.init.start;
    }
    Ok(x)
}

/// Gram–Schmidt basis of the accepted rows, to test independence cheaply.
struct Basis(Vec<Vec<f64>>);

impl Basis {
    /// Adds the row if it is independent of the ones accepted so far.
    fn accept(&mut self, row: &[f64]) -> bool {
        let norm0 = row.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm0 == 0.0 {
            return false;
        }
        let mut v = row.to_vec();
        for q in &self.0 {
            let dot: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(vi, qi)| *vi -= dot * qi);
        }
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm <= 1e-9 * norm0 {
            return false;
        }
        v.iter_mut().for_each(|x| *x /= norm);
        self.0.push(v);
        true
    }
}

fn dense_row(eq: &InitEq, n: usize) -> Vec<f64> {
    let mut row = vec![0.0; n];
    for &(i, c) in &eq.rel.terms {
        row[i] += c;
    }
    row
}

fn solve(eqs: &[InitEq], sys: &System, what: &str) -> Result<Vec<f64>, ModelError> {
    let n = sys.nodes;
    if n == 0 {
        return Ok(Vec::new());
    }
    let mut basis = Basis(Vec::new());
    let mut rows: Vec<(Vec<f64>, f64)> = Vec::new();
    let mut fixed_names: Vec<&str> = Vec::new();
    // Constraints first, so a user's start value that a gear already implies is the one named.
    let fixed = eqs.iter().filter(|e| e.value.fixed && e.constraint);
    for eq in fixed.chain(eqs.iter().filter(|e| e.value.fixed && !e.constraint)) {
        let row = dense_row(eq, n);
        fixed_names.push(&eq.variable);
        if !basis.accept(&row) {
            if row.iter().all(|&c| c == 0.0) {
                return Err(ModelError::File(format!(
                    "initial values: '{}' is fixed, but its flanges are held by ground or connected to each other",
                    eq.variable
                )));
            }
            return Err(ModelError::File(format!(
                "initial values over-determined: the fixed start {what} of '{}' follows from the other fixed ones ({}); set fixed = false on one of them",
                eq.variable,
                fixed_names[..fixed_names.len() - 1].join(", ")
            )));
        }
        rows.push((row, eq.value.start - eq.rel.offset));
    }
    for eq in eqs.iter().filter(|e| !e.value.fixed) {
        if rows.len() == n {
            break;
        }
        let row = dense_row(eq, n);
        if basis.accept(&row) {
            rows.push((row, eq.value.start - eq.rel.offset));
        }
    }
    // Shafts no start value reaches (e.g. without an inertia) start at 0.
    for i in 0..n {
        if rows.len() == n {
            break;
        }
        let mut row = vec![0.0; n];
        row[i] = 1.0;
        if basis.accept(&row) {
            rows.push((row, 0.0));
        }
    }
    let a = DMatrix::from_fn(n, n, |r, c| rows[r].0[c]);
    let b = DVector::from_iterator(n, rows.iter().map(|r| r.1));
    a.lu()
        .solve(&b)
        .map(|x| x.iter().copied().collect())
        .ok_or_else(|| {
            ModelError::File(format!(
                "initial values: the start {what}s cannot be solved"
            ))
        })
}
