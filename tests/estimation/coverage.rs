//! Monte-Carlo calibration of the 95 % intervals: 200 noise realisations of the seed's rig
//! (fixed seeds, noise level 0.5), IVF; jackknife over the 8 paired sets and bootstrap (200
//! draws of 8 sets, seed 0), both with Student's t(7). The intervals of the six diagonal
//! coefficients must cover the truth in 91–99 % of the trials. Release mode only (CI runs it
//! so; 14 s there, far longer in the debug test profile).
//!
//! Measured (seed 95), M_xx, M_yy, C_xx, C_yy, K_xx, K_yy:
//! - jackknife 94.0, 96.5, 94.5, 94.5, 92.0, 96.0 %;
//! - bootstrap 93.5, 96.5, 95.0, 94.5, 93.5, 96.0 %;
//! - the first-order sandwich (normal quantile) covers a little less on the same data —
//!   91.5, 94.5, 91.5, 91.0, 91.0, 94.0 % — reported, not asserted; it is the CLI's choice
//!   only below 3 sets.

use crate::common;
use bearing_ident::Choice;

use bearing_ident::simulate::{ImpactTest, add_noise, seed_rig};
use bearing_ident::{Identifier, Uncertainty};
use rand::SeedableRng;
use rand::rngs::StdRng;

fn coverage(uncertainty: Uncertainty, trials: usize, level: f64) -> Vec<f64> {
    let truth = seed_rig();
    let clean = ImpactTest::seed_rig().run_clean(&truth).unwrap();
    let mut rng = StdRng::seed_from_u64(95);
    let mut hits = [0usize; 6];
    for _ in 0..trials {
        let noisy: Vec<_> = clean
            .iter()
            .map(|r| add_noise(r, level, &mut rng).unwrap())
            .collect();
        let id = Identifier::new(8.0, 49.0)
            .uncertainty(uncertainty)
            .identify(&noisy)
            .unwrap();
        let half = id.interval_95().unwrap();
        let got = common::blocks(id.coefficients());
        let (t, h) = (common::blocks(&truth), common::blocks(&half));
        for b in 0..3 {
            for i in 0..2 {
                if (got[b][(i, i)] - t[b][(i, i)]).abs() <= h[b][(i, i)] {
                    hits[2 * b + i] += 1;
                }
            }
        }
    }
    hits.iter().map(|&h| h as f64 / trials as f64).collect()
}

#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "Monte-Carlo: run in release (`cargo test --release --all-features --test estimation coverage::`), as CI does"
)]
fn jackknife_and_bootstrap_intervals_cover_the_truth() {
    let trials = std::env::var("BI_TRIALS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200);
    for uncertainty in [
        Uncertainty::Jackknife,
        Uncertainty::BOOTSTRAP,
        Uncertainty::Sandwich,
    ] {
        let c = coverage(uncertainty, trials, 0.5);
        println!(
            "{}: coverage Mxx Myy Cxx Cyy Kxx Kyy = {c:?}",
            uncertainty.name()
        );
        if uncertainty == Uncertainty::Sandwich {
            continue; // reported, not asserted: first order, slightly narrow (see above)
        }
        for (k, &v) in c.iter().enumerate() {
            assert!(
                (0.91..=0.99).contains(&v),
                "{} coefficient {k}: coverage {v}",
                uncertainty.name()
            );
        }
    }
}
