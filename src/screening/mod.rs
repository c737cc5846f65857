//! Record screening for every excitation kind: dead and flat channels, identical records,
//! clipping, level outliers, double hits (impacts), and paired sets whose impedance is far from
//! the others'.
//!
//! A real test spoils some records without making them invalid: a hammer hit that did not
//! register leaves a force channel at zero, a file is passed twice, an amplifier overloads, a
//! gain is set wrong, a cable is swapped. Each goes straight into the coefficients (a dead
//! force channel in one record of sixteen scales `M` and `K` by `7/8`). This stage finds
//! them, per record and channel, and reports each as a typed [`Warning`] that names the record
//! and the channel with the numbers.
//!
//! # What is checked
//! On each record alone, as it arrives ([`Screener::push`]):
//! - **flat channel** ([`Warning::FlatChannel`]): every sample within [`FLAT_TOLERANCE`] of
//!   the channel's largest magnitude of one value (all zero, or a constant). Displacement
//!   channels always; force channels when *every* force channel of the record is flat (no
//!   excitation at all). A single flat force channel next to live ones is the undriven
//!   direction of a one-shaker test as often as a fault, so it is judged against its siblings
//!   (below) instead;
//! - **clipping** ([`Warning::Clipped`], [`quality::check_record`](crate::quality::check_record)): a run of
//!   [`Checks::clip_run`] samples at a channel's extreme, away from its mean, on every
//!   excitation;
//! - **double hit** ([`Warning::DoubleHit`]), with [`Checks::impact`] set, on impulsive
//!   records only (crest factor ≥ [`ImpactChecks::min_crest_factor`]);
//! - **identical records** ([`Warning::DuplicateRecord`]): a 64-bit hash of the bits of every
//!   sample of every channel (not the label) equal to an earlier record's, or a copy up to
//!   rounding (written again with 8 or fewer digits): a fingerprint of samples, extremes, mean
//!   and RMS per channel within [`NEAR_DUPLICATE`](crate::tolerance::NEAR_DUPLICATE) of the
//!   channel's peak.
//!
//! Across records, once all have arrived ([`Screener::across`]), each record against its
//! **siblings**, the records excited the same way: a record whose dominant force
//! ([`Record::dominant_force`](crate::Record::dominant_force)) has at least [`DOMINANCE`] times the RMS of every other force
//! channel is excited in that one direction (impacts, a shaker per direction) and its siblings
//! are the records excited in the same direction; the others (multi-input random) are
//! siblings of one another. A record with fewer than [`MIN_SIBLINGS`] siblings (itself
//! included) is judged against all records, for dead channels only (levels legitimately differ
//! between directions); with fewer than [`MIN_SIBLINGS`] records in all nothing is judged (a
//! median of two says nothing). Per channel `c` with sibling median RMS `m_c > 0` (RMS of the
//! mean-removed samples):
//! - **dead channel** ([`Warning::DeadChannel`]): `rms < `[`Checks::dead_ratio`]` · m_c`;
//! - **level outlier** ([`Warning::LevelOutlier`]): with `ℓ = ln rms` over the live siblings,
//!   `|ℓ − median ℓ| > max(`[`Checks::level_sigmas`]` · σ̂, ln `[`Checks::level_factor`]`)`,
//!   `σ̂ = 1.4826 · MAD(ℓ)`. The factor floor keeps records that agree to a fraction of a
//!   percent (simulated multisines of one RMS) from flagging each other over nothing.
//!
//! Per band line, paired sets ([`outlier_sets`]): at each line and element the median of the
//! sets' impedances (real and imaginary parts apart) and the MAD of the distances to it; a set
//! is *far* at a line when some element is more than [`Checks::set_sigmas`]` · σ̂` and more
//! than [`Checks::set_floor`] of the line's median impedance (Frobenius norm) away. A set far
//! at more than [`Checks::set_fraction`] of the tested lines is reported
//! ([`Warning::OutlierSet`]). Needs at least 3 sets. Cross-spectral estimators (H1, H2, Hv)
//! pool every record's cross-spectra line by line: their records are screened per record and
//! across siblings, not per line.
//!
//! Only small per-record summaries are kept ([`Summary`]: RMS per channel, hash, dominant
//! force), never the records.
//!
//! # Examples
//! The issue's case: a hammer hit that did not register (both force channels zero) in one of
//! sixteen impact records.
//! ```
//! use bearing_ident::screening::{Checks, Screener};
//! use bearing_ident::simulate::{ImpactTest, seed_rig};
//! use bearing_ident::{Record, Warning};
//! let mut records = ImpactTest { per_direction: 3, noise: 0.05, ..ImpactTest::seed_rig() }
//!     .run(&seed_rig())?;
//! let r = &records[1];
//! let zero = vec![0.0; r.len()];
//! records[1] = Record::new(r.label(), r.sample_rate(), vec![zero.clone(), zero],
//!     vec![r.displacement(0).to_vec(), r.displacement(1).to_vec()])?;
//! let mut screener = Screener::new(Checks::default());
//! let found: Vec<Vec<Warning>> = records.iter().map(|r| screener.push(r)).collect();
//! assert!(found[0].is_empty());
//! assert_eq!(found[1].len(), 2);
//! assert_eq!(
//!     found[1][0].to_string(),
//!     "record `impact-dof0-1`: force channel 0 is flat, every sample at 0.0000e0 \
//!      (a dead or disconnected sensor)"
//! );
//! # Ok::<(), bearing_ident::Error>(())
//! ```

mod outliers;
mod periods;
mod screener;
mod summary;

pub(crate) use outliers::outlier_sets_by;
pub use outliers::{OutlierSet, outlier_sets};
pub(crate) use periods::repeat;
pub use periods::{PeriodCheck, find_period};
pub use screener::Screener;
pub use summary::Summary;

use crate::error::{Error, Result, Warning};
use crate::quality::ImpactChecks;
use crate::statistics::{MAD_TO_SIGMA, upper_median};

pub use crate::tolerance::FLAT_CHANNEL as FLAT_TOLERANCE;

/// Sibling groups smaller than this are not judged across records.
pub const MIN_SIBLINGS: usize = 3;

/// A record is excited in one direction when its dominant force's RMS is at least this many
/// times every other force channel's.
pub const DOMINANCE: f64 = 3.0;

/// Thresholds of the record screening (see the [module docs](self)).
///
/// # Examples
/// ```
/// use bearing_ident::screening::Checks;
/// let checks = Checks::default();
/// assert!(checks.impact.is_some());
/// assert_eq!(checks.clip_run, 3);
/// assert!((checks.dead_ratio - 0.01).abs() < 1e-15);
/// assert!(checks.check().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Checks {
    /// The double-hit check of impact records ([`quality::check_record`](crate::quality::check_record)); `None` skips it.
    /// Its `clip_run` is not used ([`Checks::clip_run`] is). It applies only to impulsive
    /// records (crest factor ≥ `min_crest_factor`), so leaving it on for other excitations is
    /// harmless. Default `Some(ImpactChecks::default())`.
    pub impact: Option<ImpactChecks>,
    /// This many consecutive samples at a channel's extreme count as clipping (see
    /// [`ImpactChecks::clip_run`]). Valid `≥ 2`; default `3`.
    pub clip_run: usize,
    /// A channel is dead when its RMS is below this fraction of the same channel's median RMS
    /// over its siblings. Valid `(0, 1)`; default `0.01`.
    pub dead_ratio: f64,
    /// A level is an outlier beyond this many robust standard deviations of the siblings' log
    /// RMS… Valid finite `> 0`; default `5`.
    pub level_sigmas: f64,
    /// …and beyond this factor of their median RMS (either way). Valid finite `> 1`; default
    /// `3`.
    pub level_factor: f64,
    /// A paired set is far from the others at a line when some element of its impedance is
    /// beyond this many robust standard deviations of the sets' distances to their median…
    /// Valid finite `> 0`; default `5`.
    pub set_sigmas: f64,
    /// …and beyond this fraction of the line's median impedance (Frobenius norm). Valid
    /// finite `≥ 0`; default `0.05`.
    pub set_floor: f64,
    /// A set far at more than this fraction of the lines tested is an outlier. Valid
    /// `(0, 1)`; default `0.5` (most lines).
    pub set_fraction: f64,
}

impl Default for Checks {
    fn default() -> Self {
        Self {
            impact: Some(ImpactChecks::default()),
            clip_run: 3,
            dead_ratio: 0.01,
            level_sigmas: 5.0,
            level_factor: 3.0,
            set_sigmas: 5.0,
            set_floor: 0.05,
            set_fraction: 0.5,
        }
    }
}

impl From<ImpactChecks> for Checks {
    /// The default checks with `impact`'s double-hit settings and clip run.
    fn from(impact: ImpactChecks) -> Self {
        Self {
            impact: Some(impact),
            clip_run: impact.clip_run,
            ..Self::default()
        }
    }
}

impl Checks {
    /// The default checks without the double-hit check, for excitations that are not impacts.
    pub fn without_double_hits() -> Self {
        Self {
            impact: None,
            ..Self::default()
        }
    }

    /// Checks that every threshold is in its valid range.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first field out of range (the impact checks'
    /// own, see [`ImpactChecks::check`]).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::screening::Checks;
    /// use bearing_ident::{Error, Parameter};
    /// let bad = Checks { dead_ratio: 1.5, ..Checks::default() };
    /// assert!(matches!(bad.check(), Err(Error::InvalidParameter { name: Parameter::DeadRatio, .. })));
    /// ```
    pub fn check(&self) -> Result<()> {
        if let Some(impact) = self.impact {
            impact.check()?;
        }
        let fail = |name, value, expected| {
            Err(Error::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if self.clip_run < 2 {
            return fail(
                crate::Parameter::ClipRun,
                self.clip_run as f64,
                "at least 2 samples",
            );
        }
        if !(self.dead_ratio > 0.0 && self.dead_ratio < 1.0) {
            return fail(
                crate::Parameter::DeadRatio,
                self.dead_ratio,
                "0 < ratio < 1",
            );
        }
        if !(self.level_sigmas > 0.0 && self.level_sigmas.is_finite()) {
            return fail(
                crate::Parameter::LevelSigmas,
                self.level_sigmas,
                "finite and > 0",
            );
        }
        if !(self.level_factor > 1.0 && self.level_factor.is_finite()) {
            return fail(
                crate::Parameter::LevelFactor,
                self.level_factor,
                "finite and > 1",
            );
        }
        if !(self.set_sigmas > 0.0 && self.set_sigmas.is_finite()) {
            return fail(
                crate::Parameter::SetSigmas,
                self.set_sigmas,
                "finite and > 0",
            );
        }
        if !(self.set_floor >= 0.0 && self.set_floor.is_finite()) {
            return fail(crate::Parameter::SetFloor, self.set_floor, "finite and ≥ 0");
        }
        if !(self.set_fraction > 0.0 && self.set_fraction < 1.0) {
            return fail(
                crate::Parameter::SetFraction,
                self.set_fraction,
                "0 < fraction < 1",
            );
        }
        Ok(())
    }
}

/// A short phrase for `warning` as the reason a record was rejected.
pub(crate) fn reason(warning: &Warning) -> String {
    match warning {
        Warning::FlatChannel { channel, .. } => format!("{channel} flat"),
        Warning::DeadChannel { channel, .. } => format!("{channel} dead"),
        Warning::LevelOutlier { channel, .. } => format!("{channel} level outlier"),
        Warning::DuplicateRecord { of, .. } => format!("same samples as `{of}`"),
        Warning::OutlierSet { .. } => "impedance far from the other paired sets'".to_owned(),
        Warning::Clipped { channel, .. } => format!("{channel} clipped"),
        Warning::DoubleHit { .. } => "double hit".to_owned(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Channel;
    use crate::records::{Record, Response};
    use faer::{Mat, c64};

    fn record(label: &str, f: [Vec<f64>; 2], x: [Vec<f64>; 2]) -> Record {
        let [f0, f1] = f;
        let [x0, x1] = x;
        Record::new(label, 100.0, vec![f0, f1], vec![x0, x1]).unwrap()
    }

    fn wave(amplitude: f64, phase: f64) -> Vec<f64> {
        (0..64)
            .map(|m| amplitude * (0.37 * m as f64 + phase).sin())
            .collect()
    }

    #[test]
    fn each_invalid_setting_is_named() {
        let d = Checks::default();
        let cases = [
            (Checks { clip_run: 1, ..d }, "clip_run"),
            (
                Checks {
                    dead_ratio: 0.0,
                    ..d
                },
                "dead_ratio",
            ),
            (
                Checks {
                    level_sigmas: f64::NAN,
                    ..d
                },
                "level_sigmas",
            ),
            (
                Checks {
                    level_factor: 1.0,
                    ..d
                },
                "level_factor",
            ),
            (
                Checks {
                    set_sigmas: -1.0,
                    ..d
                },
                "set_sigmas",
            ),
            (
                Checks {
                    set_floor: f64::INFINITY,
                    ..d
                },
                "set_floor",
            ),
            (
                Checks {
                    set_fraction: 1.0,
                    ..d
                },
                "set_fraction",
            ),
            (
                Checks {
                    impact: Some(ImpactChecks {
                        double_hit_ratio: 2.0,
                        ..ImpactChecks::default()
                    }),
                    ..d
                },
                "double_hit_ratio",
            ),
        ];
        for (checks, field) in cases {
            let e = checks.check().unwrap_err();
            assert!(
                matches!(e, Error::InvalidParameter { name, .. } if name.as_str() == field),
                "{checks:?}: {e:?}"
            );
        }
        assert_eq!(Checks::without_double_hits().check(), Ok(()));
    }

    #[test]
    fn a_single_flat_force_is_left_to_the_siblings() {
        let mut s = Screener::new(Checks::default());
        let r = record(
            "one-shaker",
            [wave(10.0, 0.0), vec![0.0; 64]],
            [wave(1e-6, 0.3), wave(1e-7, 0.1)],
        );
        assert_eq!(s.push(&r), vec![]);
        let r = record(
            "probe-off",
            [wave(10.0, 0.0), wave(1.0, 0.2)],
            [vec![2.5e-4; 64], wave(1e-7, 0.1)],
        );
        assert_eq!(
            s.push(&r),
            vec![Warning::FlatChannel {
                record: "probe-off".into(),
                channel: Channel::Displacement(0),
                value: 2.5e-4
            }]
        );
    }

    #[test]
    fn siblings_judge_dead_channels_and_levels() {
        let mut s = Screener::new(Checks::without_double_hits());
        let levels = [1.0, 1.1, 0.95, 1.05, 1.0, 1.02];
        for (k, a) in levels.iter().enumerate() {
            let p = k as f64;
            let f1 = if k == 2 {
                wave(1e-3, p)
            } else {
                wave(2.0 * a, p)
            };
            let x0 = if k == 4 {
                wave(10e-6 * a, p)
            } else {
                wave(1e-6 * a, p)
            };
            let r = record(
                &format!("r{k}"),
                [wave(10.0 * a, p), f1],
                [x0, wave(1e-7, p)],
            );
            assert_eq!(s.push(&r), vec![]);
        }
        let found = s.across(&[]);
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(matches!(
            &found[0],
            (
                2,
                Warning::DeadChannel {
                    channel: Channel::Force(1),
                    ..
                }
            )
        ));
        assert!(matches!(
            &found[1],
            (4, Warning::LevelOutlier { channel: Channel::Displacement(0), rms, median_rms, .. })
                if (rms / median_rms - 10.0).abs() < 0.5
        ));
        // Left out, a record neither is judged nor counts.
        let found = s.across(&[false, false, true, false, true]);
        assert_eq!(found, vec![]);
    }

    #[test]
    fn levels_compare_only_responses_of_one_kind() {
        // Four displacement records (1e-6 m) and three of velocity (1e-3 m/s) on channel 0:
        // neither kind looks dead or out of level beside the other.
        let mut s = Screener::new(Checks::without_double_hits());
        for k in 0..7 {
            let p = k as f64;
            let (x0, kind) = if k < 4 {
                (wave(1e-6, p), Response::Displacement)
            } else {
                (wave(1e-3, p), Response::Velocity)
            };
            let r = record(
                &format!("r{k}"),
                [wave(10.0, p), wave(2.0, p)],
                [x0, wave(1e-7, p)],
            )
            .with_responses(vec![kind, Response::Displacement])
            .unwrap();
            assert_eq!(s.push(&r), vec![]);
        }
        assert_eq!(s.across(&[]), vec![]);
        // The same levels all called displacement: the velocity records are level outliers.
        let mut s = Screener::new(Checks::without_double_hits());
        for k in 0..7 {
            let p = k as f64;
            let x0 = wave(if k < 4 { 1e-6 } else { 1e-3 }, p);
            s.push(&record(
                &format!("r{k}"),
                [wave(10.0, p), wave(2.0, p)],
                [x0, wave(1e-7, p)],
            ));
        }
        let found = s.across(&[]);
        assert_eq!(found.len(), 3, "{found:?}");
        assert!(
            found
                .iter()
                .all(|(r, w)| *r >= 4 && matches!(w, Warning::LevelOutlier { .. }))
        );
    }

    #[test]
    fn fewer_than_three_siblings_are_not_judged() {
        let mut s = Screener::new(Checks::default());
        for k in 0..2 {
            let f1 = if k == 1 {
                wave(1e-6, 0.0)
            } else {
                wave(2.0, 0.0)
            };
            let r = record(
                &format!("r{k}"),
                [wave(10.0, 0.0), f1],
                [wave(1e-6, 0.1), wave(1e-6, 0.2)],
            );
            s.push(&r);
        }
        assert_eq!(s.across(&[]), vec![]);
    }

    #[test]
    fn outlier_sets_need_three() {
        let h = Some(Mat::<c64>::identity(2, 2));
        let two = vec![vec![h.clone()], vec![Some(Mat::zeros(2, 2))]];
        assert_eq!(outlier_sets(&two, &Checks::default()), vec![]);
        let three = vec![vec![h.clone()], vec![h.clone()], vec![None]];
        assert_eq!(outlier_sets(&three, &Checks::default()), vec![]);
    }
}
