//! The layout of a table row's frame: one flat array per evaluated row holding every value a
//! column reads, each once. Columns were filled one by one, each with a `match` on its kind, a
//! stride through copied workspace arrays, and a virtual call or a walk through an element's
//! values per cell: more than the row's evaluation itself. Here each row copies the workspace
//! arrays the columns read (a few `memcpy`s), the fields of the elements read, the discrete
//! variables of its state (`table.rs`: computed once per state, written only into a frame that
//! held another state), and
//! computes each distinct derived value once (a scaled value, an angle plus its offset, a
//! relative speed…); every column is then a plain read of one slot (`table.rs`), and aliases
//! (`flange_b.phi` = `J1.phi`, a torque and its negative used by two ports) share their slot.
//! Each derived value is computed with the arithmetic of the row recorder (`s * x + offset`,
//! `Rel::dot`, `value`), so the table is bit for bit the recorder's.

use std::collections::HashMap;

use super::ops::{Array, Op, Program, FIELDS};
use crate::engine::eval::{DiscreteState, Workspace};
use crate::rel::Rel;
use crate::result::output_expr::{value, Flat};
use crate::switching::element::{is_discrete, ElementValues, SwitchVar};
use crate::system::outputs::EnergyVar;
use crate::system::{Out, System};
use crate::thermal::Conductance;

/// Where the flange cut torques live in the frame: the known torques' and component sums'
/// slots (in `FlangeTorques::solve_rows`' order) and the slot of each port it solves for.
#[derive(Clone)]
pub(super) struct FlangePlan {
    pub known: Vec<u32>,
    pub totals: Vec<u32>,
    pub unknown: Vec<(usize, u32)>,
}

/// A derived value, for sharing one slot between equal computations.
#[derive(Clone, PartialEq, Eq, Hash)]
enum Key {
    Scale(u32, u64),
    Affine(u32, u64, u64),
    Diff(u32, u32),
    Mul(u32, u32),
    Dot(Vec<(u32, u64)>, Option<u64>),
    Const(u64),
    /// An expression `value` computes: its kind, index and parameter.
    Eval(u8, usize, u64),
    /// A derived variable (by the address of its formula, which the system keeps).
    Formula(usize),
}

#[derive(Clone)]
pub(super) struct Layout {
    /// Slots per frame.
    pub len: usize,
    pub time: u32,
    /// The slot of each table column after time.
    pub columns: Vec<u32>,
    /// The copied workspace arrays and their first slots.
    copies: Vec<(Array, u32)>,
    /// The elements whose fields are read, with the first of their `FIELDS.len()` slots.
    elements: Vec<(usize, u32)>,
    /// The discrete variables read (element, variable, slot).
    pub discrete: Vec<(usize, SwitchVar, u32)>,
    pub constants: Vec<(u32, f64)>,
    /// Derived values computed while the row's workspace is at hand, and those that read a
    /// flange torque (computed after the block's torques are solved).
    pre: Program,
    pub post: Program,
    /// Both lists of ops while the layout is built, in the order they may run.
    ops: (Vec<Op>, Vec<Op>),
    pub flanges: Option<FlangePlan>,
    ports: Vec<u32>,
    late: Vec<bool>,
    keys: HashMap<Key, u32>,
}

impl Layout {
    /// The frame of the columns `flat` (generals' expressions in `general`) of `sys`.
    pub(super) fn new(sys: &System, flat: &[Flat], general: &[Out]) -> Self {
        let mut l = Layout {
            len: 0,
            time: 0,
            columns: Vec::with_capacity(flat.len()),
            copies: Vec::new(),
            elements: Vec::new(),
            discrete: Vec::new(),
            constants: Vec::new(),
            pre: Program::default(),
            post: Program::default(),
            ops: (Vec::new(), Vec::new()),
            flanges: None,
            ports: Vec::new(),
            late: Vec::new(),
            keys: HashMap::new(),
        };
        l.time = l.fresh(false);
        for f in flat {
            let slot = l.column(sys, f, general);
            l.columns.push(slot);
        }
        let (pre, post) = std::mem::take(&mut l.ops);
        (l.pre, l.post) = (Program::new(pre), Program::new(post));
        l
    }

    fn column(&mut self, sys: &System, f: &Flat, general: &[Out]) -> u32 {
        match *f {
            Flat::Phi(node, s, offset) => {
                let x = self.array(sys, Array::Phi, node);
                self.affine(x, s, offset)
            }
            Flat::W(node, s) => self.scaled_read(sys, Array::W, node, s),
            Flat::A(node, s) => self.scaled_read(sys, Array::A, node, s),
            Flat::Switch(k, var, s) => {
                let x = self.switch(k, var);
                self.scale(x, s)
            }
            Flat::Signal(slot, s) => self.scaled_read(sys, Array::Signals, slot, s),
            Flat::LawTau(k, s) => self.scaled_read(sys, Array::LawTau, k, s),
            Flat::Flange(p, s) => {
                let x = self.port(sys, p);
                self.scale(x, s)
            }
            Flat::General(i, s) => {
                let x = self.out(sys, &general[i]);
                self.scale(x, s)
            }
        }
    }

    /// The slot holding `value(out)` (with the flange torques the table solves).
    fn out(&mut self, sys: &System, out: &Out) -> u32 {
        match out {
            Out::Angle(rel) => self.rel(sys, Array::Phi, rel, Some(rel.offset)),
            Out::Speed(rel) => self.rel(sys, Array::W, rel, None),
            Out::Accel(rel) => self.rel(sys, Array::A, rel, None),
            Out::LawTau(k, s) => self.scaled_read(sys, Array::LawTau, *k, *s),
            Out::Switch(k, var) => self.switch(*k, *var),
            Out::Scaled(inner, s) => {
                let x = self.out(sys, inner);
                self.scale(x, *s)
            }
            Out::Signal(slot) => self.array(sys, Array::Signals, *slot),
            Out::FlangeTau(p) => self.port(sys, *p),
            Out::HeatT(node) => self.array(sys, Array::Temps, *node),
            Out::HeatDiff(a, b) => self.temperature_difference(sys, *a, *b),
            Out::HeatNodeInflow(node, s) => self.scaled_read(sys, Array::HeatNet, *node, *s),
            Out::Energy(var) => self.array(sys, Array::Energy, energy_index(*var)),
            Out::Const(c) => self.constant(*c),
            Out::ConstraintTau(k, s) => self.scaled_read(sys, Array::ConstraintTau, *k, *s),
            // the rare shapes (a law's loss, heat through a conductance…) at the row itself,
            // each once (a law's loss is its own and its heat port's, negated)
            // a law with a heat port had its loss computed by the evaluation already
            Out::LawLoss(k) if sys.laws[*k].heat_node.is_some() => {
                self.array(sys, Array::LawLoss, *k)
            }
            Out::LawLoss(k) => self.eval(Key::Eval(0, *k, 0), out),
            Out::HeatDerT(node) => self.eval(Key::Eval(1, *node, 0), out),
            Out::Wear(k, s, o) => self.eval(Key::Eval(4, *k, s.to_bits() ^ o.to_bits()), out),
            Out::HeatLinkFlow(k, s) => self.link_flow(sys, *k, *s),
            Out::HeatCapacitorFlow(node, c) => self.eval(Key::Eval(3, *node, c.to_bits()), out),
            Out::Time => self.time,
            // its leaves' slots, then the expression over them, as `value` combines them
            Out::Formula(f) => {
                let slots: Box<[u32]> = f.leaves.iter().map(|leaf| self.out(sys, leaf)).collect();
                let key = Key::Formula(std::sync::Arc::as_ptr(f) as usize);
                self.derived(key, Op::formula(f.clone(), slots))
            }
        }
    }

    /// The heat flow through link `k` scaled by `s`, with `value`'s arithmetic:
    /// `(s·G)·(T_a − T_b)`, the product `s·G` made once when the conductance is a constant.
    fn link_flow(&mut self, sys: &System, k: usize, s: f64) -> u32 {
        let link = &sys.thermal.links[k];
        match link.g {
            Conductance::Constant(g) => {
                let diff = self.temperature_difference(sys, link.a, link.b);
                self.scale(diff, s * g)
            }
            // not a conductance times the difference: at the row itself
            Conductance::Radiation(_) => {
                self.eval(Key::Eval(2, k, s.to_bits()), &Out::HeatLinkFlow(k, s))
            }
            Conductance::Signal(slot) => {
                let diff = self.temperature_difference(sys, link.a, link.b);
                let g = self.scaled_read(sys, Array::Signals, slot, s);
                self.derived(
                    Key::Mul(g, diff),
                    Op::Mul {
                        dst: 0,
                        a: g,
                        b: diff,
                    },
                )
            }
        }
    }

    /// `T_a − T_b` of heat nodes `a` and `b`.
    fn temperature_difference(&mut self, sys: &System, a: usize, b: usize) -> u32 {
        let (a, b) = (
            self.array(sys, Array::Temps, a),
            self.array(sys, Array::Temps, b),
        );
        self.derived(Key::Diff(a, b), Op::Diff { dst: 0, a, b })
    }

    /// `value(out)` computed at each row.
    fn eval(&mut self, key: Key, out: &Out) -> u32 {
        let out = out.clone();
        self.derived(key, Op::Eval { dst: 0, out })
    }

    /// `rel.dot(x)` (plus the offset of an angle) over array `arr`, as `Rel` computes it.
    fn rel(&mut self, sys: &System, arr: Array, rel: &Rel, offset: Option<f64>) -> u32 {
        let neutral: f64 = std::iter::empty::<f64>().sum();
        match rel.terms.as_slice() {
            [] => self.constant(offset.map_or(neutral, |o| neutral + o)),
            // `neutral + c·x` is `c·x` when the neutral element is −0 (as `sum` has it)
            &[(node, c)] if neutral.to_bits() == (-0.0f64).to_bits() => {
                let x = self.array(sys, arr, node);
                match offset {
                    Some(o) => self.affine(x, c, o),
                    None => self.scale(x, c),
                }
            }
            terms => {
                match computed_coordinate(sys, arr, rel, offset) {
                    Some(Computed::Law(of_law, k)) => return self.array(sys, of_law, k),
                    Some(Computed::Element(k)) => return self.switch(k, SwitchVar::Phi),
                    None => {}
                }
                let terms: Vec<(u32, f64)> = (terms.iter())
                    .map(|&(node, c)| (self.array(sys, arr, node), c))
                    .collect();
                let key = Key::Dot(
                    terms.iter().map(|&(x, c)| (x, c.to_bits())).collect(),
                    offset.map(f64::to_bits),
                );
                let op = Op::Dot {
                    dst: 0,
                    terms: terms.into(),
                    offset,
                };
                self.derived(key, op)
            }
        }
    }

    fn scaled_read(&mut self, sys: &System, arr: Array, i: usize, s: f64) -> u32 {
        let x = self.array(sys, arr, i);
        self.scale(x, s)
    }

    /// `s · x`; `x` itself for a factor of 1 (`1·x` is `x`, bit for bit, for every value an
    /// evaluation gives: only a signalling NaN, which arithmetic never makes, would differ).
    fn scale(&mut self, x: u32, s: f64) -> u32 {
        if s == 1.0 && s.is_sign_positive() {
            return x;
        }
        self.derived(Key::Scale(x, s.to_bits()), Op::scale(x, s))
    }

    /// `s · x + offset`, the offset added even when 0 (as the row recorder does: −0 + 0 is +0).
    fn affine(&mut self, x: u32, s: f64, offset: f64) -> u32 {
        let key = Key::Affine(x, s.to_bits(), offset.to_bits());
        self.derived(
            key,
            Op::Affine {
                dst: 0,
                x,
                s,
                offset,
            },
        )
    }

    fn constant(&mut self, c: f64) -> u32 {
        if let Some(&slot) = self.keys.get(&Key::Const(c.to_bits())) {
            return slot;
        }
        let slot = self.fresh(false);
        self.constants.push((slot, c));
        self.keys.insert(Key::Const(c.to_bits()), slot);
        slot
    }

    /// The slot of a derived value: an equal one's, or a new one computed by `op`.
    fn derived(&mut self, key: Key, mut op: Op) -> u32 {
        if let Some(&slot) = self.keys.get(&key) {
            return slot;
        }
        let late = op.sources().iter().any(|&x| self.late[x as usize]);
        let dst = self.fresh(late);
        op.set_dst(dst);
        if late {
            &mut self.ops.1
        } else {
            &mut self.ops.0
        }
        .push(op);
        self.keys.insert(key, dst);
        dst
    }

    fn fresh(&mut self, late: bool) -> u32 {
        self.late.push(late);
        self.len += 1;
        u32::try_from(self.len - 1).expect("a frame of fewer than 2³² values")
    }

    fn fresh_range(&mut self, n: usize) -> u32 {
        let first = self.len;
        (0..n).for_each(|_| _ = self.fresh(false));
        u32::try_from(first).expect("a frame of fewer than 2³² values")
    }

    /// Entry `i` of a workspace array, copied whole into the frame the first time it is read.
    fn array(&mut self, sys: &System, arr: Array, i: usize) -> u32 {
        let base = match self.copies.iter().find(|(a, _)| *a == arr) {
            Some(&(_, base)) => base,
            None => {
                let base = self.fresh_range(arr.len(sys));
                self.copies.push((arr, base));
                base
            }
        };
        base + u32::try_from(i).expect("an index below 2³²")
    }

    /// Variable `var` of element `k`: one of its fields, or a discrete variable.
    fn switch(&mut self, k: usize, var: SwitchVar) -> u32 {
        if is_discrete(var) {
            if let Some(&(.., slot)) = (self.discrete.iter()).find(|d| (d.0, d.1) == (k, var)) {
                return slot;
            }
            let slot = self.fresh(false);
            self.discrete.push((k, var, slot));
            return slot;
        }
        let field = FIELDS.iter().position(|&f| f == var);
        let field = field.expect("every continuous variable is a field") as u32;
        let base = match self.elements.iter().find(|(e, _)| *e == k) {
            Some(&(_, base)) => base,
            None => {
                let base = self.fresh_range(FIELDS.len());
                self.elements.push((k, base));
                base
            }
        };
        base + field
    }

    /// The cut torque of port `p`: a known torque's slot, a solved one, or 0 (a port that is
    /// not mechanical, whose torque the recorder leaves at 0).
    fn port(&mut self, sys: &System, p: usize) -> u32 {
        if self.flanges.is_none() {
            self.plan_flanges(sys);
        }
        self.ports[p]
    }

    fn plan_flanges(&mut self, sys: &System) {
        let ft = &sys.flange_torques;
        let zero = self.constant(0.0);
        let mut ports = vec![zero; ft.ports()];
        let mut plan = FlangePlan {
            known: Vec::new(),
            totals: Vec::new(),
            unknown: Vec::new(),
        };
        for (p, out) in ft.known_ports() {
            ports[p] = self.out(sys, out);
            plan.known.push(ports[p]);
        }
        plan.totals = ft.total_outs().map(|out| self.out(sys, out)).collect();
        for &p in ft.unknown_ports() {
            ports[p] = self.fresh(true);
            plan.unknown.push((p, ports[p]));
        }
        self.ports = ports;
        self.flanges = Some(plan);
    }

    /// Writes row `t`'s values that need its workspace into `frame` (the discrete variables
    /// excepted: `discrete` writes them when the state changes).
    #[inline]
    pub(super) fn fill(
        &self,
        frame: &mut [f64],
        (sys, ws, disc): (&System, &Workspace, &DiscreteState),
        t: f64,
    ) {
        frame[self.time as usize] = t;
        for &(arr, base) in &self.copies {
            let src = arr.of(ws);
            frame[base as usize..base as usize + src.len()].copy_from_slice(src);
        }
        for &(k, base) in &self.elements {
            let slots = &mut frame[base as usize..base as usize + FIELDS.len()];
            write_fields(
                &ws.elements[k],
                slots.try_into().expect("one slot per field"),
            );
        }
        (self.pre).run_frame(frame, |out| value(out, sys, ws, disc, &[]));
    }
}

/// A sum of `rel` over `arr` the evaluation made already, with the same terms in the same order
/// (`Rel::angle`, `Rel::dot`): a law's relative angle (with its offset) or speed, which
/// `kinematics` computes, or the relative angle of a switching element along its `motion`, its
/// `phi` field (`forces`). The table reads it instead of summing again.
enum Computed {
    Law(Array, usize),
    Element(usize),
}

fn computed_coordinate(
    sys: &System,
    arr: Array,
    rel: &Rel,
    offset: Option<f64>,
) -> Option<Computed> {
    let bits =
        |r: &Rel| -> Vec<(usize, u64)> { r.terms.iter().map(|&(i, c)| (i, c.to_bits())).collect() };
    let same =
        |r: &Rel| bits(r) == bits(rel) && offset.is_none_or(|o| o.to_bits() == r.offset.to_bits());
    let law =
        |of_law| (sys.laws.iter().position(|law| same(&law.rel))).map(|k| Computed::Law(of_law, k));
    match (arr, offset) {
        (Array::Phi, Some(_)) => law(Array::LawPhi).or_else(|| {
            let element = sys.switching.iter().position(|e| same(e.motion()));
            element.map(Computed::Element)
        }),
        (Array::W, None) => law(Array::LawW),
        _ => None,
    }
}

/// The continuous variables of an element's values, in `FIELDS`' order (what `value_field`
/// reads for each), written in place rather than built and copied (a `memcpy` call each).
fn write_fields(v: &ElementValues, f: &mut [f64; FIELDS.len()]) {
    let l = &v.losses;
    (f[0], f[1], f[2], f[3], f[4]) = (v.phi, v.w, v.a, v.tau, v.sa);
    (f[5], f[6], f[7], f[8], f[9]) = (v.loss, v.tau0, v.tau0_max, v.fn_, v.mu);
    (f[10], f[11], f[12], f[13]) = (v.tau_b, v.tau_support, v.tau_loss, v.tau_eta);
    (f[14], f[15], f[16], f[17], f[18]) = (l.eta1, l.eta2, l.tbf1, l.tbf2, l.tbf_a);
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

#[cfg(test)]
mod tests {
    use super::{write_fields, FIELDS};
    use crate::switching::element::{value_field, ElementValues, Losses};

    /// `write_fields` writes `value_field` of each of `FIELDS`, on values that differ in every field.
    #[test]
    fn fields_are_value_fields() {
        let mut v = ElementValues::default();
        let mut next = 0.5;
        for x in [
            &mut v.phi,
            &mut v.w,
            &mut v.a,
            &mut v.tau,
            &mut v.sa,
            &mut v.loss,
            &mut v.tau0,
            &mut v.tau0_max,
            &mut v.fn_,
            &mut v.mu,
            &mut v.tau_b,
            &mut v.tau_support,
            &mut v.tau_loss,
            &mut v.tau_eta,
        ] {
            *x = next;
            next += 1.0;
        }
        v.losses = Losses {
            eta1: 20.5,
            eta2: 21.5,
            tbf1: 22.5,
            tbf2: 23.5,
            tbf_a: 24.5,
        };
        let mut all = [f64::NAN; FIELDS.len()];
        write_fields(&v, &mut all);
        for (var, x) in FIELDS.iter().zip(all) {
            let field = value_field(*var).expect("a continuous variable");
            assert_eq!(field(&v).to_bits(), x.to_bits(), "{var:?}");
        }
    }
}
