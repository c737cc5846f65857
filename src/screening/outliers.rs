//! The per-line test of paired sets: sets whose impedance is far from the others' at most
//! lines ([`outlier_sets`]).

use faer::{Mat, c64};

use super::{Checks, MAD_TO_SIGMA, median};

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
/// use faer::{Mat, c64};
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
    let sets = impedances.len();
    if sets < 3 {
        return Vec::new();
    }
    let lines = impedances.iter().map(Vec::len).min().unwrap_or(0);
    let (mut far, mut tested) = (vec![0; sets], vec![0; sets]);
    for l in 0..lines {
        let present: Vec<(usize, &Mat<c64>)> = impedances
            .iter()
            .enumerate()
            .filter_map(|(s, h)| h[l].as_ref().map(|h| (s, h)))
            .collect();
        if present.len() < 3 {
            continue;
        }
        let n = present[0].1.nrows();
        let centre = Mat::from_fn(n, n, |i, j| {
            let mut re: Vec<f64> = present.iter().map(|(_, h)| h[(i, j)].re).collect();
            let mut im: Vec<f64> = present.iter().map(|(_, h)| h[(i, j)].im).collect();
            c64::new(median(&mut re), median(&mut im))
        });
        let floor = checks.set_floor * centre.norm_l2();
        let mut far_here = vec![false; present.len()];
        for j in 0..n {
            for i in 0..n {
                let distances: Vec<f64> = present
                    .iter()
                    .map(|(_, h)| (h[(i, j)] - centre[(i, j)]).norm())
                    .collect();
                let sigma = MAD_TO_SIGMA * median(&mut distances.clone());
                for (f, d) in far_here.iter_mut().zip(&distances) {
                    *f |= *d > checks.set_sigmas * sigma && *d > floor;
                }
            }
        }
        for ((s, _), f) in present.iter().zip(far_here) {
            tested[*s] += 1;
            far[*s] += usize::from(f);
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
