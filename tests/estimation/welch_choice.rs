//! The Welch segment length chosen from the data (`excitation::choose_welch`) on a lightly
//! damped 2-DOF rig under random forcing, simulated in the time domain.

use crate::common;
use bearing_ident::excitation::{choose_welch, welch_len};
use bearing_ident::gate::{BiasSource, leakage_bias, leaked_flexibility, predicted_bias};
use bearing_ident::simulate::{AntiAlias, Simulator, add_noise, seed_rig};
use bearing_ident::solve::{IvfOptions, Method};
use bearing_ident::{Coefficients, Estimator, Identifier, Segmentation, Window};
use faer::Scale;
use rand::SeedableRng;
use rand::rngs::StdRng;

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

/// The seed's rig with 0.3 of its damping: ζ ≈ 2.4 %, half-power bandwidths ≈ 1.3 Hz.
fn lightly_damped() -> Coefficients {
    let rig = seed_rig();
    Coefficients::new(
        rig.mass().to_owned(),
        rig.damping() * Scale(0.3),
        rig.stiffness().to_owned(),
    )
    .unwrap()
}

/// Relative errors of the diagonal M, C, K (`[M_xx, M_yy, C_xx, C_yy, K_xx, K_yy]`).
fn diagonal_errors(got: &Coefficients, truth: &Coefficients) -> [f64; 6] {
    let (g, t) = (common::blocks(got), common::blocks(truth));
    let mut out = [0.0; 6];
    for b in 0..3 {
        for i in 0..2 {
            out[2 * b + i] = g[b][(i, i)] / t[b][(i, i)] - 1.0;
        }
    }
    out
}

/// Monte-Carlo of the leakage bias of Hann-windowed Welch H1 on a lightly damped 2-DOF rig
/// (8 records of 40 000 samples, 2 % noise, 10 seeds), at four segment lengths: the measured
/// mean damping error against the predicted damping bias ([`leakage_bias`]), and the default
/// choice ([`choose_welch`]) within 0.6 % of the truth on every diagonal coefficient in every
/// seed.
#[test]
#[ignore = "Monte-Carlo: 10 seeds × 8 records × 5 fits; run in release by .ci/run"]
fn leakage_bias_of_the_damping_is_predicted_and_the_choice_keeps_it_small() {
    let truth = lightly_damped();
    let (len, seeds) = (40_000, 10u64);
    let lengths = [2048usize, 4096, 8192, 16_384];
    let modes = truth.modes().unwrap();
    let b = modes
        .iter()
        .map(|m| 2.0 * m.damping_ratio * m.natural_frequency_hz)
        .fold(f64::INFINITY, f64::min);
    let mut sim = Simulator::new(&truth, RATE, len, AntiAlias::default()).unwrap();
    let mut mean_c = [0.0; 4];
    let mut worst_chosen: f64 = 0.0;
    let mut chosen_lengths = Vec::new();
    for seed in 0..seeds {
        let records: Vec<_> = (0..8)
            .map(|r| {
                let clean = sim
                    .random_record(format!("s{seed}r{r}"), 20.0, 1000 * seed + r)
                    .unwrap();
                let mut rng = StdRng::seed_from_u64(7 + 1000 * seed + r);
                add_noise(&clean, 0.02, &mut rng).unwrap()
            })
            .collect();
        for (i, &nperseg) in lengths.iter().enumerate() {
            let id = identifier()
                .segmentation(Segmentation::Welch { len: nperseg })
                .identify(&records)
                .unwrap();
            let e = diagonal_errors(id.coefficients(), &truth);
            mean_c[i] += 0.5 * (e[2] + e[3]) / seeds as f64;
        }
        let choice = choose_welch(&records, &identifier()).unwrap();
        chosen_lengths.push(choice.nperseg);
        let id = identifier()
            .segmentation(Segmentation::Welch {
                len: choice.nperseg,
            })
            .identify(&records)
            .unwrap();
        let e = diagonal_errors(id.coefficients(), &truth);
        println!(
            "seed {seed}: chosen {} samples, errors {e:.4?}",
            choice.nperseg
        );
        worst_chosen = e.iter().fold(worst_chosen, |w, v| w.max(v.abs()));
    }
    println!("lightest half-power bandwidth {b:.3} Hz");
    println!("nperseg | Δf (Hz) | mean C error | (Δf/B)²/3 | predicted damping bias");
    let mut predicted_c = [0.0; 4];
    for (i, &nperseg) in lengths.iter().enumerate() {
        let df = RATE / nperseg as f64;
        let freqs: Vec<f64> = bearing_ident::Band::new(8.0, 49.0)
            .unwrap()
            .lines(RATE, nperseg)
            .unwrap()
            .iter()
            .map(|&k| k as f64 * df)
            .collect();
        let leaked = leaked_flexibility(&truth, &freqs, nperseg, RATE).unwrap();
        let bias = predicted_bias(
            &truth,
            &freqs,
            leaked,
            Method::Ivf,
            &IvfOptions::default(),
            BiasSource::Leakage,
        )
        .unwrap();
        predicted_c[i] = (0..2)
            .map(|d| bias.bias.damping()[(d, d)] / truth.damping()[(d, d)])
            .sum::<f64>()
            / 2.0;
        println!(
            "{nperseg:7} | {df:.4} | {:+.3} % | {:.3} % | {:+.3} %",
            100.0 * mean_c[i],
            100.0 * leakage_bias(df, b),
            100.0 * predicted_c[i]
        );
    }
    println!(
        "chosen {chosen_lengths:?}; worst error {:.3} %",
        100.0 * worst_chosen
    );
    // The prediction is the damping's bias: within a factor 1.5 of the measured mean where it
    // stands out of the random error (the two shortest segments).
    for i in 0..2 {
        let ratio = mean_c[i] / predicted_c[i];
        assert!((1.0 / 1.5..1.5).contains(&ratio), "{}: {ratio}", lengths[i]);
    }
    assert!(worst_chosen < 0.006, "{worst_chosen}");
}

/// Random records at the command line's default settings, as a user runs them: `simulate
/// --kind random --noise 0.02` (the seed's rig, four records of 58.7 s at 6.7 kHz, 2 % noise on
/// every channel) and `identify --band 8,49` with nothing else. Over 10 seeds the mean error of
/// every coefficient is within one combined standard deviation (before: H1's force-noise bias
/// +0.023 % on M_yy and K_yy, 1.6 σ, and leakage of the damping up to 1.7 σ, because the
/// segment length was judged against error bars that carried the first fit's own leakage).
#[cfg(feature = "cli")]
#[test]
#[ignore = "Monte-Carlo: 10 simulated random tests through the CLI; run in release by .ci/run"]
fn default_random_records_are_unbiased_within_one_sigma() {
    use serde_json::Value;
    let rig = seed_rig();
    let truth = [rig.mass(), rig.damping(), rig.stiffness()];
    let dir = tempfile::tempdir().unwrap();
    let seeds: u32 = 10;
    // Per coefficient, "M[0][1]" …: the sums of the error and of the combined σ.
    let mut sums: Vec<(String, f64, f64)> = Vec::new();
    let mut no_leakage_warning = 0;
    for seed in 1..=seeds {
        let out = dir.path().join(format!("s{seed}"));
        let sim = common::run(&[
            "simulate",
            "--kind",
            "random",
            "--noise",
            "0.02",
            "--seed",
            &seed.to_string(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(sim.status.success(), "{sim:?}");
        let files = common::csv_files(&out);
        let id = common::run(
            &[
                &["identify", "--json", "--band", "8,49"][..],
                &files.iter().map(String::as_str).collect::<Vec<_>>(),
            ]
            .concat(),
        );
        assert!(id.status.success(), "{id:?}");
        let v: Value = serde_json::from_slice(&id.stdout).unwrap();
        println!("seed {seed}: {} {}", v["welch_choice"], v["warning_kinds"]);
        let warned = |kind: &str| {
            v["warning_kinds"]
                .as_array()
                .unwrap()
                .iter()
                .any(|k| k == kind)
        };
        no_leakage_warning += usize::from(!warned("leakage_bias"));
        let mut k = 0;
        for (b, key) in ["M", "C", "K"].iter().enumerate() {
            for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let e = v[key][i][j].as_f64().unwrap() - truth[b][(i, j)];
                let s = v[format!("{key}_std")][i][j].as_f64().unwrap();
                if sums.len() == k {
                    sums.push((format!("{key}[{i}][{j}]"), 0.0, 0.0));
                }
                sums[k].1 += e;
                sums[k].2 += s;
                k += 1;
            }
        }
    }
    for (name, e, s) in &sums {
        let sigmas = e / s;
        println!(
            "{name}: mean error {:+.4e}, mean σ {:.4e}, {sigmas:+.2} σ",
            e / f64::from(seeds),
            s / f64::from(seeds)
        );
        assert!(sigmas.abs() <= 1.0, "{name}: {sigmas} σ");
    }
    // The segment length is judged against the random error, as the final result judges it:
    // the leakage it leaves stays below the warning's threshold.
    assert!(no_leakage_warning >= 9, "{no_leakage_warning} of {seeds}");
}
