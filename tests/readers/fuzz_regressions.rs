//! Inputs found by fuzzing (`fuzz/`, `cargo +nightly fuzz`) or by reviewing what the fuzz
//! targets check, kept as ordinary tests. Each failed (panicked or broke an invariant) before
//! its fix.

use bearing_ident::io::{CsvLayout, read_record_from};
use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{Baseline, Coefficients, Error, Identifier};
use faer::Mat;

/// Longest error message accepted from a reader (as in `tests/readers/fuzz.rs`).
const MAX_MESSAGE: usize = 300;

fn small_identification() -> bearing_ident::Identification {
    let test = ImpactTest {
        per_direction: 1,
        ..ImpactTest::seed_rig()
    };
    Identifier::new(8.0, 49.0)
        .identify(&test.run(&seed_rig()).unwrap())
        .unwrap()
}

/// A baseline whose standard deviations are of another size than its coefficients made
/// `subtract_baseline` index out of bounds (a panic); it is now a `baseline_mismatch`.
#[test]
fn baseline_with_standard_deviations_of_another_size_is_refused() {
    let id = small_identification();
    let one = || Mat::from_fn(1, 1, |_, _| 1.0);
    let std = Coefficients::new(one(), one(), one()).unwrap();
    let dry = Baseline::new(
        id.coefficients().clone(),
        Some(std),
        id.band(),
        id.freqs_hz().to_vec(),
        id.estimator(),
        id.window(),
    );
    let e = id.subtract_baseline(dry).unwrap_err();
    assert_eq!(e.kind(), "baseline_mismatch", "{e}");
}

/// Coefficients subtracted from ±1e308 overflowed to infinity and were returned as a result.
#[test]
fn coefficient_subtraction_that_overflows_is_an_error() {
    let big = |v: f64| Mat::from_fn(1, 1, |_, _| v);
    let a = Coefficients::new(big(1.0), big(1.0), big(1e308)).unwrap();
    let b = Coefficients::new(big(1.0), big(1.0), big(-1e308)).unwrap();
    let e = a.subtract(&b).unwrap_err();
    assert!(
        matches!(
            e,
            Error::NonFiniteCoefficient {
                matrix: bearing_ident::Block::Stiffness,
                ..
            }
        ),
        "{e:?}"
    );
}

/// The CSV reader quoted a whole unparsable field and the whole header in its messages: a file
/// of one long line came back whole in the error.
#[test]
fn csv_errors_quote_little_of_the_input() {
    let layout = CsvLayout::for_dofs(1);
    let long = "9".repeat(5000) + "x";
    let field = format!("t,fx,x\n0,{long},0\n");
    let header = format!("t,{},x\n0,0,0\n", "h".repeat(5000));
    for text in [field, header] {
        let e = read_record_from(text.as_bytes(), "f.csv", &layout).unwrap_err();
        let message = e.to_string();
        assert!(message.chars().count() <= MAX_MESSAGE, "{e:?}");
    }
}

/// `Baseline::from_json` quoted whole strings (serde_json's "invalid type: string …").
#[cfg(feature = "json")]
#[test]
fn baseline_json_errors_quote_little_of_the_input() {
    let long = "q".repeat(5000);
    for text in [
        format!(r#"{{"M": [["{long}"]]}}"#),
        format!(
            r#"{{"M": [[1]], "C": [[1]], "K": [[1]], "band_hz": [1, 2], "freqs_hz": [1], "estimator": "{long}"}}"#
        ),
        format!("\"{long}"),
    ] {
        let e = Baseline::from_json(&text).unwrap_err();
        assert_eq!(e.kind(), "bad_baseline");
        assert!(e.to_string().chars().count() <= MAX_MESSAGE, "{e:?}");
    }
}

/// A force gate longer than any record (`open_s = 1e300`): the index of its first closed
/// sample overflowed `usize` (a panic with overflow checks); the gate is now simply open over
/// the whole record.
#[test]
fn force_gate_longer_than_the_record_is_open_throughout() {
    use bearing_ident::spectra::ForceGate;
    let test = ImpactTest {
        per_direction: 1,
        ..ImpactTest::seed_rig()
    };
    let records = test.run(&seed_rig()).unwrap();
    let plain = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    for open in [1e300, f64::MAX] {
        let gated = Identifier::new(8.0, 49.0)
            .force_gate(ForceGate::new(open, open).unwrap())
            .identify(&records)
            .unwrap();
        let (k, k0) = (
            gated.coefficients().stiffness()[(0, 0)],
            plain.coefficients().stiffness()[(0, 0)],
        );
        assert!((k / k0 - 1.0).abs() < 1e-9, "{k} vs {k0}");
    }
}

/// Found by the `uff` target (issue 29's run): a value field of NUL bytes was quoted by 80
/// characters, each shown escaped as `\u{0}`, and the message grew to 429 characters. Escapes
/// now count as the characters they show: the quote stays within 80 of them.
#[test]
#[cfg(feature = "uff")]
fn escaped_quotes_stay_within_their_limit() {
    let mut text = b"    -1\n    58\nID 1\nID 2\nID 3\nID 4\nID 5\n\
        \x20   1         0    0         0 NONE               3   2 NONE               0   0\n\
        \x20        2         3         1  0.00000E+00  1.00000E-03  0.00000E+00\n\
        \x20       17    0    0    0 Time                 s\n\
        \x20       13    0    0    0 Force                N\n\
        \x20        0    0    0    0 NONE                 NONE\n\
        \x20        0    0    0    0 NONE                 NONE\n\
        6.63404253"
        .to_vec();
    text.extend([0u8; 150]);
    text.extend(b"\n    -1\n");
    let e = bearing_ident::uff::parse(&text, "fuzz.uff").unwrap_err();
    let message = e.to_string();
    assert!(message.chars().count() <= 200, "{message}");
    assert!(!message.contains('\0'), "{message}");
}

/// A MAT-file array of 300 dimensions, all negative, made an error message of 2148 characters
/// (every dimension listed; found by `fuzz/fuzz_targets/mat.rs`); four are shown now.
#[cfg(feature = "mat")]
#[test]
fn a_mat_array_of_300_dimensions_is_refused_in_a_short_message() {
    let le = |v: u32| v.to_le_bytes();
    let mut file = vec![b' '; 116];
    file.extend([0; 8]);
    file.extend([0x00, 0x01, b'I', b'M']);
    let dims = vec![0xff; 4 * 300];
    let body = [
        &le(6)[..],
        &le(8),
        &[6, 0, 0, 0, 0, 0, 0, 0], // flags: double
        &le(5),
        &le(dims.len() as u32),
        &dims,
    ]
    .concat();
    file.extend([&le(14)[..], &le(body.len() as u32), &body].concat());
    let e = bearing_ident::mat::parse(&file, "dims.mat").unwrap_err();
    assert_eq!(e.kind(), "malformed_mat");
    let m = e.to_string();
    assert!(
        m.ends_with(
            ": dimensions [18446744073709551615, 18446744073709551615, 18446744073709551615, \
             18446744073709551615, … 296 more]: at least two, none negative"
        ),
        "{m}"
    );
    assert!(m.len() < MAX_MESSAGE, "{m}");
}
