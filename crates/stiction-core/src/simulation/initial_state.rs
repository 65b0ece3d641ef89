//! Initial values (design §3): the fixed start values of absolute and relative variables are
//! linear equations on the node angles (and, separately, speeds). They must be independent; the
//! freedom they leave is filled with start-value guesses, in model order, as Modelica tools do.

use crate::engine::eval::{DiscreteState, Layout};
use crate::engine::kkt::{shaft_names, undetermined_shafts};
use crate::error::ModelError;
use crate::linalg::{LinearSolver, RowBasis, SizedLu, Triplets};
use crate::result::EventRecord;
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
    Ok(initial_state_and_guesses(sys)?.x)
}

/// The initial state and, for every start-value equation, whether its guess was used.
pub struct InitialState {
    pub x: Vec<f64>,
    /// Per `sys.init_phi` equation: an unfixed start the initialization kept as an equation.
    pub phi_guess_used: Vec<bool>,
    /// The same per `sys.init_w` equation.
    pub w_guess_used: Vec<bool>,
}

/// `initial_state`, and which guesses it used (a guess is used when its row is independent of
/// the fixed rows and the guesses before it, so the start state satisfies it exactly).
pub fn initial_state_and_guesses(sys: &System) -> Result<InitialState, ModelError> {
    let n = sys.nodes;
    let lay = Layout::of(sys);
    let mut x = vec![0.0; sys.state_len()];
    let (init_phi, init_w) = with_signal_starts(sys);
    let (phi, phi_guess_used) = solve(init_phi.as_ref().unwrap_or(&sys.init_phi), sys, "angle")?;
    let (w, w_guess_used) = solve(init_w.as_ref().unwrap_or(&sys.init_w), sys, "speed")?;
    x[..n].copy_from_slice(&phi);
    x[n..2 * n].copy_from_slice(&w);
    for (k, cap) in sys.thermal.capacities.iter().enumerate() {
        x[lay.temps() + k] = cap.init.start;
    }
    for e in &sys.switching {
        e.check_start(e.motion().angle(&phi), e.motion().dot(&w))
            .map_err(|message| ModelError::Component {
                component: e.name().to_string(),
                message,
            })?;
    }
    Ok(InitialState {
        x,
        phi_guess_used,
        w_guess_used,
    })
}

type Solved = (Vec<f64>, Vec<bool>);

/// The start-value equations with the values of signals at the start time put in
/// (`InitEq::signal`: a prescribed motion's `w = w_ref`), or None when none reads a signal.
fn with_signal_starts(sys: &System) -> (Option<Vec<InitEq>>, Option<Vec<InitEq>>) {
    let reads = |eqs: &[InitEq]| eqs.iter().any(|e| e.signal.is_some());
    if !reads(&sys.init_phi) && !reads(&sys.init_w) {
        return (None, None);
    }
    let signals = sys.start_signals();
    let put = |eqs: &[InitEq]| {
        let mut eqs = eqs.to_vec();
        for eq in &mut eqs {
            if let Some(slot) = eq.signal {
                eq.value.start = signals[slot];
            }
        }
        Some(eqs)
    };
    (put(&sys.init_phi), put(&sys.init_w))
}

fn solve(eqs: &[InitEq], sys: &System, what: &str) -> Result<Solved, ModelError> {
    let n = sys.nodes;
    let mut used = vec![false; eqs.len()];
    if n == 0 {
        return Ok((Vec::new(), used));
    }
    let mut basis = RowBasis::new(n);
    // A relation's offset (a grounded flange's angle, a Disc's deltaPhi) is an angle: its
    // speed is 0, so a speed's start equation leaves it out.
    let angles = what != "speed";
    let rhs = |eq: &InitEq| eq.value.start - if angles { eq.rel.offset } else { 0.0 };
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
        rows.push((eq.rel.terms.clone(), rhs(eq)));
    }
    for (k, eq) in eqs.iter().enumerate().filter(|(_, e)| !e.value.fixed) {
        if rows.len() == n {
            break;
        }
        if basis.accept(&eq.rel.terms) {
            rows.push((eq.rel.terms.clone(), rhs(eq)));
            used[k] = true;
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
    Ok((x, used))
}

/// The initialization event log: every element whose mode differs from the one it reports as
/// before the start (every friction element's first mode, from Unknown; the LossyGears that
/// left `pre(mode) = Free` — an ideal one stays there).
pub(super) fn initialization_log(sys: &System, disc: &DiscreteState, t0: f64) -> Vec<EventRecord> {
    (sys.switching.iter().zip(&disc.switching))
        .filter(|(e, st)| st.pre.mode != e.log_start_mode())
        .map(|(e, st)| EventRecord {
            time: t0,
            component: e.name().to_string(),
            old_mode: e.log_start_mode(),
            new_mode: st.pre.mode,
            cause: "initialization".into(),
        })
        .collect()
}
