//! A relative coordinate of an element on the node angles: `rel = Σ c_i·phi_node_i + offset`.
//! Every element (spring, source, friction, gear) sees the drivetrain through such rows, and
//! applies its torque to the nodes through the same row (force on nodes = −tau·row).

/// Where a port sits: on a free node, or on ground at a fixed angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeRef {
    Node(usize),
    Ground(f64),
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rel {
    pub terms: Vec<(usize, f64)>,
    pub offset: f64,
}

impl Rel {
    /// `coef_1·port_1 + coef_2·port_2 + …`, merging terms on the same node.
    pub fn of(parts: &[(NodeRef, f64)]) -> Self {
        let mut rel = Rel::default();
        for &(node, coef) in parts {
            match node {
                NodeRef::Ground(phi) => rel.offset += coef * phi,
                NodeRef::Node(i) => match rel.terms.iter_mut().find(|(j, _)| *j == i) {
                    Some(term) => term.1 += coef,
                    None => rel.terms.push((i, coef)),
                },
            }
        }
        rel.terms.retain(|&(_, c)| c != 0.0);
        rel
    }

    /// `b − a`: the relative coordinate of a two-flange element.
    pub fn between(a: NodeRef, b: NodeRef) -> Self {
        Self::of(&[(b, 1.0), (a, -1.0)])
    }

    #[inline]
    pub fn dot(&self, v: &[f64]) -> f64 {
        self.terms.iter().map(|&(i, c)| c * v[i]).sum()
    }

    /// `Σ cᵢ·dᵢ` over the nodes both rows move.
    pub fn dot_rel(&self, other: &Rel) -> f64 {
        (self.terms.iter())
            .filter_map(|&(i, c)| {
                let (_, d) = other.terms.iter().find(|(j, _)| *j == i)?;
                Some(c * d)
            })
            .sum()
    }

    #[inline]
    pub fn angle(&self, phi: &[f64]) -> f64 {
        self.dot(phi) + self.offset
    }

    /// Adds the generalized force of a torque `tau` acting along this row: `f −= tau·row`.
    #[inline]
    pub fn apply(&self, tau: f64, f: &mut [f64]) {
        for &(i, c) in &self.terms {
            f[i] -= tau * c;
        }
    }

    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }
}
