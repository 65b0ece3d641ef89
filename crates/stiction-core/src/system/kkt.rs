//! The per-mode linear solve (design §3): accelerations `a` and constraint torques `λ` from
//! `[M Gᵀ; G 0]·[a; λ] = [f; 0]`, where G holds the permanent constraints and the rows of the
//! friction elements that are locked. The matrix depends on the mode only: factor once per mode.

use nalgebra::{DMatrix, DVector, Dyn, LU};

use super::System;

pub struct ModeMatrix {
    lu: LU<f64, Dyn, Dyn>,
    /// Friction elements whose rows are in G, in row order after the permanent constraints.
    pub locked: Vec<usize>,
    pub size: usize,
}

impl ModeMatrix {
    pub fn factor(sys: &System, locked: &[bool]) -> Result<Self, String> {
        let n = sys.nodes;
        let locked: Vec<usize> = (0..locked.len()).filter(|&k| locked[k]).collect();
        let rows: Vec<&super::Rel> = sys
            .constraints
            .iter()
            .map(|c| &c.rel)
            .chain(locked.iter().map(|&k| &sys.frictions[k].rel))
            .collect();
        let size = n + rows.len();
        let mut m = DMatrix::<f64>::zeros(size, size);
        for i in 0..n {
            m[(i, i)] = sys.mass[i];
        }
        for (r, rel) in rows.iter().enumerate() {
            for &(i, c) in &rel.terms {
                m[(n + r, i)] = c;
                m[(i, n + r)] = c;
            }
        }
        let scale = m.iter().fold(0.0f64, |acc, v| acc.max(v.abs())).max(1e-300);
        let lu = m.lu();
        let u = lu.u();
        let smallest = (0..size)
            .map(|i| u[(i, i)].abs())
            .fold(f64::INFINITY, f64::min);
        if size > 0 && smallest <= 1e-13 * scale {
            return Err(singular_message(sys, &locked));
        }
        Ok(Self { lu, locked, size })
    }

    /// Solves in place: on entry `[f; 0]`, on exit `[a; λ]`.
    pub fn solve(&self, rhs: &mut DVector<f64>) {
        if self.size > 0 {
            self.lu.solve_mut(rhs);
        }
    }
}

fn singular_message(sys: &System, locked: &[usize]) -> String {
    let massless: Vec<String> = (0..sys.nodes)
        .filter(|&i| sys.mass[i] == 0.0)
        .map(|i| format!("[{}]", sys.node_label(i)))
        .collect();
    let locked: Vec<&str> = locked
        .iter()
        .map(|&k| sys.frictions[k].name.as_str())
        .collect();
    let mut msg = String::from("the accelerations are not determined (singular system)");
    if !massless.is_empty() {
        msg += &format!(
            "; shafts without inertia: {} — give each an Inertia or hold it with a constraint",
            massless.join(", ")
        );
    }
    if !locked.is_empty() {
        msg += &format!("; locked friction elements: {}", locked.join(", "));
    }
    msg
}
