//! [`Error`]'s messages (its `Display`, one arm per variant, as `warning_text.rs` holds the
//! warnings' sentences) and the parts of them that need code: the line spacing of a band, a
//! size past a limit, an iterative fit's last change, the advice for a field test's
//! dependent responses.

use std::fmt;

use crate::Method;

use super::{Channel, Error, excerpt};

/// `names` as a list: `a`, `a or b`, `a, b or c`.
fn either(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_owned(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// Why a field identification's response pairs are singular everywhere, and what to change.
pub(super) fn rank_deficient_advice(dependent_tests: bool) -> &'static str {
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

/// An iterative fit's last relative change as messages print it: `1.234e-5`, or `not
/// reported` where the fit keeps none.
pub(super) fn change_text(change: Option<f64>) -> String {
    change.map_or_else(|| "not reported".to_owned(), |c| format!("{c:.3e}"))
}

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

/// The message of each [`Error`]: one sentence that names the input and carries its numbers.
impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidParameter {
                name,
                value,
                expected,
            } => write!(
                f,
                "parameter `{name}` = {value} is invalid: expected {expected}"
            ),
            Error::InvalidSetting { name, expected } => {
                write!(f, "parameter `{name}` is invalid: expected {expected}")
            }
            Error::UnknownName {
                what,
                given,
                expected,
            } => write!(
                f,
                "{what} `{}` is not known: expected {expected}",
                excerpt(given)
            ),
            Error::InvalidOption { message, .. } => write!(f, "{message}"),
            Error::BandText { given } => {
                write!(f, "--band `{given}`: expected LO,HI in Hz, e.g. 8,49")
            }
            Error::Baseline { path, source } => write!(f, "--baseline {path}: {source}"),
            Error::LengthMismatch {
                what,
                expected,
                actual,
            } => write!(f, "{what}: {actual} values, expected {expected}"),
            Error::TooLarge { what, value, limit } => {
                write!(f, "{what} = {} is past the limit of {limit}", size(*value))
            }
            Error::FileLimit { path, what, limit } => {
                write!(f, "{path}: {what} past the limit of {limit}")
            }
            Error::InvalidSampleRate {
                record,
                sample_rate,
            } => write!(
                f,
                "record `{record}`: sampling rate {sample_rate} Hz is not a finite positive number"
            ),
            Error::ChannelCount {
                record,
                forces,
                displacements,
            } => write!(
                f,
                "record `{record}`: {forces} force and {displacements} displacement channels; \
         a record needs n ≥ 1 of each, one per degree of freedom"
            ),
            Error::ResponseCount {
                record,
                expected,
                actual,
            } => write!(
                f,
                "record `{record}`: {actual} response kinds for {expected} response channels; \
         give one per degree of freedom"
            ),
            Error::ChannelLength {
                record,
                channel,
                expected,
                actual,
            } => write!(
                f,
                "record `{record}`: {channel} has {actual} samples, expected {expected}"
            ),
            Error::RecordTooShort {
                record,
                samples,
                minimum,
            } => write!(
                f,
                "record `{record}`: {samples} samples, at least {minimum} are needed"
            ),
            Error::NonFinite {
                record,
                channel,
                sample,
                value,
            } => write!(
                f,
                "record `{record}`: {channel}, sample {sample}: value {value} is not finite"
            ),
            Error::DeadChannel {
                record,
                channel,
                value,
            } => write!(
                f,
                "record `{record}`: {channel} and every other {} channel is flat at {value:e} over the \
         whole record: the channel was not recorded (dead sensor or amplifier, or a hammer hit \
         that did not register); leave the record out",
                if matches!(channel, Channel::Force(_)) {
                    "force"
                } else {
                    "displacement"
                }
            ),
            Error::BadRecord {
                record,
                finding,
                failure,
            } => write!(
                f,
                "record `{record}`: {finding}; the fit failed ({failure}) because of it: leave it out \
         (reject the records the screening finds)"
            ),
            Error::NoRecords => write!(f, "no records were given"),
            Error::DofMismatch {
                record,
                expected,
                actual,
            } => write!(
                f,
                "record `{record}`: {actual} degrees of freedom, expected {expected}"
            ),
            Error::SampleRateMismatch {
                record,
                expected,
                actual,
            } => write!(
                f,
                "record `{record}`: sampling rate {actual} Hz differs from {expected} Hz of the first record"
            ),
            Error::RecordLengthMismatch {
                record,
                expected,
                actual,
            } => write!(
                f,
                "record `{record}`: {actual} samples, but the first record has {expected}"
            ),
            Error::InvalidAssignment {
                record,
                excitation,
                dofs,
            } => write!(
                f,
                "record `{record}`: assigned to excitation {excitation}, but there are only {dofs} degrees of freedom"
            ),
            Error::AssignmentLength { expected, actual } => write!(
                f,
                "the excitation assignment names {actual} records, but {expected} were given"
            ),
            Error::IncompleteStep {
                freq_hz,
                direction,
                dofs,
            } => write!(
                f,
                "stepped sine at {freq_hz} Hz: no record drives direction {direction} of {dofs}; \
         every frequency step needs one record per direction"
            ),
            Error::UnclearExcitation {
                record,
                kinds,
                evidence: e,
            } => {
                let names: Vec<&str> = kinds.iter().map(|k| crate::Choice::name(*k)).collect();
                write!(
                    f,
                    "record `{record}`: cannot tell the excitation from the force, which reads as \
                     {} (crest factor {:.1}; {:.2} of its power in one peak at {:.2} Hz, \
                     steadiness {:.2}; sweep {:.2} over {} lines; period correlation {:.2}, \
                     scatter {:.2}): say which with --excitation {}",
                    either(&names),
                    e.crest_factor,
                    e.tone,
                    e.tone_hz,
                    e.steadiness,
                    e.sweep,
                    e.sweep_lines,
                    e.period_correlation,
                    e.period_scatter,
                    names.join("|"),
                )
            }
            Error::InvalidBand { low_hz, high_hz } => write!(
                f,
                "band {low_hz}–{high_hz} Hz is not a valid band (need finite 0 ≤ low < high)"
            ),
            Error::BandAboveNyquist {
                high_hz,
                nyquist_hz,
            } => write!(
                f,
                "band upper edge {high_hz} Hz is above the Nyquist frequency {nyquist_hz} Hz"
            ),
            Error::TooFewLines {
                lines,
                required,
                resolution_hz,
            } => write!(
                f,
                "the band holds {lines} usable frequency lines, at least {required} are needed \
         ({}): widen the band or lengthen the records (segments)",
                spacing(*resolution_hz)
            ),
            Error::ResponseAtZeroFrequency {
                record,
                channel,
                response,
                freq_hz,
            } => write!(
                f,
                "record `{record}`: {channel} measures {response}, which has no displacement at \
         {freq_hz} Hz (X = V/(iω) = A/(−ω²) needs ω ≠ 0): choose a band above 0 Hz"
            ),
            Error::SpectrumOverflow {
                record,
                stage,
                channel,
                freq_hz,
                peak,
            } => write!(
                f,
                "record `{record}`: the {stage} of {channel} at {freq_hz} Hz is not finite: samples up \
         to {peak:e} are too large for the transforms and their products in f64 (rescale the \
         channel, e.g. to N and m)"
            ),
            Error::NonFiniteResult { stage, freq_hz } => write!(
                f,
                "the {stage} at {freq_hz} Hz is not finite: the records' levels overflow f64 in the \
         estimator (rescale the channels, e.g. to N and m)"
            ),
            Error::RankDeficient { rank, dofs } => write!(
                f,
                "the excitations are rank-deficient: they span {rank} of {dofs} directions over the band; \
         {dofs} linearly independent excitations are needed (for example impacts in x and in y)"
            ),
            Error::SingularFit { method } => write!(
                f,
                "the {method} fit is singular: the band does not determine M, C and K (try a wider band)"
            ),
            Error::Singular { what } => write!(f, "{what} is singular"),
            Error::Decomposition { what } => write!(f, "the {what} decomposition did not converge"),
            Error::NotConverged {
                method,
                iterations,
                change,
            } => write!(
                f,
                "{method} did not converge in {iterations} iterations (last relative change {})",
                change_text(*change)
            ),
            Error::MlNeedsRepeats => write!(
                f,
                "method ml needs the records' spectra for its noise model (a ready-made FRF has none) and, for periodic records (`Segmentation::Periods`), at least 3 periods per record"
            ),
            Error::CoefficientShape {
                mass,
                damping,
                stiffness,
            } => write!(
                f,
                "coefficient matrices must be square and of one size: M is {mass:?}, C is {damping:?}, K is {stiffness:?}"
            ),
            Error::NonFiniteCoefficient { matrix, row, col } => {
                write!(f, "coefficient {matrix}[{row}][{col}] is not finite")
            }
            Error::DofCountMismatch { left, right } => write!(
                f,
                "cannot combine coefficients of {left} and {right} degrees of freedom"
            ),
            Error::BaselineMismatch { what } => write!(
                f,
                "the baseline differs from the system in its {what}: identify both with the same band, lines, estimator, window and degrees of freedom"
            ),
            #[cfg(feature = "json")]
            Error::BadBaseline { message } => write!(f, "{message}"),
            Error::SimulationDiverged {
                record,
                sample,
                step_s,
            } => write!(
                f,
                "record `{record}`: the nonlinear simulation diverged before sample {sample} (RK4 step \
         {step_s:.3e} s): check the signs and sizes of the nonlinear coefficients, or raise \
         the oversampling"
            ),
            Error::NonFiniteRegressor {
                record,
                term,
                sample,
            } => write!(
                f,
                "record `{record}`: the nonlinear term {term} is not finite at sample {sample} \
         (rescale the channels, e.g. to N and m)"
            ),
            Error::TooFewAverages {
                averages,
                inputs,
                required,
            } => write!(
                f,
                "the records give {averages} Welch segments, but the reverse path with {inputs} inputs \
         (displacements and nonlinear terms) needs at least {required}: give more or longer \
         records, or shorter segments"
            ),
            Error::LooksSwapped {
                failure,
                force_crest,
                response_crest,
            } => f.write_str(&looks_swapped(failure, *force_crest, *response_crest)),
            Error::LevelOutOfRange {
                record,
                channel,
                peak,
            } => f.write_str(&level_out_of_range(record, *channel, *peak)),
            Error::ImpedanceScale { magnitude } => f.write_str(&impedance_scale(*magnitude)),
            Error::IterationNonFinite {
                method,
                iteration,
                freq_hz,
            } => f.write_str(&iteration_non_finite(*method, *iteration, *freq_hz)),
            Error::Field(e) => e.fmt(f),
            Error::Plan {
                file,
                line,
                message,
            } => write!(f, "{file}:{line}: {message}"),
            Error::Io { path, message } => write!(f, "{path}: {message}"),
            #[cfg(feature = "csv")]
            Error::Csv {
                path,
                line,
                message,
            } => write!(f, "{path}, line {line}: {message}"),
            #[cfg(feature = "csv")]
            Error::MissingColumn {
                path,
                column,
                header,
            } => write!(
                f,
                "{path}, line 1: no column named `{column}` (header has: {header})"
            ),
            #[cfg(feature = "csv")]
            Error::CsvNonFinite { path, line, column } => write!(
                f,
                "{path}, line {line}, column `{column}`: value is not finite"
            ),
            #[cfg(feature = "csv")]
            Error::NonUniformTime {
                path,
                line,
                expected_s,
                actual_s,
                step_s,
            } => write!(
                f,
                "{path}, line {line}: time {actual_s} s is off the uniform grid (expected {expected_s} s, \
         step {step_s} s)"
            ),
            #[cfg(feature = "csv")]
            Error::CsvLimit {
                path,
                line,
                what,
                limit,
            } => write!(f, "{path}, line {line}: {what} past the limit of {limit}"),
            #[cfg(feature = "uff")]
            Error::Uff {
                path,
                block,
                line,
                message,
            } => write!(f, "{path}, block {block}, line {line}: {message}"),
            #[cfg(feature = "uff")]
            Error::UffRecord {
                path,
                load_case,
                message,
            } => write!(f, "{path}: load case {load_case}: {message}"),
            #[cfg(feature = "tdms")]
            Error::Tdms {
                path,
                offset,
                message,
            } => write!(f, "{path}, byte {offset}: {message}"),
            #[cfg(feature = "mat")]
            Error::Mat {
                path,
                offset,
                message,
            } => write!(f, "{path}, byte {offset}: {message}"),
            #[cfg(feature = "tdms")]
            Error::TdmsChannel {
                path,
                channel,
                message,
                ..
            } => write!(f, "{path}: channel `{channel}`: {message}"),
            #[cfg(feature = "tdms")]
            Error::TdmsRecord { path, message } => write!(f, "{path}: {message}"),
            #[cfg(feature = "mat")]
            Error::MatRecord {
                path,
                variable,
                message,
            } => write!(f, "{path}: `{variable}`: {message}"),
            Error::ExportDofs {
                format,
                dofs,
                expected,
            } => write!(
                f,
                "{format} needs {expected} degrees of freedom; this identification has {dofs}"
            ),
            #[cfg(feature = "plot")]
            Error::Plot { figure, message } => write!(f, "figure `{figure}`: {message}"),
        }
    }
}

#[cfg(test)]
mod tests {
    #[cfg(feature = "csv")]
    use crate::error::CsvLimitKind;
    use crate::error::{Channel, Error};

    #[test]
    fn a_baseline_failure_keeps_its_source_and_a_missing_change_is_said() {
        use std::error::Error as _;
        let inner = Error::NoRecords;
        let e = Error::Baseline {
            path: "dry/".into(),
            source: Box::new(inner.clone()),
        };
        assert_eq!(e.to_string(), "--baseline dry/: no records were given");
        assert_eq!(e.source().map(ToString::to_string), Some(inner.to_string()));
        let e = Error::NotConverged {
            method: crate::Method::Ml,
            iterations: 50,
            change: None,
        };
        assert!(
            e.to_string()
                .ends_with("(last relative change not reported)"),
            "{e}"
        );
        let e = Error::NotConverged {
            method: crate::Method::Ivf,
            iterations: 50,
            change: Some(1.5e-3),
        };
        assert!(
            e.to_string().ends_with("(last relative change 1.500e-3)"),
            "{e}"
        );
    }

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
            figure: "impedance",
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
