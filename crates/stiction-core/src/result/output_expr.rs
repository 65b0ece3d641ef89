//! Output expressions compiled for the hot loop (`Flat`: the common cases become direct lookups
//! with a scale factor) and the value of any output expression at an evaluated instant
//! (`value`): what the recorder, the probes and the table's frames all read outputs through.

use crate::engine::eval::{DiscreteState, Workspace};
use crate::switching::element::{is_discrete, ElementValues};
use crate::system::outputs::{EnergyVar, SwitchVar};
use crate::system::{Out, System};

/// An output expression compiled for the hot loop: the common cases (a node's angle, speed or
/// acceleration, a friction quantity, a signal …) become direct lookups with a scale factor.
#[derive(Debug, Clone, Copy)]
pub(super) enum Flat {
    Phi(usize, f64, f64),
    W(usize, f64),
    A(usize, f64),
    Switch(usize, SwitchVar, f64),
    Signal(usize, f64),
    LawTau(usize, f64),
    Flange(usize, f64),
    General(usize, f64),
}

impl Flat {
    /// Read from the state alone: an angle, a speed, a mode or flag.
    pub(super) fn is_direct(&self) -> bool {
        match *self {
            Flat::Phi(..) | Flat::W(..) => true,
            Flat::Switch(_, var, _) => is_discrete(var),
            _ => false,
        }
    }

    /// The state a direct one reads (`direct`): an angle's or a speed's; None for a mode or
    /// flag (read from the discrete state) and for the others (not direct).
    pub(super) fn state_read(&self, sys: &System) -> Option<usize> {
        match *self {
            Flat::Phi(node, ..) => Some(node),
            Flat::W(node, _) => Some(sys.nodes + node),
            _ => None,
        }
    }

    /// `direct` at `rows` rows of states `xs` (`n` a row), appended to `out`: an angle or a
    /// speed read with `direct`'s very arithmetic, one state a row.
    pub(super) fn direct_rows(
        &self,
        sys: &System,
        (xs, n, rows): (&[f64], usize, usize),
        disc: &DiscreteState,
        out: &mut Vec<f64>,
    ) {
        match *self {
            Flat::Phi(node, s, offset) => {
                out.extend((0..rows).map(|i| s * xs[i * n + node] + offset))
            }
            Flat::W(node, s) => {
                let j = sys.nodes + node;
                out.extend((0..rows).map(|i| s * xs[i * n + j]));
            }
            _ => out.extend((0..rows).map(|i| self.direct(sys, &xs[i * n..(i + 1) * n], disc))),
        }
    }

    /// Its value from the state alone (for `is_direct` ones).
    #[inline]
    pub(super) fn direct(&self, sys: &System, x: &[f64], disc: &DiscreteState) -> f64 {
        match *self {
            Flat::Phi(node, s, offset) => s * x[node] + offset,
            Flat::W(node, s) => s * x[sys.nodes + node],
            Flat::Switch(k, var, s) => {
                let none = ElementValues::default();
                s * sys.switching[k].variable(&disc.switching[k], &none, var)
            }
            _ => f64::NAN,
        }
    }
}

pub(super) fn compile(out: &Out, scale: f64, general: &mut Vec<Out>) -> Flat {
    let single = |rel: &crate::system::Rel| match rel.terms.as_slice() {
        [(node, c)] => Some((*node, *c)),
        _ => None,
    };
    match out {
        Out::Scaled(inner, s) => compile(inner, scale * s, general),
        Out::Angle(rel) if single(rel).is_some() => {
            let (node, c) = single(rel).expect("checked");
            Flat::Phi(node, scale * c, scale * rel.offset)
        }
        Out::Speed(rel) if single(rel).is_some() => {
            let (node, c) = single(rel).expect("checked");
            Flat::W(node, scale * c)
        }
        Out::Accel(rel) if single(rel).is_some() => {
            let (node, c) = single(rel).expect("checked");
            Flat::A(node, scale * c)
        }
        Out::Switch(k, var) => Flat::Switch(*k, *var, scale),
        Out::Signal(slot) => Flat::Signal(*slot, scale),
        Out::LawTau(k, s) => Flat::LawTau(*k, scale * s),
        Out::FlangeTau(p) => Flat::Flange(*p, scale),
        other => {
            general.push(other.clone());
            Flat::General(general.len() - 1, scale)
        }
    }
}

pub(super) fn switch_value(
    sys: &System,
    ws: &Workspace,
    disc: &DiscreteState,
    k: usize,
    var: SwitchVar,
) -> f64 {
    sys.switching[k].variable(&disc.switching[k], &ws.elements[k], var)
}

/// The value of one output expression at an evaluated instant.
pub(super) fn value(
    out: &Out,
    sys: &System,
    ws: &Workspace,
    disc: &DiscreteState,
    flange_tau: &[f64],
) -> f64 {
    match out {
        Out::Angle(rel) => rel.angle(&ws.phi),
        Out::Speed(rel) => rel.dot(&ws.w),
        Out::Accel(rel) => rel.dot(&ws.a),
        Out::LawTau(k, s) => s * ws.law_tau[*k],
        Out::LawLoss(k) => sys.laws[*k]
            .law
            .loss_power(&ws.law_ctx(sys, disc, *k), ws.law_tau[*k]),
        Out::ConstraintTau(k, s) => s * ws.constraint_tau[*k],
        Out::Switch(k, var) => switch_value(sys, ws, disc, *k, *var),
        Out::Scaled(inner, s) => s * value(inner, sys, ws, disc, flange_tau),
        Out::Signal(slot) => ws.signals[*slot],
        Out::FlangeTau(p) => flange_tau.get(*p).copied().unwrap_or(f64::NAN),
        Out::HeatT(node) => ws.temps[*node],
        Out::Wear(k, s, offset) => offset + s * ws.wear[*k],
        Out::HeatDerT(node) => sys
            .thermal
            .capacities
            .iter()
            .find(|c| c.node == *node)
            .map_or(0.0, |c| ws.heat_net[*node] / c.c),
        Out::HeatDiff(a, b) => ws.temps[*a] - ws.temps[*b],
        Out::HeatLinkFlow(k, s) => {
            let l = &sys.thermal.links[*k];
            if l.is_radiation() {
                return s * l.flow(&ws.temps, &ws.signals);
            }
            s * l.conductance(&ws.signals) * (ws.temps[l.a] - ws.temps[l.b])
        }
        Out::HeatNodeInflow(node, s) => s * ws.heat_net[*node],
        Out::HeatCapacitorFlow(node, c) => {
            let total: f64 = sys
                .thermal
                .capacities
                .iter()
                .filter(|cap| cap.node == *node)
                .map(|cap| cap.c)
                .sum();
            if total > 0.0 {
                ws.heat_net[*node] * c / total
            } else {
                0.0
            }
        }
        Out::Energy(var) => match var {
            EnergyVar::Kinetic => ws.energy[0],
            EnergyVar::Potential => ws.energy[1],
            EnergyVar::Dissipated => ws.energy[2],
            EnergyVar::Work => ws.energy[3],
        },
        Out::Const(c) => *c,
        Out::Time => ws.t,
        Out::Formula(f) => f.eval(|i| value(&f.leaves[i], sys, ws, disc, flange_tau)),
    }
}
