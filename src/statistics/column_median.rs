//! [`ColumnMedians`]: the upper medians of every column of a small table at once (the outlier
//! sets' screening: the sets of a line by their impedances' parts), ranks counted in SIMD lanes.

use faer::traits::pulp::{Arch, Simd, WithSimd};

use super::upper_median;
use crate::lanes;

/// Upper medians, in `total_cmp`'s order, of every column of a row-major `rows × m` table
/// (the sets of a line by their impedances' parts), with buffers kept across lines.
///
/// Up to [`RANK_MAX`] rows, by counting ranks for all columns at once: the value in row `i`
/// is column `e`'s median when `#{j : x_je < x_ie} ≤ ⌊rows/2⌋ < #{j : x_je ≤ x_ie}` (values
/// that compare equal have the same bits). The columns sit side by side, so each comparison
/// of two rows runs over all columns in SIMD lanes, without a branch. More rows: one
/// [`upper_median`] per column.
#[derive(Debug, Default)]
pub(crate) struct ColumnMedians {
    /// Signed keys in `total_cmp`'s order, `[row][column]`.
    keys: Vec<i64>,
    below: Vec<i64>,
    at_or_below: Vec<i64>,
    column: Vec<f64>,
    out: Vec<f64>,
}

/// Most rows [`ColumnMedians`] ranks rather than sorts per column.
const RANK_MAX: usize = 16;

impl ColumnMedians {
    /// The median of every column of the row-major `rows × m` table `x`.
    pub(crate) fn of(&mut self, x: &[f64], rows: usize, m: usize) -> &[f64] {
        self.out.clear();
        self.out.resize(m, 0.0);
        if rows > RANK_MAX {
            for e in 0..m {
                self.column.clear();
                self.column.extend(x.iter().skip(e).step_by(m));
                self.out[e] = upper_median(&mut self.column);
            }
            return &self.out;
        }
        let mid = (rows / 2) as i64;
        self.keys.clear();
        self.keys.extend(
            x.iter()
                .map(|&v| (lanes::total_order_key(v) ^ (1 << 63)) as i64),
        );
        for (i, row) in x.chunks_exact(m).enumerate() {
            self.below.clear();
            self.below.resize(m, 0);
            self.at_or_below.clear();
            self.at_or_below.resize(m, 0);
            Arch::new().dispatch(Ranks {
                keys: &self.keys,
                of: i,
                m,
                mid,
                row,
                below: &mut self.below,
                at_or_below: &mut self.at_or_below,
                out: &mut self.out,
            });
        }
        &self.out
    }
}

/// Per column, how many rows' keys lie below (at or below) row `of`'s, in one pass over the
/// rows with the columns in lanes; then `row`'s value goes to `out` in the columns where it is
/// the median (rank `mid`). A named operation, so that the SIMD dispatch compiles it for the
/// processor's widest instructions.
struct Ranks<'a> {
    keys: &'a [i64],
    of: usize,
    m: usize,
    mid: i64,
    row: &'a [f64],
    below: &'a mut [i64],
    at_or_below: &'a mut [i64],
    out: &'a mut [f64],
}

impl WithSimd for Ranks<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) {
        let m = self.m;
        let pivot = &self.keys[self.of * m..(self.of + 1) * m];
        for row in self.keys.chunks_exact(m) {
            for (((b, a), &k), &p) in self
                .below
                .iter_mut()
                .zip(self.at_or_below.iter_mut())
                .zip(row)
                .zip(pivot)
            {
                *b += i64::from(k < p);
                *a += i64::from(k <= p);
            }
        }
        let mid = self.mid;
        for (((o, &v), &b), &a) in self
            .out
            .iter_mut()
            .zip(self.row)
            .zip(self.below.iter())
            .zip(self.at_or_below.iter())
        {
            let median = (b <= mid) & (mid < a);
            *o = if median { v } else { *o };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every column's median is the sorted middle bit for bit, on both sides of
    /// [`RANK_MAX`], with ties, signed zeros, infinities and NaN.
    #[test]
    fn column_medians_are_the_sorted_middles() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let pool = [
            -0.0,
            0.0,
            1.0,
            -2.0,
            f64::INFINITY,
            f64::NAN,
            -f64::NAN,
            5e-324,
        ];
        let mut medians = ColumnMedians::default();
        for rows in 1..=RANK_MAX + 3 {
            for trial in 0..60 {
                let m = 1 + trial % 19;
                let x: Vec<f64> = (0..rows * m)
                    .map(|_| {
                        if trial % 2 == 0 {
                            pool[rng.random_range(0..pool.len())]
                        } else {
                            rng.random_range(-1.0..1.0)
                        }
                    })
                    .collect();
                let ours = medians.of(&x, rows, m).to_vec();
                for (e, ours) in ours.iter().enumerate() {
                    let mut column: Vec<f64> = x.iter().skip(e).step_by(m).copied().collect();
                    column.sort_unstable_by(f64::total_cmp);
                    assert_eq!(ours.to_bits(), column[rows / 2].to_bits(), "{rows} × {m}");
                }
            }
        }
    }
}
