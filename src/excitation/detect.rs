//! Detection of the kind of test from the records ([`Excitation::detect`]): what the strongest
//! force of the first record with a force says ([`Evidence`], whose documentation holds the
//! rules), and the kind it reads as ([`Evidence::readings`]).
//!
//! The cost is that of a few FFTs of one record: two of its length (its spectrum and that of
//! `m·f_m`, for the tone and the group delay) and the autocorrelation's two ([`find_period`]).

use std::borrow::Borrow;
use std::cell::RefCell;

use faer::c64;
use realfft::RealFftPlanner;

use super::Excitation;
use crate::choice::Choice;
use crate::error::{Channel, Error, Result};
use crate::kept::with_kept;
use crate::quality::IMPACT_CREST_FACTOR;
use crate::records::Record;
#[cfg(doc)]
use crate::screening::find_period;
use crate::screening::repeat;
use crate::tolerance::{
    PERIOD_REPEATS, PERIOD_REPEATS_DOUBT, PERIODIC_CORRELATION, PERIODIC_CORRELATION_DOUBT,
    STEADY_POWER, SWEEP_MONOTONY, SWEEP_MONOTONY_DOUBT, TONE_FRACTION, TONE_FRACTION_DOUBT,
};

thread_local! {
    /// The FFT plans, kept per thread: records of one test share a length.
    static PLANNER: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
    /// The buffers of a force's spectrum, kept per thread ([`with_kept`]).
    static BUFFERS: RefCell<Buffers> = RefCell::new(Buffers::default());
}

/// The buffers of [`Evidence::of`]: the centred force `x` and `m x_m`, their one-sided
/// spectra, the transform's scratch.
#[derive(Default)]
struct Buffers {
    x: Vec<f64>,
    moment: Vec<f64>,
    spectrum: Vec<c64>,
    moment_spectrum: Vec<c64>,
    scratch: Vec<c64>,
}

/// Fewest samples of a force whose spectrum is read: shorter ones hold no tone or sweep.
const MIN_SAMPLES: usize = 32;

/// Lines either side of the strongest peak counted in the tone: a Hann window's main lobe is
/// two lines wide either side, and a tone midway between lines spreads a little further.
const TONE_HALF_WIDTH: usize = 3;

/// A line takes part in the sweep's rank correlation when its power is at least this fraction
/// of the strongest line's: the lines a sweep crosses (its spectrum is flat over its band, give
/// or take its ripple), not the noise between them or beyond.
const SWEEP_LINE_LEVEL: f64 = 0.1;

/// Fewest lines for a rank correlation that can tell a sweep: the correlation of unrelated
/// values has a standard deviation of `1/√(n − 1)`, a quarter at 16 lines.
const SWEEP_MIN_LINES: usize = 16;

/// What a record's strongest force ([`Record::dominant_force`]) says of the kind of test: the
/// features [`Evidence::readings`] reads.
///
/// | kind | read from the force |
/// |---|---|
/// | [`SteppedSine`](Excitation::SteppedSine) | steady, with [`TONE_FRACTION`] of its power in one spectral peak (a pure tone) |
/// | [`Sweep`](Excitation::Sweep) | its frequencies arrive in order: group delay rank-correlated with frequency ([`SWEEP_MONOTONY`]) |
/// | [`Impact`](Excitation::Impact) | crest factor at least [`IMPACT_CREST_FACTOR`] |
/// | [`Periodic`](Excitation::Periodic) | an autocorrelation peak ([`PERIODIC_CORRELATION`]) at a lag at which its periods agree ([`PERIOD_REPEATS`]) |
/// | [`Random`](Excitation::Random) | none of these |
///
/// The kinds overlap, and the first that applies, in this order, decides: a tone is periodic
/// (a stepped sine); a sweep followed by a long free decay may have a hammer's crest factor
/// (a sweep), but a sweep that repeats is periodic (a periodic chirp). Each feature between its
/// threshold and its doubt level ([`TONE_FRACTION_DOUBT`], [`SWEEP_MONOTONY_DOUBT`],
/// [`PERIODIC_CORRELATION_DOUBT`], [`PERIOD_REPEATS_DOUBT`]) is read both ways; when the
/// readings give different kinds, detection names them ([`Error::UnclearExcitation`]) and
/// the user says which.
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::excitation::{Evidence, Excitation};
/// // A 12.5 Hz sine, 40 cycles at 1000 S/s: a steady pure tone.
/// let f: Vec<f64> = (0..3200).map(|m| (2.0 * std::f64::consts::PI * 12.5 * m as f64 / 1000.0).sin()).collect();
/// let r = Record::new("sine", 1000.0, vec![f], vec![vec![0.0; 3200]])?;
/// let e = Evidence::of(&r);
/// assert!(e.tone > 0.999 && (e.tone_hz - 12.5).abs() < 1e-9);
/// assert_eq!(e.readings(), [Excitation::SteppedSine]);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Evidence {
    /// Crest factor of the force ([`crest_factor`]).
    pub crest_factor: f64,
    /// Fraction of the force's power (about its mean, Hann-windowed over the whole record,
    /// summed over the one-sided lines) within three lines of its strongest peak above 0 Hz:
    /// about 1 for a pure tone.
    pub tone: f64,
    /// Frequency of that peak (Hz). (The spectrum is read over the first samples of the
    /// force, a few percent fewer, whose count has no prime factor above 5 and transforms
    /// quickly.)
    pub tone_hz: f64,
    /// Mean power of the force's weaker half over that of its stronger half: about 1 for a
    /// steady force, about 0 for a transient.
    pub steadiness: f64,
    /// Magnitude of the rank correlation (Spearman's) between frequency and the force's group
    /// delay $\tau_k = \operatorname{Re}\big(Y_k \overline{F_k}\big) / |F_k|^2$ ($F$ the DFT of
    /// the force, $Y$ that of $m f_m$) over the lines holding at least a tenth of the strongest
    /// line's power: about 1 for a sweep, whose frequencies arrive in order; 0 with fewer than
    /// 16 such lines.
    pub sweep: f64,
    /// The lines that rank correlation was taken over.
    pub sweep_lines: usize,
    /// The lag of the force's autocorrelation peak as [`find_period`] finds it, whatever its
    /// height (s); `None` without a peak.
    pub period_s: Option<f64>,
    /// The normalised autocorrelation at that lag; 0 without one.
    pub period_correlation: f64,
    /// Fraction of the force's energy between the harmonic lines of that period (its scatter
    /// from period to period, the first left out when there are three or more), at the peak's
    /// whole lag or, when above [`PERIOD_REPEATS`], the least over whole lags within 3 samples
    /// of it (noise moves a broad peak): about 0 when the force repeats; 1 without a period or
    /// below [`PERIODIC_CORRELATION_DOUBT`] (not read).
    pub period_scatter: f64,
}

/// How a feature reads against its threshold: yes, no, or either way (between its doubt level
/// and its threshold).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reading {
    Yes,
    Either,
    No,
}

impl Reading {
    /// Yes when `yes`, else either way when `either`, else no.
    fn of(yes: bool, either: bool) -> Reading {
        match (yes, either) {
            (true, _) => Reading::Yes,
            (false, true) => Reading::Either,
            _ => Reading::No,
        }
    }

    /// The values the feature may take.
    fn sides(self) -> &'static [bool] {
        match self {
            Reading::Yes => &[true],
            Reading::Either => &[true, false],
            Reading::No => &[false],
        }
    }
}

impl Evidence {
    /// The evidence of `record`'s strongest force. A flat force, or one shorter than 32
    /// samples, has no tone, steadiness or sweep (all 0).
    pub fn of(record: &Record) -> Evidence {
        let f = record.force(record.dominant_force());
        // The centred force gives the crest factor and the steadiness in one pass, then its
        // spectrum (the crest factor's own passes would centre it again).
        let (powers, spectral) = with_kept(&BUFFERS, f.len(), |buffers| {
            if !centre_into(f, &mut buffers.x) {
                return Default::default();
            }
            let powers = Powers::of(&buffers.x);
            let spectral = if f.len() >= MIN_SAMPLES {
                buffers.x.truncate(quick_len(f.len()));
                Spectral::of(buffers).unwrap_or_default()
            } else {
                Spectral::default()
            };
            (powers, spectral)
        });
        let repeat = repeat(record);
        Evidence {
            crest_factor: powers.crest,
            tone: spectral.tone,
            tone_hz: spectral.cycles * record.sample_rate(),
            steadiness: if f.len() >= MIN_SAMPLES {
                powers.steadiness
            } else {
                0.0
            },
            sweep: spectral.sweep,
            sweep_lines: spectral.lines,
            period_s: repeat.map(|r| r.period_s),
            period_correlation: repeat.map_or(0.0, |r| r.correlation),
            period_scatter: repeat.map_or(1.0, |r| r.scatter),
        }
    }

    /// The kinds this evidence reads as, in the order of [`Excitation`]'s variants: one when
    /// it is clear; two or more when a feature near its threshold, read either way, gives
    /// different kinds (see [`Evidence`]).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::excitation::{Evidence, Excitation};
    /// use bearing_ident::simulate::{ImpactTest, seed_rig};
    /// let records = ImpactTest::seed_rig().run(&seed_rig())?;
    /// let e = Evidence::of(&records[0]);
    /// assert!(e.crest_factor > 30.0);
    /// assert_eq!(e.readings(), [Excitation::Impact]);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn readings(&self) -> Vec<Excitation> {
        let tone = Reading::of(
            self.steadiness >= STEADY_POWER && self.tone >= TONE_FRACTION,
            self.steadiness >= STEADY_POWER && self.tone >= TONE_FRACTION_DOUBT,
        );
        let sweep = Reading::of(
            self.sweep >= SWEEP_MONOTONY,
            self.sweep >= SWEEP_MONOTONY_DOUBT,
        );
        let periodic = Reading::of(
            self.period_correlation >= PERIODIC_CORRELATION
                && self.period_scatter <= PERIOD_REPEATS,
            self.period_correlation >= PERIODIC_CORRELATION_DOUBT
                && self.period_scatter <= PERIOD_REPEATS_DOUBT,
        );
        let impact = self.crest_factor >= IMPACT_CREST_FACTOR;
        let mut kinds = Vec::new();
        for &tone in tone.sides() {
            for &sweep in sweep.sides() {
                for &periodic in periodic.sides() {
                    kinds.push(kind(tone, sweep, impact, periodic));
                }
            }
        }
        Excitation::ALL
            .iter()
            .copied()
            .filter(|k| kinds.contains(k))
            .collect()
    }
}

/// The kind the features say, the first that applies in the order of [`Evidence`]'s table: a tone; a
/// sweep that does not repeat; a hammer's crest factor; a repeat; else random.
fn kind(tone: bool, sweep: bool, impact: bool, periodic: bool) -> Excitation {
    if tone {
        Excitation::SteppedSine
    } else if sweep && !periodic {
        Excitation::Sweep
    } else if impact {
        Excitation::Impact
    } else if periodic {
        Excitation::Periodic
    } else {
        Excitation::Random
    }
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

    /// The kind `record`'s strongest force says ([`Evidence::readings`]): a stepped sine, a
    /// sweep, impacts, periodic or random forcing.
    ///
    /// # Errors
    /// [`Error::UnclearExcitation`] naming the record, the kinds it reads as and its
    /// [`Evidence`] when a feature near its threshold leaves two kinds or more.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Record;
    /// use bearing_ident::excitation::Excitation;
    /// use bearing_ident::simulate::multisine;
    /// let f = multisine(250, 3..=40, 1.0, 2000, 3)?;
    /// let r = Record::new("ms", 1000.0, vec![f], vec![vec![0.0; 2000]])?;
    /// assert_eq!(Excitation::from_record(&r)?, Excitation::Periodic);
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_record(record: &Record) -> Result<Excitation> {
        Excitation::from_evidence(record, Evidence::of(record))
    }

    /// [`Excitation::from_record`] from `record`'s evidence, made already.
    ///
    /// # Errors
    /// As [`Excitation::from_record`].
    pub(crate) fn from_evidence(record: &Record, evidence: Evidence) -> Result<Excitation> {
        match evidence.readings().as_slice() {
            [kind] => Ok(*kind),
            kinds => Err(Error::UnclearExcitation {
                record: record.label().to_owned(),
                kinds: kinds.to_vec(),
                evidence: Box::new(evidence),
            }),
        }
    }

    /// Detects the kind of test from the first record whose force is not flat (a hammer hit
    /// that did not register says nothing of the excitation), as [`Excitation::from_record`]
    /// reads it.
    ///
    /// # Errors
    /// [`Error::NoRecords`] for no records; [`Error::DeadChannel`] naming the first record's
    /// force 0 when every record's force is flat; [`Error::UnclearExcitation`] when the
    /// deciding record reads as two kinds or more.
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
        Excitation::from_record(deciding_record(records.iter().map(Ok::<_, Error>))?)
    }
}

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
/// or not finite. The peak is read at the smallest or the largest sample: `v/s − f̄` rounds
/// monotonically in `v`, so its largest magnitude is at one of them, the very value a pass
/// over every sample finds.
fn crest(f: &[f64]) -> f64 {
    let (low, high) = f
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let scale = high.max(-low);
    if scale <= 0.0 || !scale.is_finite() {
        return 0.0;
    }
    let mean = f.iter().map(|v| v / scale).sum::<f64>() / f.len() as f64;
    let centred = |v: f64| v / scale - mean;
    let rms = (f.iter().map(|&v| centred(v).powi(2)).sum::<f64>() / f.len() as f64).sqrt();
    let peak = centred(low).abs().max(centred(high).abs());
    if rms > 0.0 { peak / rms } else { 0.0 }
}

/// `f` over its largest magnitude, less its mean, into `x`; `false` (and `x` left as it was)
/// when flat or not finite.
fn centre_into(f: &[f64], x: &mut Vec<f64>) -> bool {
    let scale = crate::lanes::max_abs(f);
    if scale <= 0.0 || !scale.is_finite() {
        return false;
    }
    let mean = f.iter().map(|v| v / scale).sum::<f64>() / f.len() as f64;
    x.clear();
    x.extend(f.iter().map(|v| v / scale - mean));
    true
}

/// What one pass over a centred force gives: its crest factor (as [`crest`] of the force) and
/// its steadiness (mean power of its weaker half over that of its stronger; 0 when flat).
#[derive(Debug, Default)]
struct Powers {
    crest: f64,
    steadiness: f64,
}

impl Powers {
    /// From the centred force `x` ([`centred`]): each sum runs in the order of its own
    /// pass, so the values are those of separate passes.
    fn of(x: &[f64]) -> Powers {
        let (first, second) = x.split_at(x.len() / 2);
        let (mut total, mut peak) = (0.0, 0.0_f64);
        let mut half = |s: &[f64]| {
            let mut power = 0.0;
            for v in s {
                let square = v * v;
                power += square;
                total += square;
                peak = peak.max(v.abs());
            }
            power / s.len() as f64
        };
        let (a, b) = (half(first), half(second));
        let rms = (total / x.len() as f64).sqrt();
        let strong = a.max(b);
        Powers {
            crest: if rms > 0.0 { peak / rms } else { 0.0 },
            steadiness: if strong > 0.0 { a.min(b) / strong } else { 0.0 },
        }
    }
}

/// What the spectrum of a force says: its tone and the frequency of its peak (cycles per
/// sample), its sweep and the lines that was read over ([`Evidence`]); all 0 for a force too
/// short or flat.
#[derive(Debug, Default)]
struct Spectral {
    tone: f64,
    cycles: f64,
    sweep: f64,
    lines: usize,
}

impl Spectral {
    /// From the DFT of `buffers.x` (centred, at least [`MIN_SAMPLES`] long, overwritten) and
    /// that of `m x_m`.
    fn of(buffers: &mut Buffers) -> Option<Spectral> {
        let Buffers {
            x,
            moment,
            spectrum,
            moment_spectrum,
            scratch,
        } = buffers;
        let n = x.len();
        let fft = PLANNER.with(|planner| planner.borrow_mut().plan_fft_forward(n));
        moment.clear();
        moment.extend(x.iter().enumerate().map(|(m, v)| m as f64 * v));
        scratch.resize(fft.get_scratch_len(), c64::ZERO);
        spectrum.resize(n / 2 + 1, c64::ZERO);
        moment_spectrum.resize(n / 2 + 1, c64::ZERO);
        fft.process_with_scratch(x, spectrum, scratch).ok()?;
        fft.process_with_scratch(moment, moment_spectrum, scratch)
            .ok()?;
        let (tone, peak) = tone(spectrum, n);
        let (sweep, lines) = sweep(spectrum, moment_spectrum);
        Some(Spectral {
            tone,
            cycles: peak as f64 / n as f64,
            sweep,
            lines,
        })
    }
}

/// The largest length not above `n` (at least 1) whose FFT is quick, of the form
/// $2^a 3^b 5^c$: at most 6 % shorter than `n` from a thousand samples on, 3 % from 10⁵ (the
/// widest gaps between such numbers). The spectrum of a force is read over its first samples
/// of that length: a length with a large prime factor (14 555 = 5 · 41 · 71) transforms ten
/// times slower, and the last few percent of a record change neither a tone nor a sweep.
fn quick_len(n: usize) -> usize {
    let smooth = |mut m: usize| {
        for p in [2, 3, 5] {
            while m % p == 0 {
                m /= p;
            }
        }
        m == 1
    };
    (1..=n.max(1)).rev().find(|&m| smooth(m)).unwrap_or(1)
}

/// The fraction of the Hann-windowed power within [`TONE_HALF_WIDTH`] lines of the strongest
/// line above 0 Hz, and that line, from the one-sided DFT `spectrum` of `n` samples: the
/// periodic Hann window is the convolution $W_k = \tfrac12 F_k - \tfrac14 (F_{k-1} +
/// F_{k+1})$, the lines beyond either end taken from the conjugate symmetry
/// $F_{-k} = F_{n-k} = \overline{F_k}$.
fn tone(spectrum: &[c64], n: usize) -> (f64, usize) {
    let at = |j: isize| -> c64 {
        if j < 0 {
            spectrum[j.unsigned_abs()].conj()
        } else if (j as usize) < spectrum.len() {
            spectrum[j as usize]
        } else {
            spectrum[n - j as usize].conj()
        }
    };
    let hann = |k: usize| {
        let k = k as isize;
        (at(k) * 0.5 - (at(k - 1) + at(k + 1)) * 0.25).norm_sqr()
    };
    // Each line's windowed power once: the sum, the peak and the lines near it read it.
    let power: Vec<f64> = (0..spectrum.len()).map(hann).collect();
    let total: f64 = power.iter().sum();
    let peak = (1..power.len()).fold(1, |best, k| if power[k] > power[best] { k } else { best });
    let near = peak.saturating_sub(TONE_HALF_WIDTH)..(peak + TONE_HALF_WIDTH + 1).min(power.len());
    let fraction = if total > 0.0 {
        power[near].iter().sum::<f64>() / total
    } else {
        0.0
    };
    (fraction, peak)
}

/// The magnitude of the rank correlation between frequency and group delay over the lines
/// above 0 Hz holding at least [`SWEEP_LINE_LEVEL`] of the strongest line's power (0 with
/// fewer than [`SWEEP_MIN_LINES`]), and how many lines that is.
fn sweep(spectrum: &[c64], moment: &[c64]) -> (f64, usize) {
    let strongest = spectrum[1..]
        .iter()
        .map(|z| z.norm_sqr())
        .fold(0.0, f64::max);
    let level = SWEEP_LINE_LEVEL * strongest;
    let delays: Vec<f64> = (1..spectrum.len())
        .filter(|&k| spectrum[k].norm_sqr() >= level && spectrum[k].norm_sqr() > 0.0)
        .map(|k| (moment[k] * spectrum[k].conj()).re / spectrum[k].norm_sqr())
        .collect();
    let lines = delays.len();
    if lines < SWEEP_MIN_LINES {
        return (0.0, lines);
    }
    (rank_correlation(&delays).abs(), lines)
}

/// Spearman's rank correlation between the positions of `values` and their values,
/// $1 - 6 \sum_i d_i^2 / (n (n^2 - 1))$ with $d_i$ the difference of the ranks (ties, which
/// real data do not give, ranked in order).
fn rank_correlation(values: &[f64]) -> f64 {
    let n = values.len();
    // Each value's key in the order of `f64::total_cmp` (its bits, the negatives' magnitude
    // bits flipped), its position after it: sorted, the order a stable sort by value gives.
    let mut order: Vec<(i64, usize)> = values
        .iter()
        .enumerate()
        .map(|(at, v)| {
            let bits = v.to_bits() as i64;
            (bits ^ (((bits >> 63) as u64) >> 1) as i64, at)
        })
        .collect();
    order.sort_unstable();
    let squares: f64 = order
        .iter()
        .enumerate()
        .map(|(rank, &(_, at))| (rank as f64 - at as f64).powi(2))
        .sum();
    let n = n as f64;
    1.0 - 6.0 * squares / (n * (n * n - 1.0))
}

/// The first record of `records` whose force is not flat (crest factor above 0), reading
/// `records` only as far as that: records that arrive one at a time (files read in turn) are
/// read no further than the first with a force, the record that decides the excitation.
///
/// # Errors
/// The first error of `records`; [`Error::NoRecords`] for none; [`Error::DeadChannel`] naming
/// the first record's force 0 when every record's force is flat.
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::excitation::deciding_record;
/// let flat = Record::new("flat", 100.0, vec![vec![1.0; 200]], vec![vec![0.0; 200]])?;
/// let mut f = vec![0.0; 200];
/// f[5] = 1.0;
/// let hit = Record::new("hit", 100.0, vec![f], vec![vec![0.0; 200]])?;
/// let records = [flat, hit];
/// let deciding = deciding_record(records.iter().map(Ok::<_, bearing_ident::Error>))?;
/// assert_eq!(deciding.label(), "hit");
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn deciding_record<R, E>(
    records: impl IntoIterator<Item = std::result::Result<R, E>>,
) -> std::result::Result<R, E>
where
    R: Borrow<Record>,
    E: From<Error>,
{
    let mut first: Option<(String, f64)> = None;
    for record in records {
        let record = record?;
        let r = record.borrow();
        if crest_factor(r) > 0.0 {
            return Ok(record);
        }
        first.get_or_insert_with(|| (r.label().to_owned(), r.force(0)[0]));
    }
    let (record, value) = first.ok_or(Error::NoRecords)?;
    Err(Error::DeadChannel {
        record,
        channel: Channel::Force(0),
        value,
    }
    .into())
}

/// The crest factor of the record that decides the excitation ([`deciding_record`]).
///
/// # Errors
/// Those of [`deciding_record`].
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
    R: Borrow<Record>,
    E: From<Error>,
{
    deciding_record(records).map(|r| crest_factor(r.borrow()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::{AntiAlias, ImpactTest, Kind, Setup, Simulator, multisine, seed_rig};

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

    /// The kind detection should find in the records of a simulated test of `kind`.
    fn expected(kind: Kind) -> Excitation {
        match kind {
            Kind::Impact => Excitation::Impact,
            Kind::Random => Excitation::Random,
            Kind::Multisine => Excitation::Periodic,
            Kind::SteppedSine => Excitation::SteppedSine,
            Kind::Sweep => Excitation::Sweep,
        }
    }

    /// Every kind the `simulate` command makes, at 2 % and 5 % noise and three seeds, with the
    /// command's defaults (shorter random records, fewer records per direction): every
    /// record reads as its kind alone, and so do the records together. Measured (first
    /// record, over seeds and noise): impacts crest factor 34.6–34.7; random tone ≤ 0.002, sweep
    /// ≤ 0.05, period correlation ≤ 0.05; multisine correlation 0.998–0.999, scatter ≤ 0.003;
    /// stepped sine tone 0.998–0.9998, steadiness ≥ 0.99; sweep 0.998–1.0 over 121 lines.
    #[test]
    fn every_simulated_kind_reads_as_itself() {
        for kind in [
            Kind::Impact,
            Kind::Random,
            Kind::Multisine,
            Kind::SteppedSine,
            Kind::Sweep,
        ] {
            for noise in [0.02, 0.05] {
                for seed in 1..=3 {
                    let mut setup = Setup {
                        kind,
                        noise,
                        seed,
                        impacts: 1,
                        records: 1,
                        ..Setup::default()
                    };
                    if kind == Kind::Random {
                        setup.duration = Some(8.0);
                    }
                    if kind == Kind::SteppedSine {
                        setup.freqs = Some(vec![10.0, 48.0, 4.0]);
                    }
                    let records = setup.run(&seed_rig()).unwrap().records;
                    let e = Evidence::of(&records[0]);
                    println!(
                        "{kind} noise {noise} seed {seed}: crest {:.2} tone {:.4} at {:.2} Hz \
                         steadiness {:.3} sweep {:.3} over {} lines period correlation {:.3} \
                         scatter {:.3}",
                        e.crest_factor,
                        e.tone,
                        e.tone_hz,
                        e.steadiness,
                        e.sweep,
                        e.sweep_lines,
                        e.period_correlation,
                        e.period_scatter
                    );
                    for r in &records {
                        let e = Evidence::of(r);
                        assert_eq!(
                            e.readings(),
                            [expected(kind)],
                            "{kind}, noise {noise}, seed {seed}, {}: {e:?}",
                            r.label()
                        );
                    }
                    assert_eq!(Excitation::detect(&records).unwrap(), expected(kind));
                }
            }
        }
    }

    /// A sweep followed by a long free decay has nearly a hammer's crest factor, and a sweep
    /// from 20 to 30 Hz in 1 s nearly a tone's peak and a repeat one cycle later: both still
    /// read as sweeps; narrow-band random forcing (25–30 Hz), which resembles itself one
    /// cycle later but does not repeat, reads as random.
    #[test]
    fn long_tails_narrow_sweeps_and_narrow_bands() {
        let run = |kind: Kind, freqs: [f64; 2], duration: f64| {
            let setup = Setup {
                kind,
                noise: 0.05,
                records: 1,
                freqs: Some(freqs.to_vec()),
                duration: Some(duration),
                ..Setup::default()
            };
            setup.run(&seed_rig()).unwrap().records
        };
        let long = run(Kind::Sweep, [5.0, 60.0], 30.0);
        let e = Evidence::of(&long[0]);
        assert!(e.crest_factor > 6.0 && e.sweep > 0.95, "{e:?}");
        assert_eq!(e.readings(), [Excitation::Sweep]);
        let narrow = run(Kind::Sweep, [20.0, 30.0], 2.2);
        let e = Evidence::of(&narrow[0]);
        assert!(
            e.tone > TONE_FRACTION_DOUBT && e.steadiness < STEADY_POWER,
            "{e:?}"
        );
        assert_eq!(e.readings(), [Excitation::Sweep], "{e:?}");
        let band = run(Kind::Random, [25.0, 30.0], 10.0);
        let e = Evidence::of(&band[0]);
        assert!(
            e.period_correlation > PERIODIC_CORRELATION && e.period_scatter > PERIOD_REPEATS_DOUBT,
            "{e:?}"
        );
        assert_eq!(e.readings(), [Excitation::Random]);
    }

    /// A 12.5 Hz tone in noise of 0.73 of its RMS: 0.65 of the power in the tone, and the same
    /// autocorrelation one cycle later; each read either way, the force may be a stepped sine,
    /// periodic or random. Detection names the three and asks.
    #[test]
    fn an_unclear_force_names_the_kinds_it_reads_as() {
        use rand::SeedableRng;
        let n = 8000;
        let tone = crate::simulate::sine(12.5, std::f64::consts::SQRT_2, 1000.0, n).unwrap();
        let clean = Record::new("noisy-tone", 1000.0, vec![tone], vec![vec![1.0; n]]).unwrap();
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let r = crate::simulate::add_noise(&clean, 0.73, &mut rng).unwrap();
        let err = Excitation::detect(std::slice::from_ref(&r)).unwrap_err();
        let Error::UnclearExcitation {
            record,
            kinds,
            evidence: e,
        } = &err
        else {
            panic!("{err:?}")
        };
        assert_eq!(record, "noisy-tone");
        use Excitation::*;
        assert_eq!(kinds, &[Random, Periodic, SteppedSine], "{e:?}");
        assert!(
            (e.tone - 1.0 / (1.0 + 0.73f64.powi(2))).abs() < 0.02,
            "{e:?}"
        );
        assert!(e.period_correlation > PERIODIC_CORRELATION_DOUBT, "{e:?}");
        assert!(e.period_correlation < PERIODIC_CORRELATION, "{e:?}");
        assert_eq!(err.kind(), crate::ErrorKind::UnclearExcitation);
        let message = err.to_string();
        println!("{message}");
        assert!(
            message.contains("reads as random, periodic or stepped-sine"),
            "{message}"
        );
        assert!(
            message.contains("--excitation random|periodic|stepped-sine"),
            "{message}"
        );
    }

    /// Every feature near its threshold is read both ways, and only the kinds that differ are
    /// named.
    #[test]
    fn readings_at_the_thresholds() {
        let quiet = Evidence {
            crest_factor: 3.0,
            tone: 0.01,
            tone_hz: 10.0,
            steadiness: 1.0,
            sweep: 0.0,
            sweep_lines: 100,
            period_s: None,
            period_correlation: 0.0,
            period_scatter: 1.0,
        };
        let with = |f: &dyn Fn(&mut Evidence)| {
            let mut e = quiet;
            f(&mut e);
            e.readings()
        };
        use Excitation::*;
        assert_eq!(quiet.readings(), [Random]);
        assert_eq!(with(&|e| e.tone = 0.8), [SteppedSine]);
        assert_eq!(with(&|e| e.tone = 0.6), [Random, SteppedSine]);
        assert_eq!(with(&|e| (e.tone, e.steadiness) = (0.95, 0.2)), [Random]);
        assert_eq!(with(&|e| e.sweep = 0.9), [Sweep]);
        assert_eq!(with(&|e| e.sweep = 0.75), [Random, Sweep]);
        assert_eq!(with(&|e| (e.sweep, e.crest_factor) = (0.95, 9.0)), [Sweep]);
        assert_eq!(
            with(&|e| (e.sweep, e.crest_factor) = (0.8, 9.0)),
            [Impact, Sweep]
        );
        assert_eq!(with(&|e| e.crest_factor = 8.0), [Impact]);
        let periodic = |e: &mut Evidence| (e.period_correlation, e.period_scatter) = (0.9, 0.1);
        assert_eq!(with(&periodic), [Periodic]);
        // A sweep that repeats is a periodic chirp, a tone that repeats a stepped sine.
        assert_eq!(with(&|e| (periodic(e), e.sweep = 0.99).1), [Periodic]);
        assert_eq!(with(&|e| (periodic(e), e.tone = 0.99).1), [SteppedSine]);
        assert_eq!(
            with(&|e| (periodic(e), e.tone = 0.7).1),
            [Periodic, SteppedSine]
        );
        assert_eq!(
            with(&|e| (e.period_correlation, e.period_scatter) = (0.7, 0.1)),
            [Random, Periodic]
        );
        assert_eq!(
            with(&|e| (e.period_correlation, e.period_scatter) = (0.9, 0.6)),
            [Random, Periodic]
        );
        assert_eq!(
            with(&|e| (e.period_correlation, e.period_scatter) = (0.9, 0.9)),
            [Random]
        );
    }

    /// A flat or too short force has no tone, steadiness or sweep; the features of a force of
    /// 1e300 N are those of the same force of 1 N (it is scaled before it is squared).
    #[test]
    fn flat_short_and_scaled_forces() {
        let flat = Record::new("flat", 100.0, vec![vec![3.0; 500]], vec![vec![0.0; 500]]).unwrap();
        let e = Evidence::of(&flat);
        let none = |v: f64| v.abs() < f64::MIN_POSITIVE;
        assert!(none(e.tone) && none(e.steadiness) && none(e.sweep), "{e:?}");
        assert_eq!(e.sweep_lines, 0);
        assert_eq!(e.period_s, None);
        let short: Vec<f64> = (0..20).map(|m| (m as f64).sin()).collect();
        let short = Record::new("short", 100.0, vec![short], vec![vec![0.0; 20]]).unwrap();
        assert!(none(Evidence::of(&short).tone));
        let f = multisine(250, 3..=40, 1.0, 2000, 3).unwrap();
        let big: Vec<f64> = f.iter().map(|v| v * 1e300).collect();
        let zeros = vec![vec![0.0; 2000]];
        let small = Evidence::of(&Record::new("n", 1000.0, vec![f], zeros.clone()).unwrap());
        let large = Evidence::of(&Record::new("kn", 1000.0, vec![big], zeros).unwrap());
        for (a, b) in [
            (small.tone, large.tone),
            (small.sweep, large.sweep),
            (small.steadiness, large.steadiness),
            (small.crest_factor, large.crest_factor),
        ] {
            assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{a} vs {b}");
        }
    }

    /// The quick lengths: no prime factor above 5, the largest not above the length given.
    #[test]
    fn quick_lengths() {
        for (n, quick) in [
            (1, 1),
            (7, 6),
            (1000, 1000),
            (14_555, 14_400),
            (402_000, 400_000),
        ] {
            assert_eq!(quick_len(n), quick, "{n}");
        }
    }

    /// Spearman's correlation of values in order is 1, in reverse −1.
    #[test]
    fn rank_correlation_of_ordered_values() {
        let up: Vec<f64> = (0..20).map(|v| (v as f64).powi(3)).collect();
        let down: Vec<f64> = up.iter().rev().copied().collect();
        assert!((rank_correlation(&up) - 1.0).abs() < 1e-15);
        assert!((rank_correlation(&down) + 1.0).abs() < 1e-15);
    }

    /// The ranks are those of a stable sort by `f64::total_cmp`, bit for bit: ties ranked in
    /// order, negatives, signed zeros and infinities included.
    #[test]
    fn rank_correlation_ranks_as_a_stable_sort() {
        let stable = |values: &[f64]| {
            let mut order: Vec<usize> = (0..values.len()).collect();
            order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
            let squares: f64 = order
                .iter()
                .enumerate()
                .map(|(rank, &at)| (rank as f64 - at as f64).powi(2))
                .sum();
            let n = values.len() as f64;
            1.0 - 6.0 * squares / (n * (n * n - 1.0))
        };
        let values: Vec<f64> = (0..200u64)
            .map(|m| {
                let h = m.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 58;
                match h % 7 {
                    0 => 0.0,
                    1 => -0.0,
                    2 => f64::NEG_INFINITY,
                    _ => (h as f64 - 30.0) * 0.25,
                }
            })
            .collect();
        assert_eq!(
            rank_correlation(&values).to_bits(),
            stable(&values).to_bits()
        );
    }
    /// The features read in shared passes are those of separate ones, bit for bit: the
    /// evidence's crest factor is [`crest_factor`]'s (the job lets the first record's
    /// evidence decide when it is not 0), and [`crest`]'s peak, read at the extremes, is the
    /// largest over every sample.
    #[test]
    fn shared_passes_give_the_separate_passes_bits() {
        let by_every_sample = |f: &[f64]| {
            let scale = f.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
            let mean = f.iter().map(|v| v / scale).sum::<f64>() / f.len() as f64;
            let centred = |v: &f64| v / scale - mean;
            let rms = (f.iter().map(|v| centred(v).powi(2)).sum::<f64>() / f.len() as f64).sqrt();
            f.iter().map(|v| centred(v).abs()).fold(0.0, f64::max) / rms
        };
        let mut sim = Simulator::new(&seed_rig(), 500.0, 4000, AntiAlias::default()).unwrap();
        let random = sim.random_record("random", 40.0, 2).unwrap();
        let impacts = ImpactTest::seed_rig().run(&seed_rig()).unwrap();
        for r in [&random, &impacts[0], &impacts[3]] {
            assert_eq!(
                Evidence::of(r).crest_factor.to_bits(),
                crest_factor(r).to_bits(),
                "{}",
                r.label()
            );
            for c in 0..r.dofs() {
                for f in [r.force(c), r.displacement(c)] {
                    let shifted: Vec<f64> = f.iter().map(|v| 2.0 - 3.0 * v).collect();
                    for f in [f, &shifted[..]] {
                        assert_eq!(crest(f).to_bits(), by_every_sample(f).to_bits());
                    }
                }
            }
        }
    }
}
