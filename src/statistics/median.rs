//! Medians, deviations and quantiles of samples: the crate's robust statistics, one home.
//!
//! Two medians, for two uses: [`median`], the midpoint of the two middles of an even count
//! (of a neighbourhood of lines, of coherences: a statistic that is reported or compared),
//! and [`upper_median`], one element of the values found by selection (the record checks,
//! over channels of millions of samples, and their siblings); the integer-key selection
//! behind a channel's median is [`select`](super::select), the upper medians of every column
//! of a small table at once [`ColumnMedians`](super::ColumnMedians).

/// `1/Φ⁻¹(3/4)`: the median absolute deviation of Gaussian noise times this is its standard
/// deviation.
pub(crate) const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// The median of `values`, reordering them: the middle value, or the mean of the two middles
/// of an even count; `None` for none.
pub(crate) fn median(values: &mut [f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let m = values.len() / 2;
    Some(if values.len() % 2 == 1 {
        values[m]
    } else {
        0.5 * (values[m - 1] + values[m])
    })
}

/// The upper median of `values` (of an even count, the upper of the two middles), reordering
/// them; NaN for none. The median of the record checks ([`quality`](crate::quality),
/// [`screening`](crate::screening)): one element of the values, found by selection.
pub(crate) fn upper_median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mid = values.len() / 2;
    if values.len() <= SORT_MAX {
        // A few values (the siblings of a record): sorting them is faster than the
        // selection's set-up, and puts the same element in the middle.
        values.sort_unstable_by(f64::total_cmp);
        return values[mid];
    }
    *values.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Most values [`upper_median`] sorts rather than selects among.
const SORT_MAX: usize = 16;

/// The `q` quantile (nearest rank) of `values`, reordering them; 0 for an empty slice.
pub(crate) fn quantile(values: &mut [f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let rank = ((values.len() - 1) as f64 * q).round() as usize;
    let (_, v, _) = values.select_nth_unstable_by(rank, f64::total_cmp);
    *v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_is_the_middle_or_the_mean_of_the_two() {
        assert_eq!(median(&mut []), None);
        assert!((median(&mut [3.0, 1.0, 2.0]).unwrap() - 2.0).abs() < 1e-15);
        assert!((median(&mut [4.0, 1.0]).unwrap() - 2.5).abs() < 1e-15);
    }

    #[test]
    fn upper_median_is_the_upper_middle() {
        assert!((upper_median(&mut [3.0, 1.0, 2.0]) - 2.0).abs() < 1e-15);
        assert!((upper_median(&mut [4.0, 1.0, 3.0, 2.0]) - 3.0).abs() < 1e-15);
    }

    /// The sorted middle bit for bit, ties, signed zeros, infinities and NaN included, on both
    /// sides of [`SORT_MAX`].
    #[test]
    fn upper_median_is_the_sorted_middle() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(17);
        let pool = [
            -0.0,
            0.0,
            1.0,
            -1.0,
            2.5,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
            1e-310,
        ];
        for len in 1..=SORT_MAX + 3 {
            for trial in 0..400 {
                let values: Vec<f64> = (0..len)
                    .map(|_| {
                        if trial % 2 == 0 {
                            pool[rng.random_range(0..pool.len())]
                        } else {
                            rng.random_range(-1.0..1.0)
                        }
                    })
                    .collect();
                let mut sorted = values.clone();
                sorted.sort_unstable_by(f64::total_cmp);
                let ours = upper_median(&mut values.clone());
                assert_eq!(ours.to_bits(), sorted[len / 2].to_bits(), "{values:?}");
            }
        }
    }
}
