//! The record screener ([`Screener`]): each record alone as it arrives, then each against its
//! siblings once all have arrived.

use std::collections::{BTreeMap, HashMap};

use crate::error::{Channel, Warning};
use crate::quality::{self, ImpactChecks, MedianBuffers, Scan};
use crate::records::{Record, Response};

use super::summary::{Summary, flat};
use super::{Checks, MAD_TO_SIGMA, MIN_SIBLINGS, upper_median};
use crate::tolerance::NEAR_DUPLICATE;

/// Screens records one at a time, keeping only their [`Summary`], then across them.
///
/// # Examples
/// The same record passed twice under two labels:
/// ```
/// use bearing_ident::screening::{Checks, Screener};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// use bearing_ident::Warning;
/// let records = ImpactTest { per_direction: 1, noise: 0.05, ..ImpactTest::seed_rig() }
///     .run(&seed_rig())?;
/// let r = &records[0];
/// let copy = bearing_ident::Record::new("copy.csv", r.sample_rate(),
///     vec![r.force(0).to_vec(), r.force(1).to_vec()],
///     vec![r.displacement(0).to_vec(), r.displacement(1).to_vec()])?;
/// let mut screener = Screener::new(Checks::default());
/// assert!(screener.push(&records[0]).is_empty());
/// assert!(screener.push(&records[1]).is_empty());
/// assert_eq!(
///     screener.push(&copy),
///     vec![Warning::DuplicateRecord { record: "copy.csv".into(), of: "impact-dof0-0".into() }]
/// );
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Screener {
    checks: Checks,
    summaries: Vec<Summary>,
    first_with: HashMap<u64, usize>,
    /// The records of `first_with` by the bits of their [`Summary::peak_sum`] (non-negative,
    /// so the bits order as the numbers): where a copy up to rounding is looked for.
    by_peak_sum: BTreeMap<u64, Vec<usize>>,
    /// The double-hit check's buffers, kept from one record to the next.
    buffers: MedianBuffers,
}

impl Screener {
    /// A screener with `checks` (check them first: [`Checks::check`]; invalid
    /// thresholds give meaningless findings, never a panic).
    pub fn new(checks: Checks) -> Self {
        Self {
            checks,
            summaries: Vec::new(),
            first_with: HashMap::new(),
            by_peak_sum: BTreeMap::new(),
            buffers: MedianBuffers::default(),
        }
    }

    /// The summaries of the records pushed, in order.
    pub fn summaries(&self) -> &[Summary] {
        &self.summaries
    }

    /// Screens `record` on its own and against the earlier ones' hashes, and keeps its
    /// summary: flat channels, clipping, a double hit, a duplicate of an earlier record (in
    /// that order). Empty if it passes.
    pub fn push(&mut self, record: &Record) -> Vec<Warning> {
        let label = record.label();
        let mut found = Vec::new();
        let n = record.dofs();
        // One pass over each channel serves the flat test, the record checks and the summary.
        let scans = Scan::channels(record);
        let dominant = record.dominant_force();
        let forces_flat: Vec<Option<f64>> = scans[..n].iter().map(flat).collect();
        if forces_flat.iter().all(Option::is_some) {
            for (c, v) in forces_flat.iter().enumerate() {
                found.push(Warning::FlatChannel {
                    record: label.to_owned(),
                    channel: Channel::Force(c),
                    value: v.unwrap_or_default(),
                });
            }
        }
        for c in 0..n {
            if let Some(value) = flat(&scans[n + c]) {
                found.push(Warning::FlatChannel {
                    record: label.to_owned(),
                    channel: Channel::Displacement(c),
                    value,
                });
            }
        }
        // Clipping on every excitation; the double hit only with the impact checks (and even
        // then only on impulsive records).
        let impact = self.checks.impact.unwrap_or(ImpactChecks {
            min_crest_factor: f64::INFINITY,
            ..ImpactChecks::default()
        });
        let impact = ImpactChecks {
            clip_run: self.checks.clip_run,
            ..impact
        };
        let issues = quality::check_scanned(record, &impact, dominant, &scans, &mut self.buffers);
        found.extend(quality::warnings(record, &issues));
        let mut summary = Summary::scanned(record, dominant, &scans);
        summary.flat = found
            .iter()
            .filter_map(|w| match w {
                Warning::FlatChannel { channel, .. } => Some(*channel),
                _ => None,
            })
            .collect();
        // The same bits, or (a copy written with fewer digits) the same values up to rounding,
        // looked for among the records of about the same sum of peaks only (not every earlier
        // record: 10 000 records made 50 million comparisons).
        let first = self.first_with.get(&summary.hash).copied().or_else(|| {
            self.about_the_same_peaks(&summary)
                .filter(|&f| summary.copies(&self.summaries[f]))
                .min()
        });
        match first {
            Some(first) => found.push(Warning::DuplicateRecord {
                record: label.to_owned(),
                of: self.summaries[first].label.clone(),
            }),
            None => {
                self.first_with.insert(summary.hash, self.summaries.len());
                let sum = summary.peak_sum();
                if sum.is_finite() && sum > 0.0 {
                    let records = self.by_peak_sum.entry(sum.to_bits()).or_default();
                    records.push(self.summaries.len());
                }
            }
        }
        self.summaries.push(summary);
        found
    }

    /// The earlier records (of `first_with`) whose [`Summary::peak_sum`] is within twice
    /// [`NEAR_DUPLICATE`] of `summary`'s, relative (once for the copy, once more to spare for
    /// the sums' rounding): every record `summary` [copies](Summary::copies) is among them.
    fn about_the_same_peaks(&self, summary: &Summary) -> impl Iterator<Item = usize> + '_ {
        let sum = summary.peak_sum();
        // A copy has some channel not zero: a positive sum.
        let range = (sum.is_finite() && sum > 0.0).then(|| {
            let lo = sum * (1.0 - 2.0 * NEAR_DUPLICATE);
            let hi = sum * (1.0 + 2.0 * NEAR_DUPLICATE);
            lo.to_bits()..=hi.to_bits()
        });
        range
            .into_iter()
            .flat_map(|range| self.by_peak_sum.range(range))
            .flat_map(|(_, records)| records.iter().copied())
    }

    /// Screens every record pushed against its siblings (see the [module docs](crate::screening)): dead
    /// channels and level outliers, as `(record index, warning)` in record order. Records
    /// with `excluded[r]` (left out already) are neither judged nor counted among siblings;
    /// `excluded` shorter than the records pushed excludes nothing beyond its end. Channels
    /// already reported flat are not judged again.
    pub fn across(&self, excluded: &[bool]) -> Vec<(usize, Warning)> {
        let included: Vec<usize> = (0..self.summaries.len())
            .filter(|&r| !excluded.get(r).copied().unwrap_or(false))
            .collect();
        let mut groups: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for &r in &included {
            groups
                .entry(self.summaries[r].pattern())
                .or_default()
                .push(r);
        }
        let mut found = Vec::new();
        let log_floor = self.checks.level_factor.ln();
        type Key = (Option<usize>, Channel, Option<Response>);
        let mut cache: HashMap<Key, Siblings> = HashMap::new();
        for &r in &included {
            let summary = &self.summaries[r];
            let key = summary.pattern();
            let (key, siblings, with_level) = match &groups[&key] {
                g if g.len() >= MIN_SIBLINGS => (Some(key), g, true),
                _ if included.len() >= MIN_SIBLINGS => (None, &included, false),
                _ => continue,
            };
            for channel in summary.channels() {
                if summary.flat.contains(&channel) {
                    continue;
                }
                let kind = summary.kind(channel);
                let s = cache
                    .entry((key, channel, kind))
                    .or_insert_with(|| self.siblings(siblings, channel, kind));
                if s.median_rms <= 0.0 {
                    continue;
                }
                let rms = summary.rms(channel);
                let record = summary.label.clone();
                let median_rms = s.median_rms;
                if rms < self.checks.dead_ratio * median_rms {
                    found.push((
                        r,
                        Warning::DeadChannel {
                            record,
                            channel,
                            rms,
                            median_rms,
                        },
                    ));
                    continue;
                }
                let off = (rms.ln() - s.centre).abs();
                if with_level && off > log_floor && off > self.checks.level_sigmas * s.sigma {
                    found.push((
                        r,
                        Warning::LevelOutlier {
                            record,
                            channel,
                            rms,
                            median_rms,
                            sigmas: off / s.sigma,
                        },
                    ));
                }
            }
        }
        found
    }

    /// The statistics of `channel` over the records `siblings` whose channel measures `kind`
    /// (a response's [`Response`]; `None` for a force).
    fn siblings(&self, siblings: &[usize], channel: Channel, kind: Option<Response>) -> Siblings {
        let values: Vec<f64> = siblings
            .iter()
            .filter(|&&r| self.summaries[r].kind(channel) == kind)
            .map(|&r| self.summaries[r].rms(channel))
            .collect();
        let median_rms = upper_median(&mut values.clone());
        let mut logs: Vec<f64> = values
            .iter()
            .filter(|&&v| v >= self.checks.dead_ratio * median_rms && v > 0.0)
            .map(|v| v.ln())
            .collect();
        let centre = upper_median(&mut logs);
        logs.iter_mut().for_each(|l| *l = (*l - centre).abs());
        Siblings {
            median_rms,
            centre,
            sigma: MAD_TO_SIGMA * upper_median(&mut logs),
        }
    }
}

/// A channel's level over a record's siblings.
#[derive(Debug, Clone, Copy)]
struct Siblings {
    /// Median RMS.
    median_rms: f64,
    /// Median log RMS of the live ones.
    centre: f64,
    /// `1.4826 · MAD` of their log RMS.
    sigma: f64,
}
