//! [`Scan`]: one pass over a channel, shared by the record checks and the screening.

use faer::traits::pulp::{Arch, Simd, WithSimd};

use super::CLIP_TOLERANCE;
use crate::lanes::LANES;
use crate::records::Record;

/// What two passes over a channel give the record checks and the screening: its extremes and
/// mean (the first pass), its RMS about the mean and a digest of its samples' bits (the
/// second). The sums run in [`LANES`] independent lanes (sample `m` in lane `m mod LANES`, see
/// [`crate::lanes`]) and round as lane-wise sums do; extremes are those of a left-to-right
/// pass. The smallest change between consecutive samples, which only a run at an extreme
/// needs, is left to [`smallest_step`].
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
    /// [`CHAINS`] interleaved chains (sample `m` in chain `m mod CHAINS`) of [`mix`] over the
    /// samples' bits, each step a bijection of `h` and one-to-one in the sample, so records
    /// that differ in one sample always differ here.
    pub(crate) digest: [u64; CHAINS],
    /// Samples at either extreme within the clipping tolerance ([`near_extremes`]: at or
    /// above its top or at or below its bottom, counted once): no run at an extreme is longer,
    /// so fewer than the run the clipping check asks for clears the channel without its pass.
    pub(crate) near_extremes: usize,
}

/// The levels `(top, bottom)` within [`CLIP_TOLERANCE`] of the range `hi − lo` from the
/// extremes `hi`, `lo`: samples at or above `top` (at or below `bottom`) sit at an extreme for
/// the clipping check. One expression for the scan's count and the check's runs, so both
/// compare against the same bits.
#[inline(always)]
pub(crate) fn near_extremes(lo: f64, hi: f64) -> (f64, f64) {
    let tol = CLIP_TOLERANCE * (hi - lo);
    (hi - tol, lo + tol)
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

/// The second pass of [`Scan::new`] (`Σ (x − x̄)²`, the digest and the count at the extremes
/// between `top` and `bottom`) as an operation of faer's SIMD dispatch.
struct Spread<'a> {
    x: &'a [f64],
    mean: f64,
    top: f64,
    bottom: f64,
}

impl WithSimd for Spread<'_> {
    type Output = (f64, [u64; CHAINS], usize);

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) -> Self::Output {
        Scan::spread(self.x, self.mean, self.top, self.bottom)
    }
}

/// Independent chains of the digest, four SIMD registers of [`LANES`] chains each: enough
/// steps in flight that the digest costs little beside the sum of squares it is computed
/// beside.
const CHAINS: usize = 4 * LANES;

/// The digest's chains before any sample: the first digits of π, four to a row, each row
/// rotated by 8 bits more than the one before.
const DIGEST_START: [u64; CHAINS] = {
    let pi = [
        0x243f_6a88_85a3_08d3_u64,
        0x1319_8a2e_0370_7344,
        0xa409_3822_299f_31d0,
        0x082e_fa98_ec4e_6c89,
    ];
    let mut start = [0; CHAINS];
    let mut k = 0;
    while k < CHAINS {
        start[k] = pi[k % LANES].rotate_left(8 * (k / LANES) as u32);
        k += 1;
    }
    start
};

/// One step of a digest chain: `u = h ⊕ bits(v)`, then `u ← u + (u ≪ 21)` (a product by the
/// odd `1 + 2²¹`) and `u ← u ⊕ (u ≫ 29)`. Each operation is a bijection of `u`, and `u` one of
/// `h` and one-to-one in `v`; shifts and additions only, so that four chains share one SIMD
/// register (AVX2 has no 64-bit product).
#[inline(always)]
fn mix(h: u64, v: f64) -> u64 {
    let u = h ^ v.to_bits();
    let u = u.wrapping_add(u << 21);
    u ^ (u >> 29)
}

impl Scan {
    /// The scans of every channel of `record`: its forces, then its responses.
    pub(crate) fn channels(record: &Record) -> Vec<Self> {
        let n = record.dofs();
        (0..n)
            .map(|c| Self::new(record.force(c)))
            .chain((0..n).map(|c| Self::new(record.displacement(c))))
            .collect()
    }

    /// Both passes over `x`.
    pub(crate) fn new(x: &[f64]) -> Self {
        let mut scan = Arch::new().dispatch(Pass(x));
        if !x.is_empty() {
            let n = x.len() as f64;
            scan.mean /= n;
            let (top, bottom) = near_extremes(scan.lo, scan.hi);
            let (squares, digest, count) = Arch::new().dispatch(Spread {
                x,
                mean: scan.mean,
                top,
                bottom,
            });
            scan.rms = (squares / n).sqrt();
            scan.digest = digest;
            scan.near_extremes = count;
        }
        scan
    }

    /// The first pass over `x` (its `mean` still the sum, its `rms` 0), each of its folds in
    /// [`LANES`] lanes (kept as separate arrays, so each fold's lanes pack into SIMD
    /// registers). Samples are finite (a `Record` guarantees it), so comparisons stand in for
    /// `f64::min`/`max`.
    #[inline(always)]
    fn folded(x: &[f64]) -> Self {
        let (mut lo, mut hi, mut sum) = Self::whole_lanes(x);
        let rest = x.chunks_exact(LANES).remainder();
        for (j, &v) in rest.iter().enumerate() {
            lo[j] = lo[j].min(v);
            hi[j] = hi[j].max(v);
            sum[j] += v;
        }
        let min4 = |a: [f64; LANES]| a[0].min(a[1]).min(a[2].min(a[3]));
        Self {
            lo: min4(lo),
            hi: hi[0].max(hi[1]).max(hi[2].max(hi[3])),
            mean: (sum[0] + sum[1]) + (sum[2] + sum[3]),
            rms: 0.0,
            digest: DIGEST_START,
            near_extremes: 0,
        }
    }

    /// The lanes' minima, maxima and sums over the whole groups of [`LANES`] samples of `x`: a
    /// loop of its own, which the compiler turns into one SIMD minimum, maximum and sum per
    /// group (written in [`Scan::folded`] beside the remainder's `f64::min`, it compiled to
    /// compares, blends and lane shuffles, five times the instructions).
    #[inline(always)]
    fn whole_lanes(x: &[f64]) -> ([f64; LANES], [f64; LANES], [f64; LANES]) {
        let mut lo = [f64::INFINITY; LANES];
        let mut hi = [f64::NEG_INFINITY; LANES];
        let mut sum = [0.0; LANES];
        for c in x.chunks_exact(LANES) {
            for j in 0..LANES {
                let v = c[j];
                lo[j] = if v < lo[j] { v } else { lo[j] };
                hi[j] = if v > hi[j] { v } else { hi[j] };
                sum[j] += v;
            }
        }
        (lo, hi, sum)
    }

    /// The second pass over `x`: `Σ (x − c)²` as [`crate::lanes::sum_sq_dev`] sums it (the same
    /// operations in the same lanes, so the same bits), the digest's chains, and the number of
    /// samples at or above `top` or at or below `bottom`.
    #[inline(always)]
    fn spread(x: &[f64], c: f64, top: f64, bottom: f64) -> (f64, [u64; CHAINS], usize) {
        let mut a = [0.0; LANES];
        let mut near = [0u64; LANES];
        let mut digest = DIGEST_START;
        let groups = x.chunks_exact(CHAINS);
        let tail = groups.remainder();
        for g in groups {
            for q in 0..CHAINS / LANES {
                for j in 0..LANES {
                    let v = g[q * LANES + j];
                    a[j] += (v - c) * (v - c);
                    near[j] += u64::from((v >= top) | (v <= bottom));
                }
            }
            for (h, &v) in digest.iter_mut().zip(g) {
                *h = mix(*h, v);
            }
        }
        for (m, &v) in tail.iter().enumerate() {
            a[m % LANES] += (v - c) * (v - c);
            near[m % LANES] += u64::from((v >= top) | (v <= bottom));
            digest[m] = mix(digest[m], v);
        }
        let near = near.iter().sum::<u64>() as usize;
        ((a[0] + a[1]) + (a[2] + a[3]), digest, near)
    }
}

/// `min |x_{m+1} − x_m|` over the non-zero changes, +∞ if none: a channel's quantisation step
/// (the changes in [`LANES`] lanes, change `m` in lane `m mod LANES`; a minimum is exact in
/// any order).
pub(crate) fn smallest_step(x: &[f64]) -> f64 {
    struct Steps<'a>(&'a [f64]);
    impl WithSimd for Steps<'_> {
        type Output = f64;
        #[inline(always)]
        fn with_simd<S: Simd>(self, _: S) -> f64 {
            let x = self.0;
            let mut step = [f64::INFINITY; LANES];
            if x.len() < 2 {
                return f64::INFINITY;
            }
            let (before, after) = (&x[..x.len() - 1], &x[1..]);
            let b = before.chunks_exact(LANES);
            let a = after.chunks_exact(LANES);
            let (b_rest, a_rest) = (b.remainder(), a.remainder());
            for (b, a) in b.zip(a) {
                for j in 0..LANES {
                    let d = (a[j] - b[j]).abs();
                    step[j] = if d > 0.0 && d < step[j] { d } else { step[j] };
                }
            }
            for (j, (b, a)) in b_rest.iter().zip(a_rest).enumerate() {
                let d = (a - b).abs();
                step[j] = if d > 0.0 && d < step[j] { d } else { step[j] };
            }
            step[0].min(step[1]).min(step[2].min(step[3]))
        }
    }
    Arch::new().dispatch(Steps(x))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes;

    /// The second pass sums the squares as [`lanes::sum_sq_dev`] does, bit for bit, at every
    /// length about the digest's groups; a change of one sample (or one sample's sign) changes
    /// the digest, whichever chain it falls in.
    #[test]
    fn second_pass_matches_the_lanes_and_the_digest_sees_every_sample() {
        for len in [0, 1, 3, 4, 5, 15, 16, 17, 31, 33, 100, 8191] {
            let x: Vec<f64> = (0..len)
                .map(|m| (m as f64 * 0.37).sin() * 3.0 + 0.25)
                .collect();
            let scan = Scan::new(&x);
            if len > 0 {
                let n = len as f64;
                let mean = lanes::sum(&x) / n;
                assert_eq!(scan.mean.to_bits(), mean.to_bits(), "length {len}");
                let rms = (lanes::sum_sq_dev(&x, mean) / n).sqrt();
                assert_eq!(scan.rms.to_bits(), rms.to_bits(), "length {len}");
            }
            for m in 0..len {
                let mut y = x.clone();
                y[m] = -y[m];
                assert_ne!(
                    Scan::new(&y).digest,
                    scan.digest,
                    "length {len}, sample {m}"
                );
            }
        }
    }

    /// The count at the extremes is that of a plain filter against [`near_extremes`]'s levels,
    /// at every length about the lanes and groups, with samples at both extremes, scattered
    /// or in runs.
    #[test]
    fn count_at_the_extremes_is_the_filtered_count() {
        for len in [1, 3, 4, 5, 16, 17, 33, 100, 8191] {
            let mut x: Vec<f64> = (0..len).map(|m| (m as f64 * 0.37).sin()).collect();
            for m in (0..len).step_by(7) {
                x[m] = 1.5;
            }
            for m in (3..len).step_by(11) {
                x[m] = -2.0;
            }
            let scan = Scan::new(&x);
            let (top, bottom) = near_extremes(scan.lo, scan.hi);
            let filtered = x.iter().filter(|&&v| v >= top || v <= bottom).count();
            assert_eq!(scan.near_extremes, filtered, "length {len}");
            assert!(filtered >= 1);
        }
    }
}
