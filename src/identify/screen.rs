//! On the way to the spectra: record screening ([`crate::screening`]) for records at hand
//! and for records that stream in, the per-line test of paired sets, and the force-gate check
//! against the force pulses ([`ForceGateCheck`]); after the spectra, interference lines left out
//! and the record a failed fit can blame (one far out of scale with its siblings).

use std::borrow::Cow;
use std::time::Instant;

use crate::error::{Result, Warning};
use crate::frf::{Frf, FrfBuilder};
use crate::gate::ForceGateCheck;
use crate::records::Record;
use crate::screening::{self, Checks, Screener};
use crate::spectra::Segmentation;

use super::Settings;
use super::timings::{Timings, timed};

impl Settings {
    /// A check of the force gate against the pulses, when a gate is set on whole records.
    pub(super) fn pulse_check(&self) -> Option<ForceGateCheck> {
        match (self.force_gate, self.segmentation) {
            (Some(g), Segmentation::WholeRecord) => Some(ForceGateCheck::new(g)),
            _ => None,
        }
    }

    /// [`Warning::ForceGateShort`] if the force gate closes on a pulse of `records`.
    pub(super) fn pulse_warning(&self, records: &[Record]) -> Option<Warning> {
        let mut pulses = self.pulse_check();
        for r in records {
            observe(r, &mut pulses);
        }
        pulses.and_then(|p| p.warning())
    }

    /// The per-line test of paired sets ([`screening::outlier_sets`]) on what `builder`
    /// holds; under `reject` the outlying sets' records are taken back out. The sets' own
    /// impedances are the finish's work, done here first and kept for it: timed as `frf`.
    pub(super) fn screen_sets(
        &self,
        builder: &mut FrfBuilder,
        checks: &Checks,
        reject: bool,
        warnings: &mut Vec<Warning>,
        t: &mut Timings,
    ) -> Result<()> {
        let excitation = timed(&mut t.screen, || builder.excitations(&self.assignment))?;
        let table = timed(&mut t.frf, || builder.set_table(&excitation));
        let start = Instant::now();
        let outliers = screening::outlier_sets_by(
            table.sets(),
            table.lines(),
            table.dofs(),
            |s, l| table.impedance(s, l),
            checks,
        );
        let mut out = Vec::new();
        for o in outliers {
            let members = &table.records[o.set];
            let labels: Vec<String> = members
                .iter()
                .map(|&r| builder.label(r).to_owned())
                .collect();
            let warning = Warning::OutlierSet {
                records: labels.clone(),
                far_lines: o.far_lines,
                lines: o.lines,
            };
            if reject {
                let reason = screening::reason(&warning);
                out.extend(members.iter().copied());
                warnings.push(warning);
                warnings.extend(labels.into_iter().map(|record| Warning::Rejected {
                    record,
                    reason: reason.clone(),
                }));
            } else {
                warnings.push(warning);
            }
        }
        drop(table);
        builder.remove(&out);
        t.screen += start.elapsed();
        Ok(())
    }
}

/// Notes the force pulses of `record` for the force-gate check.
pub(super) fn observe(record: &Record, pulses: &mut Option<ForceGateCheck>) {
    if let Some(p) = pulses {
        let forces = (0..record.dofs()).map(|i| record.force(i));
        p.record(forces, 1.0 / record.sample_rate());
    }
}

/// Screens records that are all at hand: which to keep (all unless `reject`) and the warnings,
/// in record order (the per-line test of paired sets is separate, see
/// [`screening::outlier_sets`]).
pub(super) fn screen_batch(
    records: &[Record],
    checks: Checks,
    reject: bool,
) -> (Vec<bool>, Vec<Warning>) {
    let mut screener = Screener::new(checks);
    let mut findings: Vec<Vec<Warning>> = records.iter().map(|r| screener.push(r)).collect();
    let excluded: Vec<bool> = findings.iter().map(|f| reject && !f.is_empty()).collect();
    for (r, w) in screener.across(&excluded) {
        findings[r].push(w);
    }
    let kept = findings.iter().map(|f| !reject || f.is_empty()).collect();
    (kept, reported(screener.summaries(), findings, reject))
}

/// The records `kept`, borrowed when all are (the usual case: nothing is copied).
pub(super) fn kept_records<'a>(records: &'a [Record], kept: &[bool]) -> Cow<'a, [Record]> {
    if kept.iter().all(|&k| k) {
        return Cow::Borrowed(records);
    }
    let kept = records.iter().zip(kept).filter(|(_, k)| **k);
    Cow::Owned(kept.map(|(r, _)| r.clone()).collect())
}

/// The screening's warnings in record order, each faulty record's findings followed, under
/// `reject`, by its [`Warning::Rejected`].
pub(super) fn reported(
    summaries: &[screening::Summary],
    findings: Vec<Vec<Warning>>,
    reject: bool,
) -> Vec<Warning> {
    let mut warnings = Vec::new();
    for (summary, found) in summaries.iter().zip(findings) {
        if found.is_empty() {
            continue;
        }
        let reason: Vec<String> = found.iter().map(screening::reason).collect();
        warnings.extend(found);
        if reject {
            warnings.push(Warning::Rejected {
                record: summary.label().to_owned(),
                reason: reason.join("; "),
            });
        }
    }
    warnings
}

/// The record and, in words, the finding of a screening warning that puts a record far out of
/// scale with its siblings (a dead channel, a level outlier), if `w` is one.
pub(super) fn out_of_scale(w: &crate::Warning) -> Option<(String, String)> {
    match w {
        crate::Warning::DeadChannel {
            record,
            channel,
            rms,
            median_rms,
        }
        | crate::Warning::LevelOutlier {
            record,
            channel,
            rms,
            median_rms,
            ..
        } => Some((
            record.clone(),
            format!(
                "{channel} has RMS {rms:.3e}, {:.1e} times the median {median_rms:.3e} of its \
                 sibling records",
                rms / median_rms
            ),
        )),
        _ => None,
    }
}

/// `frf` without its interference lines (a force line far above its neighbours that the
/// responses do not follow: [`crate::frf::interference`]), and a
/// [`Warning::InterferenceLine`] for each run of them.
pub(super) fn without_interference(frf: Frf, builder: &FrfBuilder) -> (Frf, Vec<Warning>) {
    let Some(force) = builder.force_auto_spectra(&frf) else {
        return (frf, Vec::new());
    };
    let coherence: Vec<f64> = (0..frf.line_count())
        .map(|k| {
            frf.multiple_coherence(k)
                .map_or(1.0, |c| c.iter().copied().fold(f64::INFINITY, f64::min))
        })
        .collect();
    let found = crate::frf::interference::interference_lines(&force, &coherence);
    if found.is_empty() {
        return (frf, Vec::new());
    }
    let out: Vec<usize> = found.iter().flat_map(|i| i.lines.iter().copied()).collect();
    let warnings = found
        .iter()
        .map(|i| Warning::InterferenceLine {
            freq_hz: frf.freqs_hz()[i.peak],
            channel: crate::Channel::Force(i.channel),
            ratio: i.ratio,
            lines: i.lines.len(),
        })
        .collect();
    let kept = frf.retain_lines(|k| !out.contains(&k));
    (kept, warnings)
}
