//! What a table row's frame (`frame.rs`) is made of: the workspace arrays it copies, the
//! fields of an element's values, and the derived values computed in it.

use std::collections::HashMap;
use std::sync::Arc;

use crate::engine::eval::Workspace;
use crate::switching::element::SwitchVar;
use crate::system::formula::Formula;
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
    /// The laws' relative angles and speeds (`kinematics`) and losses (`Workspace::law_loss`).
    LawPhi,
    LawW,
    LawLoss,
    Temps,
    HeatNet,
    Energy,
    ConstraintTau,
}

impl Array {
    pub(super) fn len(self, sys: &System) -> usize {
        match self {
            Array::Phi | Array::W | Array::A => sys.nodes,
            Array::Signals => sys.signals.slots,
            Array::LawTau | Array::LawPhi | Array::LawW | Array::LawLoss => sys.laws.len(),
            Array::Temps | Array::HeatNet => sys.thermal.nodes,
            Array::Energy => 4,
            Array::ConstraintTau => sys.constraints.len(),
        }
    }

    #[inline]
    pub(super) fn of(self, ws: &Workspace) -> &[f64] {
        match self {
            // One arm per array: alike in shape, each a different field.
            Array::Phi => &ws.phi,
            Array::W => &ws.w,
            Array::A => &ws.a,
            Array::Signals => &ws.signals,
            Array::LawTau => &ws.law_tau,
            Array::LawPhi => &ws.law_phi,
            Array::LawW => &ws.law_w,
            Array::LawLoss => &ws.law_loss,
            Array::Temps => &ws.temps,
            Array::HeatNet => &ws.heat_net,
            Array::Energy => &ws.energy,
            Array::ConstraintTau => &ws.constraint_tau,
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
    /// `x · y` (a conductance times a temperature difference)
    Mul { dst: u32, a: u32, b: u32 },
    /// `Rel::dot` (`Σ c·x` as `sum` adds), plus an angle's offset
    Dot {
        dst: u32,
        terms: Box<[(u32, f64)]>,
        offset: Option<f64>,
    },
    /// `value` of an expression at the row's workspace
    Eval { dst: u32, out: Out },
    /// A derived variable: its formula over the slots of its leaves
    Formula {
        dst: u32,
        formula: Arc<Formula<Out>>,
        slots: Box<[u32]>,
    },
}

impl Op {
    pub(super) fn scale(x: u32, s: f64) -> Self {
        Op::Scale { dst: 0, x, s }
    }

    pub(super) fn formula(formula: Arc<Formula<Out>>, slots: Box<[u32]>) -> Self {
        Op::Formula {
            dst: 0,
            formula,
            slots,
        }
    }

    pub(super) fn set_dst(&mut self, slot: u32) {
        match self {
            Op::Scale { dst, .. }
            | Op::Affine { dst, .. }
            | Op::Diff { dst, .. }
            | Op::Mul { dst, .. }
            | Op::Dot { dst, .. }
            | Op::Eval { dst, .. }
            | Op::Formula { dst, .. } => *dst = slot,
        }
    }

    /// The slots it reads.
    pub(super) fn sources(&self) -> Vec<u32> {
        match self {
            Op::Scale { x, .. } | Op::Affine { x, .. } => vec![*x],
            Op::Diff { a, b, .. } | Op::Mul { a, b, .. } => vec![*a, *b],
            Op::Dot { terms, .. } => terms.iter().map(|&(x, _)| x).collect(),
            Op::Eval { .. } => Vec::new(),
            Op::Formula { slots, .. } => slots.to_vec(),
        }
    }
}

/// Derived values grouped by level (an op reads only slots below its level: copied ones, or
/// those of lower levels) and by kind, so that each kind runs as a loop of its own rather than
/// a `match` per op; the order within a level does not matter, nothing in it reads another.
#[derive(Default, Clone)]
pub(super) struct Program {
    levels: Vec<Level>,
}

/// A `Dot` op: its slot, terms and offset.
type Dot = (u32, Box<[(u32, f64)]>, Option<f64>);

/// A `Formula` op: its slot, the derived variable's formula and its leaves' slots.
type FormulaOp = (u32, Arc<Formula<Out>>, Box<[u32]>);

#[derive(Default, Clone)]
struct Level {
    eval: Vec<(u32, Out)>,
    diff: Vec<(u32, u32, u32)>,
    mul: Vec<(u32, u32, u32)>,
    dot: Vec<Dot>,
    affine: Vec<(u32, u32, f64, f64)>,
    scale: Vec<(u32, u32, f64)>,
    formula: Vec<FormulaOp>,
}

impl Program {
    /// The ops, each after those it reads.
    pub(super) fn new(ops: Vec<Op>) -> Self {
        let mut level_of: HashMap<u32, usize> = HashMap::new();
        let mut levels: Vec<Level> = Vec::new();
        for op in ops {
            let sources = op.sources();
            let below = sources.iter().map(|x| level_of.get(x).map_or(0, |l| l + 1));
            let l = below.max().unwrap_or(0);
            if levels.len() <= l {
                levels.resize_with(l + 1, Level::default);
            }
            let level = &mut levels[l];
            let dst = match op {
                Op::Scale { dst, x, s } => (level.scale.push((dst, x, s)), dst).1,
                Op::Affine { dst, x, s, offset } => (level.affine.push((dst, x, s, offset)), dst).1,
                Op::Diff { dst, a, b } => (level.diff.push((dst, a, b)), dst).1,
                Op::Mul { dst, a, b } => (level.mul.push((dst, a, b)), dst).1,
                Op::Dot { dst, terms, offset } => (level.dot.push((dst, terms, offset)), dst).1,
                Op::Eval { dst, out } => (level.eval.push((dst, out)), dst).1,
                Op::Formula {
                    dst,
                    formula,
                    slots,
                } => (level.formula.push((dst, formula, slots)), dst).1,
            };
            level_of.insert(dst, l);
        }
        Self { levels }
    }

    /// Computes every op's slot of `frame`; `eval` gives `value` of an expression at the row.
    #[inline]
    pub(super) fn run<S: Slots + ?Sized>(&self, frame: &mut S, eval: impl Fn(&Out) -> f64) {
        for l in &self.levels {
            for (dst, out) in &l.eval {
                frame.set(*dst, eval(out));
            }
            for &(dst, a, b) in &l.diff {
                frame.set(dst, frame.get(a) - frame.get(b));
            }
            for &(dst, a, b) in &l.mul {
                frame.set(dst, frame.get(a) * frame.get(b));
            }
            for (dst, terms, offset) in &l.dot {
                let dot: f64 = terms.iter().map(|&(x, c)| c * frame.get(x)).sum();
                frame.set(*dst, offset.map_or(dot, |o| dot + o));
            }
            for &(dst, x, s, offset) in &l.affine {
                frame.set(dst, s * frame.get(x) + offset);
            }
            for &(dst, x, s) in &l.scale {
                frame.set(dst, s * frame.get(x));
            }
            for (dst, formula, slots) in &l.formula {
                let v = formula.eval(|i| frame.get(slots[i]));
                frame.set(*dst, v);
            }
        }
    }

    /// `run` on a frame, through `Page` when the frame is one page.
    #[inline]
    pub(super) fn run_frame(&self, frame: &mut [f64], eval: impl Fn(&Out) -> f64) {
        match frame.len() {
            PAGE => {
                let page = frame.try_into().expect("one page");
                self.run(&mut Page(page), eval);
            }
            _ => self.run(frame, eval),
        }
    }
}

/// Values of a frame page: what a `u8` index reaches.
pub(super) const PAGE: usize = 256;

/// A frame's slots, read and written by index.
pub(super) trait Slots {
    fn get(&self, i: u32) -> f64;
    fn set(&mut self, i: u32, v: f64);
}

impl Slots for [f64] {
    #[inline]
    fn get(&self, i: u32) -> f64 {
        self[i as usize]
    }

    #[inline]
    fn set(&mut self, i: u32, v: f64) {
        self[i as usize] = v;
    }
}

/// A frame of one page (the common case: a few hundred values at most): every slot is below
/// `PAGE`, so it is its own `u8`, which indexes the fixed-size page without a bounds check.
pub(super) struct Page<'a>(&'a mut [f64; PAGE]);

impl Slots for Page<'_> {
    #[inline]
    fn get(&self, i: u32) -> f64 {
        self.0[usize::from(i as u8)]
    }

    #[inline]
    fn set(&mut self, i: u32, v: f64) {
        self.0[usize::from(i as u8)] = v;
    }
}
