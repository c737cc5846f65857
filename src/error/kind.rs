//! [`Error::kind`]: the stable name of each kind of error, for scripts and logs.

use super::Error;

impl Error {
    /// Every name [`Error::kind`] returns, each once (bindings to other languages make an
    /// exception class of each).
    pub const KINDS: &'static [&'static str] = &[
        "malformed_csv",
        "missing_column",
        "non_finite",
        "nonuniform_time",
        "inconsistent_records",
        "bad_band",
        "rank_deficient",
        "not_converged",
        "io_error",
        "record_too_short",
        "invalid_argument",
        "singular",
        "bad_coefficients",
        "baseline_mismatch",
        "ml_needs_repeats",
        "plot_error",
        "dead_channel",
        "too_large",
        "bad_baseline",
        "malformed_uff",
        "invalid_input",
        "missing_response",
        "underdetermined",
        "bad_record",
    ];

    /// A stable snake_case name of the kind of error, for scripts and logs (the CLI prints it as
    /// `{"error": KIND}`): `malformed_csv`, `missing_column`, `non_finite`, `nonuniform_time`,
    /// `inconsistent_records`, `bad_band`, `rank_deficient`, `not_converged`, `io_error`,
    /// `record_too_short`, `invalid_argument`, `singular`, `bad_coefficients`,
    /// `baseline_mismatch`, `ml_needs_repeats`, `plot_error`, `dead_channel`, `too_large`,
    /// `bad_baseline`, `malformed_uff`, and for field identification `invalid_input`,
    /// `missing_response`, `underdetermined`. The README's table lists every one (a unit test checks it).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Error;
    /// assert_eq!(Error::RankDeficient { rank: 1, dofs: 2 }.kind(), "rank_deficient");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            #[cfg(feature = "csv")]
            Error::Csv { .. } => "malformed_csv",
            #[cfg(feature = "csv")]
            Error::MissingColumn { .. } => "missing_column",
            #[cfg(feature = "csv")]
            Error::CsvNonFinite { .. } => "non_finite",
            Error::NonFinite { .. }
            | Error::SpectrumOverflow { .. }
            | Error::NonFiniteResult { .. }
            | Error::NonFiniteRegressor { .. }
            | Error::LevelOutOfRange { .. }
            | Error::ImpedanceScale { .. }
            | Error::IterationNonFinite { .. } => "non_finite",
            Error::DeadChannel { .. } => "dead_channel",
            #[cfg(feature = "csv")]
            Error::NonUniformTime { .. } => "nonuniform_time",
            Error::InvalidSampleRate { .. }
            | Error::ChannelCount { .. }
            | Error::ResponseCount { .. }
            | Error::ChannelLength { .. }
            | Error::NoRecords
            | Error::DofMismatch { .. }
            | Error::SampleRateMismatch { .. }
            | Error::RecordLengthMismatch { .. }
            | Error::InvalidAssignment { .. }
            | Error::AssignmentLength { .. } => "inconsistent_records",
            Error::InvalidBand { .. }
            | Error::BandAboveNyquist { .. }
            | Error::TooFewLines { .. }
            | Error::ResponseAtZeroFrequency { .. } => "bad_band",
            Error::RankDeficient { .. } | Error::IncompleteStep { .. } => "rank_deficient",
            Error::NotConverged { .. } => "not_converged",
            Error::Io { .. } => "io_error",
            Error::RecordTooShort { .. } | Error::TooFewAverages { .. } => "record_too_short",
            Error::Baseline { source, .. } => source.kind(),
            Error::LooksSwapped { failure, .. } => failure.kind(),
            Error::BandText { .. } => "bad_band",
            Error::InvalidParameter { .. }
            | Error::InvalidOption { .. }
            | Error::UnknownName { .. }
            | Error::LengthMismatch { .. } => "invalid_argument",
            Error::SingularFit { .. } | Error::Singular { .. } | Error::Decomposition { .. } => {
                "singular"
            }
            #[cfg(feature = "csv")]
            Error::CsvLimit { .. } => "too_large",
            Error::TooLarge { .. } => "too_large",
            Error::FileLimit { .. } => "too_large",
            Error::BadRecord { .. } => "bad_record",
            Error::BaselineMismatch { .. } => "baseline_mismatch",
            #[cfg(feature = "json")]
            Error::BadBaseline { .. } => "bad_baseline",
            Error::MlNeedsRepeats => "ml_needs_repeats",
            #[cfg(feature = "plot")]
            Error::Plot { .. } => "plot_error",
            Error::CoefficientShape { .. }
            | Error::NonFiniteCoefficient { .. }
            | Error::DofCountMismatch { .. } => "bad_coefficients",
            #[cfg(feature = "uff")]
            Error::Uff { .. } => "malformed_uff",
            #[cfg(feature = "uff")]
            Error::UffRecord { .. } => "inconsistent_records",
            Error::ExportDofs { .. } => "invalid_argument",
            Error::SimulationDiverged { .. } => "non_finite",
            Error::FieldInput { .. } => "invalid_input",
            Error::FieldNonFinite { .. } => "non_finite",
            Error::MissingResponse { .. } => "missing_response",
            Error::Underdetermined { .. } => "underdetermined",
            Error::FieldRankDeficient { .. } => "rank_deficient",
        }
    }
}

#[cfg(test)]
mod tests {
    /// The quoted strings of `text` that follow `marker` (which ends in a quote).
    fn quoted_after<'a>(text: &'a str, marker: &str) -> Vec<&'a str> {
        text.match_indices(marker)
            .map(|(at, _)| {
                let rest = &text[at + marker.len()..];
                &rest[..rest.find('"').expect("closing quote")]
            })
            .collect()
    }

    #[test]
    fn readme_lists_every_error_kind() {
        let source = include_str!("kind.rs");
        // Every string literal of `Error::kind`'s body is a kind.
        let start = source.find("impl Error {").expect("impl Error");
        let body = &source[start..];
        let body = &body[body.find("pub fn kind(&self)").expect("kind")..];
        let body = &body[..body.find("\n}\n").expect("end of impl")];
        let mut kinds: Vec<&str> = body.split('"').skip(1).step_by(2).collect();
        assert!(kinds.len() >= 17, "found only {kinds:?}");
        // `KINDS` lists each of them once, and nothing else (the names of cargo features in
        // the body's `cfg` attributes are not kinds).
        let mut listed: Vec<&str> = super::Error::KINDS.to_vec();
        let mut found: Vec<&str> = body
            .split('"')
            .collect::<Vec<_>>()
            .windows(2)
            .step_by(2)
            .filter(|w| !w[0].ends_with("feature = "))
            .map(|w| w[1])
            .collect();
        listed.sort_unstable();
        found.sort_unstable();
        found.dedup();
        assert_eq!(
            listed, found,
            "Error::KINDS and the arms of Error::kind differ"
        );
        // The CLI's own kinds for failures outside the library.
        kinds.extend(quoted_after(
            include_str!("../bin/bearing-ident/main.rs"),
            "kind: \"",
        ));
        let readme = include_str!("../../README.md");
        for kind in kinds {
            assert!(
                readme.contains(&format!("| `{kind}` |")),
                "README's error table lacks `{kind}`"
            );
        }
    }
}
