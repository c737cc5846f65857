//! [`ColumnMedians`]: the upper medians of every column of a small table at once (the outlier
//! sets' screening: the sets of a line by their impedances' parts), by a median network or
//! ranks counted, the columns in SIMD lanes.

use faer::traits::pulp::{Arch, Simd, WithSimd};

use super::upper_median;

/// Upper medians, in `total_cmp`'s order, of every column of a row-major `rows × m` table
/// (the sets of a line by their impedances' parts), with buffers kept across lines.
///
/// Up to [`NETWORK_MAX`] rows, by a median network ([`MEDIAN_NETWORKS`]) run on whole rows:
/// each compare-exchange of two rows orders every column's pair at once, in SIMD lanes,
/// without a branch. Up to [`RANK_MAX`] rows, by counting ranks for all columns at once: the value in row `i`
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

/// Most rows [`ColumnMedians`] puts through a median network.
const NETWORK_MAX: usize = 8;

/// For `n` inputs, the compare-exchanges `(a, b)` (`a < b`: the smaller to `a`) of an optimal
/// sorting network (Knuth, *The Art of Computer Programming* vol. 3, §5.3.4) kept only where
/// the middle output (rank `⌊n/2⌋`) depends on them: after them that wire holds the upper
/// median, whatever the inputs (the 0-1 principle; the test checks every input of 0s and 1s).
const MEDIAN_NETWORKS: [&[(usize, usize)]; NETWORK_MAX + 1] = [
    &[],
    &[],
    &[(0, 1)],
    &[(0, 2), (0, 1), (1, 2)],
    &[(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)],
    &[
        (0, 3),
        (1, 4),
        (0, 2),
        (1, 3),
        (0, 1),
        (2, 4),
        (1, 2),
        (3, 4),
        (2, 3),
    ],
    &[
        (0, 5),
        (1, 3),
        (2, 4),
        (1, 2),
        (3, 4),
        (0, 3),
        (2, 5),
        (2, 3),
        (4, 5),
        (3, 4),
    ],
    &[
        (0, 6),
        (2, 3),
        (4, 5),
        (0, 2),
        (1, 4),
        (3, 6),
        (0, 1),
        (2, 5),
        (3, 4),
        (1, 2),
        (4, 6),
        (2, 3),
        (4, 5),
        (3, 4),
    ],
    &[
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7),
        (2, 4),
        (3, 5),
        (1, 4),
        (3, 6),
        (3, 4),
    ],
];

/// A signed key in `total_cmp`'s order: the bits as a signed integer, the magnitude's bits
/// flipped when the sign is set. Its own inverse.
#[inline(always)]
fn signed_key(bits: i64) -> i64 {
    bits ^ (((bits >> 63) as u64) >> 1) as i64
}

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
        self.keys.clear();
        self.keys
            .extend(x.iter().map(|&v| signed_key(v.to_bits() as i64)));
        if rows <= NETWORK_MAX {
            let pairs = MEDIAN_NETWORKS[rows];
            let keys = &mut self.keys[..rows * m];
            Arch::new().dispatch(Network { keys, m, pairs });
            let mid = rows / 2;
            let middle = &self.keys[mid * m..(mid + 1) * m];
            for (o, &k) in self.out.iter_mut().zip(middle) {
                *o = f64::from_bits(signed_key(k) as u64);
            }
            return &self.out;
        }
        let mid = (rows / 2) as i64;
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

/// The compare-exchanges `pairs` run on the rows of the row-major `keys` (`m` columns), each
/// over all columns at once: a named operation, so that the SIMD dispatch compiles it for the
/// processor's widest instructions.
struct Network<'a> {
    keys: &'a mut [i64],
    m: usize,
    pairs: &'a [(usize, usize)],
}

impl WithSimd for Network<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) {
        let m = self.m;
        for &(a, b) in self.pairs {
            let (before, from_b) = self.keys.split_at_mut(b * m);
            let row_a = &mut before[a * m..(a + 1) * m];
            for (p, q) in row_a.iter_mut().zip(&mut from_b[..m]) {
                let (u, v) = (*p, *q);
                *p = u.min(v);
                *q = u.max(v);
            }
        }
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

    /// Each median network puts the median of every input of 0s and 1s on its middle wire
    /// (the 0-1 principle: then it does so for any input).
    #[test]
    fn median_networks_take_every_binary_input_to_its_median() {
        for (n, pairs) in MEDIAN_NETWORKS.iter().enumerate().skip(1) {
            for bits in 0u32..1 << n {
                let mut wires: Vec<u32> = (0..n).map(|i| bits >> i & 1).collect();
                for &(a, b) in *pairs {
                    assert!(a < b && b < n, "n {n}: ({a}, {b})");
                    let (u, v) = (wires[a], wires[b]);
                    (wires[a], wires[b]) = (u.min(v), u.max(v));
                }
                let ones = bits.count_ones() as usize;
                let median = u32::from(n / 2 >= n - ones);
                assert_eq!(wires[n / 2], median, "n {n}, input {bits:b}");
            }
        }
    }

    /// The signed keys order as `total_cmp` and give the value back.
    #[test]
    fn signed_keys_order_as_total_cmp() {
        let v = [
            -f64::NAN,
            f64::NEG_INFINITY,
            -1e300,
            -1.0,
            -5e-324,
            -0.0,
            0.0,
            5e-324,
            1.0,
            f64::MAX,
            f64::INFINITY,
            f64::NAN,
        ];
        for w in v.windows(2) {
            let key = |x: f64| signed_key(x.to_bits() as i64);
            assert!(key(w[0]) < key(w[1]), "{} < {}", w[0], w[1]);
        }
        for x in v {
            let back = signed_key(signed_key(x.to_bits() as i64)) as u64;
            assert_eq!(back, x.to_bits());
        }
    }

    /// Every column's median is the sorted middle bit for bit, on every side of
    /// [`NETWORK_MAX`] and [`RANK_MAX`], with ties, signed zeros, infinities and NaN.
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
