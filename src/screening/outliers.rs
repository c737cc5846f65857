//! The per-line test of paired sets: sets whose impedance is far from the others' at most
//! lines ([`outlier_sets`]).

use faer::{Mat, MatRef, c64};

use super::{Checks, MAD_TO_SIGMA};
use crate::statistics::ColumnMedians;

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
