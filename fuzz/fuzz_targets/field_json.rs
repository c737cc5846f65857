//! `RotorModel::from_json` and `FieldTests::from_json` over arbitrary text (the input split in
//! two at its first NUL byte: rotor, then tests), and `field::identify` on what both read when
//! the model is small. Invariants: no panic; an error is one of the field input kinds with a
//! short message; coefficients given are finite.
#![no_main]

use bearing_ident::field::{self, FieldTests, RotorModel};
use libfuzzer_sys::fuzz_target;

/// Longest error message accepted.
const MAX_MESSAGE: usize = 400;

/// Largest model identified (the solve is cubic in it; the readers are fuzzed at any size).
const MAX_DOFS: usize = 24;

fn check_error(e: &bearing_ident::Error) {
    assert!(
        matches!(
            e.kind(),
            "invalid_input" | "non_finite" | "rank_deficient" | "too_large"
        ),
        "{}: {e}",
        e.kind()
    );
    let message = e.to_string();
    assert!(
        message.chars().count() <= MAX_MESSAGE,
        "{} characters: {message}",
        message.chars().count()
    );
}

fuzz_target!(|data: &[u8]| {
    let (rotor, tests) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &b""[..]),
    };
    let (Ok(rotor), Ok(tests)) = (std::str::from_utf8(rotor), std::str::from_utf8(tests)) else {
        return;
    };
    let rotor = RotorModel::from_json(rotor).map_err(|e| check_error(&e));
    let tests = FieldTests::from_json(tests).map_err(|e| check_error(&e));
    let (Ok(rotor), Ok(tests)) = (rotor, tests) else {
        return;
    };
    if rotor.dofs() > MAX_DOFS || tests.responses.len() > 256 {
        return;
    }
    match field::identify(&rotor, &tests) {
        Ok(id) => {
            for b in id.bearings() {
                for c in b.coefficients.iter().flatten() {
                    for v in c.stiffness.iter().chain(&c.damping).flatten() {
                        assert!(v.is_finite(), "{c:?}");
                    }
                }
            }
        }
        Err(e) => {
            let message = e.to_string();
            assert!(message.chars().count() <= MAX_MESSAGE, "{message}");
        }
    }
});
