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
//! Detection ([`Excitation::detect`]) tells impacts from random forcing by the crest factor of
//! the force ([`crest_factor`], [`IMPACT_CREST_FACTOR`]), and periodic forcing (a multisine or
//! a stepped drive repeated) from random by the force's autocorrelation ([`find_period`]),
//! which also gives the period; stepped sines and sweeps are the user's to say. This module sits after [`identify`](crate::identify): it configures an
//! [`Identifier`] and no stage imports it.

use crate::error::{Channel, Error, Result};
use crate::frf::Estimator;
use crate::identify::{Identifier, Screening};
use crate::records::Record;
use crate::screening::{Checks, find_period};
use crate::spectra::{Segmentation, Window};

mod welch;

pub use welch::{LINES_PER_BANDWIDTH, MIN_AVERAGES, WelchChoice, choose_welch};

pub use crate::quality::IMPACT_CREST_FACTOR;

/// Fewest samples of a Welch segment or a period (as [`Segmentation::segment_len`] requires).
const MIN_SEGMENT: usize = 8;

/// Crest factor of a record's strongest force channel ([`Record::dominant_force`]): peak over
/// RMS about the mean,
///
/// $$ \mathrm{CF} = \frac{\max_m |f_m - \bar f|}{\sqrt{\tfrac1N \sum_m (f_m - \bar f)^2}}. $$
///
/// The force is scaled by its largest magnitude first, so huge forces do not overflow; a flat
/// (or non-finite) force has crest factor 0.
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::excitation::crest_factor;
/// // One hit in 100 samples: peak 0.99, RMS about the mean 0.0995.
/// let mut f = vec![0.0; 100];
/// f[10] = 1.0;
/// let r = Record::new("hit", 100.0, vec![f], vec![vec![0.0; 100]])?;
/// assert!((crest_factor(&r) - 0.99 / 0.0099f64.sqrt()).abs() < 1e-9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn crest_factor(record: &Record) -> f64 {
    crest(record.force(record.dominant_force()))
}

/// The largest crest factor of a record's response channels (as [`crest_factor`] of a
/// force): about 4 to 5 for responses to random or swept forcing, up to about 8 for a lightly
/// damped response to a hit, 30 and more for a hammer's force. Read only to name a likely
/// cause when a run fails (force and response columns exchanged).
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::excitation::response_crest_factor;
/// let mut hit = vec![0.0; 100];
/// hit[10] = 1.0;
/// let r = Record::new("swapped", 100.0, vec![vec![1.0; 100]], vec![hit])?;
/// assert!((response_crest_factor(&r) - 0.99 / 0.0099f64.sqrt()).abs() < 1e-9);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn response_crest_factor(record: &Record) -> f64 {
    (0..record.dofs())
        .map(|c| crest(record.displacement(c)))
        .fold(0.0, f64::max)
}

/// Peak over RMS about the mean of `f`, scaled by its largest magnitude first; 0 when flat
/// or not finite.
fn crest(f: &[f64]) -> f64 {
    let scale = f.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
    if scale <= 0.0 || !scale.is_finite() {
        return 0.0;
    }
    let mean = f.iter().map(|v| v / scale).sum::<f64>() / f.len() as f64;
    let centred = |v: &f64| v / scale - mean;
    let rms = (f.iter().map(|v| centred(v).powi(2)).sum::<f64>() / f.len() as f64).sqrt();
    let peak = f.iter().map(|v| centred(v).abs()).fold(0.0, f64::max);
    if rms > 0.0 { peak / rms } else { 0.0 }
}

/// The crest factor that decides the excitation ([`Excitation::detect`]): that of the first
/// record whose force is not flat, reading `records` only as far as needed, so records that
/// arrive one at a time (files read in turn) are read no further than the first with a force.
///
/// # Errors
/// The first error of `records`; [`Error::NoRecords`] for none; [`Error::DeadChannel`] naming
/// the first record's force 0 when every record's force is flat.
///
/// # Examples
/// ```
/// use bearing_ident::excitation::{IMPACT_CREST_FACTOR, deciding_crest_factor};
/// use bearing_ident::simulate::{ImpactTest, seed_rig};
/// let records = ImpactTest::seed_rig().run(&seed_rig())?;
/// let crest = deciding_crest_factor(records.iter().map(Ok::<_, bearing_ident::Error>))?;
/// assert!(crest > IMPACT_CREST_FACTOR);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn deciding_crest_factor<R, E>(
    records: impl IntoIterator<Item = std::result::Result<R, E>>,
) -> std::result::Result<f64, E>
where
    R: std::borrow::Borrow<Record>,
    E: From<Error>,
{
    let mut first: Option<(String, f64)> = None;
    for record in records {
        let record = record?;
        let record = record.borrow();
        let crest = crest_factor(record);
        if crest > 0.0 {
            return Ok(crest);
        }
        first.get_or_insert_with(|| (record.label().to_owned(), record.force(0)[0]));
    }
    let (record, value) = first.ok_or(Error::NoRecords)?;
    Err(Error::DeadChannel {
        record,
        channel: Channel::Force(0),
        value,
    }
    .into())
}

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
    /// The kind a crest factor says: [`Impact`](Excitation::Impact) at and above
    /// [`IMPACT_CREST_FACTOR`], else [`Random`](Excitation::Random).
    pub fn from_crest_factor(crest: f64) -> Excitation {
        if crest >= IMPACT_CREST_FACTOR {
            Excitation::Impact
        } else {
            Excitation::Random
        }
    }

    /// The kind a crest factor and a record say: [`Impact`](Excitation::Impact) at and above
    /// [`IMPACT_CREST_FACTOR`]; else [`Periodic`](Excitation::Periodic) when the record's
    /// force repeats ([`find_period`]: a multisine or a stepped drive repeated), else
    /// [`Random`](Excitation::Random).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Record;
    /// use bearing_ident::excitation::{Excitation, crest_factor};
    /// use bearing_ident::simulate::multisine;
    /// let f = multisine(250, 3..=40, 1.0, 2000, 3)?;
    /// let r = Record::new("ms", 1000.0, vec![f], vec![vec![0.0; 2000]])?;
    /// assert_eq!(Excitation::from_record(crest_factor(&r), &r), Excitation::Periodic);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_record(crest: f64, record: &Record) -> Excitation {
        match Excitation::from_crest_factor(crest) {
            Excitation::Random if find_period(record).is_some() => Excitation::Periodic,
            kind => kind,
        }
    }

    /// Detects impacts, periodic or random forcing from the [`crest_factor`] of the first
    /// record whose force is not flat (a hammer hit that did not register says nothing of the
    /// excitation) and, below the impact level, whether the first record's force repeats
    /// ([`Excitation::from_record`]).
    ///
    /// # Errors
    /// [`Error::NoRecords`] for no records; [`Error::DeadChannel`] naming the first record's
    /// force 0 when every record's force is flat.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::excitation::Excitation;
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest::seed_rig().run(&seed_rig())?;
    /// assert_eq!(Excitation::detect(&records)?, Excitation::Impact);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn detect(records: &[Record]) -> Result<Excitation> {
        let crest = deciding_crest_factor(records.iter().map(Ok::<_, Error>))?;
        Ok(Excitation::from_record(crest, &records[0]))
    }

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
    use crate::simulate::{AntiAlias, ImpactTest, Simulator, multisine, seed_rig};

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
    fn detects_impacts() {
        let records = ImpactTest::seed_rig().run(&seed_rig()).unwrap();
        assert!(crest_factor(&records[0]) > 10.0);
        assert_eq!(Excitation::detect(&records).unwrap(), Excitation::Impact);
    }

    #[test]
    fn detects_random() {
        let mut sim = Simulator::new(&seed_rig(), 6700.0, 8192, AntiAlias::default()).unwrap();
        let records: Vec<Record> = (0..2)
            .map(|r| sim.random_record(format!("r{r}"), 50.0, r).unwrap())
            .collect();
        let crest = crest_factor(&records[0]);
        assert!(crest > 2.0 && crest < IMPACT_CREST_FACTOR, "{crest}");
        assert_eq!(Excitation::detect(&records).unwrap(), Excitation::Random);
    }

    #[test]
    fn multisine_is_not_an_impact() {
        let period = 6700;
        let drive = multisine(period, 8..=49, 50.0, 2 * period, 3).unwrap();
        let mut sim =
            Simulator::new(&seed_rig(), 6700.0, drive.len(), AntiAlias::default()).unwrap();
        let record = sim
            .held_record("ms", &[drive, vec![0.0; 2 * period]])
            .unwrap();
        let crest = crest_factor(&record);
        assert!(crest > 1.0 && crest < IMPACT_CREST_FACTOR, "{crest}");
        // Two periods are the least that show a repeat: it is found (a lag of half the record).
        assert_eq!(Excitation::detect(&[record]).unwrap(), Excitation::Periodic);
    }

    #[test]
    fn flat_records_are_skipped_then_refused() {
        let flat = Record::new("flat", 100.0, vec![vec![2.0; 200]], vec![vec![0.0; 200]]).unwrap();
        assert!(crest_factor(&flat).abs() < f64::MIN_POSITIVE);
        let mut f = vec![0.0; 200];
        f[5] = 1.0;
        let hit = Record::new("hit", 100.0, vec![f], vec![vec![0.0; 200]]).unwrap();
        assert_eq!(
            Excitation::detect(&[flat.clone(), hit]).unwrap(),
            Excitation::Impact
        );
        assert!(matches!(
            Excitation::detect(&[flat.clone(), flat]),
            Err(Error::DeadChannel { ref record, channel: Channel::Force(0), .. }) if record == "flat"
        ));
        assert!(matches!(Excitation::detect(&[]), Err(Error::NoRecords)));
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
