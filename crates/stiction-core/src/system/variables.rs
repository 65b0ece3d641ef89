//! Derived variables as output variables: each `[variables]` expression (`model::Expr`) with
//! its names resolved against the system's outputs — an earlier derived variable, a Modelica
//! constant, a `[parameters]` number, `time`, or any output variable — into a `Formula` whose
//! leaves are output expressions (`Out`). Every reader of outputs (the row recorder, the probes
//! of metrics and sweeps, the table engine, `Simulation::values` and so the FMU) then reads a
//! derived variable as it reads any other: `Out::Formula` evaluates the leaves the way each
//! reader evaluates them and combines them with `Formula::eval`, the same arithmetic for all.
//!
//! `der(x)` is exact, never a finite difference: the derivative of an angle is the speed of
//! the same coordinate (`J.phi` → `J.w`, `c.phi_rel` → `c.w_rel`, a flange's angle → its
//! speed), of a speed its acceleration, of a temperature its rate (`der_T`); a name whose
//! derivative is a recorded variable of the same component (`phi` → `w`, `w` → `a`) reads that.
//! Anything else is refused, naming the variable and the construct.

use std::sync::Arc;

use super::formula::{Formula, Node};
use super::outputs::Out;
use crate::error::{ModelError, ModelResult};
use crate::model::{near, DerivedSpec, Expr, CONSTANTS};

/// A variable's name and its derivative's, by the last part of a name (as Python's derived
/// variables had them).
const DERIVATIVES: &[(&str, &str)] = &[
    ("phi", "w"),
    ("phi_rel", "w_rel"),
    ("w", "a"),
    ("w_rel", "a_rel"),
    ("phi_a", "w_a"),
    ("w_a", "a_a"),
];

/// Resolves `spec` against `outputs` (the system's, derived variables before it among them)
/// and the `[parameters]` numbers.
pub fn resolve(
    spec: &DerivedSpec,
    outputs: &[(String, Out)],
    parameters: &[(String, f64)],
) -> ModelResult<Formula<Out>> {
    let mut f = Formula {
        root: Node::Const(0.0),
        leaves: Vec::new(),
    };
    let mut resolver = Resolver {
        outputs,
        parameters,
        leaves: &mut f.leaves,
    };
    f.root = (resolver.node(&spec.expr)).map_err(|why| {
        ModelError::File(format!(
            "variable '{}' = \"{}\": {why}",
            spec.name, spec.text
        ))
    })?;
    Ok(f)
}

struct Resolver<'a> {
    outputs: &'a [(String, Out)],
    parameters: &'a [(String, f64)],
    leaves: &'a mut Vec<Out>,
}

impl Resolver<'_> {
    fn node(&mut self, e: &Expr) -> Result<Node, String> {
        let boxed = |r: &mut Self, e: &Expr| r.node(e).map(Box::new);
        Ok(match e {
            Expr::Num(v) => Node::Const(*v),
            Expr::Name(name) => self.name(name)?,
            Expr::Der(name) => self.der(name)?,
            Expr::Neg(x) => Node::Neg(boxed(self, x)?),
            Expr::Not(x) => Node::Not(boxed(self, x)?),
            Expr::Bin(op, a, b) => Node::Bin(*op, boxed(self, a)?, boxed(self, b)?),
            Expr::If(c, a, b) => Node::If(boxed(self, c)?, boxed(self, a)?, boxed(self, b)?),
            Expr::Call(f, args) => Node::Call(
                f,
                args.iter()
                    .map(|a| self.node(a))
                    .collect::<Result<_, _>>()?,
            ),
        })
    }

    fn leaf(&mut self, out: Out) -> Node {
        self.leaves.push(out);
        Node::Leaf(self.leaves.len() - 1)
    }

    fn output(&self, name: &str) -> Option<&Out> {
        (self.outputs.iter()).find_map(|(n, out)| (n == name).then_some(out))
    }

    fn name(&mut self, name: &str) -> Result<Node, String> {
        if let Some(out) = self.output(name) {
            return Ok(self.leaf(out.clone()));
        }
        if let Some(&(_, c)) = CONSTANTS.iter().find(|(n, _)| *n == name) {
            return Ok(Node::Const(c));
        }
        if let Some(&(_, c)) = self.parameters.iter().find(|(n, _)| n == name) {
            return Ok(Node::Const(c));
        }
        if name == "time" {
            return Ok(self.leaf(Out::Time));
        }
        let names: Vec<String> = self.outputs.iter().map(|(n, _)| n.clone()).collect();
        Err(match near(name, &names) {
            None => format!("unknown variable '{name}' (no result variable, parameter or earlier derived variable of that name)"),
            Some((prefix, found)) => format!("unknown variable '{name}' (variables of {prefix}: {}…)", found.join(", ")),
        })
    }

    fn der(&mut self, name: &str) -> Result<Node, String> {
        let refuse = |why: &str| format!("der({name}): {why}");
        if name == "time" {
            return Ok(Node::Const(1.0));
        }
        let out = self.output(name).ok_or_else(|| {
            refuse("der(…) takes a result variable (an angle, a speed, a temperature)")
        })?;
        if matches!(out, Out::Formula(_)) {
            return Err(refuse(
                "the derivative of a derived variable is not known (write it over recorded variables)",
            ));
        }
        let (head, last) = name.rsplit_once('.').unwrap_or(("", name));
        let by_name = (DERIVATIVES.iter())
            .find(|(v, _)| *v == last)
            .and_then(|(_, d)| self.output(&format!("{head}.{d}")));
        let rate = match by_name {
            Some(rate) => Some(rate.clone()),
            None => derivative(out),
        };
        let rate = rate.ok_or_else(|| {
            refuse(&format!(
                "no recorded variable is the derivative of '{name}' (der works on angles, speeds and temperatures)"
            ))
        })?;
        Ok(self.leaf(rate))
    }
}

/// The output expression that is the time derivative of `out`, where one is recorded.
fn derivative(out: &Out) -> Option<Out> {
    match out {
        Out::Angle(rel) => Some(Out::Speed(rel.clone())),
        Out::Speed(rel) => Some(Out::Accel(rel.clone())),
        Out::HeatT(node) => Some(Out::HeatDerT(*node)),
        Out::Scaled(inner, s) => derivative(inner).map(|d| Out::Scaled(Box::new(d), *s)),
        Out::Const(_) => Some(Out::Const(0.0)),
        Out::Time => Some(Out::Const(1.0)),
        _ => None,
    }
}

/// The derived variables of `specs` as outputs appended to `outputs`, in their order; a name
/// already taken is refused.
pub fn append(
    outputs: &mut Vec<(String, Out)>,
    specs: &[DerivedSpec],
    parameters: &[(String, f64)],
) -> ModelResult<()> {
    for spec in specs {
        let taken = spec.name == "time"
            || (outputs.iter())
                .any(|(n, _)| n == &spec.name || n.split('.').next() == Some(spec.name.as_str()));
        if taken {
            return Err(ModelError::File(format!(
                "variable '{}': the name is already used (a component or another variable)",
                spec.name
            )));
        }
        let formula = resolve(spec, outputs, parameters)?;
        outputs.push((spec.name.clone(), Out::Formula(Arc::new(formula))));
    }
    Ok(())
}
