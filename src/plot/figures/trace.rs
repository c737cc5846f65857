//! How much of a time trace the record figure shows and how it draws a long one: the force
//! plot's span around an impact, and min/max decimation to a few points per pixel.

use crate::Channel;
use crate::excitation::{IMPACT_CREST_FACTOR, crest_factor};
use crate::quality::ImpactIssue;
use crate::records::Record;

/// The time span of the force plot: for an impulsive record (its [`crest_factor`] at least [`IMPACT_CREST_FACTOR`]) the pulse
/// and what follows it closely — four times the peak's time, at least 80 ms past it, and the
/// force gate and any double hit with a quarter to spare; else the whole record.
pub(crate) fn force_span(
    record: &Record,
    gate: Option<crate::spectra::ForceGate>,
    issues: &[ImpactIssue],
) -> f64 {
    let fs = record.sample_rate();
    let whole = record.len() as f64 / fs;
    if crest_factor(record) < IMPACT_CREST_FACTOR {
        return whole;
    }
    let f = record.force(record.dominant_force());
    let mean = f.iter().sum::<f64>() / f.len() as f64;
    let Some((m, _)) = f
        .iter()
        .map(|v| (v - mean).abs())
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return whole;
    };
    let t_peak = m as f64 / fs;
    let mut end = (4.0 * t_peak).max(t_peak + 0.08);
    if let Some(g) = gate {
        end = end.max(1.25 * (g.open_s() + g.taper_s()));
    }
    for issue in issues {
        match *issue {
            ImpactIssue::DoubleHit { second_s, .. } => end = end.max(1.25 * second_s),
            ImpactIssue::Clipped {
                channel: Channel::Force(_),
                at_s,
                run,
                ..
            } => end = end.max(1.25 * (at_s + run as f64 / fs)),
            _ => {}
        }
    }
    // Two significant digits, rounded up: a readable span in the title.
    let step = 10f64.powf(end.log10().floor() - 1.0);
    ((end / step).ceil() * step).min(whole)
}

/// The minimum and maximum of `values` in each of `buckets` equal time slices, in time
/// order, divided by `scale`: a trace of any length drawn with a few points per pixel.
pub(crate) fn min_max(values: &[f64], fs: f64, scale: f64, buckets: usize) -> Vec<(f64, f64)> {
    let len = values.len();
    if len <= 2 * buckets {
        return values
            .iter()
            .enumerate()
            .map(|(m, v)| (m as f64 / fs, v / scale))
            .collect();
    }
    let mut out = Vec::with_capacity(2 * buckets);
    for b in 0..buckets {
        let (lo, hi) = (
            b * len / buckets,
            ((b + 1) * len / buckets).max(b * len / buckets + 1),
        );
        let slice = &values[lo..hi];
        let (mut imin, mut imax) = (0, 0);
        for (k, v) in slice.iter().enumerate() {
            if *v < slice[imin] {
                imin = k;
            }
            if *v > slice[imax] {
                imax = k;
            }
        }
        let (a, b) = (imin.min(imax), imin.max(imax));
        out.push(((lo + a) as f64 / fs, slice[a] / scale));
        if b != a {
            out.push(((lo + b) as f64 / fs, slice[b] / scale));
        }
    }
    out
}
