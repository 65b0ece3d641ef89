//! Initial values (design §3): the fixed start values of absolute and relative variables are
//! linear equations on the node angles (and, separately, speeds). They must be independent; the
//! freedom they leave is filled with start-value guesses, in model order, as Modelica tools do.

use crate::engine::eval::Layout;
use crate::engine::kkt::{shaft_names, undetermined_shafts};
use crate::error::ModelError;
use crate::linalg::{LinearSolver, RowBasis, SizedLu, Triplets};
use crate::system::{InitEq, System};

/// What can be known of a model before a run: its start values solve, and every shaft's motion
/// is determined by something (an inertia, a damper, a constraint) in some mode.
pub fn check_model(sys: &System) -> Result<(), ModelError> {
    initial_state(sys)?;
    match undetermined_shafts(sys) {
        None => Ok(()),
        Some(nodes) => Err(ModelError::File(format!(
            "the motion of shafts without inertia is not determined: {} — give each an Inertia or a Damper, or hold it with a constraint",
            shaft_names(sys, &nodes)
        ))),
    }
}

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
    for e in &sys.switching {
        e.check_start(e.motion().dot(&w))
            .map_err(|message| ModelError::Component {
                component: e.name().to_string(),
                message,
            })?;
    }
    Ok(x)
}

fn solve(eqs: &[InitEq], sys: &System, what: &str) -> Result<Vec<f64>, ModelError> {
    let n = sys.nodes;
    if n == 0 {
        return Ok(Vec::new());
    }
    let mut basis = RowBasis::new(n);
    let mut rows: Vec<(Vec<(usize, f64)>, f64)> = Vec::new();
    let mut fixed_names: Vec<&str> = Vec::new();
    // Constraints first, so a user's start value that a gear already implies is the one named.
    let fixed = eqs.iter().filter(|e| e.value.fixed && e.constraint);
    for eq in fixed.chain(eqs.iter().filter(|e| e.value.fixed && !e.constraint)) {
        fixed_names.push(&eq.variable);
        if !basis.accept(&eq.rel.terms) {
            if eq.rel.terms.iter().all(|&(_, c)| c == 0.0) {
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
        rows.push((eq.rel.terms.clone(), eq.value.start - eq.rel.offset));
    }
    for eq in eqs.iter().filter(|e| !e.value.fixed) {
        if rows.len() == n {
            break;
        }
        if basis.accept(&eq.rel.terms) {
            rows.push((eq.rel.terms.clone(), eq.value.start - eq.rel.offset));
        }
    }
    // Shafts no start value reaches (e.g. without an inertia) start at 0.
    for i in 0..n {
        if rows.len() == n {
            break;
        }
        if basis.accept(&[(i, 1.0)]) {
            rows.push((vec![(i, 1.0)], 0.0));
        }
    }
    let mut a = Triplets::new(n);
    for (r, (row, _)) in rows.iter().enumerate() {
        for &(c, v) in row {
            a.add(r, c, v);
        }
    }
    let mut x: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let factors = SizedLu.factor(&a).map_err(|_| {
        ModelError::File(format!(
            "initial values: the start {what}s cannot be solved"
        ))
    })?;
    factors.solve_in_place(&mut x);
    Ok(x)
}
