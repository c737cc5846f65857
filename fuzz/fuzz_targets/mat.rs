//! `mat::parse` over arbitrary bytes, as they are and behind a MATLAB `-v7.3` user block and
//! HDF5's signature (so that the HDF5 reader sees them from the superblock on). Invariants: no
//! panic; an error is `malformed_mat` with a short message; records built from what is read
//! (the default channels) never panic, and fail only with a typed error. Seed the corpus with
//! `tests/mat/fixtures/*.mat` (level 5 and `-v7.3`).
#![no_main]

use bearing_ident::mat;
use libfuzzer_sys::fuzz_target;

/// Longest error message accepted (the label and fixed text included).
const MAX_MESSAGE: usize = 400;

fn check(data: &[u8]) {
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
}

fuzz_target!(|data: &[u8]| {
    check(data);
    if !data.starts_with(b"MATLAB 7.3") && data.get(512..516) != Some(b"\x89HDF") {
        let mut v73 = b"MATLAB 7.3 MAT-file".to_vec();
        v73.resize(512, b' ');
        v73.extend_from_slice(b"\x89HDF\r\n\x1a\n");
        v73.extend_from_slice(data);
        check(&v73);
    }
});
