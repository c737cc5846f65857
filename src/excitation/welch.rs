//! The Welch segment length for random excitation chosen from the data: a first fit gives the
//! modes, the line spacing is set well inside the lightest mode's half-power bandwidth, and
//! the record is cut into as many segments as that spacing allows ([`choose_welch`]).

use super::{MIN_SEGMENT, welch_len};
use crate::error::{Error, Result};
use crate::gate::{BiasSource, leaked_flexibility, predicted_bias};
use crate::identify::{Identifier, Spectra};
use crate::records::Record;
use crate::solve::{IvfOptions, Method};
use crate::spectra::Segmentation;
use crate::tolerance::BIAS_SIGMAS;

/// Fewest lines per half-power bandwidth `2ζf_n` of the lightest mode that [`choose_welch`]
/// aims for: the peak's leakage bias ([`leakage_bias`](crate::gate::leakage_bias)) is then
/// about `(1/8)²/3 ≈ 0.5 %`; the damping's, predicted from the model, decides beyond.
pub const LINES_PER_BANDWIDTH: f64 = 8.0;

/// Fewest Welch segments over all records (Hann, 50 % overlap) [`choose_welch`] leaves: the
/// random error of H1 with `q` inputs goes as `1/(n_d − q)`, so a handful of averages per
/// input at least.
pub const MIN_AVERAGES: usize = 16;

/// The segment length [`choose_welch`] picked and why.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct WelchChoice {
    /// Samples per segment (a power of two).
    pub nperseg: usize,
    /// Line spacing `f_s / nperseg` (Hz).
    pub resolution_hz: f64,
    /// Segments per record (50 % overlap).
    pub segments_per_record: usize,
    /// Half-power bandwidth `2ζf_n` of the lightest mode in the band from the first fit (Hz);
    /// `None` if no mode lies in the band (the default length is kept).
    pub lightest_bandwidth_hz: Option<f64>,
    /// Predicted relative leakage bias of the damping at the chosen length (the largest over
    /// the diagonal of `C`, the coefficient leakage biases most), from the first fit's model
    /// ([`leaked_flexibility`]); `None` when it could not be predicted.
    pub predicted_bias: Option<f64>,
    /// The largest predicted leakage bias of any coefficient at the chosen length, in the
    /// first fit's standard deviations of the random error (`budget.random`: its combined
    /// ones carry its own leakage); `None` when it could not be predicted.
    pub predicted_sigmas: Option<f64>,
    /// Whether the records were too short for [`LINES_PER_BANDWIDTH`] lines, or for a
    /// predicted bias below [`BIAS_SIGMAS`] standard deviations, with [`MIN_AVERAGES`]
    /// segments (the segment is then the longest that leaves them).
    pub record_limited: bool,
}

/// The Welch segment length for random `records` (all of one length) identified with
/// `identifier`: a first fit with [`welch_len`] segments (by the identifier's method, its
/// coefficients and their sandwich standard deviations: the fit alone, without the model
/// check, error bars or bias of an identification) gives the model and the random error; the
/// lightest mode in the band (half-power bandwidth `B = 2ζf_n`) sets the line
/// spacing `Δf ≤ B /` [`LINES_PER_BANDWIDTH`]; the segment is then doubled while the leakage
/// bias predicted from the model ([`leaked_flexibility`], [`predicted_bias`]) exceeds
/// [`BIAS_SIGMAS`] standard deviations of the random error on some coefficient (the first
/// fit's, which longer segments leave about the same: they trade averages for lines). Each length is the shortest power
/// of two that meets these, never shorter than the default (shorter segments trade lines for
/// averages at about the same information, and leak more), and halved back while the records
/// give fewer than [`MIN_AVERAGES`] segments. Use it with [`Identifier::segmentation`]; an
/// explicit length (`--nperseg`) overrides it.
///
/// # Errors
/// [`Error::NoRecords`] for no records; the errors of the first fit (those
/// [`Identifier::identify`] gives at the default length).
///
/// # Examples
/// ```
/// use bearing_ident::excitation::{choose_welch, welch_len};
/// use bearing_ident::simulate::{AntiAlias, Simulator, seed_rig};
/// use bearing_ident::{Estimator, Identifier, Window};
/// let mut sim = Simulator::new(&seed_rig(), 500.0, 16_384, AntiAlias::default())?;
/// let records = vec![sim.random_record("r", 20.0, 3)?];
/// let id = Identifier::new(8.0, 49.0).estimator(Estimator::H1).window(Window::Hann);
/// let choice = choose_welch(&records, &id)?;
/// // ζ ≈ 0.08 at 28 Hz: B ≈ 4.5 Hz, Δf ≤ 0.56 Hz wants 1024 samples; the default (2048)
/// // is finer already, leaks little against one record's scatter, and is kept.
/// assert_eq!(choice.nperseg, welch_len(16_384));
/// assert!(choice.predicted_bias.unwrap() < 0.005);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn choose_welch(records: &[Record], identifier: &Identifier) -> Result<WelchChoice> {
    let method = identifier.check()?.method();
    Ok(choose_with_spectra(records, identifier, method)?.0)
}

/// [`choose_welch`] with the first fit by `method`, and the spectra of that fit (the records
/// screened and transformed at the default length by `identifier`'s settings): when the
/// choice is the default length, they are the final identification's
/// ([`Spectra::finish`]).
///
/// # Errors
/// As [`choose_welch`].
pub(crate) fn choose_with_spectra(
    records: &[Record],
    identifier: &Identifier,
    method: Method,
) -> Result<(WelchChoice, Spectra)> {
    let first = records.first().ok_or(Error::NoRecords)?;
    let (len, rate) = (first.len(), first.sample_rate());
    let default = welch_len(len);
    let mut spectra = identifier
        .clone()
        .segmentation(Segmentation::Welch { len: default })
        .spectra(records)?;
    let fit = spectra.quick_fit(method)?;
    let band = fit.band;
    let model = &fit.coefficients;
    let lightest = model
        .modes()?
        .iter()
        .filter(|m| (band.low_hz()..=band.high_hz()).contains(&m.natural_frequency_hz))
        .map(|m| 2.0 * m.damping_ratio * m.natural_frequency_hz)
        .filter(|b| b.is_finite() && *b > 0.0)
        .reduce(f64::min);
    let averages =
        |seg: usize| Segmentation::Welch { len: seg }.starts(len).count() * records.len();
    let allowed = |seg: usize| seg <= len && averages(seg) >= MIN_AVERAGES;
    // The leakage bias a segment length would add, predicted from the first fit: the
    // damping's (relative, largest over the diagonal) and the worst in standard deviations.
    let predicted = |seg: usize| -> Option<(f64, f64)> {
        let freqs: Vec<f64> = band
            .lines(rate, seg)
            .ok()?
            .iter()
            .map(|&k| k as f64 * rate / seg as f64)
            .collect();
        let leaked = leaked_flexibility(model, &freqs, seg, rate).ok()?;
        let bias = predicted_bias(
            model,
            &freqs,
            leaked,
            method,
            &IvfOptions::default(),
            BiasSource::Leakage,
        )
        .ok()?;
        let damping = (0..model.dofs())
            .map(|i| (bias.bias.damping()[(i, i)] / model.damping()[(i, i)]).abs())
            .fold(0.0, f64::max);
        // Against the random error alone: error bars that carried the first fit's own
        // (shorter segments') leakage bias would hide the bias they are to judge.
        let sigmas = fit
            .random
            .as_ref()
            .and_then(|s| bias.worst_in(s))
            .map(|w| w.3)?;
        Some((damping, sigmas))
    };
    // The last prediction made, with its length: the chosen length's is not made twice.
    let mut last: Option<(usize, Option<(f64, f64)>)> = None;
    let (nperseg, record_limited) = match lightest {
        None => (default, false),
        Some(b) => {
            let wanted = (rate * LINES_PER_BANDWIDTH / b).ceil() as usize;
            let mut seg = wanted.max(MIN_SEGMENT).next_power_of_two().max(default);
            let mut limited = false;
            while seg > default && !allowed(seg) {
                seg /= 2;
                limited = true;
            }
            // Longer while the predicted bias stands out of the random error.
            while !limited {
                let prediction = predicted(seg);
                last = Some((seg, prediction));
                if !prediction.is_some_and(|(_, z)| z > BIAS_SIGMAS) {
                    break;
                }
                if allowed(2 * seg) {
                    seg *= 2;
                } else {
                    limited = true;
                }
            }
            (seg, limited)
        }
    };
    let resolution_hz = rate / nperseg as f64;
    let prediction = lightest.and_then(|_| match last {
        Some((seg, prediction)) if seg == nperseg => prediction,
        _ => predicted(nperseg),
    });
    let choice = WelchChoice {
        nperseg,
        resolution_hz,
        segments_per_record: Segmentation::Welch { len: nperseg }.starts(len).count(),
        lightest_bandwidth_hz: lightest,
        predicted_bias: prediction.map(|p| p.0),
        predicted_sigmas: prediction.map(|p| p.1),
        record_limited,
    };
    Ok((choice, spectra))
}
