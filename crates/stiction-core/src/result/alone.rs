//! Variables computed alone, without the row's mode solve: a result asked for one variable
//! that needs only the kinematics of each row (an angle or a speed between shafts, the kinetic
//! energy, time) computes that variable and nothing else, not every variable of every row.
//! The arithmetic is the row recorder's (`recorder.rs`), so the values are the table's bit
//! for bit; anything that reads the solve (an acceleration, a torque, a loss) is not alone.

use super::output_expr::{compile, value, Flat};
use super::SimResult;
use crate::engine::eval::{kinematics, DiscreteState, Workspace};
use crate::system::outputs::EnergyVar;
use crate::system::{Out, System};

/// Whether `out` needs only the kinematics of a row. An angle or a speed only of shafts with
/// inertia: a massless shaft's speed is the solve's (`massless_speeds`), not the state's.
fn kinematic(out: &Out, sys: &System) -> bool {
    let massive = |terms: &[(usize, f64)]| terms.iter().all(|&(n, _)| sys.mass[n] > 0.0);
    match out {
        Out::Energy(EnergyVar::Kinetic) | Out::Time | Out::Const(_) => true,
        Out::Angle(rel) | Out::Speed(rel) => massive(&rel.terms),
        Out::Scaled(inner, _) => kinematic(inner, sys),
        Out::Formula(f) => f.leaves.iter().all(|leaf| kinematic(leaf, sys)),
        _ => false,
    }
}

/// `value` after `kinematics` alone: the kinetic energy summed as `heat_and_energy` sums it.
fn kinematic_value(out: &Out, sys: &System, ws: &Workspace, disc: &DiscreteState) -> f64 {
    match out {
        Out::Energy(EnergyVar::Kinetic) => (sys.mass.iter().zip(&ws.w))
            .map(|(m, w)| 0.5 * m * w * w)
            .sum(),
        Out::Scaled(inner, s) => s * kinematic_value(inner, sys, ws, disc),
        Out::Formula(f) => f.eval(|i| kinematic_value(&f.leaves[i], sys, ws, disc)),
        other => value(other, sys, ws, disc, &[]),
    }
}

impl SimResult {
    /// Whether output `c` (0-based, without time) is computed alone: read from the states, or
    /// from the kinematics of each row, in every system the rows were computed with.
    pub(super) fn alone(&self, c: usize) -> bool {
        let mut general = Vec::new();
        let flat = compile(&self.system.outputs[c].1, 1.0, &mut general);
        flat.is_direct()
            || self.segments().iter().all(|(_, _, sys)| {
                let mut general = Vec::new();
                match compile(&sys.outputs[c].1, 1.0, &mut general) {
                    Flat::General(i, _) => kinematic(&general[i], sys),
                    _ => false,
                }
            })
    }

    /// Output `c` over every row from the kinematics alone (for `alone` ones that are not
    /// direct), scaled as the recorder scales a general output.
    pub(super) fn kinematic_column(&self, c: usize) -> Vec<f64> {
        let tr = &self.trajectory;
        let mut values = Vec::with_capacity(tr.rows());
        for (first, end, sys) in self.segments() {
            let mut general = Vec::new();
            let Flat::General(i, s) = compile(&sys.outputs[c].1, 1.0, &mut general) else {
                // not a kinematic column (`alone` says which are): no value, not a panic
                values.resize(end, f64::NAN);
                continue;
            };
            let mut ws = Workspace::new(sys);
            // without prescribed motions or followers the angles and speeds are the states:
            // no signals, no laws' coordinates (the 1000-ladder's energy 34 -> 5 ms)
            let states_only = !sys.prescribes() && sys.followers.is_empty();
            let n = sys.nodes;
            for r in first..end {
                let disc = &self.discs[tr.disc[r] as usize];
                if states_only {
                    ws.t = tr.t[r];
                    ws.phi.copy_from_slice(&tr.x(r)[..n]);
                    ws.w.copy_from_slice(&tr.x(r)[n..2 * n]);
                } else {
                    kinematics(sys, disc, tr.t[r], tr.x(r), tr.horizon[r], &mut ws);
                }
                values.push(s * kinematic_value(&general[i], sys, &ws, disc));
            }
        }
        values
    }
}
