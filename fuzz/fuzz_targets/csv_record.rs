//! `read_record_from` over arbitrary bytes, with the first byte choosing a layout (1–3 degrees
//! of freedom, or one column used as force and displacement). Invariants: no panic; an error
//! message quotes little of the input; a record read has finite samples and a finite positive
//! sampling rate.
#![no_main]

use bearing_ident::io::{CsvLayout, read_record_from};
use libfuzzer_sys::fuzz_target;

/// Longest error message accepted (the label and fixed text included).
const MAX_MESSAGE: usize = 400;

fuzz_target!(|data: &[u8]| {
    let Some((&choice, text)) = data.split_first() else {
        return;
    };
    let layout = match choice % 5 {
        0 => CsvLayout::for_dofs(1),
        1 => CsvLayout::for_dofs(2),
        2 => CsvLayout::for_dofs(3),
        3 => CsvLayout {
            time: "t".into(),
            forces: vec!["a".into()],
            displacements: vec!["a".into()],
        },
        _ => CsvLayout {
            time: String::new(),
            forces: vec!["f".into(), "g".into()],
            displacements: vec!["x".into(), "".into()],
        },
    };
    match read_record_from(text, "fuzz.csv", &layout) {
        Ok(record) => {
            assert!(record.sample_rate().is_finite() && record.sample_rate() > 0.0);
            assert!(record.len() >= bearing_ident::records::MIN_SAMPLES);
            for c in 0..record.dofs() {
                assert!(record.force(c).iter().all(|v| v.is_finite()));
                assert!(record.displacement(c).iter().all(|v| v.is_finite()));
            }
        }
        Err(e) => {
            let message = e.to_string();
            assert!(!e.kind().is_empty());
            assert!(
                message.chars().count() <= MAX_MESSAGE,
                "{} characters: {message}",
                message.chars().count()
            );
        }
    }
});
