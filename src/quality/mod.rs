//! Quality checks of impact records: double hits and clipping.
//!
//! What lives where: the thresholds ([`ImpactChecks`]), the issues and the record's check are
//! here; the one pass over a channel shared with the screening in `scan.rs`, the double-hit
//! check in `double_hit.rs`, the clipping check in `clipping.rs`.
//!
//! Two faults spoil a real impact test without making the record invalid:
//!
//! - a **double hit**: the hammer bounces and strikes again, so the force holds two pulses and
//!   its spectrum a comb of notches where the impedance is poorly determined;
//! - **overload** (clipping): a channel saturates its ADC or amplifier range and holds a flat
//!   top of repeated extreme values, so the record is no longer the response of a linear system.
//!
//! [`check_record`] looks for both in one [`Record`] and returns every [`ImpactIssue`] found;
//! [`warnings`] turns them into [`Warning`]s that name the record. This stage reads records
//! only; whether a record with issues is warned about or rejected is the caller's choice.
//!
//! # Examples
//! ```
//! use bearing_ident::quality::{ImpactChecks, ImpactIssue, check_record};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//!
//! let checks = ImpactChecks::default();
//! checks.check()?;
//! let records = ImpactTest { per_direction: 1, noise: 0.05, ..ImpactTest::seed_rig() }
//!     .run(&seed_rig())?;
//! for record in &records {
//!     assert_eq!(check_record(record, &checks), Vec::<ImpactIssue>::new());
//! }
//! # Ok::<(), bearing_ident::Error>(())
//! ```

mod clipping;
mod double_hit;
mod scan;
use clipping::clipping;
pub(crate) use double_hit::MedianBuffers;
use double_hit::double_hit;
pub(crate) use scan::Scan;

use std::fmt;

use crate::error::{Channel, Error, Result, Warning};
use crate::records::Record;

/// The force has returned to zero after a pulse when `|f − baseline|` falls below this fraction
/// of the main peak (or below the noise floor, whichever is higher).
pub const RETURN_FRACTION: f64 = 0.05;

/// The noise floor is this many robust standard deviations, `σ̂ = 1.4826 · MAD`: an excursion
/// of a Gaussian noise sample beyond it has probability `1.2·10⁻¹⁵`.
pub const NOISE_SIGMAS: f64 = 8.0;

/// A pulse has ended (or not yet begun) once this many consecutive samples are below the
/// return level.
pub const QUIET_SAMPLES: usize = 3;

pub use crate::tolerance::CLIP_LEVEL as CLIP_TOLERANCE;

/// An extreme counts as a clipping level only if it lies at least this fraction of the
/// channel's range away from the channel's mean: a flat stretch at the resting level (the
/// exactly-zero pre-trigger of a one-sided force pulse, say) is not an overload.
pub const CLIP_SIDE_FRACTION: f64 = 0.25;

/// Crest factor at and above which a record's force is an impact.
///
/// Impacts concentrate their force in a few samples: crest factors of 10–100. Random forcing
/// has Gaussian-like crest factors of 3–5; a sine has `√2`, a multisine about 2–4. The crest
/// factor of the first record with a force is compared with 8 ([`Excitation::detect`](crate::Excitation::detect)); the
/// double-hit check of [`ImpactChecks`] applies only above it, and the record figure of `plot` shows
/// the pulse of such records.
///
/// # Examples
/// ```
/// use bearing_ident::excitation::{Excitation, IMPACT_CREST_FACTOR};
/// assert_eq!(Excitation::from_crest_factor(IMPACT_CREST_FACTOR), Excitation::Impact);
/// assert_eq!(Excitation::from_crest_factor(4.0), Excitation::Random);
/// ```
pub const IMPACT_CREST_FACTOR: f64 = 8.0;

/// Thresholds of the impact quality checks.
///
/// # Examples
/// ```
/// use bearing_ident::quality::ImpactChecks;
/// let checks = ImpactChecks::default();
/// assert_eq!(checks.clip_run, 3);
/// assert!((checks.double_hit_ratio - 0.1).abs() < 1e-15);
/// assert!((checks.min_crest_factor - 8.0).abs() < 1e-15);
/// assert!(checks.check().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactChecks {
    /// A pulse after (or before) the main one, once the force has returned to near zero, is a
    /// double hit if its peak exceeds this fraction of the main peak. Valid `(0, 1)`; default
    /// `0.1`.
    pub double_hit_ratio: f64,
    /// This many consecutive samples at a channel's maximum or minimum (within
    /// [`CLIP_TOLERANCE`] of its range) count as clipping. Valid `≥ 2` (every channel has one
    /// sample at its maximum); default `3`.
    pub clip_run: usize,
    /// The double-hit check applies only to impulsive records, whose dominant force has a crest
    /// factor `peak / RMS` (about the baseline) of at least this; a random or periodic
    /// excitation has no "main pulse". Clipping is checked on every record. Valid finite
    /// `≥ 0` (values up to 1 check every record); default `8`.
    pub min_crest_factor: f64,
}

impl Default for ImpactChecks {
    fn default() -> Self {
        Self {
            double_hit_ratio: 0.1,
            clip_run: 3,
            min_crest_factor: IMPACT_CREST_FACTOR,
        }
    }
}

impl ImpactChecks {
    /// Checks that every threshold is in its valid range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first field out of range: `double_hit_ratio`
    /// outside `(0, 1)`, `clip_run < 2`, `min_crest_factor` negative or not finite.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::quality::ImpactChecks;
    /// use bearing_ident::{Error, Parameter};
    /// let bad = ImpactChecks { clip_run: 1, ..ImpactChecks::default() };
    /// assert!(matches!(
    ///     bad.check(),
    ///     Err(Error::InvalidParameter { name: Parameter::ClipRun, .. })
    /// ));
    /// ```
    pub fn check(&self) -> Result<()> {
        if !(self.double_hit_ratio > 0.0 && self.double_hit_ratio < 1.0) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::DoubleHitRatio,
                value: self.double_hit_ratio,
                expected: "0 < ratio < 1",
            });
        }
        if self.clip_run < 2 {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::ClipRun,
                value: self.clip_run as f64,
                expected: "at least 2 samples",
            });
        }
        if !(self.min_crest_factor >= 0.0 && self.min_crest_factor.is_finite()) {
            return Err(Error::InvalidParameter {
                name: crate::Parameter::MinCrestFactor,
                value: self.min_crest_factor,
                expected: "finite and ≥ 0",
            });
        }
        Ok(())
    }
}

/// A fault found in one record by [`check_record`].
///
/// # Examples
/// ```
/// use bearing_ident::Channel;
/// use bearing_ident::quality::ImpactIssue;
/// let issue = ImpactIssue::Clipped {
///     channel: Channel::Force(0),
///     value: 350.0,
///     run: 6,
///     at_s: 0.0212,
/// };
/// assert_eq!(
///     issue.to_string(),
///     "force channel 0 clipped: 6 consecutive samples at 3.5000e2 from 0.0212 s"
/// );
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum ImpactIssue {
    /// The dominant force channel holds a second pulse, separated from the main one by a return
    /// to near zero.
    DoubleHit {
        /// The force channel checked (the record's
        /// [`dominant_force`](Record::dominant_force)).
        channel: usize,
        /// Time of the main (largest) pulse's peak sample (s from the first sample).
        first_s: f64,
        /// Time of the extra pulse's peak sample (s); before `first_s` if the larger hit came
        /// second.
        second_s: f64,
        /// Peak of the extra pulse over the main peak, both about the baseline, in `(0, 1]`.
        ratio: f64,
    },
    /// A channel sits at its maximum or minimum for a run of consecutive samples.
    Clipped {
        /// The channel.
        channel: Channel,
        /// The clipping level: the channel's maximum or minimum (N or m).
        value: f64,
        /// Length of the longest run at that level (samples).
        run: usize,
        /// Time of the run's first sample (s).
        at_s: f64,
    },
}

impl fmt::Display for ImpactIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImpactIssue::DoubleHit {
                channel,
                first_s,
                second_s,
                ratio,
            } => write!(
                f,
                "double hit on force channel {channel}: a second pulse at {second_s:.4} s of \
                 {ratio:.2} × the main peak at {first_s:.4} s"
            ),
            ImpactIssue::Clipped {
                channel,
                value,
                run,
                at_s,
            } => write!(
                f,
                "{channel} clipped: {run} consecutive samples at {value:.4e} from {at_s:.4} s"
            ),
        }
    }
}

impl ImpactIssue {
    /// The [`Warning`] that reports this issue for the record labelled `record`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Warning;
    /// use bearing_ident::quality::ImpactIssue;
    /// let issue = ImpactIssue::DoubleHit { channel: 0, first_s: 0.021, second_s: 0.051, ratio: 0.3 };
    /// let w = issue.warning("hit-x-3");
    /// assert!(matches!(w, Warning::DoubleHit { ref record, .. } if record == "hit-x-3"));
    /// assert_eq!(
    ///     w.to_string(),
    ///     "record `hit-x-3`: double hit, a second pulse at 0.0510 s of 0.30 × the main peak"
    /// );
    /// ```
    pub fn warning(&self, record: &str) -> Warning {
        match *self {
            ImpactIssue::DoubleHit {
                second_s, ratio, ..
            } => Warning::DoubleHit {
                record: record.to_owned(),
                second_s,
                ratio,
            },
            ImpactIssue::Clipped { channel, value, .. } => Warning::Clipped {
                record: record.to_owned(),
                channel,
                value,
            },
        }
    }
}

/// The warnings that report `issues` found in `record`, one per issue and in the same order.
///
/// # Examples
/// ```
/// use bearing_ident::{Channel, Record, Warning};
/// use bearing_ident::quality::{ImpactChecks, check_record, warnings};
/// // A 1-DOF record whose force saturates at 80 N for four samples.
/// let mut f = vec![0.0; 64];
/// f[10..16].copy_from_slice(&[30.0, 80.0, 80.0, 80.0, 80.0, 30.0]);
/// let x: Vec<f64> = (0..64).map(|m| 1e-6 * (0.3 * m as f64).sin()).collect();
/// let record = Record::new("hit-7", 1000.0, vec![f], vec![x])?;
/// let issues = check_record(&record, &ImpactChecks::default());
/// let w = warnings(&record, &issues);
/// assert_eq!(
///     w,
///     vec![Warning::Clipped { record: "hit-7".into(), channel: Channel::Force(0), value: 80.0 }]
/// );
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn warnings(record: &Record, issues: &[ImpactIssue]) -> Vec<Warning> {
    issues.iter().map(|i| i.warning(record.label())).collect()
}

/// Checks one record for a double hit and for clipped channels.
///
/// Issues come in this order: the double hit, if any, then clipping by channel (forces, then
/// displacements, each in DOF order; the maximum before the minimum).
///
/// **Double hit**, on the dominant force channel `f`
/// ([`Record::dominant_force`]):
/// 1. baseline `b` = median of `f` (the upper median for an even length); noise
///    `σ̂ = 1.4826 · median|f − b|` (the MAD, robust to the pulses);
/// 2. main peak `P = max|f − b|` at sample `p`; records with a crest factor
///    `P / rms(f − b)` below [`ImpactChecks::min_crest_factor`] are not checked;
/// 3. return level `r = max(`[`RETURN_FRACTION`]` · P, `[`NOISE_SIGMAS`]` · σ̂)`; the main
///    pulse spans from `p` out to the first [`QUIET_SAMPLES`] consecutive samples with
///    `|f − b| < r` on either side;
/// 4. outside that span, the largest excursion of the main pulse's sign,
///    `s·(f − b)` with `s = sign(f_p − b)`, is a double hit if it exceeds
///    `max(`[`ImpactChecks::double_hit_ratio`]` · P, r)` — above the noise floor as well as
///    the ratio, so noise alone never reports one. Swings of the opposite sign are ringing,
///    not a hammer (a hammer pushes, it never pulls).
///
/// At most one double hit is reported (the largest extra pulse). A bounce that strikes before
/// the force has returned below `r` merges with the main pulse and is not seen.
///
/// **Clipping**, on every channel `x` with a non-zero range `R = max x − min x`: for each
/// extreme `e ∈ {max x, min x}` the longest run of consecutive samples with `|x − e| ≤`
/// [`CLIP_TOLERANCE`]` · R`; a run of at least [`ImpactChecks::clip_run`] samples is clipping
/// provided `|e − mean x| ≥ `[`CLIP_SIDE_FRACTION`]` · R`, so a flat resting level that
/// happens to be the extreme (a noise-free pre-trigger before a one-sided pulse) is not
/// reported. A constant channel is not reported. Nor is a run flanked on both sides by samples
/// within one quantisation step of the extreme (the step being the smallest non-zero change
/// between consecutive samples): a smooth peak of a quantised (ADC-coded) signal sits on its
/// top code for a few samples, an overload is approached from well below (an overload barely
/// past the level, its flanks within one step, is therefore not reported: it distorts by at
/// most one step).
///
/// Cost: one copy of the dominant force for the two medians (linear-time selection; skipped
/// when `min_crest_factor` is infinite), two passes over it and two passes over every channel
/// (one shared with the screening, one for the runs); nothing else is allocated per sample.
///
/// The thresholds are not validated here: call [`ImpactChecks::check`] once for a batch
/// (invalid thresholds give meaningless issues, never a panic).
///
/// # Examples
/// A hammer that bounces back 30 ms after the hit with 30 % of the force:
/// ```
/// use bearing_ident::quality::{ImpactChecks, ImpactIssue, check_record};
/// use bearing_ident::simulate::{AntiAlias, Impact, Simulator, seed_rig};
///
/// let mut sim = Simulator::new(&seed_rig(), 6700.0, 8040, AntiAlias::default())?;
/// let hit = |peak_n: f64, start_s: f64| Impact {
///     direction: vec![1.0, 0.0],
///     peak_n,
///     duration_s: 0.002,
///     start_s,
/// };
/// let record = sim.record("bounce", &[hit(500.0, 0.02), hit(150.0, 0.05)])?;
/// let issues = check_record(&record, &ImpactChecks::default());
/// assert_eq!(issues.len(), 1);
/// let ImpactIssue::DoubleHit { channel, second_s, ratio, .. } = issues[0] else {
///     panic!("expected a double hit, got {issues:?}");
/// };
/// assert_eq!(channel, 0);
/// assert!((second_s - 0.051).abs() < 0.002); // peak of the second pulse
/// assert!((ratio - 0.3).abs() < 0.01);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn check_record(record: &Record, checks: &ImpactChecks) -> Vec<ImpactIssue> {
    let scans = Scan::channels(record);
    let mut buffers = MedianBuffers::default();
    check_scanned(
        record,
        checks,
        record.dominant_force(),
        &scans,
        &mut buffers,
    )
}

/// [`check_record`] from the record's dominant force and the [`Scan`]s of its channels (forces,
/// then displacements, in DOF order), each done once by the caller and shared; `buffers` kept by
/// the caller from one record to the next.
pub(crate) fn check_scanned(
    record: &Record,
    checks: &ImpactChecks,
    dominant: usize,
    scans: &[Scan],
    buffers: &mut MedianBuffers,
) -> Vec<ImpactIssue> {
    let fs = record.sample_rate();
    let mut issues = Vec::new();
    let channel = dominant;
    if let Some((first, second, ratio)) =
        double_hit(record.force(channel), checks, &scans[channel], buffers)
    {
        issues.push(ImpactIssue::DoubleHit {
            channel,
            first_s: first as f64 / fs,
            second_s: second as f64 / fs,
            ratio,
        });
    }
    let n = record.dofs();
    for (c, scan) in scans[..n].iter().enumerate() {
        let x = record.force(c);
        clipping(Channel::Force(c), x, scan, fs, checks, &mut issues);
    }
    for c in 0..n {
        let x = record.displacement(c);
        clipping(
            Channel::Displacement(c),
            x,
            &scans[n + c],
            fs,
            checks,
            &mut issues,
        );
    }
    issues
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(force: Vec<f64>, displacement: Vec<f64>) -> Record {
        Record::new("t", 1000.0, vec![force], vec![displacement]).unwrap()
    }

    /// A smooth displacement with no repeated extremes.
    fn smooth(n: usize) -> Vec<f64> {
        (0..n).map(|m| 1e-6 * (0.3 * m as f64).sin()).collect()
    }

    /// Triangular pulse of `peak` centred on `at`, 5 samples wide.
    pub(super) fn pulse(f: &mut [f64], at: usize, peak: f64) {
        for (k, w) in [0.5, 1.0, 0.5].iter().enumerate() {
            f[at + k - 1] += peak * w;
        }
    }

    #[test]
    fn each_invalid_setting_is_named() {
        let d = ImpactChecks::default();
        let cases = [
            (
                ImpactChecks {
                    double_hit_ratio: 0.0,
                    ..d
                },
                "double_hit_ratio",
            ),
            (
                ImpactChecks {
                    double_hit_ratio: 1.0,
                    ..d
                },
                "double_hit_ratio",
            ),
            (
                ImpactChecks {
                    double_hit_ratio: f64::NAN,
                    ..d
                },
                "double_hit_ratio",
            ),
            (ImpactChecks { clip_run: 1, ..d }, "clip_run"),
            (
                ImpactChecks {
                    min_crest_factor: -1.0,
                    ..d
                },
                "min_crest_factor",
            ),
            (
                ImpactChecks {
                    min_crest_factor: f64::INFINITY,
                    ..d
                },
                "min_crest_factor",
            ),
        ];
        for (checks, field) in cases {
            let e = checks.check().unwrap_err();
            assert!(
                matches!(e, Error::InvalidParameter { name, .. } if name.as_str() == field),
                "{checks:?}: {e:?}"
            );
            assert_eq!(e.kind(), "invalid_argument");
        }
        assert_eq!(ImpactChecks { clip_run: 2, ..d }.check(), Ok(()));
    }

    #[test]
    fn second_pulse_after_return_to_zero_is_a_double_hit() {
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        pulse(&mut f, 90, 25.0);
        let issues = check_record(&record(f, smooth(200)), &ImpactChecks::default());
        assert_eq!(
            issues,
            vec![ImpactIssue::DoubleHit {
                channel: 0,
                first_s: 0.050,
                second_s: 0.090,
                ratio: 0.25
            }]
        );
    }

    #[test]
    fn larger_hit_second_reports_the_earlier_one() {
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 40.0);
        pulse(&mut f, 90, 100.0);
        let issues = check_record(&record(f, smooth(200)), &ImpactChecks::default());
        assert_eq!(
            issues,
            vec![ImpactIssue::DoubleHit {
                channel: 0,
                first_s: 0.090,
                second_s: 0.050,
                ratio: 0.4
            }]
        );
    }

    #[test]
    fn bounce_without_return_to_zero_is_one_pulse() {
        // The force dips to 30 % between the hits: never below the 5 % return level.
        let mut f = vec![0.0; 200];
        f[48..55].copy_from_slice(&[50.0, 100.0, 60.0, 30.0, 30.0, 40.0, 20.0]);
        let issues = check_record(&record(f, smooth(200)), &ImpactChecks::default());
        assert_eq!(issues, vec![]);
    }

    #[test]
    fn opposite_swing_is_not_a_second_hit() {
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        pulse(&mut f, 90, -40.0);
        let issues = check_record(&record(f, smooth(200)), &ImpactChecks::default());
        assert_eq!(issues, vec![]);
    }

    #[test]
    fn excursion_below_the_ratio_is_not_a_double_hit() {
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        pulse(&mut f, 90, 9.0);
        let r = record(f, smooth(200));
        assert_eq!(check_record(&r, &ImpactChecks::default()), vec![]);
        let finer = ImpactChecks {
            double_hit_ratio: 0.08,
            ..ImpactChecks::default()
        };
        assert!(matches!(
            check_record(&r, &finer)[..],
            [ImpactIssue::DoubleHit { second_s, .. }] if (second_s - 0.090).abs() < 1e-12
        ));
    }

    #[test]
    fn low_crest_factor_skips_the_double_hit_check() {
        // A train of ten pulses, 100 N down to 55 N: crest factor about 4.
        let mut f = vec![0.0; 200];
        for k in 0..10 {
            pulse(&mut f, 10 + 20 * k, 100.0 - 5.0 * k as f64);
        }
        let r = record(f, smooth(200));
        assert_eq!(check_record(&r, &ImpactChecks::default()), vec![]);
        let always = ImpactChecks {
            min_crest_factor: 0.0,
            ..ImpactChecks::default()
        };
        assert_eq!(
            check_record(&r, &always),
            vec![ImpactIssue::DoubleHit {
                channel: 0,
                first_s: 0.010,
                second_s: 0.030,
                ratio: 0.95
            }]
        );
    }

    #[test]
    fn flat_top_at_each_extreme_is_clipping() {
        let mut x = smooth(200);
        for v in &mut x[20..25] {
            *v = 2e-6;
        }
        for v in &mut x[100..104] {
            *v = -3e-6;
        }
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        let issues = check_record(&record(f, x), &ImpactChecks::default());
        assert_eq!(
            issues,
            vec![
                ImpactIssue::Clipped {
                    channel: Channel::Displacement(0),
                    value: 2e-6,
                    run: 5,
                    at_s: 0.020
                },
                ImpactIssue::Clipped {
                    channel: Channel::Displacement(0),
                    value: -3e-6,
                    run: 4,
                    at_s: 0.100
                },
            ]
        );
    }

    #[test]
    fn run_shorter_than_clip_run_is_not_clipping() {
        let mut x = smooth(200);
        x[20] = 2e-6;
        x[21] = 2e-6;
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        let r = record(f, x);
        assert_eq!(check_record(&r, &ImpactChecks::default()), vec![]);
        let two = ImpactChecks {
            clip_run: 2,
            ..ImpactChecks::default()
        };
        assert_eq!(check_record(&r, &two).len(), 1);
    }

    #[test]
    fn resting_level_at_the_extreme_is_not_clipping() {
        // Exactly zero before and after a positive pulse: zero is the minimum, and it is the
        // resting level.
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        let r = record(f, smooth(200));
        assert_eq!(check_record(&r, &ImpactChecks::default()), vec![]);
    }

    #[test]
    fn constant_channel_is_not_clipping() {
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        let r = Record::new(
            "t",
            1000.0,
            vec![f, vec![0.0; 200]],
            vec![smooth(200), vec![1e-3; 200]],
        )
        .unwrap();
        assert_eq!(check_record(&r, &ImpactChecks::default()), vec![]);
    }

    #[test]
    fn issues_become_warnings_naming_the_record() {
        let mut f = vec![0.0; 200];
        pulse(&mut f, 50, 100.0);
        pulse(&mut f, 90, 30.0);
        let r = Record::new("hit-x-2", 1000.0, vec![f], vec![smooth(200)]).unwrap();
        let issues = check_record(&r, &ImpactChecks::default());
        let w = warnings(&r, &issues);
        assert_eq!(
            w,
            vec![Warning::DoubleHit {
                record: "hit-x-2".into(),
                second_s: 0.090,
                ratio: 0.3
            }]
        );
    }
}
