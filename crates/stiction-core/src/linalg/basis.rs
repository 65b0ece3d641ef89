//! `RowBasis`, the one rank test. Rows of a drivetrain are nearly all of two kinds: `φi − φj`
//! (a lock or a connection between two shafts, any scale) and `φi` (a lock to the housing). For
//! those, a row depends on the kept ones exactly when it closes a cycle in the graph of shafts
//! (the housing one more vertex), which union–find answers in near-constant time. The first
//! row of another kind (a gear ratio) switches to the general test, an incremental QR, with the
//! rows kept so far replayed in order — so the answers are those of the QR throughout.

use super::RANK_TOLERANCE;

/// The kept rows' terms one after another, and where each row ends (one allocation for all:
/// a mode change offers every lock).
#[derive(Default)]
struct Rows {
    terms: Vec<(usize, f64)>,
    ends: Vec<usize>,
}

impl Rows {
    fn push(&mut self, terms: &[(usize, f64)]) {
        self.terms.extend_from_slice(terms);
        self.ends.push(self.terms.len());
    }

    #[cfg(test)]
    fn len(&self) -> usize {
        self.ends.len()
    }

    fn iter(&self) -> impl Iterator<Item = &[(usize, f64)]> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts.zip(&self.ends).map(|(a, &b)| &self.terms[a..b])
    }
}

/// Rows offered in priority order are kept when independent of those kept before.
pub struct RowBasis {
    dim: usize,
    /// While every kept row is a graph edge: the forest of kept edges and the rows, in order.
    graph: Option<(Forest, Rows)>,
    dense: Dense,
}

impl RowBasis {
    pub fn new(dim: usize) -> Self {
        Self {
            dim,
            graph: Some((Forest::new(dim + 1), Rows::default())),
            dense: Dense::new(dim),
        }
    }

    /// Whether the row (sparse terms) is a nonzero combination of the kept rows.
    pub fn depends(&mut self, terms: &[(usize, f64)]) -> bool {
        match (self.edge(terms), &mut self.graph) {
            (Edge::Zero, _) => false,
            (Edge::Between(a, b), Some((forest, _))) => forest.find(a) == forest.find(b),
            _ => {
                self.switch_to_general();
                self.dense.depends(terms)
            }
        }
    }

    /// Keeps the row if it is independent of the rows kept so far; a zero row is never kept.
    pub fn accept(&mut self, terms: &[(usize, f64)]) -> bool {
        match (self.edge(terms), &mut self.graph) {
            (Edge::Zero, _) => false,
            (Edge::Between(a, b), Some((forest, rows))) => {
                let joined = forest.union(a, b);
                if joined {
                    rows.push(terms);
                }
                joined
            }
            _ => {
                self.switch_to_general();
                self.dense.accept(terms)
            }
        }
    }

    #[cfg(test)]
    pub fn rank(&self) -> usize {
        match &self.graph {
            Some((_, rows)) => rows.len(),
            None => self.dense.rank(),
        }
    }

    fn switch_to_general(&mut self) {
        if let Some((_, rows)) = self.graph.take() {
            for row in rows.iter() {
                self.dense.accept(row);
            }
        }
    }

    /// The row as an edge of the shaft graph (vertex `dim` is the housing), if it is one. The
    /// terms are merged by node in a small array (no allocation per row: a mode change offers
    /// every lock); a row over more than four nodes is a general one.
    fn edge(&self, terms: &[(usize, f64)]) -> Edge {
        let mut nz = [(0usize, 0.0f64); 4];
        let mut len = 0;
        for &(i, c) in terms {
            match nz[..len].iter_mut().find(|(j, _)| *j == i) {
                Some(t) => t.1 += c,
                None if len == 4 => return Edge::General,
                None => {
                    nz[len] = (i, c);
                    len += 1;
                }
            }
        }
        let mut kept = nz[..len].iter().filter(|&&(_, c)| c != 0.0);
        match (kept.next(), kept.next(), kept.next()) {
            (None, _, _) => Edge::Zero,
            (Some(&(i, _)), None, _) => Edge::Between(i, self.dim),
            (Some(&(i, a)), Some(&(j, b)), None) if a == -b => Edge::Between(i, j),
            _ => Edge::General,
        }
    }
}

enum Edge {
    Zero,
    Between(usize, usize),
    General,
}

/// Union–find with path halving.
struct Forest(Vec<usize>);

impl Forest {
    fn new(n: usize) -> Self {
        Self((0..n).collect())
    }

    fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    /// Joins the two sets; false when they were one already.
    fn union(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
        ra != rb
    }
}

/// The general test: an orthonormal basis of the rows kept so far (modified Gram–Schmidt, i.e. a QR factorization
/// of the kept rows built one row at a time, which keeps the priority order).
pub(super) struct Dense {
    dim: usize,
    kept: Vec<Vec<f64>>,
}

impl Dense {
    pub fn new(dim: usize) -> Self {
        Self {
            dim,
            kept: Vec::new(),
        }
    }

    /// The row's norm and what is left of it after removing the kept rows' directions.
    fn residual(&self, terms: &[(usize, f64)]) -> (f64, Vec<f64>) {
        let mut v = vec![0.0; self.dim];
        for &(i, c) in terms {
            v[i] += c;
        }
        let norm0 = norm(&v);
        for q in &self.kept {
            let dot: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(x, qi)| *x -= dot * qi);
        }
        (norm0, v)
    }

    /// Whether the row (sparse terms) is a nonzero combination of the kept rows.
    pub fn depends(&self, terms: &[(usize, f64)]) -> bool {
        let (norm0, v) = self.residual(terms);
        norm0 > 0.0 && norm(&v) <= RANK_TOLERANCE * norm0
    }

    /// Keeps the row if it is independent of the rows kept so far; a zero row is never kept.
    pub fn accept(&mut self, terms: &[(usize, f64)]) -> bool {
        let (norm0, mut v) = self.residual(terms);
        let left = norm(&v);
        if norm0 == 0.0 || left <= RANK_TOLERANCE * norm0 {
            return false;
        }
        v.iter_mut().for_each(|x| *x /= left);
        self.kept.push(v);
        true
    }

    #[cfg(test)]
    pub fn rank(&self) -> usize {
        self.kept.len()
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}
