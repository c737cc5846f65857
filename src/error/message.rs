//! The parts of [`Error`](super::Error)'s messages that need code: the line spacing of a band, a
//! size past a limit, an iterative fit's last change, the advice for a field test's dependent
//! responses.

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
pub(super) fn spacing(resolution_hz: Option<f64>) -> String {
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
