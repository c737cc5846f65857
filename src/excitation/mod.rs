//! The kind of test that produced a set of records — impacts, random forcing, periodic or
//! multisine forcing, stepped sines, sweeps — with its detection from the records and the
//! processing each kind calls for (estimator, segmentation, window, screening checks), so a
//! library user gets the same defaults as the `bearing-ident` tool.
//!
//! | kind | estimator | segmentation | window | double-hit check |
//! |---|---|---|---|---|
//! | [`Impact`](Excitation::Impact) | paired sets | whole record | rectangular | yes |
//! | [`Random`](Excitation::Random) | H1 | Welch, [`welch_len`] | Hann | no |
//! | [`Periodic`](Excitation::Periodic) | H1 | whole periods | rectangular | no |
//! | [`SteppedSine`](Excitation::SteppedSine) | paired sets | whole record | rectangular | no |
//! | [`Sweep`](Excitation::Sweep) | paired sets | whole record | rectangular | no |
//!
//! Detection ([`Excitation::detect`], in `detect.rs`) reads the strongest force of the first
//! record with a force ([`Evidence`]): a steady pure tone is a stepped sine, frequencies that
//! arrive in order a sweep, a hammer's crest factor ([`crest_factor`], [`IMPACT_CREST_FACTOR`])
//! impacts, a force that repeats ([`find_period`], which also gives the period) periodic
//! forcing, and anything else random forcing; when a feature near its threshold leaves two
//! kinds, it names them and asks ([`Error::UnclearExcitation`]). This module sits after
//! [`identify`](crate::identify): it configures an [`Identifier`] and no stage imports it.
//!
//! | file | what lives there |
//! |---|---|
//! | `mod.rs` | [`Excitation`] and each kind's processing |
//! | `detect.rs` | [`Evidence`], [`Excitation::detect`], [`crest_factor`], [`deciding_record`] |
//! | `welch.rs` | [`choose_welch`]: the Welch length from a first fit |

use crate::error::{Error, Result};
use crate::frf::Estimator;
use crate::identify::{Identifier, Screening};
use crate::records::Record;
use crate::screening::{Checks, find_period};
use crate::spectra::{Segmentation, Window};

mod detect;
mod welch;

pub use detect::{
    Evidence, crest_factor, deciding_crest_factor, deciding_record, response_crest_factor,
};
#[cfg(feature = "job")]
pub(crate) use welch::choose_with_spectra;
pub use welch::{LINES_PER_BANDWIDTH, MIN_AVERAGES, WelchChoice, choose_welch};

pub use crate::quality::IMPACT_CREST_FACTOR;

/// Fewest samples of a Welch segment or a period (as [`Segmentation::segment_len`] requires).
const MIN_SEGMENT: usize = 8;

/// Welch segment length for random excitation: the largest power of two not above an eighth
/// of the record, and at least 8 samples,
///
/// $$ L = 2^{\lfloor \log_2 \max(\lfloor N/8 \rfloor,\ 8) \rfloor}, $$
///
/// so a record gives at least 15 half-overlapping segments.
///
/// # Examples
/// ```
/// use bearing_ident::excitation::welch_len;
/// assert_eq!(welch_len(8192), 1024);
/// assert_eq!(welch_len(400_000), 32_768); // an eighth is 50 000
/// assert_eq!(welch_len(20), 8);
/// ```
pub fn welch_len(record_len: usize) -> usize {
    let eighth = (record_len / 8).max(MIN_SEGMENT);
    if eighth.is_power_of_two() {
        eighth
    } else {
        eighth.next_power_of_two() / 2
    }
}

/// The kind of test that produced a set of records.
///
/// Its methods give the processing each kind calls for (see the [module](self) table);
/// [`Excitation::configure`] applies them all to an [`Identifier`].
///
/// # Examples
/// ```
/// use bearing_ident::excitation::Excitation;
/// use bearing_ident::{Estimator, Window};
/// let random: Excitation = "random".parse()?;
/// assert_eq!(random, Excitation::Random);
/// assert_eq!(random.estimator(None), Estimator::H1);
/// assert_eq!(random.window(), Window::Hann);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Excitation {
    /// Impacts: paired sets, whole-record DFT, no window.
    Impact,
    /// Random: MIMO H1 with Welch segments (Hann, 50 % overlap).
    Random,
    /// Periodic or multisine in steady state: MIMO H1 over whole periods (the period is given
    /// to [`Excitation::segmentation`]), no window, the excited lines only.
    Periodic,
    /// Stepped sine: one drive frequency per record; amplitude and phase at that frequency
    /// ([`Identifier::identify_stepped_sine`]).
    SteppedSine,
    /// Sine sweep followed by free decay: as impacts (paired sets, whole record).
    Sweep,
}

impl Excitation {
    /// The impedance estimator for this kind, or the `chosen` one: random forcing H1, periodic
    /// forcing H1 (paired sets are replaced by H1: periods are not paired), the others paired
    /// sets.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Estimator;
    /// use bearing_ident::excitation::Excitation;
    /// assert_eq!(Excitation::Impact.estimator(None), Estimator::PairedSets);
    /// assert_eq!(Excitation::Impact.estimator(Some(Estimator::H2)), Estimator::H2);
    /// assert_eq!(Excitation::Periodic.estimator(Some(Estimator::PairedSets)), Estimator::H1);
    /// ```
    pub fn estimator(self, chosen: Option<Estimator>) -> Estimator {
        match self {
            Excitation::Random => chosen.unwrap_or(Estimator::H1),
            Excitation::Periodic => match chosen {
                None | Some(Estimator::PairedSets) => Estimator::H1,
                Some(e) => e,
            },
            _ => chosen.unwrap_or(Estimator::PairedSets),
        }
    }

    /// How records of this kind are cut, for `estimator` (from [`Excitation::estimator`]) and
    /// records like `record`:
    /// - random forcing: Welch segments of [`welch_len`] samples, or the whole record for
    ///   paired sets;
    /// - periodic forcing: whole periods of `round(period_s · f_s)` samples, the period found
    ///   in the record ([`find_period`]) when `period_s` is `None`;
    /// - the others: the whole record.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `"period"` for periodic forcing without `period_s`
    /// and no period in the record (value NaN) or with a period of fewer than 8 samples or more than the record.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Estimator, Record, Segmentation};
    /// use bearing_ident::excitation::Excitation;
    /// let r = Record::new("r", 100.0, vec![vec![0.0; 1000]], vec![vec![0.0; 1000]])?;
    /// let periods = Excitation::Periodic.segmentation(Estimator::H1, &r, Some(0.5))?;
    /// assert_eq!(periods, Segmentation::Periods { len: 50 });
    /// let welch = Excitation::Random.segmentation(Estimator::H1, &r, None)?;
    /// assert_eq!(welch, Segmentation::Welch { len: 64 });
    /// // A flat record has no period of its own to fall back on.
    /// assert!(Excitation::Periodic.segmentation(Estimator::H1, &r, None).is_err());
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn segmentation(
        self,
        estimator: Estimator,
        record: &Record,
        period_s: Option<f64>,
    ) -> Result<Segmentation> {
        Ok(match self {
            Excitation::Random if estimator == Estimator::PairedSets => Segmentation::WholeRecord,
            Excitation::Random => Segmentation::Welch {
                len: welch_len(record.len()),
            },
            Excitation::Periodic => {
                let period =
                    period_s
                        .or_else(|| find_period(record))
                        .ok_or(Error::InvalidParameter {
                            name: crate::Parameter::Period,
                            value: f64::NAN,
                            expected: "a period (s) for periodic excitation",
                        })?;
                let len = (period * record.sample_rate()).round();
                if !(len >= MIN_SEGMENT as f64 && len <= record.len() as f64) {
                    return Err(Error::InvalidParameter {
                        name: crate::Parameter::Period,
                        value: period,
                        expected: "8 samples up to the record length",
                    });
                }
                Segmentation::Periods { len: len as usize }
            }
            _ => Segmentation::WholeRecord,
        })
    }

    /// The window for this kind: Hann for random forcing, else rectangular (impacts and
    /// transients decay within the record; whole periods are leakage-free).
    pub fn window(self) -> Window {
        match self {
            Excitation::Random => Window::Hann,
            _ => Window::Rectangular,
        }
    }

    /// The screening checks for this kind: all of them for impacts, all but the double-hit
    /// check for the others ([`Checks::without_double_hits`]).
    pub fn checks(self) -> Checks {
        if self == Excitation::Impact {
            Checks::default()
        } else {
            Checks::without_double_hits()
        }
    }

    /// `identifier` with this kind's estimator, segmentation, window and screening (records
    /// left in and warned about, [`Screening::Warn`]) for records like `record`; the
    /// `period_s` of periodic forcing. Settings this does not name are left as they were.
    ///
    /// # Errors
    /// Those of [`Excitation::segmentation`].
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Identifier, Segmentation, Window};
    /// use bearing_ident::excitation::Excitation;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest::seed_rig().run(&seed_rig())?;
    /// let kind = Excitation::detect(&records)?;
    /// let id = kind.configure(Identifier::new(8.0, 49.0), &records[0], None)?.identify(&records)?;
    /// assert_eq!(id.segmentation(), Segmentation::WholeRecord);
    /// assert_eq!(id.window(), Window::Rectangular);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn configure(
        self,
        identifier: Identifier,
        record: &Record,
        period_s: Option<f64>,
    ) -> Result<Identifier> {
        let estimator = self.estimator(None);
        Ok(identifier
            .estimator(estimator)
            .segmentation(self.segmentation(estimator, record, period_s)?)
            .window(self.window())
            .screening(Screening::Warn(self.checks())))
    }
}

impl crate::Choice for Excitation {
    const OPTION: &'static str = "excitation";
    const ALL: &'static [Excitation] = &[
        Excitation::Impact,
        Excitation::Random,
        Excitation::Periodic,
        Excitation::SteppedSine,
        Excitation::Sweep,
    ];

    /// `"impact"`, `"random"`, `"periodic"`, `"stepped-sine"` or `"sweep"` (the command
    /// line's `--excitation` values, beside `auto`).
    fn name(self) -> &'static str {
        match self {
            Excitation::Impact => "impact",
            Excitation::Random => "random",
            Excitation::Periodic => "periodic",
            Excitation::SteppedSine => "stepped-sine",
            Excitation::Sweep => "sweep",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Excitation::Impact => "impacts: paired sets, whole-record DFT, no window",
            Excitation::Random => "random: MIMO H1 over Welch segments (Hann, 50 % overlap)",
            Excitation::Periodic => {
                "periodic or multisine in steady state: H1 over whole periods, excited lines only"
            }
            Excitation::SteppedSine => "stepped sine: one drive frequency per record",
            Excitation::Sweep => "sine sweep then free decay: as impacts",
        }
    }
}

crate::choice::choice_text!(Excitation);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        crate::choice::tests::round_trips::<Excitation>();
        assert_eq!(
            "Stepped_Sine".parse::<Excitation>().unwrap(),
            Excitation::SteppedSine
        );
        for bad in ["auto", "", "steppedsine", "periodic:1"] {
            let err = bad.parse::<Excitation>().unwrap_err();
            assert!(
                matches!(
                    err,
                    Error::UnknownName {
                        what: "excitation",
                        ..
                    }
                ),
                "{err}"
            );
            assert!(err.to_string().contains("stepped-sine"), "{err}");
        }
    }

    #[test]
    fn defaults_per_kind() {
        let r = Record::new("r", 1000.0, vec![vec![0.0; 4000]], vec![vec![0.0; 4000]]).unwrap();
        let table = [
            (
                Excitation::Impact,
                Estimator::PairedSets,
                Segmentation::WholeRecord,
                Window::Rectangular,
            ),
            (
                Excitation::Random,
                Estimator::H1,
                Segmentation::Welch { len: 256 },
                Window::Hann,
            ),
            (
                Excitation::Periodic,
                Estimator::H1,
                Segmentation::Periods { len: 500 },
                Window::Rectangular,
            ),
            (
                Excitation::SteppedSine,
                Estimator::PairedSets,
                Segmentation::WholeRecord,
                Window::Rectangular,
            ),
            (
                Excitation::Sweep,
                Estimator::PairedSets,
                Segmentation::WholeRecord,
                Window::Rectangular,
            ),
        ];
        for (kind, estimator, segmentation, window) in table {
            assert_eq!(kind.estimator(None), estimator, "{kind}");
            assert_eq!(
                kind.segmentation(estimator, &r, Some(0.5)).unwrap(),
                segmentation,
                "{kind}"
            );
            assert_eq!(kind.window(), window, "{kind}");
            assert_eq!(kind.checks().impact.is_some(), kind == Excitation::Impact);
        }
        // Paired sets on random records take the whole record.
        assert_eq!(
            Excitation::Random
                .segmentation(Estimator::PairedSets, &r, None)
                .unwrap(),
            Segmentation::WholeRecord
        );
        assert_eq!(
            Excitation::Random.estimator(Some(Estimator::Hv)),
            Estimator::Hv
        );
    }

    #[test]
    fn periods_out_of_range_are_refused() {
        let r = Record::new("r", 1000.0, vec![vec![0.0; 4000]], vec![vec![0.0; 4000]]).unwrap();
        for period in [0.007, 4.001, f64::NAN, -1.0] {
            assert!(
                matches!(
                    Excitation::Periodic.segmentation(Estimator::H1, &r, Some(period)),
                    Err(Error::InvalidParameter {
                        name: crate::Parameter::Period,
                        ..
                    })
                ),
                "{period}"
            );
        }
        assert_eq!(
            Excitation::Periodic
                .segmentation(Estimator::H1, &r, Some(0.008))
                .unwrap(),
            Segmentation::Periods { len: 8 }
        );
        assert_eq!(
            Excitation::Periodic
                .segmentation(Estimator::H1, &r, Some(4.0))
                .unwrap(),
            Segmentation::Periods { len: 4000 }
        );
    }

    #[test]
    fn welch_len_rule() {
        for (n, len) in [
            (0, 8),
            (64, 8),
            (127, 8),
            (128, 16),
            (8192, 1024),
            (9000, 1024),
        ] {
            assert_eq!(welch_len(n), len, "{n}");
        }
    }
}
