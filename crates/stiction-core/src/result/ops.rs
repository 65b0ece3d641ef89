//! What a table row's frame (`frame.rs`) is made of: the workspace arrays it copies, the
//! fields of an element's values, and the derived values computed in it.

use crate::engine::eval::Workspace;
use crate::switching::element::SwitchVar;
use crate::system::{Out, System};

/// An element's continuous variables, in the order the frame holds its fields.
pub(super) const FIELDS: [SwitchVar; 19] = {
    use SwitchVar as V;
    [
        V::Phi,
        V::W,
        V::A,
        V::Tau,
        V::Sa,
        V::LossPower,
        V::Tau0,
        V::Tau0Max,
        V::Fn,
        V::Mu,
        V::TauB,
        V::TauSupport,
        V::TauLoss,
        V::TauEta,
        V::Eta1,
        V::Eta2,
        V::Tbf1,
        V::Tbf2,
        V::TbfA,
    ]
};

/// A workspace array the frame copies whole.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Array {
    Phi,
    W,
    A,
    Signals,
    LawTau,
    Temps,
    HeatNet,
    Energy,
}

impl Array {
    pub(super) fn len(self, sys: &System) -> usize {
        match self {
            Array::Phi | Array::W | Array::A => sys.nodes,
            Array::Signals => sys.signals.slots,
            Array::LawTau => sys.laws.len(),
            Array::Temps | Array::HeatNet => sys.thermal.nodes,
            Array::Energy => 4,
        }
    }

    #[inline]
    pub(super) fn of(self, ws: &Workspace) -> &[f64] {
        match self {
            Array::Phi => &ws.phi,
            Array::W => &ws.w,
            Array::A => &ws.a,
            Array::Signals => &ws.signals,
            Array::LawTau => &ws.law_tau,
            Array::Temps => &ws.temps,
            Array::HeatNet => &ws.heat_net,
            Array::Energy => &ws.energy,
        }
    }
}

/// A value computed from other slots of the frame into slot `dst`, with the arithmetic of the
/// row recorder's expression it stands for.
#[derive(Debug, Clone)]
pub(super) enum Op {
    /// `s · x`
    Scale { dst: u32, x: u32, s: f64 },
    /// `s · x + offset`
    Affine {
        dst: u32,
        x: u32,
        s: f64,
        offset: f64,
    },
    /// `x − y` (a temperature difference)
    Diff { dst: u32, a: u32, b: u32 },
    /// `Rel::dot` (`Σ c·x` as `sum` adds), plus an angle's offset
    Dot {
        dst: u32,
        terms: Box<[(u32, f64)]>,
        offset: Option<f64>,
    },
    /// `value` of an expression at the row's workspace
    Eval { dst: u32, out: Out },
}

impl Op {
    pub(super) fn scale(x: u32, s: f64) -> Self {
        Op::Scale { dst: 0, x, s }
    }

    pub(super) fn set_dst(&mut self, slot: u32) {
        match self {
            Op::Scale { dst, .. }
            | Op::Affine { dst, .. }
            | Op::Diff { dst, .. }
            | Op::Dot { dst, .. }
            | Op::Eval { dst, .. } => *dst = slot,
        }
    }

    /// The slots it reads.
    pub(super) fn sources(&self) -> Vec<u32> {
        match self {
            Op::Scale { x, .. } | Op::Affine { x, .. } => vec![*x],
            Op::Diff { a, b, .. } => vec![*a, *b],
            Op::Dot { terms, .. } => terms.iter().map(|&(x, _)| x).collect(),
            Op::Eval { .. } => Vec::new(),
        }
    }

    /// Computes its slot of `frame`; `eval` gives `value` of an expression at the row.
    #[inline]
    pub(super) fn apply(&self, frame: &mut [f64], eval: impl Fn(&Out) -> f64) {
        let (dst, v) = match self {
            Op::Scale { dst, x, s } => (dst, s * frame[*x as usize]),
            Op::Affine { dst, x, s, offset } => (dst, s * frame[*x as usize] + offset),
            Op::Diff { dst, a, b } => (dst, frame[*a as usize] - frame[*b as usize]),
            Op::Dot { dst, terms, offset } => {
                let dot: f64 = terms.iter().map(|&(x, c)| c * frame[x as usize]).sum();
                (dst, offset.map_or(dot, |o| dot + o))
            }
            Op::Eval { dst, out } => (dst, eval(out)),
        };
        frame[*dst as usize] = v;
    }
}
