//! `Baseline::from_json` over arbitrary text; a baseline read is then subtracted from a small
//! identification of the same shape. Invariants: no panic; error messages quote little of the
//! input; a subtraction that succeeds gives finite coefficients.
#![no_main]

use std::sync::LazyLock;

use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{Baseline, Coefficients, Identification, Identifier};
use libfuzzer_sys::fuzz_target;

/// Longest error message accepted.
const MAX_MESSAGE: usize = 300;

/// A 2-DOF identification to subtract the baselines from.
static SYSTEM: LazyLock<Identification> = LazyLock::new(|| {
    let test = ImpactTest {
        per_direction: 1,
        ..ImpactTest::seed_rig()
    };
    let records = test.run(&seed_rig()).expect("the seed rig simulates");
    Identifier::new(8.0, 49.0)
        .identify(&records)
        .expect("the seed rig identifies")
});

fn assert_finite(c: &Coefficients) {
    for m in [c.mass(), c.damping(), c.stiffness()] {
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                assert!(m[(i, j)].is_finite(), "{c:?}");
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Baseline::from_json(text) {
        Ok(baseline) => {
            // The processing rarely matches; the coefficients are subtracted regardless.
            if let Ok(bearing) = SYSTEM.coefficients().subtract(baseline.coefficients()) {
                assert_finite(&bearing);
            }
            if let Ok((bearing, std)) = SYSTEM.subtract_baseline(baseline) {
                assert_finite(&bearing);
                std.as_ref().map(assert_finite);
            }
        }
        Err(e) => {
            assert_eq!(e.kind(), "bad_baseline");
            let message = e.to_string();
            assert!(
                message.chars().count() <= MAX_MESSAGE,
                "{} characters: {message}",
                message.chars().count()
            );
        }
    }
});
