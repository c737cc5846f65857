//! The Welch segment length chosen from the data (`excitation::choose_welch`) on a lightly
//! damped 2-DOF rig under random forcing, simulated in the time domain.

use bearing_ident::excitation::{choose_welch, welch_len};
use bearing_ident::gate::leakage_bias;
use bearing_ident::simulate::{AntiAlias, Simulator, seed_rig};
use bearing_ident::{Coefficients, Estimator, Identifier, Segmentation, Window};
use faer::Scale;

const RATE: f64 = 500.0;
const LEN: usize = 16_384;
const RECORDS: u64 = 8;

/// The seed's rig with a tenth of its damping: ζ ≈ 0.8 %, half-power bandwidths ≈ 0.45 Hz.
fn light_rig() -> Coefficients {
    let rig = seed_rig();
    Coefficients::new(
        rig.mass().to_owned(),
        rig.damping() * Scale(0.1),
        rig.stiffness().to_owned(),
    )
    .unwrap()
}

fn identifier() -> Identifier {
    Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .window(Window::Hann)
}

/// Worst relative error of the diagonal damping.
fn damping_error(got: &Coefficients, truth: &Coefficients) -> f64 {
    (0..2)
        .map(|i| (got.damping()[(i, i)] / truth.damping()[(i, i)] - 1.0).abs())
        .fold(0.0, f64::max)
}

/// Eight records of 32.8 s under random forcing on both axes. The default (an eighth of the
/// record, 2048 samples, Δf = 0.24 Hz: 1.9 lines per half-power bandwidth) leaks; the first
/// fit's bandwidth (0.51 Hz; the default's leakage widens it from the true 0.45 Hz) asks for
/// 8 lines in it: 8192 samples, Δf = 0.061 Hz, 3 segments per record, 24 averages.
#[test]
fn chosen_segments_cut_the_leakage_bias() {
    let truth = light_rig();
    let mut sim = Simulator::new(&truth, RATE, LEN, AntiAlias::default()).unwrap();
    let records: Vec<_> = (0..RECORDS)
        .map(|s| sim.random_record(format!("r{s}"), 20.0, 5 + s).unwrap())
        .collect();
    let choice = choose_welch(&records, &identifier()).unwrap();
    println!("{choice:?}");
    assert_eq!(welch_len(LEN), 2048);
    assert_eq!(choice.nperseg, 8192);
    assert!(!choice.record_limited);
    assert_eq!(choice.segments_per_record, 3);
    let b = choice.lightest_bandwidth_hz.unwrap();
    let b_true = 2.0 * 0.1 * 131.98 / (2.0 * 4.8) / (2.0 * std::f64::consts::PI);
    assert!((b / b_true - 1.0).abs() < 0.2, "{b} vs {b_true}");
    let fit = |len: usize| {
        identifier()
            .segmentation(Segmentation::Welch { len })
            .identify(&records)
            .unwrap()
    };
    let (default, chosen) = (fit(welch_len(LEN)), fit(choice.nperseg));
    let (e_default, e_chosen) = (
        damping_error(default.coefficients(), &truth),
        damping_error(chosen.coefficients(), &truth),
    );
    println!(
        "C error: default {:.2} % (predicted bias {:.2} %), chosen {:.2} % (predicted {:.2} %)",
        100.0 * e_default,
        100.0 * leakage_bias(RATE / welch_len(LEN) as f64, b),
        100.0 * e_chosen,
        100.0 * choice.predicted_bias.unwrap()
    );
    assert!(e_chosen < 0.25 * e_default, "{e_chosen} vs {e_default}");
    assert!(e_chosen < 0.03, "{e_chosen}");
    // Two records only: 16 averages need segments no longer than the default; it is kept.
    let few = choose_welch(&records[..2], &identifier()).unwrap();
    assert_eq!(few.nperseg, welch_len(LEN));
    assert!(few.record_limited);
}
