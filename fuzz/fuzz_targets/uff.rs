//! `uff::parse` over arbitrary bytes. Invariants: no panic; an error is `malformed_uff` with a
//! short message; what is read writes (ASCII) and reads back to as many functions of the same
//! lengths and types; building records from it never panics.
#![no_main]

use bearing_ident::uff;
use libfuzzer_sys::fuzz_target;

/// Longest error message accepted (the label and fixed text included).
const MAX_MESSAGE: usize = 400;

fuzz_target!(|data: &[u8]| {
    match uff::parse(data, "fuzz.uff") {
        Ok(functions) => {
            let _ = uff::records(&functions, "fuzz.uff");
            let mut out = Vec::new();
            // A binary value that is NaN or infinite cannot be written in ASCII: that is an error.
            if uff::write(&mut out, &functions).is_ok() {
                let back = uff::parse(&out, "again.uff").expect("what was written reads back");
                assert_eq!(back.len(), functions.len());
                for (a, b) in functions.iter().zip(&back) {
                    assert_eq!(a.ordinate.len(), b.ordinate.len());
                    assert_eq!(a.ordinate_type(), b.ordinate_type());
                    assert_eq!(a.function_type, b.function_type);
                    assert_eq!(a.response.node, b.response.node);
                    assert_eq!(a.response.direction, b.response.direction);
                }
            }
        }
        Err(e) => {
            assert!(matches!(e.kind(), "malformed_uff" | "too_large"), "{e}");
            let message = e.to_string();
            assert!(
                message.chars().count() <= MAX_MESSAGE,
                "{} characters: {message}",
                message.chars().count()
            );
        }
    }
});
