//! Bounded byte-fuzzing of the readers on stable, in the normal test suite (the unbounded
//! fuzzers are in `fuzz/`, run with `cargo +nightly fuzz`): arbitrary bytes and mutated valid
//! files must give a record or a typed error, never a panic, and an error message must not
//! echo the input (it quotes at most 80 characters of it).

use bearing_ident::Record;
use bearing_ident::io::{CsvLayout, read_record_from, write_record_to};
use proptest::prelude::*;

/// Longest error message accepted: a short label, the fixed text, numbers and one quote of at
/// most 80 characters fit well below it; an echoed line or header does not.
const MAX_MESSAGE: usize = 300;

/// A valid record file of `n` degrees of freedom and 40 samples.
fn valid_csv(n: usize) -> Vec<u8> {
    let channel = |k: usize| -> Vec<f64> {
        (0..40)
            .map(|m| (0.3 * (m * (k + 1)) as f64).sin() * 10f64.powi(k as i32 - 3))
            .collect()
    };
    let record = Record::new(
        "valid",
        1000.0,
        (0..n).map(channel).collect(),
        (n..2 * n).map(channel).collect(),
    )
    .unwrap();
    let mut bytes = Vec::new();
    write_record_to(&mut bytes, &record, &CsvLayout::for_dofs(n)).unwrap();
    bytes
}

/// One edit of a file.
#[derive(Debug, Clone)]
enum Mutation {
    /// Replace the byte at (position mod length).
    Set(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Truncate(usize),
    /// Insert `count` copies of a byte: long fields and lines.
    Run(usize, u8, usize),
    /// Repeat the line holding the position.
    DuplicateLine(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let interesting = prop::sample::select(vec![
        b',', b'\n', b'\r', b'"', b'-', b'e', b'.', b'0', b'9', b' ', b'N', b'i', 0xff, 0,
    ]);
    prop_oneof![
        (any::<usize>(), interesting.clone()).prop_map(|(p, b)| Mutation::Set(p, b)),
        (any::<usize>(), any::<u8>()).prop_map(|(p, b)| Mutation::Set(p, b)),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..12))
            .prop_map(|(p, v)| Mutation::Insert(p, v)),
        (any::<usize>(), 1usize..40).prop_map(|(p, n)| Mutation::Delete(p, n)),
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), interesting, 100usize..3000).prop_map(|(p, b, n)| Mutation::Run(p, b, n)),
        any::<usize>().prop_map(Mutation::DuplicateLine),
    ]
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    let at = |p: usize, len: usize| if len == 0 { 0 } else { p % (len + 1) };
    match m {
        Mutation::Set(p, b) if !bytes.is_empty() => {
            let i = p % bytes.len();
            bytes[i] = *b;
        }
        Mutation::Set(..) => {}
        Mutation::Insert(p, v) => {
            let i = at(*p, bytes.len());
            bytes.splice(i..i, v.iter().copied());
        }
        Mutation::Delete(p, n) => {
            let i = at(*p, bytes.len());
            let end = (i + n).min(bytes.len());
            bytes.drain(i..end);
        }
        Mutation::Truncate(p) => bytes.truncate(at(*p, bytes.len())),
        Mutation::Run(p, b, n) => {
            let i = at(*p, bytes.len());
            bytes.splice(i..i, std::iter::repeat_n(*b, *n));
        }
        Mutation::DuplicateLine(p) => {
            let i = at(*p, bytes.len()).min(bytes.len().saturating_sub(1));
            let start = bytes[..i]
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |s| s + 1);
            let end = bytes[i..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(bytes.len(), |e| i + e + 1);
            let line = bytes[start..end].to_vec();
            bytes.splice(end..end, line);
        }
    }
}

/// The error kinds a CSV record's bytes can cause: malformed text, a missing column, a
/// non-number, a broken time grid, too few samples, a documented limit passed.
const READ_KINDS: [&str; 6] = [
    "malformed_csv",
    "missing_column",
    "non_finite",
    "nonuniform_time",
    "record_too_short",
    "too_large",
];

/// Reads `bytes` with `layout` and checks the reader's contract.
fn check_csv(bytes: &[u8], layout: &CsvLayout) -> Result<(), TestCaseError> {
    match read_record_from(bytes, "fuzz.csv", layout) {
        Ok(r) => {
            prop_assert!(r.sample_rate().is_finite() && r.sample_rate() > 0.0);
            for c in 0..r.dofs() {
                prop_assert!(
                    r.force(c)
                        .iter()
                        .chain(r.displacement(c))
                        .all(|v| v.is_finite())
                );
            }
        }
        Err(e) => {
            let message = e.to_string();
            // A reading error of the kinds the output reference lists for data, naming the file.
            prop_assert!(
                READ_KINDS.contains(&e.kind().as_str()),
                "{}: {}",
                e.kind(),
                message
            );
            prop_assert!(message.contains("fuzz.csv"), "{}", message);
            prop_assert!(
                message.chars().count() <= MAX_MESSAGE,
                "{} characters: {}",
                message.chars().count(),
                message
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn csv_reader_takes_arbitrary_bytes(
        bytes in prop::collection::vec(any::<u8>(), 0..2048),
        n in 1usize..=3,
    ) {
        check_csv(&bytes, &CsvLayout::for_dofs(n))?;
    }

    #[test]
    fn csv_reader_takes_mutated_files(
        n in 1usize..=3,
        mutations in prop::collection::vec(mutation(), 1..6),
    ) {
        let mut bytes = valid_csv(n);
        for m in &mutations {
            apply(&mut bytes, m);
        }
        check_csv(&bytes, &CsvLayout::for_dofs(n))?;
    }
}

/// The unmutated file reads: the mutation test starts from a valid file.
#[test]
fn the_valid_files_read() {
    for n in 1..=3 {
        let r =
            read_record_from(valid_csv(n).as_slice(), "valid", &CsvLayout::for_dofs(n)).unwrap();
        assert_eq!((r.dofs(), r.len()), (n, 40));
    }
}

#[cfg(feature = "json")]
mod json {
    use super::*;
    use bearing_ident::Baseline;

    /// A saved identification as `identify --json` writes it (abridged).
    const VALID: &str = r#"{"method":"ivf","estimator":"paired","window":"exp","window_decay_per_s":2.5,
"n":2,"band_hz":[8.0,49.0],"freqs_hz":[8.0,9.0,10.0,11.0],
"M":[[4.7,0.01],[0.02,4.69]],"C":[[131.9,-2.1],[1.5,130.2]],"K":[[146300.0,-120.5],[80.1,145900.0]],
"M_std":[[0.01,0.002],[0.002,0.01]],"C_std":[[0.5,0.1],[0.1,0.5]],"K_std":[[120.0,30.0],[30.0,110.0]],
"warnings":[],"warning_kinds":[]}"#;

    fn check_json(text: &str) -> Result<(), TestCaseError> {
        if let Err(e) = Baseline::from_json(text) {
            let message = e.to_string();
            prop_assert_eq!(e.kind(), "bad_baseline");
            prop_assert!(
                message.chars().count() <= MAX_MESSAGE,
                "{} characters: {}",
                message.chars().count(),
                message
            );
        }
        Ok(())
    }

    #[test]
    fn the_valid_json_reads() {
        let b = Baseline::from_json(VALID).unwrap();
        assert_eq!(b.coefficients().stiffness()[(1, 1)], 145900.0);
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

        #[test]
        fn baseline_reader_takes_arbitrary_text(text in "\\PC{0,512}") {
            check_json(&text)?;
        }

        #[test]
        fn baseline_reader_takes_mutated_files(
            mutations in prop::collection::vec(mutation(), 1..6),
        ) {
            let mut bytes = VALID.as_bytes().to_vec();
            for m in &mutations {
                apply(&mut bytes, m);
            }
            check_json(&String::from_utf8_lossy(&bytes))?;
        }
    }
}
