//! The clipping check: runs of samples at a channel's extremes (an overloaded ADC or
//! amplifier), found in blocks of [`CLIP_BLOCK`] samples tested at once in SIMD lanes.

use faer::traits::pulp::{Arch, Simd, WithSimd};

use super::scan::{near_extremes, smallest_step};
use super::{CLIP_SIDE_FRACTION, ImpactChecks, ImpactIssue, Scan};
use crate::error::Channel;

/// Longest run of consecutive samples meeting a condition, tracked one sample at a time.
#[derive(Debug, Clone, Copy, Default)]
struct Run {
    current: usize,
    current_start: usize,
    longest: usize,
    longest_start: usize,
}

impl Run {
    #[inline(always)]
    fn push(&mut self, i: usize, hit: bool) {
        if !hit {
            self.current = 0;
            return;
        }
        if self.current == 0 {
            self.current_start = i;
        }
        self.current += 1;
        if self.current > self.longest {
            (self.longest, self.longest_start) = (self.current, self.current_start);
        }
    }
}

/// The longest runs of samples at or above `top` and at or below `bottom` ([`clipping`]), as
/// an operation of faer's SIMD dispatch (a named type, so that the pass is compiled for the
/// instruction set chosen).
struct ExtremeRuns<'a> {
    x: &'a [f64],
    top: f64,
    bottom: f64,
}

impl WithSimd for ExtremeRuns<'_> {
    type Output = (Run, Run);

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) -> (Run, Run) {
        let Self { x, top, bottom } = self;
        let (mut at_hi, mut at_lo) = (Run::default(), Run::default());
        // Most blocks hold no sample near either extreme: one (vectorised) test clears a block.
        for (k, block) in x.chunks(CLIP_BLOCK).enumerate() {
            if !block
                .iter()
                .fold(false, |a, &v| a | (v >= top) | (v <= bottom))
            {
                at_hi.current = 0;
                at_lo.current = 0;
                continue;
            }
            for (j, &v) in block.iter().enumerate() {
                let i = k * CLIP_BLOCK + j;
                at_hi.push(i, v >= top);
                at_lo.push(i, v <= bottom);
            }
        }
        (at_hi, at_lo)
    }
}

/// Samples tested at once for a sample near an extreme ([`clipping`]).
const CLIP_BLOCK: usize = 16;

/// Pushes a [`ImpactIssue::Clipped`] for each clipped extreme of channel `x`.
pub(super) fn clipping(
    channel: Channel,
    x: &[f64],
    scan: &Scan,
    fs: f64,
    checks: &ImpactChecks,
    issues: &mut Vec<ImpactIssue>,
) {
    let (lo, hi) = (scan.lo, scan.hi);
    let range = hi - lo;
    if range <= 0.0 {
        return;
    }
    // Fewer samples at the extremes than a run needs (the scan counted them against the same
    // levels): no run is long enough, the channel is cleared without a pass of its own.
    if scan.near_extremes < checks.clip_run {
        return;
    }
    let mean = scan.mean;
    // The quantisation step: the smallest non-zero change between consecutive samples, found
    // only for a run long enough to report (one more pass over the channel).
    let mut step = None;
    let (top, bottom) = near_extremes(lo, hi);
    let (at_hi, at_lo) = Arch::new().dispatch(ExtremeRuns { x, top, bottom });
    for (value, run) in [(hi, at_hi), (lo, at_lo)] {
        if run.longest < checks.clip_run || (value - mean).abs() < CLIP_SIDE_FRACTION * range {
            continue;
        }
        // A smooth peak of a quantised signal sits on its top code for a few samples too, but
        // is flanked on both sides by samples one step below: not an overload.
        let end = run.longest_start + run.longest;
        let flanks = [
            run.longest_start.checked_sub(1).map(|i| x[i]),
            x.get(end).copied(),
        ];
        let quantised_peak = flanks.iter().all(|v| {
            v.is_some_and(|v| {
                let step = *step.get_or_insert_with(|| smallest_step(x));
                (value - v).abs() <= step * (1.0 + crate::tolerance::QUANTISATION_STEP)
            })
        });
        if !quantised_peak {
            issues.push(ImpactIssue::Clipped {
                channel,
                value,
                run: run.longest,
                at_s: run.longest_start as f64 / fs,
            });
        }
    }
}
