//! Passes over a channel's samples in [`LANES`] independent lanes: sample `m` goes to lane
//! `m mod LANES`, each lane folds its samples in order, and the lanes are combined at the end.
//! Independent lanes break the one dependency chain of a left-to-right fold, so the compiler
//! keeps several additions (or comparisons) in flight and packs them into SIMD registers; a
//! left-to-right sum waits for each addition in turn, about four times slower.
//!
//! A lane-wise sum rounds differently from a left-to-right one (within the usual
//! `N·ε·Σ|x|`); minima and maxima are exact either way.

use faer::traits::pulp::Arch;

/// Runs `pass` compiled for the widest SIMD instructions this processor has (AVX2 and FMA
/// on most x86-64), found at run time by faer's SIMD layer (`pulp`); the same operations in
/// the same order, so the same results, on any processor.
#[inline(always)]
pub(crate) fn simd<R>(pass: impl FnOnce() -> R) -> R {
    Arch::new().dispatch(pass)
}

/// Independent accumulators of a pass.
pub(crate) const LANES: usize = 4;

/// Folds `x` in lanes: `step(lane accumulator, sample)` per sample, lanes started at `init`,
/// the remainder (fewer than [`LANES`] samples at the end) folded into lanes `0..`.
#[inline(always)]
fn fold<T: Copy>(x: &[f64], init: T, step: impl Fn(T, f64) -> T) -> [T; LANES] {
    let mut acc = [init; LANES];
    let chunks = x.chunks_exact(LANES);
    let rest = chunks.remainder();
    for c in chunks {
        for (a, &v) in acc.iter_mut().zip(c) {
            *a = step(*a, v);
        }
    }
    for (a, &v) in acc.iter_mut().zip(rest) {
        *a = step(*a, v);
    }
    acc
}

/// `Σ x`.
pub(crate) fn sum(x: &[f64]) -> f64 {
    let a = simd(|| fold(x, 0.0, |a, v| a + v));
    (a[0] + a[1]) + (a[2] + a[3])
}

/// `Σ s·x`, each `s·x` rounded first (as a scaled copy of `x` would be), lanes combined as
/// `(a₀ + a₁) + (a₂ + a₃)` (as every sum here).
pub(crate) fn sum_scaled(x: &[f64], s: f64) -> f64 {
    let a = simd(|| fold(x, 0.0, |a, v| a + v * s));
    (a[0] + a[1]) + (a[2] + a[3])
}

/// `Σ (x − c)²`.
pub(crate) fn sum_sq_dev(x: &[f64], c: f64) -> f64 {
    let s = simd(|| fold(x, 0.0, |a, v| a + (v - c) * (v - c)));
    (s[0] + s[1]) + (s[2] + s[3])
}

/// `Σ (s·x − c)²`, each `s·x` rounded first (as a scaled copy of `x` would be).
pub(crate) fn sum_sq_dev_scaled(x: &[f64], s: f64, c: f64) -> f64 {
    let a = simd(|| fold(x, 0.0, |a, v| a + (v * s - c) * (v * s - c)));
    (a[0] + a[1]) + (a[2] + a[3])
}

/// `max |x|` (0 for none; samples are finite).
pub(crate) fn max_abs(x: &[f64]) -> f64 {
    let m = simd(|| {
        fold(
            x,
            0.0,
            |a: f64, v: f64| if v.abs() > a { v.abs() } else { a },
        )
    });
    m.into_iter().fold(0.0, f64::max)
}

/// `#{m : |x_m − c| ≤ t}`.
pub(crate) fn count_within(x: &[f64], c: f64, t: f64) -> usize {
    simd(|| fold(x, 0usize, |a, v| a + usize::from((v - c).abs() <= t)))
        .into_iter()
        .sum()
}

/// `(m, |x_m − c|)` at the largest `|x − c|`, the first such `m` (`(0, 0)` for none).
pub(crate) fn peak(x: &[f64], c: f64) -> (usize, f64) {
    simd(|| first_max(x, |v| (v - c).abs()))
}

/// `(m, s·(x_m − c))` at the largest positive `s·(x − c)`, the first such `m` (`(0, 0)` when
/// none is positive): the reference of [`first_peak_signed`].
#[cfg(test)]
pub(crate) fn peak_signed(x: &[f64], c: f64, s: f64) -> (usize, f64) {
    simd(|| first_max(x, |v| s * (v - c)))
}

/// The first `m` with the largest positive `d(x_m)`, and that value (`(0, 0)` for none).
#[inline(always)]
fn first_max(x: &[f64], d: impl Fn(f64) -> f64) -> (usize, f64) {
    let mut best = [(0, 0.0_f64); LANES];
    let chunks = x.chunks_exact(LANES);
    let rest = chunks.remainder();
    for (k, chunk) in chunks.enumerate() {
        for (j, (b, &v)) in best.iter_mut().zip(chunk).enumerate() {
            let d = d(v);
            if d > b.1 {
                *b = (k * LANES + j, d);
            }
        }
    }
    let start = x.len() - rest.len();
    for (j, (b, &v)) in best.iter_mut().zip(rest).enumerate() {
        let d = d(v);
        if d > b.1 {
            *b = (start + j, d);
        }
    }
    // Each lane holds its first largest; of equal lanes the earliest sample wins.
    best.into_iter()
        .fold((0, 0.0), |a, b| match b.1.total_cmp(&a.1) {
            std::cmp::Ordering::Greater => b,
            std::cmp::Ordering::Equal if b.0 < a.0 => b,
            _ => a,
        })
}

/// [`peak`] in two passes: the largest `|x − c|` in lanes (packed into SIMD registers, which
/// the index [`peak`] carries keeps out), then the first sample at it. The same result.
pub(crate) fn first_peak(x: &[f64], c: f64) -> (usize, f64) {
    first_at_max(x, |v| (v - c).abs())
}

/// [`peak_signed`] in two passes, as [`first_peak`]. The same result.
pub(crate) fn first_peak_signed(x: &[f64], c: f64, s: f64) -> (usize, f64) {
    first_at_max(x, |v| s * (v - c))
}

/// The first `m` with the largest positive `d(x_m)`, and that value (`(0, 0)` for none), as
/// [`first_max`] finds it: the largest value in lanes, then the first sample that reaches it
/// (`d` evaluated the same way both times, so the same bits).
#[inline(always)]
fn first_at_max(x: &[f64], d: impl Fn(f64) -> f64 + Copy) -> (usize, f64) {
    let lanes = simd(|| {
        fold(x, 0.0, |a: f64, v: f64| {
            let d = d(v);
            if d > a { d } else { a }
        })
    });
    let top = lanes
        .into_iter()
        .fold(0.0, |a: f64, b| if b > a { b } else { a });
    // The same bits: `top` is positive when it is used, a number whose bits are its only ones.
    match x.iter().position(|&v| d(v).to_bits() == top.to_bits()) {
        Some(m) if top > 0.0 => (m, top),
        _ => (0, 0.0),
    }
}

/// `f64::total_cmp`'s order as unsigned integers: a negative value has every bit flipped,
/// any other its sign bit.
#[inline(always)]
pub(crate) fn total_order_key(v: f64) -> u64 {
    let bits = v.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// [`total_order_key`] of every sample, into `keys` (cleared first).
pub(crate) fn total_order_keys(x: &[f64], keys: &mut Vec<u64>) {
    keys.clear();
    simd(|| keys.extend(x.iter().map(|&v| total_order_key(v))));
}

/// Whether every sample is finite (the lanes keep `|x| ≤ f64::MAX`; a NaN fails it too).
pub(crate) fn all_finite(x: &[f64]) -> bool {
    simd(|| fold(x, true, |a, v| a & (v.abs() <= f64::MAX)))
        .into_iter()
        .all(|a| a)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two-pass peaks against the one-pass ones, bit for bit, on ties (the first wins), on
    /// every remainder length, and with no positive value.
    #[test]
    fn two_pass_peaks_are_the_one_pass_ones() {
        for len in [0, 1, 2, 3, 4, 5, 7, 8, 9, 63, 64, 65, 1001] {
            let x: Vec<f64> = (0..len)
                .map(|m| ((m * 37 % 11) as f64 - 5.0) * 0.5)
                .collect();
            for c in [0.0, 0.25, -1.0, 10.0] {
                let same = |a: (usize, f64), b: (usize, f64)| {
                    assert_eq!((a.0, a.1.to_bits()), (b.0, b.1.to_bits()), "{len} {c}");
                };
                same(first_peak(&x, c), peak(&x, c));
                for s in [1.0, -1.0] {
                    same(first_peak_signed(&x, c, s), peak_signed(&x, c, s));
                }
            }
        }
    }

    #[test]
    fn sums_match_a_plain_fold_on_exact_values() {
        // Small integers and quarters: every sum is exact, whatever the order. (An empty sum is
        // +0 here, −0 for `Iterator::sum`.)
        let same = |a: f64, b: f64| assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
        for n in 1..13 {
            let x: Vec<f64> = (0..n).map(|m| (m * 7 % 5) as f64 - 2.0).collect();
            let mean = 0.5;
            same(
                sum_sq_dev(&x, mean),
                x.iter().map(|v| (v - mean) * (v - mean)).sum(),
            );
            same(sum(&x), x.iter().sum());
            same(sum_scaled(&x, 0.25), x.iter().map(|v| v * 0.25).sum());
            same(
                sum_sq_dev_scaled(&x, 0.25, mean),
                x.iter().map(|v| (v * 0.25 - mean).powi(2)).sum(),
            );
            same(max_abs(&x), x.iter().fold(0.0, |m: f64, v| m.max(v.abs())));
        }
    }

    #[test]
    fn peak_is_the_first_largest_deviation() {
        for n in 1..12 {
            for at in 0..n {
                for twin in 0..n {
                    let mut x = vec![1.0; n];
                    x[at] = 4.0;
                    x[twin] = -2.0; // |−2 − 1| = 3 = |4 − 1|: a tie
                    let expected = if at == twin { twin } else { at.min(twin) };
                    let (m, d) = peak(&x, 1.0);
                    assert_eq!(
                        (m, d.to_bits()),
                        (expected, 3f64.to_bits()),
                        "n {n} {at} {twin}"
                    );
                }
            }
        }
        assert_eq!(peak(&[1.0, 1.0], 1.0), (0, 0.0));
        // Signed: the first largest s·(x − c) that is positive, as a left-to-right scan finds.
        let scan = |x: &[f64], c: f64, s: f64| {
            let mut best = (0, 0.0);
            for (m, &v) in x.iter().enumerate() {
                if s * (v - c) > best.1 {
                    best = (m, s * (v - c));
                }
            }
            best
        };
        for n in 0..12 {
            for seed in 0..40_u32 {
                let x: Vec<f64> = (0..n)
                    .map(|m| f64::from((m as u32 * 7 + seed * 13) % 5) - 2.0)
                    .collect();
                for s in [1.0, -1.0] {
                    assert_eq!(peak_signed(&x, 0.5, s), scan(&x, 0.5, s), "{x:?} {s}");
                }
            }
        }
        assert_eq!(peak_signed(&[-3.0, -1.0], 0.0, 1.0), (0, 0.0));
        let x: Vec<f64> = (0..11).map(f64::from).collect();
        assert_eq!(count_within(&x, 5.0, 2.0), 5);
        assert_eq!(count_within(&x, 5.0, 1.5), 3);
    }

    #[test]
    fn a_non_finite_sample_anywhere_is_found() {
        for n in 1..10 {
            for at in 0..n {
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut x = vec![1.0; n];
                    x[at] = bad;
                    assert!(!all_finite(&x), "n {n} at {at} {bad}");
                }
            }
            assert!(all_finite(&vec![f64::MAX; n]));
        }
        assert!(all_finite(&[]));
    }
}
