//! [`Scan`]: one pass over a channel, shared by the record checks and the screening.

use crate::records::Record;

/// What one pass over a channel gives the record checks and the screening: its extremes and
/// sum, the smallest non-zero change between consecutive samples, and a digest of its samples'
/// bits. Each is computed exactly as the separate passes it replaces did (the same folds, in
/// the same order), so results do not change.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scan {
    /// `min x` (folded with `f64::min` from +∞).
    pub(crate) lo: f64,
    /// `max x` (folded with `f64::max` from −∞).
    pub(crate) hi: f64,
    /// `Σ x`, left to right from 0.
    pub(crate) sum: f64,
    /// `min |x_{m+1} − x_m|` over the non-zero changes, +∞ if none.
    pub(crate) step: f64,
    /// Four interleaved lanes of `h ← rotl((h ⊕ bits) · M, 29)` over the samples' bits, each
    /// step a bijection of `h`, so records that differ in one sample always differ here.
    pub(crate) digest: [u64; 4],
}

/// Odd multiplier of the digest (the 64-bit golden ratio).
const DIGEST_MULTIPLIER: u64 = 0x9e37_79b9_7f4a_7c15;

impl Scan {
    /// The scans of every channel of `record`: its forces, then its responses.
    pub(crate) fn channels(record: &Record) -> Vec<Self> {
        let n = record.dofs();
        (0..n)
            .map(|c| Self::new(record.force(c)))
            .chain((0..n).map(|c| Self::new(record.displacement(c))))
            .collect()
    }

    /// One pass over `x`.
    pub(crate) fn new(x: &[f64]) -> Self {
        let (mut lo, mut hi, mut sum, mut step) =
            (f64::INFINITY, f64::NEG_INFINITY, 0.0, f64::INFINITY);
        let mut digest = [
            0x243f_6a88_85a3_08d3_u64,
            0x1319_8a2e_0370_7344,
            0xa409_3822_299f_31d0,
            0x082e_fa98_ec4e_6c89,
        ];
        let mut prev = x.first().copied().unwrap_or_default();
        for (m, &v) in x.iter().enumerate() {
            lo = lo.min(v);
            hi = hi.max(v);
            sum += v;
            let d = (v - prev).abs();
            if d > 0.0 {
                step = step.min(d);
            }
            prev = v;
            let h = &mut digest[m % 4];
            *h = ((*h ^ v.to_bits()).wrapping_mul(DIGEST_MULTIPLIER)).rotate_left(29);
        }
        Self {
            lo,
            hi,
            sum,
            step,
            digest,
        }
    }
}
