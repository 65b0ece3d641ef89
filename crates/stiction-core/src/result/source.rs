//! An output expression read cheaply at many rows. `value` walks the `Out` tree at every call
//! (a recursive `match`, and a virtual `variable` call for an element's torque); the flange cut
//! torques ask for about one such value per flange per row. The common shapes — an element's
//! continuous variable, a law's torque, an acceleration, a constant, each possibly scaled once —
//! become a direct read (which the table also does from its copied arrays); anything else still
//! goes through `value`. The arithmetic is `value`'s (`s * x`, `rel.dot`), so the values are the
//! same bits.

use super::value;
use crate::engine::eval::{DiscreteState, Workspace};
use crate::rel::Rel;
use crate::switching::element::{value_field, ElementValues};
use crate::system::outputs::EnergyVar;
use crate::system::{Out, System};

/// Where a value is read.
#[derive(Clone)]
pub(super) enum Read {
    /// A continuous variable of switching element `k`, as a field of its values.
    Field(usize, fn(&ElementValues) -> f64),
    LawTau(usize),
    /// `rel.dot(a)` of the node accelerations (an Inertia's `J·a`).
    Accel(Rel),
    Const(f64),
    // the rest only from the workspace (the table does not copy what they read)
    Angle(Rel),
    Speed(Rel),
    ConstraintTau(usize),
    Signal(usize),
    HeatT(usize),
    HeatDiff(usize, usize),
    HeatNodeInflow(usize),
    Energy(usize),
    Other(Out),
}

/// A read and the factor `value` multiplies it by, if any.
#[derive(Clone)]
pub(super) struct Source {
    pub(super) read: Read,
    pub(super) scale: Option<f64>,
}

impl Source {
    pub(super) fn of(out: &Out) -> Self {
        let direct = |out: &Out| match out {
            Out::Switch(k, var) => value_field(*var).map(|f| (Read::Field(*k, f), None)),
            Out::LawTau(k, s) => Some((Read::LawTau(*k), Some(*s))),
            Out::Accel(rel) => Some((Read::Accel(rel.clone()), None)),
            Out::Const(c) => Some((Read::Const(*c), None)),
            Out::Angle(rel) => Some((Read::Angle(rel.clone()), None)),
            Out::Speed(rel) => Some((Read::Speed(rel.clone()), None)),
            Out::ConstraintTau(k, s) => Some((Read::ConstraintTau(*k), Some(*s))),
            Out::Signal(slot) => Some((Read::Signal(*slot), None)),
            Out::HeatT(node) => Some((Read::HeatT(*node), None)),
            Out::HeatDiff(a, b) => Some((Read::HeatDiff(*a, *b), None)),
            Out::HeatNodeInflow(node, s) => Some((Read::HeatNodeInflow(*node), Some(*s))),
            Out::Energy(var) => Some((Read::Energy(energy_index(*var)), None)),
            _ => None,
        };
        let (read, scale) = match out {
            // `s * value(inner)` with an unscaled inner read
            Out::Scaled(inner, s) => match direct(inner) {
                Some((read, None)) => (read, Some(*s)),
                _ => (Read::Other(out.clone()), None),
            },
            _ => direct(out).unwrap_or((Read::Other(out.clone()), None)),
        };
        Self { read, scale }
    }

    /// Whether the table reads it from its copied arrays (`flanges.rs`) rather than from the
    /// workspace of its row.
    pub(super) fn in_block(&self) -> bool {
        matches!(
            self.read,
            Read::Field(..) | Read::LawTau(_) | Read::Accel(_) | Read::Const(_)
        )
    }

    /// Its value at an evaluated instant (`flange_tau` as `value` takes it).
    #[inline]
    pub(super) fn eval(
        &self,
        sys: &System,
        ws: &Workspace,
        disc: &DiscreteState,
        flange_tau: &[f64],
    ) -> f64 {
        let read = match &self.read {
            Read::Field(k, f) => f(&ws.elements[*k]),
            Read::LawTau(k) => ws.law_tau[*k],
            Read::Accel(rel) => rel.dot(&ws.a),
            Read::Const(c) => *c,
            Read::Angle(rel) => rel.angle(&ws.phi),
            Read::Speed(rel) => rel.dot(&ws.w),
            Read::ConstraintTau(k) => ws.constraint_tau[*k],
            Read::Signal(slot) => ws.signals[*slot],
            Read::HeatT(node) => ws.temps[*node],
            Read::HeatDiff(a, b) => ws.temps[*a] - ws.temps[*b],
            Read::HeatNodeInflow(node) => ws.heat_net[*node],
            Read::Energy(i) => ws.energy[*i],
            Read::Other(out) => value(out, sys, ws, disc, flange_tau),
        };
        self.scaled(read)
    }

    /// The read value times the factor, if any.
    #[inline]
    pub(super) fn scaled(&self, read: f64) -> f64 {
        match self.scale {
            Some(s) => s * read,
            None => read,
        }
    }
}

/// Where `value` reads an energy in `Workspace::energy`.
fn energy_index(var: EnergyVar) -> usize {
    match var {
        EnergyVar::Kinetic => 0,
        EnergyVar::Potential => 1,
        EnergyVar::Dissipated => 2,
        EnergyVar::Work => 3,
    }
}
