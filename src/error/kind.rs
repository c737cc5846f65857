//! [`ErrorKind`] and [`Error::kind`]: the stable name of each kind of error, for scripts and logs.

use super::Error;
use super::table::named_table;

named_table! {
    /// The kind of an [`Error`]: what a script or another language's binding tells apart.
    ///
    /// Several variants of [`Error`] share a kind (a NaN sample and an overflowing spectrum are
    /// both [`ErrorKind::NonFinite`]); [`ErrorKind::as_str`] is the stable snake_case name
    /// printed in JSON. [`ErrorKind::ALL`] lists every kind whatever the cargo features
    /// (bindings to other languages make an exception class of each).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::ErrorKind;
    /// assert_eq!(ErrorKind::BadBand.as_str(), "bad_band");
    /// assert_eq!(ErrorKind::BadBand, "bad_band");
    /// assert!(ErrorKind::ALL.contains(&ErrorKind::TooLarge));
    /// ```
    pub enum ErrorKind {
        /// A ragged CSV line, or text that is not a number.
        MalformedCsv => "malformed_csv",
        /// A named column is not in a CSV header.
        MissingColumn => "missing_column",
        /// A NaN or infinite sample, or a spectrum, impedance or result that overflows `f64`.
        NonFinite => "non_finite",
        /// A CSV time column off its uniform grid.
        NonuniformTime => "nonuniform_time",
        /// Records of different shapes or sampling rates, or an assignment that does not fit them.
        InconsistentRecords => "inconsistent_records",
        /// A band that is empty, inverted, above Nyquist, or holds too few lines.
        BadBand => "bad_band",
        /// The excitations do not span every direction.
        RankDeficient => "rank_deficient",
        /// An iterative fit did not converge (and was asked to fail).
        NotConverged => "not_converged",
        /// A file that cannot be opened, read or written.
        IoError => "io_error",
        /// A record too short for its segments or averages.
        RecordTooShort => "record_too_short",
        /// An option or setting out of its range, or a name that is not one of a choice's.
        InvalidArgument => "invalid_argument",
        /// A fit or a decomposition is singular.
        Singular => "singular",
        /// `M`, `C`, `K` of mismatched shapes or holding NaN.
        BadCoefficients => "bad_coefficients",
        /// A baseline identified with another band, lines, estimator or window.
        BaselineMismatch => "baseline_mismatch",
        /// Maximum likelihood without records for its noise model, or too few periods.
        MlNeedsRepeats => "ml_needs_repeats",
        /// A figure could not be drawn.
        PlotError => "plot_error",
        /// Every force (or displacement) channel of a record is flat.
        DeadChannel => "dead_channel",
        /// An input or a requested size past a documented limit.
        TooLarge => "too_large",
        /// A baseline file that is not a result this crate wrote.
        BadBaseline => "bad_baseline",
        /// A Universal File that cannot be read.
        MalformedUff => "malformed_uff",
        /// A TDMS file that cannot be read.
        MalformedTdms => "malformed_tdms",
        /// Data of a kind the reader does not read (a TDMS channel of strings, or with a
        /// scaling other than linear or polynomial).
        Unsupported => "unsupported",
        /// A MATLAB MAT-file that cannot be read.
        MalformedMat => "malformed_mat",
        /// Field identification: a rotor model or test set that is not well formed.
        InvalidInput => "invalid_input",
        /// Field identification: a probe without its response at some speed and test.
        MissingResponse => "missing_response",
        /// Field identification: too few measured DOFs, or probes that cannot determine the bearing forces.
        Underdetermined => "underdetermined",
        /// The fit failed and the screening had found one record far out of scale with its siblings.
        BadRecord => "bad_record",
        /// The force reads as more than one kind of test: the excitation must be given.
        UnclearExcitation => "unclear_excitation",
    }
}

/// A kind equals its name: `e.kind() == "bad_band"` reads as the JSON does.
impl PartialEq<&str> for ErrorKind {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

/// A kind equals its name, from the name's side.
impl PartialEq<ErrorKind> for &str {
    fn eq(&self, other: &ErrorKind) -> bool {
        *self == other.as_str()
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for ErrorKind {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

impl Error {
    /// The kind of error, for scripts and logs: [`ErrorKind::as_str`] is its stable
    /// snake_case name (the CLI prints it as `{"error": KIND}`). The guide's output reference
    /// (`docs/guide/reference-output.md`) lists every one (a unit test checks it).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::{Error, ErrorKind};
    /// let e = Error::RankDeficient { rank: 1, dofs: 2 };
    /// assert_eq!(e.kind(), ErrorKind::RankDeficient);
    /// assert_eq!(e.kind().as_str(), "rank_deficient");
    /// ```
    pub fn kind(&self) -> ErrorKind {
        match self {
            #[cfg(feature = "csv")]
            Error::Csv { .. } => ErrorKind::MalformedCsv,
            #[cfg(feature = "csv")]
            Error::MissingColumn { .. } => ErrorKind::MissingColumn,
            #[cfg(feature = "csv")]
            Error::CsvNonFinite { .. } => ErrorKind::NonFinite,
            Error::NonFinite { .. }
            | Error::SpectrumOverflow { .. }
            | Error::NonFiniteResult { .. }
            | Error::NonFiniteRegressor { .. }
            | Error::LevelOutOfRange { .. }
            | Error::ImpedanceScale { .. }
            | Error::IterationNonFinite { .. } => ErrorKind::NonFinite,
            Error::DeadChannel { .. } => ErrorKind::DeadChannel,
            #[cfg(feature = "csv")]
            Error::NonUniformTime { .. } => ErrorKind::NonuniformTime,
            Error::InvalidSampleRate { .. }
            | Error::ChannelCount { .. }
            | Error::ResponseCount { .. }
            | Error::ChannelLength { .. }
            | Error::NoRecords
            | Error::DofMismatch { .. }
            | Error::SampleRateMismatch { .. }
            | Error::RecordLengthMismatch { .. }
            | Error::InvalidAssignment { .. }
            | Error::AssignmentLength { .. } => ErrorKind::InconsistentRecords,
            Error::InvalidBand { .. }
            | Error::BandAboveNyquist { .. }
            | Error::TooFewLines { .. }
            | Error::ResponseAtZeroFrequency { .. } => ErrorKind::BadBand,
            Error::RankDeficient { .. } | Error::IncompleteStep { .. } => ErrorKind::RankDeficient,
            Error::NotConverged { .. } => ErrorKind::NotConverged,
            Error::Io { .. } => ErrorKind::IoError,
            Error::RecordTooShort { .. } | Error::TooFewAverages { .. } => {
                ErrorKind::RecordTooShort
            }
            Error::Baseline { source, .. } => source.kind(),
            Error::LooksSwapped { failure, .. } => failure.kind(),
            Error::BandText { .. } => ErrorKind::BadBand,
            Error::InvalidParameter { .. }
            | Error::InvalidSetting { .. }
            | Error::InvalidOption { .. }
            | Error::UnknownName { .. }
            | Error::LengthMismatch { .. } => ErrorKind::InvalidArgument,
            Error::SingularFit { .. } | Error::Singular { .. } | Error::Decomposition { .. } => {
                ErrorKind::Singular
            }
            #[cfg(feature = "csv")]
            Error::CsvLimit { .. } => ErrorKind::TooLarge,
            Error::TooLarge { .. } => ErrorKind::TooLarge,
            Error::FileLimit { .. } => ErrorKind::TooLarge,
            Error::BadRecord { .. } => ErrorKind::BadRecord,
            Error::UnclearExcitation { .. } => ErrorKind::UnclearExcitation,
            Error::BaselineMismatch { .. } => ErrorKind::BaselineMismatch,
            #[cfg(feature = "json")]
            Error::BadBaseline { .. } => ErrorKind::BadBaseline,
            Error::MlNeedsRepeats => ErrorKind::MlNeedsRepeats,
            #[cfg(feature = "plot")]
            Error::Plot { .. } => ErrorKind::PlotError,
            Error::CoefficientShape { .. }
            | Error::NonFiniteCoefficient { .. }
            | Error::DofCountMismatch { .. } => ErrorKind::BadCoefficients,
            #[cfg(feature = "uff")]
            Error::Uff { .. } => ErrorKind::MalformedUff,
            #[cfg(feature = "uff")]
            Error::UffRecord { .. } => ErrorKind::InconsistentRecords,
            #[cfg(feature = "tdms")]
            Error::Tdms { .. } => ErrorKind::MalformedTdms,
            #[cfg(feature = "tdms")]
            Error::TdmsChannel { unsupported, .. } => {
                if *unsupported {
                    ErrorKind::Unsupported
                } else {
                    ErrorKind::MissingColumn
                }
            }
            #[cfg(feature = "tdms")]
            Error::TdmsRecord { .. } => ErrorKind::InconsistentRecords,
            #[cfg(feature = "mat")]
            Error::Mat { .. } => ErrorKind::MalformedMat,
            #[cfg(feature = "mat")]
            Error::MatRecord { .. } => ErrorKind::InconsistentRecords,
            Error::ExportDofs { .. } => ErrorKind::InvalidArgument,
            Error::SimulationDiverged { .. } => ErrorKind::NonFinite,
            Error::Plan { .. } => ErrorKind::InvalidInput,
            Error::Field(e) => e.kind(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ErrorKind;

    /// The quoted strings of `text` that follow `marker` (which ends in a quote).
    fn quoted_after(text: &str, marker: &str) -> Vec<String> {
        text.match_indices(marker)
            .map(|(at, _)| {
                let rest = &text[at + marker.len()..];
                rest[..rest.find('"').expect("closing quote")].to_owned()
            })
            .collect()
    }

    /// The kinds the command-line tool gives its own failures (`kind: "…"` in any file of
    /// `src/bin/`).
    fn cli_kinds(dir: &std::path::Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).expect("src/bin is readable") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                cli_kinds(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).expect("a source file");
                out.extend(quoted_after(&text, "kind: \""));
            }
        }
    }

    /// The output reference's error table and the kinds agree both ways: every kind of the library and of
    /// the command-line tool has a row, and every row is such a kind.
    #[test]
    fn the_output_reference_lists_every_error_kind() {
        let mut kinds: Vec<String> = ErrorKind::ALL.iter().map(|k| k.as_str().into()).collect();
        assert!(kinds.len() >= 17, "found only {kinds:?}");
        for k in ErrorKind::ALL {
            assert_eq!(*k, k.as_str());
        }
        let bin = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/bin");
        let mut cli = Vec::new();
        cli_kinds(&bin, &mut cli);
        assert!(
            cli.iter().any(|k| k == "io_error"),
            "no CLI kinds found: {cli:?}"
        );
        kinds.extend(cli);
        kinds.sort_unstable();
        kinds.dedup();
        let reference = include_str!("../../docs/guide/reference-output.md");
        let table = &reference[reference
            .find("| KIND | cause |")
            .expect("the output reference's error table")..];
        let table = &table[..table.find("\n\n").expect("the table's end")];
        let mut rows: Vec<String> = table
            .lines()
            .filter_map(|line| line.strip_prefix("| `")?.split('`').next())
            .map(str::to_owned)
            .collect();
        rows.sort_unstable();
        assert_eq!(
            rows, kinds,
            "the output reference's error table and the kinds differ"
        );
    }
}
