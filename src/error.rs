//! The one error type of the crate and its [`Result`] alias.
//!
//! Every failure that a user's data can cause is a variant here, with named fields that carry the
//! numbers needed to find the problem: the record's label, the channel, the sample index, the
//! frequency line. Panics are reserved for broken API contracts and are documented under
//! `# Panics` where they can happen.

use std::fmt;

/// A measured channel of a [`Record`](crate::records::Record).
///
/// Force channels and displacement channels are numbered from zero, in the order of the
/// degrees of freedom.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Force channel `i` (N).
    Force(usize),
    /// Displacement channel `i` (m).
    Displacement(usize),
}

impl fmt::Display for Channel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Channel::Force(i) => write!(f, "force channel {i}"),
            Channel::Displacement(i) => write!(f, "displacement channel {i}"),
        }
    }
}

/// Everything that can go wrong in `bearing-ident`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A record's sampling rate is not a finite positive number.
    #[error("record `{record}`: sampling rate {sample_rate} Hz is not a finite positive number")]
    InvalidSampleRate {
        /// Label of the record.
        record: String,
        /// The rejected sampling rate in Hz.
        sample_rate: f64,
    },
    /// A record has no force channels or no displacement channels, or a different number of each.
    #[error(
        "record `{record}`: {forces} force and {displacements} displacement channels; \
         a record needs n ≥ 1 of each, one per degree of freedom"
    )]
    ChannelCount {
        /// Label of the record.
        record: String,
        /// Number of force channels given.
        forces: usize,
        /// Number of displacement channels given.
        displacements: usize,
    },
    /// A channel of a record is longer or shorter than the record's first force channel.
    #[error("record `{record}`: {channel} has {actual} samples, expected {expected}")]
    ChannelLength {
        /// Label of the record.
        record: String,
        /// The channel whose length differs.
        channel: Channel,
        /// Length of the record's first force channel.
        expected: usize,
        /// Length of this channel.
        actual: usize,
    },
    /// A record is too short to carry a spectrum.
    #[error("record `{record}`: {samples} samples, at least {minimum} are needed")]
    RecordTooShort {
        /// Label of the record.
        record: String,
        /// Number of samples in the record.
        samples: usize,
        /// Smallest accepted number of samples.
        minimum: usize,
    },
    /// A sample is NaN or infinite.
    #[error("record `{record}`: {channel}, sample {sample}: value {value} is not finite")]
    NonFinite {
        /// Label of the record.
        record: String,
        /// The channel holding the value.
        channel: Channel,
        /// Zero-based sample index.
        sample: usize,
        /// The offending value.
        value: f64,
    },
    /// No records were given.
    #[error("no records were given")]
    NoRecords,
    /// A record has a different number of degrees of freedom than asked for or than the others.
    #[error("record `{record}`: {actual} degrees of freedom, expected {expected}")]
    DofMismatch {
        /// Label of the record.
        record: String,
        /// Expected number of degrees of freedom.
        expected: usize,
        /// The record's number of degrees of freedom.
        actual: usize,
    },
    /// Records in one identification have different sampling rates.
    #[error(
        "record `{record}`: sampling rate {actual} Hz differs from {expected} Hz of the first record"
    )]
    SampleRateMismatch {
        /// Label of the record.
        record: String,
        /// Sampling rate of the first record (Hz).
        expected: f64,
        /// Sampling rate of this record (Hz).
        actual: f64,
    },
    /// Records in one identification have different lengths.
    #[error("record `{record}`: {actual} samples, but the first record has {expected}")]
    RecordLengthMismatch {
        /// Label of the record.
        record: String,
        /// Length of the first record.
        expected: usize,
        /// Length of this record.
        actual: usize,
    },
    /// The frequency band is empty, inverted, negative or not finite.
    #[error("band {low_hz}–{high_hz} Hz is not a valid band (need finite 0 ≤ low < high)")]
    InvalidBand {
        /// Lower edge (Hz).
        low_hz: f64,
        /// Upper edge (Hz).
        high_hz: f64,
    },
    /// The band reaches above the Nyquist frequency of the records.
    #[error("band upper edge {high_hz} Hz is above the Nyquist frequency {nyquist_hz} Hz")]
    BandAboveNyquist {
        /// Upper edge of the band (Hz).
        high_hz: f64,
        /// Half the sampling rate (Hz).
        nyquist_hz: f64,
    },
    /// The band holds too few frequency lines for the number of unknowns.
    #[error(
        "the band holds {lines} usable frequency lines, at least {required} are needed \
         (line spacing {resolution_hz} Hz)"
    )]
    TooFewLines {
        /// Usable lines in the band.
        lines: usize,
        /// Lines needed.
        required: usize,
        /// Spacing of the lines (Hz).
        resolution_hz: f64,
    },
    /// An explicit excitation assignment does not fit the records.
    #[error(
        "record `{record}`: assigned to excitation {excitation}, but there are only {dofs} degrees of freedom"
    )]
    InvalidAssignment {
        /// Label of the record.
        record: String,
        /// The excitation index given.
        excitation: usize,
        /// Number of degrees of freedom.
        dofs: usize,
    },
    /// An explicit excitation assignment has a different length than the record list.
    #[error("the excitation assignment names {actual} records, but {expected} were given")]
    AssignmentLength {
        /// Number of records.
        expected: usize,
        /// Length of the assignment.
        actual: usize,
    },
    /// The excitations do not span all degrees of freedom.
    #[error(
        "the excitations are rank-deficient: they span {rank} of {dofs} directions over the band; \
         {dofs} linearly independent excitations are needed (for example impacts in x and in y)"
    )]
    RankDeficient {
        /// Estimated rank of the excitation.
        rank: usize,
        /// Number of degrees of freedom.
        dofs: usize,
    },
    /// The stacked least-squares or instrumental-variable system is singular.
    #[error(
        "the {method} fit is singular: the band does not determine M, C and K (try a wider band)"
    )]
    SingularFit {
        /// The method that failed.
        method: &'static str,
    },
    /// A matrix that must be inverted is singular.
    #[error("{what} is singular")]
    Singular {
        /// What was being inverted.
        what: &'static str,
    },
    /// An iterative fit did not converge and the caller asked for convergence.
    #[error(
        "{method} did not converge in {iterations} iterations (last relative change {change:.3e})"
    )]
    NotConverged {
        /// The method.
        method: &'static str,
        /// Iterations run.
        iterations: usize,
        /// Block-wise relative change at the last iteration.
        change: f64,
    },
    /// Mass, damping and stiffness matrices do not have one common square shape.
    #[error(
        "coefficient matrices must be square and of one size: M is {mass:?}, C is {damping:?}, K is {stiffness:?}"
    )]
    CoefficientShape {
        /// Shape of M.
        mass: (usize, usize),
        /// Shape of C.
        damping: (usize, usize),
        /// Shape of K.
        stiffness: (usize, usize),
    },
    /// A coefficient matrix holds NaN or infinity.
    #[error("coefficient {matrix}[{row}][{col}] is not finite")]
    NonFiniteCoefficient {
        /// "M", "C" or "K".
        matrix: &'static str,
        /// Row index.
        row: usize,
        /// Column index.
        col: usize,
    },
    /// Two sets of coefficients that must be combined have different sizes.
    #[error("cannot combine coefficients of {left} and {right} degrees of freedom")]
    DofCountMismatch {
        /// Degrees of freedom of the left operand.
        left: usize,
        /// Degrees of freedom of the right operand.
        right: usize,
    },
    /// A dry-structure baseline was identified differently from the system it is subtracted
    /// from.
    #[error(
        "the baseline differs from the system in its {what}: identify both with the same band, lines, estimator, window and degrees of freedom"
    )]
    BaselineMismatch {
        /// What differs.
        what: &'static str,
    },
    /// A saved baseline (the JSON of an earlier identification) cannot be read (feature
    /// `json`, [`Baseline::from_json`](crate::Baseline::from_json)).
    #[error("{message}")]
    BadBaseline {
        /// What is wrong, naming the key; at most about 80 characters of the input are quoted.
        message: String,
    },
    /// Maximum likelihood needs the noise covariances of the spectra, which only repeated
    /// periods give here.
    #[error(
        "method ml needs the noise covariances that repeated periods give: periodic records with `Segmentation::Periods` (CLI `--excitation periodic --period S`), at least 3 periods per record"
    )]
    MlNeedsRepeats,
    /// A numeric parameter is outside its valid range.
    #[error("parameter `{name}` = {value} is invalid: expected {expected}")]
    InvalidParameter {
        /// Name of the parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// A file could not be opened, read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What the operating system said.
        message: String,
    },
    /// A CSV line is ragged or holds text that is not a number.
    #[error("{path}, line {line}: {message}")]
    Csv {
        /// The file.
        path: String,
        /// One-based line number.
        line: u64,
        /// What is wrong with the line.
        message: String,
    },
    /// A named column is not in a CSV file's header.
    #[error("{path}, line 1: no column named `{column}` (header has: {header})")]
    MissingColumn {
        /// The file.
        path: String,
        /// The column asked for.
        column: String,
        /// The header's column names, comma-separated (at most 80 characters, then `…`).
        header: String,
    },
    /// A CSV value is NaN or infinite.
    #[error("{path}, line {line}, column `{column}`: value is not finite")]
    CsvNonFinite {
        /// The file.
        path: String,
        /// One-based line number.
        line: u64,
        /// The column.
        column: String,
    },
    /// The time column of a CSV file is not uniformly sampled.
    #[error(
        "{path}, line {line}: time {actual_s} s is off the uniform grid (expected {expected_s} s, \
         step {step_s} s)"
    )]
    NonUniformTime {
        /// The file.
        path: String,
        /// One-based line number.
        line: u64,
        /// Time on the uniform grid (s).
        expected_s: f64,
        /// Time in the file (s).
        actual_s: f64,
        /// Grid step (s).
        step_s: f64,
    },
    /// A figure could not be drawn (feature `plot`).
    #[error("figure `{figure}`: {message}")]
    Plot {
        /// The figure: `"flexibility"`, `"impedance"`, `"coherence"`, `"per_frequency"`,
        /// `"records"` or `"convergence"`.
        figure: &'static str,
        /// What the drawing library said.
        message: String,
    },
    /// A matrix decomposition from faer did not converge.
    #[error("the {what} decomposition did not converge")]
    Decomposition {
        /// Which decomposition.
        what: &'static str,
    },
    /// A step of a stepped-sine test has no record driving one of the directions.
    #[error(
        "stepped sine at {freq_hz} Hz: no record drives direction {direction} of {dofs}; \
         every frequency step needs one record per direction"
    )]
    IncompleteStep {
        /// Drive frequency of the step (Hz).
        freq_hz: f64,
        /// The first direction without a record.
        direction: usize,
        /// Number of degrees of freedom.
        dofs: usize,
    },
}

/// Something a user should know about an identification that did not stop it.
///
/// Warnings travel with the result (see
/// [`Identification::warnings`](crate::identify::Identification::warnings)); each says what was
/// seen, with the numbers.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// Some lines have a condition number above the warning threshold.
    IllConditioned {
        /// Lines above the threshold.
        lines: usize,
        /// Lines in the band.
        of: usize,
        /// Frequency of the worst line (Hz).
        worst_hz: f64,
        /// Condition number of the worst line.
        worst: f64,
        /// The warning threshold.
        threshold: f64,
    },
    /// Lines were dropped because the multiple coherence of some output was below the
    /// threshold.
    LowCoherence {
        /// Lines dropped.
        lines: usize,
        /// The threshold.
        threshold: f64,
    },
    /// The jackknife had fewer than 3 replicates; the sandwich standard deviations are
    /// reported instead.
    FewReplicates {
        /// Replicates available (paired sets or records).
        replicates: usize,
    },
    /// Lines of the band were dropped because a matrix could not be inverted.
    DroppedLines {
        /// Frequencies of the dropped lines (Hz).
        freqs_hz: Vec<f64>,
    },
    /// Records left out of the paired sets (unequal counts per direction).
    UnpairedRecords {
        /// Labels of the records left out.
        records: Vec<String>,
    },
    /// An iterative fit stopped at its iteration limit before meeting its tolerance.
    NotConverged {
        /// Iterations run.
        iterations: usize,
        /// Block-wise relative change at the last iteration.
        change: f64,
    },
    /// An iterative fit diverged; the result is its best iterate.
    Diverged {
        /// Iterations run before divergence was detected.
        iterations: usize,
        /// The iterate returned (0 = the least-squares start).
        fallback_iteration: usize,
    },
    /// An impact record holds a second hammer pulse (see
    /// [`quality::check_record`](crate::quality::check_record)).
    DoubleHit {
        /// Label of the record.
        record: String,
        /// Time of the second pulse's peak (s from the record's first sample).
        second_s: f64,
        /// Its peak over the main peak.
        ratio: f64,
    },
    /// A channel of a record sits at its extreme value for several samples: the ADC or
    /// amplifier was overloaded (see [`quality::check_record`](crate::quality::check_record)).
    Clipped {
        /// Label of the record.
        record: String,
        /// The clipped channel.
        channel: Channel,
        /// The clipping level (N or m).
        value: f64,
    },
    /// A record was left out of the identification because it failed a quality check.
    Rejected {
        /// Label of the record.
        record: String,
        /// Why, in words (for example the issues found).
        reason: String,
    },
    /// Maximum likelihood kept its IVF start.
    MlFellBack {
        /// Why.
        reason: String,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::IllConditioned {
                lines,
                of,
                worst_hz,
                worst,
                threshold,
            } => write!(
                f,
                "{lines} of {of} lines have a condition number above {threshold:.3e} \
                 (worst {worst:.3e} at {worst_hz:.3} Hz): excitations close to dependent"
            ),
            Warning::LowCoherence { lines, threshold } => write!(
                f,
                "{lines} lines dropped with a multiple coherence below {threshold}"
            ),
            Warning::FewReplicates { replicates } => write!(
                f,
                "only {replicates} replicates for the jackknife (3 needed): sandwich standard deviations reported"
            ),
            Warning::DroppedLines { freqs_hz } => write!(
                f,
                "{} lines dropped (singular matrices) at {:?} Hz",
                freqs_hz.len(),
                freqs_hz
            ),
            Warning::UnpairedRecords { records } => write!(
                f,
                "{} records left out of the paired sets: {}",
                records.len(),
                records.join(", ")
            ),
            Warning::NotConverged { iterations, change } => write!(
                f,
                "not converged after {iterations} iterations (relative change {change:.3e})"
            ),
            Warning::Diverged {
                iterations,
                fallback_iteration,
            } => write!(
                f,
                "diverged after {iterations} iterations; returning iterate {fallback_iteration}"
            ),
            Warning::DoubleHit {
                record,
                second_s,
                ratio,
            } => write!(
                f,
                "record `{record}`: double hit, a second pulse at {second_s:.4} s of {ratio:.2} × the main peak"
            ),
            Warning::Clipped {
                record,
                channel,
                value,
            } => write!(f, "record `{record}`: {channel} clipped at {value:.4e}"),
            Warning::Rejected { record, reason } => {
                write!(f, "record `{record}` rejected: {reason}")
            }
            Warning::MlFellBack { reason } => {
                write!(f, "maximum likelihood kept the IVF result: {reason}")
            }
        }
    }
}

impl Warning {
    /// A stable snake_case name of the kind of warning, for scripts and logs (the CLI's JSON
    /// lists them as `warning_kinds`, in the order of `warnings`).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Warning;
    /// assert_eq!(Warning::FewReplicates { replicates: 2 }.kind(), "few_replicates");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            Warning::IllConditioned { .. } => "ill_conditioned",
            Warning::LowCoherence { .. } => "low_coherence",
            Warning::FewReplicates { .. } => "few_replicates",
            Warning::DroppedLines { .. } => "dropped_lines",
            Warning::UnpairedRecords { .. } => "unpaired_records",
            Warning::NotConverged { .. } => "not_converged",
            Warning::Diverged { .. } => "diverged",
            Warning::DoubleHit { .. } => "double_hit",
            Warning::Clipped { .. } => "clipped",
            Warning::Rejected { .. } => "rejected",
            Warning::MlFellBack { .. } => "ml_fell_back",
        }
    }
}

impl Error {
    /// A stable snake_case name of the kind of error, for scripts and logs (the CLI prints it as
    /// `{"error": KIND}`): `malformed_csv`, `missing_column`, `non_finite`, `nonuniform_time`,
    /// `inconsistent_records`, `bad_band`, `rank_deficient`, `not_converged`, `io_error`,
    /// `record_too_short`, `invalid_argument`, `singular`, `bad_coefficients`,
    /// `baseline_mismatch`, `bad_baseline`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Error;
    /// assert_eq!(Error::RankDeficient { rank: 1, dofs: 2 }.kind(), "rank_deficient");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            Error::Csv { .. } => "malformed_csv",
            Error::MissingColumn { .. } => "missing_column",
            Error::NonFinite { .. } | Error::CsvNonFinite { .. } => "non_finite",
            Error::NonUniformTime { .. } => "nonuniform_time",
            Error::InvalidSampleRate { .. }
            | Error::ChannelCount { .. }
            | Error::ChannelLength { .. }
            | Error::NoRecords
            | Error::DofMismatch { .. }
            | Error::SampleRateMismatch { .. }
            | Error::RecordLengthMismatch { .. }
            | Error::InvalidAssignment { .. }
            | Error::AssignmentLength { .. } => "inconsistent_records",
            Error::InvalidBand { .. }
            | Error::BandAboveNyquist { .. }
            | Error::TooFewLines { .. } => "bad_band",
            Error::RankDeficient { .. } | Error::IncompleteStep { .. } => "rank_deficient",
            Error::NotConverged { .. } => "not_converged",
            Error::Io { .. } => "io_error",
            Error::RecordTooShort { .. } => "record_too_short",
            Error::InvalidParameter { .. } => "invalid_argument",
            Error::SingularFit { .. } | Error::Singular { .. } | Error::Decomposition { .. } => {
                "singular"
            }
            Error::BaselineMismatch { .. } => "baseline_mismatch",
            Error::BadBaseline { .. } => "bad_baseline",
            Error::MlNeedsRepeats => "ml_needs_repeats",
            Error::Plot { .. } => "plot_error",
            Error::CoefficientShape { .. }
            | Error::NonFiniteCoefficient { .. }
            | Error::DofCountMismatch { .. } => "bad_coefficients",
        }
    }
}

/// `Result` with the crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

// faer 0.24's decomposition errors do not implement `std::error::Error`, so they are mapped here
// by hand.
impl From<faer::linalg::solvers::SvdError> for Error {
    fn from(_: faer::linalg::solvers::SvdError) -> Self {
        Error::Decomposition {
            what: "singular value",
        }
    }
}

impl From<faer::linalg::solvers::EvdError> for Error {
    fn from(_: faer::linalg::solvers::EvdError) -> Self {
        Error::Decomposition { what: "eigenvalue" }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_display_names_kind_and_index() {
        assert_eq!(Channel::Force(1).to_string(), "force channel 1");
        assert_eq!(
            Channel::Displacement(0).to_string(),
            "displacement channel 0"
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

    #[test]
    fn quality_warnings_name_the_record_and_numbers() {
        let w = Warning::DoubleHit {
            record: "hit-x-1".into(),
            second_s: 0.0512,
            ratio: 0.31,
        };
        assert_eq!(
            w.to_string(),
            "record `hit-x-1`: double hit, a second pulse at 0.0512 s of 0.31 × the main peak"
        );
        let w = Warning::Clipped {
            record: "hit-y-2".into(),
            channel: Channel::Displacement(1),
            value: -2.5e-4,
        };
        assert_eq!(
            w.to_string(),
            "record `hit-y-2`: displacement channel 1 clipped at -2.5000e-4"
        );
        let w = Warning::Rejected {
            record: "hit-y-3".into(),
            reason: "force channel 1 clipped".into(),
        };
        assert_eq!(
            w.to_string(),
            "record `hit-y-3` rejected: force channel 1 clipped"
        );
    }

    #[test]
    fn plot_errors_name_the_figure() {
        let e = Error::Plot {
            figure: "impedance",
            message: "disk full".into(),
        };
        assert_eq!(e.kind(), "plot_error");
        assert_eq!(e.to_string(), "figure `impedance`: disk full");
    }

    #[test]
    fn faer_errors_convert() {
        let e: Error = faer::linalg::solvers::SvdError::NoConvergence.into();
        assert!(matches!(e, Error::Decomposition { .. }));
        let e: Error = faer::linalg::solvers::EvdError::NoConvergence.into();
        assert!(matches!(e, Error::Decomposition { .. }));
    }
}
