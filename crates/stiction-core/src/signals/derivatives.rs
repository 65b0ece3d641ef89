//! Exact time derivatives of signals, for the motion sources that follow a signal exactly
//! (MSL's `Sources.Speed`/`Position` with `exact = true`: a Modelica tool differentiates the
//! input symbolically). The blocks are pure functions of time and their inputs, so each block
//! carries its derivatives forward (`Block::jet`): value, first and second derivative.
//! Only the slots a source asks for are written, into slots of their own appended after the
//! ordinary ones, so a model without such a source evaluates no jet at all.

use super::SignalGraph;

/// A signal's value and its first two time derivatives.
pub type Jet = [f64; 3];

/// A requested derivative: slot `of`'s `order`-th time derivative (1 or 2), written into
/// `slot` at every evaluation of the signals.
#[derive(Debug, Clone)]
pub struct Derivative {
    pub of: usize,
    pub order: usize,
    pub slot: usize,
    /// Who asked (a component) and for which of its inputs, for messages.
    pub owner: String,
    pub port: &'static str,
}

impl SignalGraph {
    /// Writes every requested derivative after the values were evaluated. A slot no block
    /// writes (a model input) has no known derivative (NaN; `underivable` refuses it first).
    pub(super) fn eval_derivatives(&self, t: f64, horizon: f64, values: &mut [f64]) {
        let mut jets: Vec<Jet> = values.iter().map(|&v| [v, f64::NAN, f64::NAN]).collect();
        let mut u = [[0.0; 3]; 4];
        for b in &self.blocks {
            for (k, &slot) in b.inputs.iter().enumerate() {
                u[k] = jets[slot];
            }
            let jet = b.block.jet(t, horizon, &u[..b.inputs.len()]);
            let [_, d1, d2] = jet.unwrap_or([0.0, f64::NAN, f64::NAN]);
            // the value stays the one `eval` computed, bit for bit
            jets[b.output] = [values[b.output], d1, d2];
        }
        for d in &self.derivatives {
            values[d.slot] = jets[d.of][d.order];
        }
    }

    /// The first requested derivative that is not known, with why: its slot is a model input
    /// (`inputs`: slot and name) or comes through a block without derivatives. Asked once,
    /// after the blocks are in evaluation order.
    pub fn underivable(&self, inputs: &[(usize, String)]) -> Option<(&Derivative, String)> {
        if self.derivatives.is_empty() {
            return None;
        }
        let mut why: Vec<Option<String>> = (0..self.slots)
            .map(|_| Some("a signal no block computes".to_string()))
            .collect();
        for (slot, name) in inputs {
            why[*slot] = Some(format!(
                "model input '{name}', whose derivative is not known"
            ));
        }
        let zeros = [[0.0; 3]; 4];
        for b in &self.blocks {
            let from_input = b.inputs.iter().find_map(|&s| why[s].clone());
            why[b.output] = match from_input {
                Some(reason) => Some(reason),
                None if b
                    .block
                    .jet(0.0, f64::INFINITY, &zeros[..b.inputs.len()])
                    .is_none() =>
                {
                    Some(format!(
                        "component '{}', whose output has no known derivative",
                        b.owner
                    ))
                }
                None => None,
            };
        }
        (self.derivatives.iter()).find_map(|d| why[d.of].clone().map(|reason| (d, reason)))
    }
}

/// The jet of `k·u`.
pub fn scaled(k: f64, u: Jet) -> Jet {
    u.map(|v| k * v)
}

/// The jet of `u·v` (Leibniz).
pub fn product(u: Jet, v: Jet) -> Jet {
    [
        u[0] * v[0],
        u[1] * v[0] + u[0] * v[1],
        u[2] * v[0] + 2.0 * u[1] * v[1] + u[0] * v[2],
    ]
}

/// The jet of `a·u + b·v`.
pub fn linear(a: f64, u: Jet, b: f64, v: Jet) -> Jet {
    [0, 1, 2].map(|k| a * u[k] + b * v[k])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leibniz_rule_of_a_product() {
        // u = t², v = sin t at t = 0.7
        let t: f64 = 0.7;
        let u = [t * t, 2.0 * t, 2.0];
        let v = [t.sin(), t.cos(), -t.sin()];
        let p = product(u, v);
        let exact_d2 = 2.0 * t.sin() + 4.0 * t * t.cos() - t * t * t.sin();
        assert!((p[1] - (2.0 * t * t.sin() + t * t * t.cos())).abs() < 1e-14);
        assert!((p[2] - exact_d2).abs() < 1e-14);
    }
}
