//! [`SparseRows`]: a matrix kept as rows of its nonzero entries, for the simulators' state
//! updates, whose matrices are mostly exact zeros.

use faer::Mat;

/// A matrix stored by rows, each row its nonzero entries `(column, value)` in column order.
/// Skipping exact zeros leaves every row's sum bit for bit as the dense product computes it
/// (the same nonzero terms, in the same order).
///
/// The linear simulator's transition matrix `Φ` is mostly zeros because each channel's filter
/// reads the structure and its own sections, never another channel's (a third of the entries
/// remain for two degrees of freedom); a filter's own `A`, a cascade of second-order
/// sections, couples each state to at most three others.
#[derive(Debug, Clone)]
pub(super) struct SparseRows {
    /// Where each row's entries start in `entries`; the last is `entries.len()`.
    row_start: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

impl SparseRows {
    pub(super) fn new(m: &Mat<f64>) -> Self {
        let mut row_start = Vec::with_capacity(m.nrows() + 1);
        let mut entries = Vec::new();
        for i in 0..m.nrows() {
            row_start.push(entries.len());
            entries.extend(
                (0..m.ncols())
                    .map(|j| (j, m[(i, j)]))
                    .filter(|&(_, value)| value != 0.0),
            );
        }
        row_start.push(entries.len());
        Self { row_start, entries }
    }

    /// The nonzero entries `(column, value)` of row `i`.
    pub(super) fn row(&self, i: usize) -> &[(usize, f64)] {
        &self.entries[self.row_start[i]..self.row_start[i + 1]]
    }

    /// `state ← M state`, through `next`.
    pub(super) fn propagate(&self, state: &mut Vec<f64>, next: &mut Vec<f64>) {
        for (i, out) in next.iter_mut().enumerate() {
            *out = self
                .row(i)
                .iter()
                .fold(0.0, |s, &(j, value)| s + value * state[j]);
        }
        std::mem::swap(state, next);
    }
}
