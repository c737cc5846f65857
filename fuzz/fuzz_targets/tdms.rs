//! `tdms::parse` over arbitrary bytes. Invariants: no panic; an error is `malformed_tdms` or
//! `too_large` with a short message; values read are at most the file's bytes (at least one
//! byte per value); building records from what is read never panics.
#![no_main]

use bearing_ident::tdms::{self, RecordBy, TdmsLayout};
use libfuzzer_sys::fuzz_target;

/// Longest error message accepted (the label and fixed text included).
const MAX_MESSAGE: usize = 400;

fuzz_target!(|data: &[u8]| {
    match tdms::parse(data, "fuzz.tdms") {
        Ok(file) => {
            let values: usize = file
                .groups
                .iter()
                .flat_map(|g| &g.channels)
                .map(|c| c.values.len())
                .sum();
            assert!(values <= data.len(), "{values} values from {} bytes", data.len());
            for record_by in [RecordBy::File, RecordBy::Group] {
                let layout = TdmsLayout {
                    time: "t".into(),
                    forces: vec!["fx".into()],
                    responses: vec!["x".into()],
                    record_by,
                    ..TdmsLayout::default()
                };
                let _ = tdms::records(&file, "fuzz.tdms", &layout);
            }
        }
        Err(e) => {
            assert!(matches!(e.kind().as_str(), "malformed_tdms" | "too_large"), "{e}");
            let message = e.to_string();
            assert!(
                message.chars().count() <= MAX_MESSAGE,
                "{} characters: {message}",
                message.chars().count()
            );
        }
    }
});
