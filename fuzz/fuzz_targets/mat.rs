//! `mat::parse` over arbitrary bytes. Invariants: no panic; an error is `malformed_mat` with a
//! short message; records built from what is read (the default channels) never panic, and
//! fail only with a typed error.
#![no_main]

use bearing_ident::mat;
use libfuzzer_sys::fuzz_target;

/// Longest error message accepted (the label and fixed text included).
const MAX_MESSAGE: usize = 400;

fuzz_target!(|data: &[u8]| {
    match mat::parse(data, "fuzz.mat") {
        Ok(variables) => {
            let _ = mat::records(&variables, "fuzz.mat", &mat::MatLayout::default());
            for v in &variables {
                let _ = (v.array.class(), v.array.size_text());
            }
        }
        Err(e) => {
            assert_eq!(e.kind(), "malformed_mat", "{e}");
            let message = e.to_string();
            assert!(
                message.chars().count() <= MAX_MESSAGE,
                "{} characters: {message}",
                message.chars().count()
            );
        }
    }
});
