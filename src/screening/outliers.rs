//! The per-line test of paired sets: sets whose impedance is far from the others' at most
//! lines ([`outlier_sets`]).

use faer::traits::pulp::{Arch, Simd, WithSimd};
use faer::{Mat, MatRef, c64};

use super::{Checks, MAD_TO_SIGMA, upper_median};
use crate::lanes;

/// A paired set found far from the others by [`outlier_sets`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutlierSet {
    /// Index of the set.
    pub set: usize,
    /// Lines where it is far out.
    pub far_lines: usize,
    /// Lines tested (where at least 3 sets have an impedance).
    pub lines: usize,
}

/// The sets whose impedance is far from the others' at most lines (see the
/// [module docs](crate::screening)): `impedances[set][line]` is the set's own `n × n` impedance at a band
/// line (`None` where it could not be computed). Lines where fewer than 3 sets have one are
/// not tested.
///
/// # Examples
/// Four sets agree within 1 %, the fifth has its columns swapped:
/// ```
/// use bearing_ident::screening::{Checks, OutlierSet, outlier_sets};
/// use faer::{Mat, MatRef, c64};
/// let h = |k: f64, swap: bool| -> Option<Mat<c64>> {
///     let m = [[146e3 * k, 22e3], [11e3, 169e3 * k]];
///     Some(Mat::from_fn(2, 2, |i, j| c64::new(m[i][if swap { 1 - j } else { j }], 800.0)))
/// };
/// let sets: Vec<Vec<Option<Mat<c64>>>> = (0..5)
///     .map(|s| (0..10).map(|l| h(1.0 + 0.002 * ((s * 3 + l) % 5) as f64, s == 4)).collect())
///     .collect();
/// assert_eq!(
///     outlier_sets(&sets, &Checks::default()),
///     vec![OutlierSet { set: 4, far_lines: 10, lines: 10 }]
/// );
/// ```
pub fn outlier_sets(impedances: &[Vec<Option<Mat<c64>>>], checks: &Checks) -> Vec<OutlierSet> {
    let lines = impedances.iter().map(Vec::len).min().unwrap_or(0);
    let n = impedances
        .iter()
        .flatten()
        .flatten()
        .next()
        .map_or(0, Mat::nrows);
    let flat: Vec<Vec<Option<Vec<c64>>>> = impedances
        .iter()
        .map(|set| {
            set.iter()
                .map(|h| {
                    h.as_ref()
                        .map(|h| h.col_iter().flat_map(|c| c.iter().copied()).collect())
                })
                .collect()
        })
        .collect();
    outlier_sets_by(flat.len(), lines, n, |s, l| flat[s][l].as_deref(), checks)
}

/// [`outlier_sets`] on `sets × lines` impedances given by `impedance(set, line)`, each a
/// column-major `n × n` slice (`None` where it could not be computed).
pub(crate) fn outlier_sets_by<'a>(
    sets: usize,
    lines: usize,
    n: usize,
    impedance: impl Fn(usize, usize) -> Option<&'a [c64]>,
    checks: &Checks,
) -> Vec<OutlierSet> {
    if sets < 3 {
        return Vec::new();
    }
    let (mut far, mut tested) = (vec![0; sets], vec![0; sets]);
    // Buffers of one line, reused: the sets present and their impedances side by side
    // (`[set][element]`, column-major elements; then as real numbers, each real part before
    // its imaginary part), the line's median impedance, the squared distances to it
    // (compared squared: `d > k·σ` exactly when `d² > k²σ²`, for `d, σ ≥ 0`, and the median
    // of the squares is the square of the median), the sets found far.
    let mut present: Vec<usize> = Vec::with_capacity(sets);
    let mut values: Vec<c64> = Vec::new();
    let mut centre: Vec<c64> = Vec::new();
    let (mut parts, mut squares, mut sigma2) = (Vec::new(), Vec::new(), Vec::new());
    let mut medians = ColumnMedians::default();
    let mut far_here = Vec::with_capacity(sets);
    let sigmas2 = checks.set_sigmas * checks.set_sigmas;
    let nn = n * n;
    for l in 0..lines {
        present.clear();
        values.clear();
        for s in 0..sets {
            if let Some(h) = impedance(s, l) {
                present.push(s);
                values.extend_from_slice(h);
            }
        }
        if present.len() < 3 {
            continue;
        }
        // The median impedance, real and imaginary parts of every element apart.
        parts.clear();
        parts.extend(values.iter().flat_map(|z| [z.re, z.im]));
        let centre_parts = medians.of(&parts, present.len(), 2 * nn);
        centre.clear();
        centre.extend(centre_parts.chunks_exact(2).map(|p| c64::new(p[0], p[1])));
        let floor = checks.set_floor * MatRef::from_column_major_slice(&centre, n, n).norm_l2();
        let floor2 = floor * floor;
        // Squared distances to it, `[set][element]`, and their median per element.
        squares.clear();
        for h in values.chunks_exact(nn) {
            squares.extend(h.iter().zip(&centre).map(|(&z, &c)| (z - c).norm_sqr()));
        }
        sigma2.clear();
        let mad2 = medians.of(&squares, present.len(), nn);
        sigma2.extend(mad2.iter().map(|&m| MAD_TO_SIGMA * MAD_TO_SIGMA * m));
        far_here.clear();
        far_here.extend(squares.chunks_exact(nn).map(|d2| {
            d2.iter()
                .zip(&sigma2)
                .any(|(&d2, &s2)| d2 > sigmas2 * s2 && d2 > floor2)
        }));
        for (&s, &f) in present.iter().zip(&far_here) {
            tested[s] += 1;
            far[s] += usize::from(f);
        }
    }
    (0..sets)
        .filter(|&s| tested[s] > 0 && far[s] as f64 > checks.set_fraction * tested[s] as f64)
        .map(|s| OutlierSet {
            set: s,
            far_lines: far[s],
            lines: tested[s],
        })
        .collect()
}

/// Upper medians, in `total_cmp`'s order, of every column of a row-major `rows × m` table
/// (the sets of a line by their impedances' parts), with buffers kept across lines.
///
/// Up to [`RANK_MAX`] rows, by counting ranks for all columns at once: the value in row `i`
/// is column `e`'s median when `#{j : x_je < x_ie} ≤ ⌊rows/2⌋ < #{j : x_je ≤ x_ie}` (values
/// that compare equal have the same bits). The columns sit side by side, so each comparison
/// of two rows runs over all columns in SIMD lanes, without a branch. More rows: one
/// [`median`] per column.
#[derive(Debug, Default)]
struct ColumnMedians {
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
    fn of(&mut self, x: &[f64], rows: usize, m: usize) -> &[f64] {
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
