//! The parts of [`Error`](super::Error)'s messages that need code (the line spacing of a band, a
//! size past a limit, the advice for a field test's dependent responses), and the longer
//! sentences, kept here so that the enum reads as a list of variants.

use super::{Channel, SpectrumKind};
use crate::Method;

/// The kind of a channel in words: `force` or `displacement`.
fn kind_of(channel: Channel) -> &'static str {
    if matches!(channel, Channel::Force(_)) {
        "force"
    } else {
        "displacement"
    }
}

/// [`Error::LooksSwapped`](super::Error::LooksSwapped).
pub(super) fn looks_swapped(
    failure: &super::Error,
    force_crest: f64,
    response_crest: f64,
) -> String {
    format!(
        "{failure}; the response columns look like a hammer's force (crest factor \
         {response_crest:.1}, an impact's is 8 or more) and the force columns do not \
         ({force_crest:.1}): are the columns of --force and --disp exchanged?"
    )
}

/// [`Error::IncompleteStep`](super::Error::IncompleteStep).
pub(super) fn incomplete_step(freq_hz: f64, direction: usize, dofs: usize) -> String {
    format!(
        "stepped sine at {freq_hz} Hz: no record drives direction {direction} of {dofs}; every \
         frequency step needs one record per direction"
    )
}

/// [`Error::NonFiniteResult`](super::Error::NonFiniteResult).
pub(super) fn non_finite_result(stage: super::Quantity, freq_hz: f64) -> String {
    format!(
        "the {stage} at {freq_hz} Hz is not finite: the records' levels overflow f64 in the \
         estimator (rescale the channels, e.g. to N and m)"
    )
}

/// [`Error::RankDeficient`](super::Error::RankDeficient).
pub(super) fn rank_deficient(rank: usize, dofs: usize) -> String {
    format!(
        "the excitations are rank-deficient: they span {rank} of {dofs} directions over the \
         band; {dofs} linearly independent excitations are needed (for example impacts in x \
         and in y)"
    )
}

/// [`Error::NonFiniteRegressor`](super::Error::NonFiniteRegressor).
pub(super) fn non_finite_regressor(record: &str, term: &str, sample: usize) -> String {
    format!(
        "record `{record}`: the nonlinear term {term} is not finite at sample {sample} (rescale \
         the channels, e.g. to N and m)"
    )
}

/// [`Error::MissingResponse`](super::Error::MissingResponse).
pub(super) fn missing_response(speed_rad_s: f64, test: &str, node: usize, dir: &str) -> String {
    format!(
        "no response at {speed_rad_s} rad/s, test `{test}`, node {node}, direction {dir}: every \
         speed and test needs every probe"
    )
}

/// [`Error::ChannelCount`](super::Error::ChannelCount).
pub(super) fn channel_count(record: &str, forces: usize, displacements: usize) -> String {
    format!(
        "record `{record}`: {forces} force and {displacements} displacement channels; a record \
         needs n ≥ 1 of each, one per degree of freedom"
    )
}

/// [`Error::ResponseCount`](super::Error::ResponseCount).
pub(super) fn response_count(record: &str, expected: usize, actual: usize) -> String {
    format!(
        "record `{record}`: {actual} response kinds for {expected} response channels; give one \
         per degree of freedom"
    )
}

/// [`Error::DeadChannel`](super::Error::DeadChannel).
pub(super) fn dead_channel(record: &str, channel: Channel, value: f64) -> String {
    format!(
        "record `{record}`: {channel} and every other {} channel is flat at {value:e} over the \
         whole record: the channel was not recorded (dead sensor or amplifier, or a hammer hit \
         that did not register); leave the record out",
        kind_of(channel)
    )
}

/// [`Error::BadRecord`](super::Error::BadRecord).
pub(super) fn bad_record(record: &str, finding: &str, failure: &str) -> String {
    format!(
        "record `{record}`: {finding}; the fit failed ({failure}) because of it: leave it out \
         (reject the records the screening finds)"
    )
}

/// [`Error::TooFewLines`](super::Error::TooFewLines).
pub(super) fn too_few_lines(lines: usize, required: usize, resolution_hz: Option<f64>) -> String {
    format!(
        "the band holds {lines} usable frequency lines, at least {required} are needed ({}): \
         widen the band or lengthen the records (segments)",
        spacing(resolution_hz)
    )
}

/// [`Error::SpectrumOverflow`](super::Error::SpectrumOverflow).
pub(super) fn spectrum_overflow(
    record: &str,
    stage: SpectrumKind,
    channel: Channel,
    freq_hz: f64,
    peak: f64,
) -> String {
    format!(
        "record `{record}`: the {stage} of {channel} at {freq_hz} Hz is not finite: samples up \
         to {peak:e} are too large for the transforms and their products in f64 (rescale the \
         channel, e.g. to N and m)"
    )
}

/// [`Error::LevelOutOfRange`](super::Error::LevelOutOfRange): below 1 an underflow of every
/// channel of the kind, above an overflow of this one.
pub(super) fn level_out_of_range(record: &str, channel: Channel, peak: f64) -> String {
    let kind = kind_of(channel);
    if peak < 1.0 {
        let subnormal = if peak < f64::MIN_POSITIVE {
            ", subnormal values with fewer than 53 significant bits"
        } else {
            ""
        };
        format!(
            "record `{record}`: every {kind} channel peaks at or below {peak:.3e} ({channel} \
             the highest){subnormal}: the squares and products every spectrum forms underflow \
             f64, so the record carries no usable {kind}: the channels are in a unit far too \
             large (rescale them, e.g. to N and m)"
        )
    } else {
        format!(
            "record `{record}`: {channel} peaks at {peak:.3e}: the squares and products every \
             spectrum forms overflow f64: the channel is in a unit far too small (rescale it, \
             e.g. to N and m)"
        )
    }
}

/// [`Error::ImpedanceScale`](super::Error::ImpedanceScale).
pub(super) fn impedance_scale(magnitude: f64) -> String {
    format!(
        "the impedance (force over response) is about {magnitude:.1e} N/m over the band: the \
         squares the fit forms of it and of its inverse leave f64, so the fit cannot be \
         computed; force and response channels in units that far apart (N/m are 1e3 to 1e10 \
         for bearings) are a unit error: rescale them, e.g. to N and m"
    )
}

/// [`Error::IterationNonFinite`](super::Error::IterationNonFinite).
pub(super) fn iteration_non_finite(
    method: Method,
    iteration: usize,
    freq_hz: Option<f64>,
) -> String {
    let at = match freq_hz {
        Some(f) => format!("the model impedance K − ω²M + iωC or its inverse at {f} Hz"),
        None => "its normal equations (all lines together)".to_owned(),
    };
    format!(
        "{method} iteration {iteration} met NaN or infinity in {at}: not a slow convergence \
         but values beyond f64 (check the records' units and levels; a narrower band away from \
         an undamped resonance)"
    )
}

/// [`Error::MlNeedsRepeats`](super::Error::MlNeedsRepeats).
pub(super) fn ml_needs_repeats() -> &'static str {
    "method ml needs the records' spectra for its noise model (a ready-made FRF has none) and, \
     for periodic records (`Segmentation::Periods`), at least 3 periods per record"
}

/// [`Error::TooFewAverages`](super::Error::TooFewAverages).
pub(super) fn too_few_averages(averages: usize, inputs: usize, required: usize) -> String {
    format!(
        "the records give {averages} Welch segments, but the reverse path with {inputs} inputs \
         (displacements and nonlinear terms) needs at least {required}: give more or longer \
         records, or shorter segments"
    )
}

/// [`Error::SimulationDiverged`](super::Error::SimulationDiverged).
pub(super) fn simulation_diverged(record: &str, sample: usize, step_s: f64) -> String {
    format!(
        "record `{record}`: the nonlinear simulation diverged before sample {sample} (RK4 step \
         {step_s:.3e} s): check the signs and sizes of the nonlinear coefficients, or raise the \
         oversampling"
    )
}

/// [`Error::FieldRankDeficient`](super::Error::FieldRankDeficient).
pub(super) fn field_rank_deficient(bearing: &str, worst: f64, dependent_tests: bool) -> String {
    format!(
        "bearing `{bearing}`: the two tests' responses are dependent at every speed (smallest \
         condition number {worst:.3e}): {}",
        rank_deficient_advice(dependent_tests)
    )
}

/// Why a field identification's response pairs are singular everywhere, and what to change.
fn rank_deficient_advice(dependent_tests: bool) -> &'static str {
    if dependent_tests {
        "the two tests' added imbalance forces are proportional (masses in one plane give a \
         rank-1 pair whatever their angles): put the second test's masses in another plane"
    } else {
        "the added forces differ, so the supports are nearly isotropic (circular orbits, which \
         imbalance tests cannot separate) or the rotor's response leaves the tests dependent"
    }
}

/// `line spacing … Hz`, or that it is unknown.
fn spacing(resolution_hz: Option<f64>) -> String {
    match resolution_hz {
        Some(df) => format!("line spacing {df} Hz"),
        None => "line spacing unknown: fewer than two lines given".to_owned(),
    }
}

/// A size for a message: whole numbers in full up to 10¹⁵, scientific beyond.
pub(super) fn size(value: f64) -> String {
    if value.abs() < 1e15 {
        format!("{value}")
    } else {
        format!("{value:.3e}")
    }
}

#[cfg(test)]
mod tests {
    #[cfg(feature = "csv")]
    use crate::error::CsvLimitKind;
    use crate::error::{Channel, Error};

    #[test]
    fn messages_carry_the_numbers() {
        let e = Error::NonFinite {
            record: "x1.csv".into(),
            channel: Channel::Displacement(1),
            sample: 42,
            value: f64::NAN,
        };
        let s = e.to_string();
        assert!(s.contains("x1.csv") && s.contains("displacement channel 1") && s.contains("42"));
        let e = Error::RankDeficient { rank: 1, dofs: 2 };
        assert!(e.to_string().contains("1 of 2"));
    }

    /// The causes of a failed fit that are not the fit's: levels, units, NaN in an iteration.
    #[test]
    fn level_scale_and_iteration_messages_name_the_cause() {
        let e = Error::LevelOutOfRange {
            record: "hit-3.csv".into(),
            channel: Channel::Displacement(1),
            peak: 6.1e-314,
        };
        assert_eq!(e.kind(), "non_finite");
        assert_eq!(
            e.to_string(),
            "record `hit-3.csv`: every displacement channel peaks at or below 6.100e-314 \
             (displacement channel 1 the highest), subnormal values with fewer than 53 \
             significant bits: the squares and products every spectrum forms underflow f64, so \
             the record carries no usable displacement: the channels are in a unit far too \
             large (rescale them, e.g. to N and m)"
        );
        let e = Error::LevelOutOfRange {
            record: "hit-3.csv".into(),
            channel: Channel::Force(0),
            peak: 4.5e302,
        };
        assert!(
            e.to_string()
                .contains("force channel 0 peaks at 4.500e302: the squares")
        );
        let e = Error::ImpedanceScale { magnitude: 1.2e205 };
        assert_eq!(e.kind(), "non_finite");
        assert!(
            e.to_string()
                .starts_with("the impedance (force over response) is about 1.2e205 N/m")
        );
        let e = Error::IterationNonFinite {
            method: crate::Method::Ivf,
            iteration: 3,
            freq_hz: Some(12.5),
        };
        assert_eq!(e.kind(), "non_finite");
        assert!(
            e.to_string().starts_with(
                "ivf iteration 3 met NaN or infinity in the model impedance K − ω²M + iωC or \
                 its inverse at 12.5 Hz: not a slow convergence"
            ),
            "{e}"
        );
        let e = Error::IterationNonFinite {
            method: crate::Method::Ivf,
            iteration: 1,
            freq_hz: None,
        };
        assert!(
            e.to_string()
                .contains("in its normal equations (all lines together)")
        );
    }

    #[test]
    fn limits_are_too_large() {
        let e = Error::TooLarge {
            what: "samples per record",
            value: 6.7e33,
            limit: 16_777_216.0,
        };
        assert_eq!(e.kind(), "too_large");
        assert_eq!(
            e.to_string(),
            "samples per record = 6.700e33 is past the limit of 16777216"
        );
        #[cfg(feature = "csv")]
        {
            let e = Error::CsvLimit {
                path: "f.csv".into(),
                line: 1,
                what: CsvLimitKind::LineBytes,
                limit: 1 << 20,
            };
            assert_eq!(e.kind(), "too_large");
            assert_eq!(
                e.to_string(),
                "f.csv, line 1: line length (bytes) past the limit of 1048576"
            );
        }
    }

    #[test]
    fn export_dofs_name_both_counts() {
        let e = Error::ExportDofs {
            format: "a ROSS bearing element",
            dofs: 3,
            expected: 2,
        };
        assert_eq!(e.kind(), "invalid_argument");
        assert_eq!(
            e.to_string(),
            "a ROSS bearing element needs 2 degrees of freedom; this identification has 3"
        );
    }

    #[test]
    #[cfg(feature = "plot")]
    fn plot_errors_name_the_figure() {
        let e = Error::Plot {
            figure: crate::plot::Figure::Impedance,
            message: "disk full".into(),
        };
        assert_eq!(e.kind(), "plot_error");
        assert_eq!(e.to_string(), "figure `impedance`: disk full");
    }

    #[test]
    fn too_few_lines_says_the_spacing_or_that_it_is_unknown() {
        let e = Error::TooFewLines {
            lines: 1,
            required: 6,
            resolution_hz: None,
        };
        assert_eq!(e.kind(), "bad_band");
        assert!(!e.to_string().contains("NaN"), "{e}");
        assert!(e.to_string().contains("unknown"), "{e}");
        let e = Error::TooFewLines {
            lines: 0,
            required: 6,
            resolution_hz: Some(0.5),
        };
        assert!(e.to_string().contains("holds 0 usable") && e.to_string().contains("0.5 Hz"));
    }
}
