//! The seed's rig (Diaz & San Andrés 1999): a 2-DOF system of about 4.7 kg with
//! K_xx = 146.3 kN/m and K_yy = 169.1 kN/m, 8 impacts per direction at 6700 samples/s for
//! 1.2 s, identified over 8–49 Hz, with measurement noise.

use crate::common;

use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{Identifier, Method};

#[test]
fn seed_rig_with_noise_is_recovered_within_its_error_bars() {
    let truth = seed_rig();
    let records = ImpactTest {
        noise: 0.1,
        seed: 1999,
        ..ImpactTest::seed_rig()
    }
    .run(&truth)
    .unwrap();
    assert_eq!(records.len(), 16);
    assert_eq!(records[0].len(), 8040);

    let id = Identifier::new(8.0, 49.0)
        .method(Method::Ivf)
        .identify(&records)
        .unwrap();
    // The band of the seed: 49 lines from 8.33 to 48.33 Hz at 0.8333 Hz spacing.
    assert_eq!(id.freqs_hz().len(), 49);
    assert!((id.freqs_hz()[0] - 8.3333).abs() < 1e-3);
    assert!((id.freqs_hz()[48] - 48.3333).abs() < 1e-3);
    assert_eq!(id.frf().averages(), 8);
    assert!(id.converged());
    assert!(id.iterations() <= 10, "{} iterations", id.iterations());
    assert!(id.warnings().is_empty(), "{:?}", id.warnings());
    // Orthogonal impacts: the displacement matrix is well conditioned over the band.
    assert!(id.conditioning().worst() < 10.0);

    // Each diagonal coefficient within 6 sandwich standard deviations (see tests/estimation/properties.rs
    // for why 6σ̂), and the standard deviations small: the test is informative.
    let std = id.std_dev().unwrap();
    for (b, (got, (t, s))) in common::blocks(id.coefficients())
        .iter()
        .zip(common::blocks(&truth).iter().zip(common::blocks(std)))
        .enumerate()
    {
        for i in 0..2 {
            let err = (got[(i, i)] - t[(i, i)]).abs();
            println!(
                "block {b} ({i},{i}): error {:.3e} = {:.2} σ̂, σ̂/value {:.2e}",
                err / t[(i, i)],
                err / s[(i, i)],
                s[(i, i)] / t[(i, i)]
            );
            assert!(err < 6.0 * s[(i, i)], "block {b} ({i},{i})");
            assert!(s[(i, i)] < 0.01 * t[(i, i)], "block {b}: σ̂ above 1 %");
        }
    }
    // The flexibility fit explains the direct terms (the seed reports 94–98 %).
    assert!(id.fit_r2()[(0, 0)] > 0.95 && id.fit_r2()[(1, 1)] > 0.95);
    // And natural frequencies within 0.1 %.
    for (a, b) in id.modes().unwrap().iter().zip(truth.modes().unwrap()) {
        assert!((a.natural_frequency_hz / b.natural_frequency_hz - 1.0).abs() < 1e-3);
    }
}
