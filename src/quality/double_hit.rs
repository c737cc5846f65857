//! The double-hit check of an impact record's dominant force ([`double_hit`]): a second
//! pulse after the force has returned to quiet, with the medians (baseline and noise) it
//! needs, and the shortcuts that skip them when the answer is known without.

use crate::lanes;
use crate::statistics::{MAD_TO_SIGMA, select};

use super::{ImpactChecks, NOISE_SIGMAS, QUIET_SAMPLES, RETURN_FRACTION, Scan};

/// Below this range of the force (and above zero), `f − b` may square to zero: the
/// double-hit check then runs even when no crest factor can pass, to keep its answer on
/// such a force exactly as before. At or above it, some `|f − b| ≥ range/2` squares to a
/// positive number (a finite range keeps the peak finite), the RMS is positive and an infinite
/// crest-factor threshold rejects the record before anything else is computed; a zero range
/// has no peak.
const SQUARES_TO_ZERO: f64 = 1e-150;

/// The value of a key of [`lanes::total_order_keys`].
fn from_total_order_key(key: u64) -> f64 {
    let flip = if key >> 63 == 1 { 1 << 63 } else { u64::MAX };
    f64::from_bits(key ^ flip)
}

/// Buffers of the double-hit check's medians, kept from one record to the next so that the
/// check allocates nothing once they have grown to a channel's length.
#[derive(Debug, Clone, Default)]
pub(crate) struct MedianBuffers {
    /// The channel's keys (of its samples, then of their deviations).
    keys: Vec<u64>,
    /// The selection's scratch ([`select::select`]).
    inside: Vec<u64>,
}

/// The level below which `f` is quiet about `baseline`: a fraction of the peak, or the noise
/// (the MAD of the deviations, as a standard deviation) when that is higher
/// (`max(`[`RETURN_FRACTION`]` · peak, `[`NOISE_SIGMAS`]` · σ)`). When more than half the
/// deviations are within `t` (below), the MAD is too, and the noise term stays below the
/// fraction of the peak by [`QUIET_MARGIN`]: the level is then the fraction, without the
/// second median. `keys` is scratch of `f`'s length, `inside` the selection's.
fn quiet_level(
    f: &[f64],
    baseline: f64,
    peak: f64,
    keys: &mut [u64],
    inside: &mut Vec<u64>,
) -> f64 {
    let fraction = RETURN_FRACTION * peak;
    let t = fraction / (NOISE_SIGMAS * MAD_TO_SIGMA) * (1.0 - QUIET_MARGIN);
    let mid = f.len() / 2;
    if lanes::count_within(f, baseline, t) > mid {
        return fraction;
    }
    for (k, v) in keys.iter_mut().zip(f) {
        *k = (v - baseline).abs().to_bits();
    }
    let sigma = MAD_TO_SIGMA * f64::from_bits(select::select(keys, mid, inside));
    fraction.max(NOISE_SIGMAS * sigma)
}

/// Relative margin of the quiet-level shortcut in [`double_hit`]: far above the rounding of
/// its few products, far below any change of the answer.
const QUIET_MARGIN: f64 = 1e-12;

/// Whether the crest factor of `f` about its median `b` (peak `max |f − b|` over RMS about
/// `b`) is surely below `threshold`, known without the median: a median lies within one
/// standard deviation `σ` of the mean `m` (both over the `N` samples), so the peak is at most
/// `P + σ` with `P = max |f − m|`, the RMS at least `σ`, and the crest factor at most
/// `1 + P/σ`. Kept clear of rounding by a relative margin; `false` whenever `σ` or `P` is
/// not a positive finite number. Random and periodic forces (crest factors of 3–5) skip the
/// medians of the double-hit check this way.
fn crest_factor_below(scan: &Scan, threshold: f64) -> bool {
    const MARGIN: f64 = 1e-9;
    let (mean, sigma) = (scan.mean, scan.rms);
    let p = (scan.hi - mean).max(mean - scan.lo);
    let usable = sigma.is_normal() && p.is_finite();
    usable && (p + sigma) * (1.0 + MARGIN) < threshold * sigma
}

/// `(main peak sample, extra peak sample, ratio)` of a double hit in `f`, if there is one.
/// (`scan` is `f`'s [`Scan`]; `buffers` are kept by the caller across records.)
pub(super) fn double_hit(
    f: &[f64],
    checks: &ImpactChecks,
    scan: &Scan,
    buffers: &mut MedianBuffers,
) -> Option<(usize, usize, f64)> {
    // No crest factor passes an infinite threshold: the answer is `None` (see
    // [`SQUARES_TO_ZERO`]), found here without the medians.
    let range = scan.hi - scan.lo;
    let threshold_infinite = checks.min_crest_factor.is_infinite() && checks.min_crest_factor > 0.0;
    let squares_positive = range.is_finite() && range >= SQUARES_TO_ZERO;
    if threshold_infinite && (range <= 0.0 || squares_positive) {
        return None;
    }
    let n = f.len();
    if crest_factor_below(scan, checks.min_crest_factor) {
        return None;
    }
    // Both medians select on integer keys of the same order (`total_cmp`'s, and for the
    // non-negative deviations their bits): the same elements as selecting on the floats, with
    // cheaper comparisons.
    let mid = n / 2;
    let MedianBuffers { keys, inside } = buffers;
    lanes::total_order_keys(f, keys);
    let baseline = from_total_order_key(select::select(keys, mid, inside));
    let (p, peak) = lanes::first_peak(f, baseline);
    let rms = (lanes::sum_sq_dev(f, baseline) / n as f64).sqrt();
    // Samples are finite (a `Record` guarantees it), so `peak` is a number.
    if peak <= 0.0 || peak < checks.min_crest_factor * rms {
        return None;
    }
    let sign = (f[p] - baseline).signum();
    let floor = quiet_level(f, baseline, peak, keys, inside);
    let quiet = |i: usize| (f[i] - baseline).abs() < floor;

    // First sample after the main pulse: the start of the first quiet run after p.
    let mut after = n;
    let mut run = 0;
    for i in p + 1..n {
        run = if quiet(i) { run + 1 } else { 0 };
        if run == QUIET_SAMPLES {
            after = i + 1 - QUIET_SAMPLES;
            break;
        }
    }
    // One past the last sample before the main pulse: the end of the last quiet run before p.
    let mut before = 0;
    run = 0;
    for i in (0..p).rev() {
        run = if quiet(i) { run + 1 } else { 0 };
        if run == QUIET_SAMPLES {
            before = i + QUIET_SAMPLES;
            break;
        }
    }

    // The largest excursion the main pulse's way outside it, its first sample on a tie (the
    // part before the pulse first): a second hit if above the threshold.
    let threshold = (checks.double_hit_ratio * peak).max(floor);
    let (q0, e0) = lanes::first_peak_signed(&f[..before], baseline, sign);
    let (q1, e1) = lanes::first_peak_signed(&f[after..], baseline, sign);
    let (q, e) = if e1 > e0 { (after + q1, e1) } else { (q0, e0) };
    (e > threshold).then_some((p, q, e / peak))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quality::tests::pulse;
    use crate::statistics::upper_median;

    /// Uniform numbers in `[0, 1)` from a 64-bit linear congruential generator seeded by `seed`.
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / 2f64.powi(53)
        }
    }

    /// The bound of [`crest_factor_below`] never excludes a crest factor that is reached: at
    /// a threshold equal to the true crest factor about the median, it must not answer "below".
    #[test]
    fn crest_factor_bound_holds_on_skewed_and_offset_signals() {
        let mut uniform = uniform(11);
        let n = 4000;
        let noise: Vec<f64> = (0..n)
            .map(|_| uniform() + uniform() + uniform() - 1.5)
            .collect();
        let signals: Vec<Vec<f64>> = vec![
            noise.clone(),
            noise.iter().map(|v| 1e3 + v).collect(),
            (0..n).map(|m| (m as f64 * 0.05).sin()).collect(),
            // Mostly zero with a tenth at 1: the median sits far from the mean.
            (0..n)
                .map(|m| if m % 10 == 0 { 1.0 } else { 0.0 })
                .collect(),
            (0..n)
                .map(|m| if m % 2 == 0 { 1.0 } else { -1.0 })
                .collect(),
            (0..n).map(|_| -uniform().ln()).collect(),
            noise
                .iter()
                .enumerate()
                .map(|(m, v)| if m == 900 { 40.0 } else { 0.01 * v })
                .collect(),
        ];
        for (k, f) in signals.iter().enumerate() {
            let scan = Scan::new(f);
            let b = upper_median(&mut f.clone());
            let peak = f.iter().fold(0.0, |p: f64, v| p.max((v - b).abs()));
            let rms = (f.iter().map(|v| (v - b) * (v - b)).sum::<f64>() / n as f64).sqrt();
            let crest = peak / rms;
            assert!(
                !crest_factor_below(&scan, crest),
                "signal {k}: crest {crest}"
            );
            assert!(
                crest_factor_below(&scan, 2.0 * crest + 2.0),
                "signal {k}: loose"
            );
        }
    }

    #[test]
    fn total_order_keys_sort_as_total_cmp() {
        let v = [
            f64::NEG_INFINITY,
            -1e300,
            -1.0,
            -1e-320,
            -0.0,
            0.0,
            1e-320,
            1.0,
            f64::MAX,
            f64::INFINITY,
        ];
        for w in v.windows(2) {
            assert!(
                lanes::total_order_key(w[0]) < lanes::total_order_key(w[1]),
                "{} < {}",
                w[0],
                w[1]
            );
        }
        for &x in &v {
            assert_eq!(
                from_total_order_key(lanes::total_order_key(x)).to_bits(),
                x.to_bits()
            );
        }
        // The double-hit medians (on keys) against `median` (on floats), odd and even counts.
        for n in [7, 8, 301, 302] {
            let f: Vec<f64> = (0..n)
                .map(|m| ((m * 37 % 101) as f64 - 50.0) * 0.1)
                .collect();
            let mut keys = Vec::new();
            lanes::total_order_keys(&f, &mut keys);
            let by_key = from_total_order_key(*keys.select_nth_unstable(n / 2).1);
            assert_eq!(by_key.to_bits(), upper_median(&mut f.clone()).to_bits());
        }
    }

    /// The quiet level with its shortcut against both medians taken the plain way, on pulses
    /// over noise from negligible to dominant (either side of the shortcut's test).
    #[test]
    fn quiet_level_is_that_of_the_two_medians() {
        let mut uniform = uniform(3);
        let mut noise = || uniform() - 0.5;
        let mut shortcuts = 0;
        for level in [0.0, 1e-6, 1e-3, 3e-3, 1e-2, 0.03, 0.1, 1.0] {
            for n in [9000, 9001] {
                let mut f: Vec<f64> = (0..n).map(|_| 2.0 + level * noise()).collect();
                pulse(&mut f, 3000, 1.0);
                let baseline = upper_median(&mut f.clone());
                let (_, peak) = lanes::peak(&f, baseline);
                let mut dev: Vec<f64> = f.iter().map(|v| (v - baseline).abs()).collect();
                let sigma = MAD_TO_SIGMA * upper_median(&mut dev);
                let plain = (RETURN_FRACTION * peak).max(NOISE_SIGMAS * sigma);
                let level_here = quiet_level(&f, baseline, peak, &mut vec![0; n], &mut Vec::new());
                assert_eq!(
                    level_here.to_bits(),
                    plain.to_bits(),
                    "noise {level}, n {n}"
                );
                shortcuts += usize::from(NOISE_SIGMAS * sigma < RETURN_FRACTION * peak);
            }
        }
        assert!(
            (4..16).contains(&shortcuts),
            "both sides tested: {shortcuts}"
        );
    }
}
