//! A derived variable's expression (`[variables]`, `slip = "J1.w - J2.w"`) as the runs
//! evaluate it: a tree over numbered leaves — output expressions (`Out`) once `variables`
//! has resolved the names — and `Formula::eval`, the one arithmetic every reader of outputs
//! combines the leaves' values with (the row recorder, the probes, the table engine).

use crate::model::BinOp;

/// An expression over `leaves` (output expressions, `Out`, in a system).
#[derive(Debug)]
pub struct Formula<L> {
    pub(super) root: Node,
    pub leaves: Vec<L>,
}

#[derive(Debug)]
pub(super) enum Node {
    Leaf(usize),
    Const(f64),
    Neg(Box<Node>),
    Not(Box<Node>),
    Bin(BinOp, Box<Node>, Box<Node>),
    If(Box<Node>, Box<Node>, Box<Node>),
    Call(&'static str, Vec<Node>),
}

impl<L> Formula<L> {
    /// The sum of the leaves (a composite's `lossPower`, its parts' added).
    pub fn sum(leaves: Vec<L>) -> Self {
        let root = (1..leaves.len()).fold(Node::Leaf(0), |acc, k| {
            Node::Bin(BinOp::Add, Box::new(acc), Box::new(Node::Leaf(k)))
        });
        Self { root, leaves }
    }

    /// The value at one row, given each leaf's value there.
    #[inline]
    pub fn eval(&self, leaf: impl Fn(usize) -> f64) -> f64 {
        self.root.eval(&leaf)
    }
}

fn truth(x: f64) -> bool {
    x != 0.0
}

fn flag(b: bool) -> f64 {
    f64::from(u8::from(b))
}

/// NumPy's `maximum`/`minimum`: a NaN on either side gives NaN.
fn nan_or(a: f64, b: f64, pick: fn(f64, f64) -> f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        pick(a, b)
    }
}

/// NumPy's `sign`: −1, 0 or 1, NaN for NaN.
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        x
    }
}

const RPM: f64 = 2.0 * std::f64::consts::PI / 60.0;

impl Node {
    fn eval(&self, leaf: &impl Fn(usize) -> f64) -> f64 {
        match self {
            Node::Leaf(i) => leaf(*i),
            Node::Const(c) => *c,
            Node::Neg(x) => -x.eval(leaf),
            Node::Not(x) => flag(!truth(x.eval(leaf))),
            Node::If(c, a, b) => match truth(c.eval(leaf)) {
                true => a.eval(leaf),
                false => b.eval(leaf),
            },
            Node::Bin(op, a, b) => {
                let (a, b) = (a.eval(leaf), b.eval(leaf));
                match op {
                    BinOp::Add => a + b,
                    BinOp::Sub => a - b,
                    BinOp::Mul => a * b,
                    BinOp::Div => a / b,
                    BinOp::Pow => a.powf(b),
                    BinOp::Lt => flag(a < b),
                    BinOp::Le => flag(a <= b),
                    BinOp::Gt => flag(a > b),
                    BinOp::Ge => flag(a >= b),
                    BinOp::Eq => flag(a == b),
                    BinOp::Ne => flag(a != b),
                    BinOp::And => flag(truth(a) && truth(b)),
                    BinOp::Or => flag(truth(a) || truth(b)),
                }
            }
            Node::Call(func, args) => {
                let x = args[0].eval(leaf);
                let y = || args[1].eval(leaf);
                match *func {
                    "sin" => x.sin(),
                    "cos" => x.cos(),
                    "tan" => x.tan(),
                    "asin" => x.asin(),
                    "acos" => x.acos(),
                    "atan" => x.atan(),
                    "atan2" => x.atan2(y()),
                    "sinh" => x.sinh(),
                    "cosh" => x.cosh(),
                    "tanh" => x.tanh(),
                    "exp" => x.exp(),
                    "log" => x.ln(),
                    "log10" => x.log10(),
                    "sqrt" => x.sqrt(),
                    "abs" => x.abs(),
                    "sign" => sign(x),
                    "floor" => x.floor(),
                    "ceil" => x.ceil(),
                    "max" => nan_or(x, y(), f64::max),
                    "min" => nan_or(x, y(), f64::min),
                    "from_rpm" => x * RPM,
                    "to_rpm" => x / RPM,
                    "from_degC" => x + 273.15,
                    "to_degC" => x - 273.15,
                    "from_deg" => x * std::f64::consts::PI / 180.0,
                    "to_deg" => x * 180.0 / std::f64::consts::PI,
                    other => unreachable!("the parser knows no function '{other}'"),
                }
            }
        }
    }
}
