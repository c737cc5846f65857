//! [`Scan`]: one pass over a channel, shared by the record checks and the screening.

use faer::traits::pulp::{Arch, Simd, WithSimd};

use crate::lanes::{self, LANES};
use crate::records::Record;

/// What two passes over a channel give the record checks and the screening: its extremes and
/// mean, the smallest non-zero change between consecutive samples and a digest of its samples'
/// bits (the first pass), and its RMS about the mean (the second). The passes run in [`LANES`]
/// independent lanes (sample `m` in lane `m mod LANES`, see [`crate::lanes`]): extremes,
/// smallest change and digest are those of a left-to-right pass, the sums round as lane-wise
/// sums do.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scan {
    /// `min x`.
    pub(crate) lo: f64,
    /// `max x`.
    pub(crate) hi: f64,
    /// `x̄ = Σ x / N` (0 for no samples).
    pub(crate) mean: f64,
    /// `√(Σ (x − x̄)² / N)` (0 for no samples).
    pub(crate) rms: f64,
    /// `min |x_{m+1} − x_m|` over the non-zero changes, +∞ if none.
    pub(crate) step: f64,
    /// Four interleaved lanes of `h ← rotl((h ⊕ bits) · M, 29)` over the samples' bits, each
    /// step a bijection of `h`, so records that differ in one sample always differ here.
    pub(crate) digest: [u64; 4],
}

/// [`Scan::new`]'s pass as an operation of faer's SIMD dispatch: a named type rather than a
/// closure, so that the whole pass is inlined into the instruction set chosen.
struct Pass<'a>(&'a [f64]);

impl WithSimd for Pass<'_> {
    type Output = Scan;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) -> Scan {
        Scan::folded(self.0)
    }
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

    /// The first pass over `x` (its `mean` still the sum, its `rms` 0), each of its folds in [`LANES`] lanes (kept as separate arrays, so
    /// each fold's lanes pack into SIMD registers). Samples are finite (a `Record` guarantees
    /// it), so comparisons stand in for `f64::min`/`max`.
    pub(crate) fn new(x: &[f64]) -> Self {
        let mut scan = Arch::new().dispatch(Pass(x));
        if !x.is_empty() {
            let n = x.len() as f64;
            scan.mean /= n;
            scan.rms = (lanes::sum_sq_dev(x, scan.mean) / n).sqrt();
        }
        scan
    }

    #[inline(always)]
    fn folded(x: &[f64]) -> Self {
        let mut lo = [f64::INFINITY; LANES];
        let mut hi = [f64::NEG_INFINITY; LANES];
        let mut sum = [0.0; LANES];
        let mut step = [f64::INFINITY; LANES];
        let mut digest = [
            0x243f_6a88_85a3_08d3_u64,
            0x1319_8a2e_0370_7344,
            0xa409_3822_299f_31d0,
            0x082e_fa98_ec4e_6c89,
        ];
        let mut prev = x.first().copied().unwrap_or_default();
        let chunks = x.chunks_exact(LANES);
        let rest = chunks.remainder();
        for c in chunks {
            let v: [f64; LANES] = [c[0], c[1], c[2], c[3]];
            let before = [prev, c[0], c[1], c[2]];
            for j in 0..LANES {
                lo[j] = if v[j] < lo[j] { v[j] } else { lo[j] };
                hi[j] = if v[j] > hi[j] { v[j] } else { hi[j] };
                sum[j] += v[j];
                let d = (v[j] - before[j]).abs();
                step[j] = if d > 0.0 && d < step[j] { d } else { step[j] };
            }
            for j in 0..LANES {
                digest[j] =
                    ((digest[j] ^ v[j].to_bits()).wrapping_mul(DIGEST_MULTIPLIER)).rotate_left(29);
            }
            prev = c[LANES - 1];
        }
        for (j, &v) in rest.iter().enumerate() {
            lo[j] = lo[j].min(v);
            hi[j] = hi[j].max(v);
            sum[j] += v;
            let d = (v - prev).abs();
            if d > 0.0 {
                step[j] = step[j].min(d);
            }
            digest[j] = ((digest[j] ^ v.to_bits()).wrapping_mul(DIGEST_MULTIPLIER)).rotate_left(29);
            prev = v;
        }
        let min4 = |a: [f64; LANES]| a[0].min(a[1]).min(a[2].min(a[3]));
        Self {
            lo: min4(lo),
            hi: hi[0].max(hi[1]).max(hi[2].max(hi[3])),
            mean: (sum[0] + sum[1]) + (sum[2] + sum[3]),
            rms: 0.0,
            step: min4(step),
            digest,
        }
    }
}
