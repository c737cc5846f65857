//! Maximum likelihood on impact and random records (no repeated periods): the residual noise
//! models (`solve::ml::noise`), quick checks, and the Monte-Carlo comparison with the
//! Cramér–Rao bound and with IVF on the same data (release only).

use crate::common;

use bearing_ident::records::Record;
use bearing_ident::simulate::{AntiAlias, ImpactTest, Simulator, seed_rig};
use bearing_ident::solve::ml::{MlData, NoiseModel, crlb};
use bearing_ident::spectra::{Segmentation, SpectralEstimator, Window};
use bearing_ident::{Coefficients, Estimator, Identifier, Method};
use faer::{Mat, c64};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

/// Random excitation: one record, independent white forces on both axes at once.
const RANDOM_RATE: f64 = 500.0;
const RANDOM_LEN: usize = 32_768;
const RANDOM_SEGMENT: usize = 4096;

fn impact_records() -> Vec<Record> {
    ImpactTest::seed_rig().run(&seed_rig()).unwrap()
}

fn random_records() -> Vec<Record> {
    let mut sim =
        Simulator::new(&seed_rig(), RANDOM_RATE, RANDOM_LEN, AntiAlias::default()).unwrap();
    vec![sim.random_record("shaker", 20.0, 11).unwrap()]
}

/// White noise of standard deviation `sx` (m) on every displacement sample; forces clean
/// (output noise: the assumption of H1 and of the residual noise model).
fn with_noise(records: &[Record], sx: f64, rng: &mut StdRng) -> Vec<Record> {
    let d = Normal::new(0.0, sx).unwrap();
    records
        .iter()
        .map(|r| {
            let disps = (0..2)
                .map(|c| {
                    r.displacement(c)
                        .iter()
                        .map(|v| v + d.sample(rng))
                        .collect()
                })
                .collect();
            let forces = (0..2).map(|c| r.force(c).to_vec()).collect();
            Record::new(r.label(), r.sample_rate(), forces, disps).unwrap()
        })
        .collect()
}

fn impact_identifier(estimator: Estimator, method: Method) -> Identifier {
    Identifier::new(8.0, 49.0)
        .estimator(estimator)
        .segmentation(Segmentation::WholeRecord)
        .method(method)
}

fn random_identifier(method: Method) -> Identifier {
    Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Welch {
            len: RANDOM_SEGMENT,
        })
        .window(Window::Hann)
        .method(method)
}

/// The Cramér–Rao bound for `clean` records cut into `segments` (start, length) with
/// `window`, white displacement noise `sx` (per-line variance `σ² Δt² Σ w²`), independent
/// spectra, times `inflation` on the covariance.
fn bound(clean: &[Record], len: usize, window: Window, sx: f64, inflation: f64) -> [f64; 6] {
    let r0 = &clean[0];
    let rate = r0.sample_rate();
    let mut est = SpectralEstimator::new(len, rate, window).unwrap();
    let df = rate / len as f64;
    let lines: Vec<usize> = ((8.0 / df).ceil() as usize..=(49.0 / df).floor() as usize).collect();
    let mut columns: Vec<[Vec<c64>; 4]> = Vec::new();
    for r in clean {
        let starts: Vec<usize> = Segmentation::Welch { len }.starts(r.len()).collect();
        for start in starts {
            let seg = start..start + len;
            let mut spec = |ch: &[f64]| est.transform(&ch[seg.clone()]).to_vec();
            columns.push([
                spec(r.force(0)),
                spec(r.force(1)),
                spec(r.displacement(0)),
                spec(r.displacement(1)),
            ]);
        }
    }
    let j = columns.len();
    let (mut x, mut f) = (Vec::new(), Vec::new());
    for &k in &lines {
        f.push(Mat::from_fn(2, j, |i, c| columns[c][i][k]));
        x.push(Mat::from_fn(2, j, |i, c| columns[c][2 + i][k]));
    }
    let dt = 1.0 / rate;
    let power = est.window_power();
    let var = sx * sx * dt * dt * power;
    let diag = |v: f64| Mat::from_fn(2, 2, |i, j| c64::new(if i == j { v } else { 0.0 }, 0.0));
    let l = lines.len();
    let data = MlData::new(
        lines.iter().map(|&k| k as f64 * df).collect(),
        &x,
        &f,
        &vec![diag(var); l],
        &vec![Mat::zeros(2, 2); l],
        &vec![Mat::zeros(2, 2); l],
    )
    .unwrap();
    common::diagonal(&crlb(&seed_rig(), &data).unwrap()).map(|s| s * inflation.sqrt())
}

/// ML runs on impacts (paired sets and H1) and on random records, reports its noise model,
/// never costs more than IVF, and lands near the truth.
#[test]
fn ml_identifies_impact_and_random_records() {
    let truth = seed_rig();
    let mut rng = StdRng::seed_from_u64(3);
    let impacts = impact_records();
    let noisy = with_noise(&impacts, 0.1 * common::rms(&impacts, false), &mut rng);
    for estimator in [Estimator::PairedSets, Estimator::H1] {
        let id = impact_identifier(estimator, Method::Ml)
            .identify(&noisy)
            .unwrap();
        let report = id.ml().unwrap();
        assert_eq!(report.noise_model, NoiseModel::ImpactResiduals);
        assert!(report.fell_back.is_none(), "{report:?}");
        assert!(report.cost <= report.start_cost);
        assert!((0.7..1.3).contains(&report.cost_ratio), "{report:?}");
        let err = common::block_relative_error(id.coefficients(), &truth);
        assert!(err < 0.02, "{estimator:?}: {err}");
        assert!(id.std_dev().is_some());
    }
    let random = random_records();
    let noisy = with_noise(&random, 0.3 * common::rms(&random, false), &mut rng);
    let id = random_identifier(Method::Ml).identify(&noisy).unwrap();
    let report = id.ml().unwrap();
    assert_eq!(report.noise_model, NoiseModel::WelchResiduals);
    assert!(report.fell_back.is_none(), "{report:?}");
    let err = common::block_relative_error(id.coefficients(), &truth);
    assert!(err < 0.02, "random: {err}");
}

/// ML on whole records under an exponential window warns that its error bars are too narrow
/// (the window correlates neighbouring lines; `undecayed_impacts_…` measures it); without the
/// window it does not.
#[test]
fn ml_warns_on_windowed_whole_records() {
    let mut rng = StdRng::seed_from_u64(4);
    let impacts = impact_records();
    let noisy = with_noise(&impacts, 0.1 * common::rms(&impacts, false), &mut rng);
    let warned = |id: &bearing_ident::Identification| {
        id.warnings()
            .iter()
            .any(|w| w.kind() == "ml_windowed_records")
    };
    let plain = impact_identifier(Estimator::PairedSets, Method::Ml)
        .identify(&noisy)
        .unwrap();
    assert!(!warned(&plain));
    let windowed = impact_identifier(Estimator::PairedSets, Method::Ml)
        .window(Window::exponential_to(0.01, 1.2))
        .identify(&noisy)
        .unwrap();
    assert!(warned(&windowed));
    assert!(common::block_relative_error(windowed.coefficients(), &seed_rig()) < 0.02);
}

/// Runs `trials` noisy copies of `clean` through ML and IVF and checks the targets of the
/// issue: ML std / bound in 0.8–1.3, IVF std / ML std ≥ 1.5, |bias| < 3.5 standard errors,
/// 95 % interval coverage 93–97 %.
fn monte_carlo(
    clean: &[Record],
    sx: f64,
    trials: usize,
    seed: u64,
    bound: [f64; 6],
    ml: &Identifier,
    ivf: &Identifier,
) {
    let truth = common::diagonal(&seed_rig());
    let names = ["M_xx", "M_yy", "C_xx", "C_yy", "K_xx", "K_yy"];
    let mut rng = StdRng::seed_from_u64(seed);
    let (mut a, mut b, mut covered, mut ratio) = (Vec::new(), Vec::new(), [0usize; 6], Vec::new());
    let mut reported = [0.0; 6];
    for _ in 0..trials {
        let noisy = with_noise(clean, sx, &mut rng);
        let m = ml.identify(&noisy).unwrap();
        let i = ivf.identify(&noisy).unwrap();
        assert!(m.ml().unwrap().fell_back.is_none());
        ratio.push(m.ml().unwrap().cost_ratio);
        let (est, half) = (
            common::diagonal(m.coefficients()),
            common::diagonal(&m.interval_95().unwrap()),
        );
        let sd = common::diagonal(m.std_dev().unwrap());
        for k in 0..6 {
            reported[k] += sd[k] / trials as f64;
            if (est[k] - truth[k]).abs() <= half[k] {
                covered[k] += 1;
            }
        }
        a.push(est);
        b.push(common::diagonal(i.coefficients()));
    }
    let stats = |v: &[[f64; 6]], i: usize| {
        let m = v.iter().map(|r| r[i]).sum::<f64>() / v.len() as f64;
        let s = (v.iter().map(|r| (r[i] - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt();
        (m, s)
    };
    let mean_ratio = ratio.iter().sum::<f64>() / ratio.len() as f64;
    println!("mean cost ratio {mean_ratio:.3}");
    let mut failures = Vec::new();
    for i in 0..6 {
        let ((mm, ms), (im, is)) = (stats(&a, i), stats(&b, i));
        let bias = (mm - truth[i]) / (ms / (trials as f64).sqrt());
        let coverage = covered[i] as f64 / trials as f64;
        println!(
            "{}: ml {:+.3} % ± {:.3} % ({:.2} bound; reported {:.2} bound; bias {:+.2} SE, coverage {:.3}) ivf {:+.3} % ± {:.3} % ({:.2}× ml)",
            names[i],
            100.0 * (mm / truth[i] - 1.0),
            100.0 * ms / truth[i],
            ms / bound[i],
            reported[i] / bound[i],
            bias,
            coverage,
            100.0 * (im / truth[i] - 1.0),
            100.0 * is / truth[i],
            is / ms
        );
        if !(0.8..=1.3).contains(&(ms / bound[i])) {
            failures.push(format!("{}: std/bound {:.3}", names[i], ms / bound[i]));
        }
        if is / ms < 1.5 {
            failures.push(format!("{}: ivf/ml {:.3}", names[i], is / ms));
        }
        if bias.abs() >= 3.5 {
            failures.push(format!("{}: bias {bias:.2} SE", names[i]));
        }
        if !(0.93..=0.97).contains(&coverage) {
            failures.push(format!("{}: coverage {coverage:.3}", names[i]));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

fn env(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Monte-Carlo on the seed's impact test (8 hits per direction, 1.2 s at 6700 samples/s, 49
/// lines) with a high noise floor on the displacements: white noise of 1.0 × the
/// displacement RMS, clean forces, 300 trials (seed 2024), paired sets. The bound: the
/// Cramér–Rao bound on the clean spectra with the true per-line variance `σ² N Δt²`.
///
/// Measured (M_xx, M_yy, C_xx, C_yy, K_xx, K_yy): ML std / bound 0.97, 1.02, 1.05, 1.01,
/// 0.97, 1.01 (reported σ 1.01–1.02 × the bound); IVF std / ML std 2.60, 2.16, 2.34, 1.91,
/// 2.40, 2.04; bias +1.38, −0.57, +0.30, +0.67, +1.10, −0.26 SE; 95 % coverage 0.960,
/// 0.947, 0.950, 0.957, 0.970, 0.957. Seed 7: 0.95–1.04 ×, IVF 1.99–2.40 ×, coverage
/// 0.937–0.967. With H1 instead of paired sets (`BI_H1=1`): 0.97–1.05 ×, IVF 1.54–1.98 ×,
/// coverage 0.950–0.970.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "Monte-Carlo: run in release (`cargo test --release --all-features --test estimation ml_records::`), as CI does"
)]
fn ml_on_impacts_reaches_the_bound_and_beats_ivf() {
    let clean = impact_records();
    let sx = env("BI_LX", 1.0) * common::rms(&clean, false);
    let len = clean[0].len();
    let b = bound(&clean, len, Window::Rectangular, sx, 1.0);
    let estimator = if env("BI_H1", 0.0) > 0.0 {
        Estimator::H1
    } else {
        Estimator::PairedSets
    };
    monte_carlo(
        &clean,
        sx,
        env("BI_TRIALS", 300.0) as usize,
        env("BI_SEED", 2024.0) as u64,
        b,
        &impact_identifier(estimator, Method::Ml),
        &impact_identifier(estimator, Method::Ivf),
    );
}

/// Monte-Carlo on random excitation (white forces on both axes at once, one record of 65.5 s
/// at 500 samples/s, Welch 4096 with Hann at 50 %: 15 segments, 336 lines) with output noise
/// of 1.0 × the displacement RMS, the forces fixed and clean, 300 trials (seed 2024). The
/// bound: the Fisher information of the clean segments' spectra with the true per-line
/// variance `σ² Δt² Σw²`, times the Welch correlation inflation `35/18 + (1/6)(S − 1)/S`
/// (`frf::moments`).
///
/// Measured: ML std / bound 1.04, 0.98, 1.05, 1.06, 1.04, 0.99 (reported σ 1.00–1.01 × the
/// bound); IVF / ML 1.97, 1.98, 2.05, 1.76, 1.85, 1.90; bias −1.18, −1.39, +0.98, +0.29,
/// −1.11, −0.70 SE; coverage 0.955, 0.950, 0.945, 0.950, 0.950, 0.930. Seed 7: 0.99–1.03 ×,
/// IVF 1.90–2.06 ×, coverage 0.935–0.960, C_yy bias +3.3 SE (+0.22 %). With the noise
/// pooled to 96 degrees of freedom instead of 288 the spread was 1.01–1.07 × and C_yy's
/// coverage 0.927 (`tolerance::POOLED_NOISE_DOF`).
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "Monte-Carlo: run in release (`cargo test --release --all-features --test estimation ml_records::`), as CI does"
)]
fn ml_on_random_records_reaches_the_bound_and_beats_ivf() {
    let clean = random_records();
    let sx = env("BI_LX", 1.0) * common::rms(&clean, false);
    let segments = Segmentation::Welch {
        len: RANDOM_SEGMENT,
    }
    .starts(RANDOM_LEN)
    .count() as f64;
    // Hann at 50 %: neighbouring lines and segments correlate (`frf::moments`).
    let inflation = 35.0 / 18.0 + 2.0 / 12.0 * (segments - 1.0) / segments;
    let b = bound(&clean, RANDOM_SEGMENT, Window::Hann, sx, inflation);
    monte_carlo(
        &clean,
        sx,
        env("BI_TRIALS", 200.0) as usize,
        env("BI_SEED", 2024.0) as u64,
        b,
        &random_identifier(Method::Ml),
        &random_identifier(Method::Ivf),
    );
}

/// When the assumption breaks: lightly damped impacts (a tenth of the seed rig's damping,
/// ζ ≈ 0.8 %, decay time 0.7 s) that have not decayed in their 1.2 s records, rectangular
/// window, 0.1 × RMS displacement noise, 100 trials. The leakage of the cut-off responses is
/// not noise but a bias the same in every trial: the residual model counts it as noise, the
/// error bars widen, and the bias stays. Measured: C_xx +7.5 %, C_yy +12.5 % (spread 0.7 %,
/// reported σ 6.3 %: coverage 1.00 and 0.48), M −0.3/−0.7 %, K +0.1/−0.5 %. At 1.0 × RMS
/// noise the fits scatter wildly (C ± 360 %) with error bars far too narrow (M_xx coverage
/// 0.03). The test checks that the bias is there (a change that claimed to fix it should
/// replace this test).
///
/// With the exponential window that such records need (`BI_EXP=0.01`, decaying to 1 % at
/// the record's end) the bias goes (C −0.05 %, +0.11 %; M, K within 0.07 %), but the error
/// bars come out 1.3–2.3 × too narrow (coverage 0.50–0.88): the window correlates
/// neighbouring lines of a whole record, which the residual model does not account for.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "Monte-Carlo: run in release (`cargo test --release --all-features --test estimation ml_records::`), as CI does"
)]
fn undecayed_impacts_leave_a_bias_the_error_bars_do_not_cover() {
    let rig = seed_rig();
    let light = Coefficients::new(
        rig.mass().to_owned(),
        rig.damping() * faer::Scale(0.1),
        rig.stiffness().to_owned(),
    )
    .unwrap();
    // The simulator's impact campaign refuses records that do not decay: hit by hand.
    let mut sim = Simulator::new(&light, 6700.0, 8040, AntiAlias::default()).unwrap();
    let clean: Vec<Record> = (0..16)
        .map(|h| {
            let (dof, sign) = (h / 8, if h % 2 == 0 { 1.0 } else { -1.0 });
            let mut direction = vec![0.05 * sign; 2];
            direction[dof] = 1.0;
            let impact = bearing_ident::simulate::Impact {
                direction,
                peak_n: 500.0 * (1.0 + 0.02 * (h % 5) as f64),
                duration_s: 0.002,
                start_s: 0.02,
            };
            sim.record(format!("hit-{h}"), &[impact]).unwrap()
        })
        .collect();
    let sx = env("BI_LX", 0.1) * common::rms(&clean, false);
    let truth = common::diagonal(&light);
    let mut rng = StdRng::seed_from_u64(2024);
    let trials = env("BI_TRIALS", 100.0) as usize;
    let (mut est, mut sd) = (vec![[0.0; 6]; trials], vec![[0.0; 6]; trials]);
    for t in 0..trials {
        let noisy = with_noise(&clean, sx, &mut rng);
        let mut idr = impact_identifier(Estimator::PairedSets, Method::Ml);
        if env("BI_EXP", 0.0) > 0.0 {
            idr = idr.window(Window::exponential_to(env("BI_EXP", 0.0), 1.2));
        }
        let id = idr.identify(&noisy).unwrap();
        est[t] = common::diagonal(id.coefficients());
        sd[t] = common::diagonal(id.std_dev().unwrap());
    }
    let names = ["M_xx", "M_yy", "C_xx", "C_yy", "K_xx", "K_yy"];
    let mut worst_bias: f64 = 0.0;
    for i in 0..6 {
        let mean = est.iter().map(|r| r[i]).sum::<f64>() / trials as f64;
        let spread =
            (est.iter().map(|r| (r[i] - mean).powi(2)).sum::<f64>() / (trials - 1) as f64).sqrt();
        let reported = sd.iter().map(|r| r[i]).sum::<f64>() / trials as f64;
        let covered = est
            .iter()
            .zip(&sd)
            .filter(|(e, s)| (e[i] - truth[i]).abs() <= 1.96 * s[i])
            .count() as f64
            / trials as f64;
        let bias = (mean - truth[i]) / (spread / (trials as f64).sqrt());
        worst_bias = worst_bias.max(bias.abs());
        println!(
            "{}: ml {:+.2} % ± {:.2} % (reported {:.2} %), bias {:+.1} SE, coverage {:.2}",
            names[i],
            100.0 * (mean / truth[i] - 1.0),
            100.0 * spread / truth[i],
            100.0 * reported / truth[i],
            bias,
            covered
        );
    }
    assert!(worst_bias > 5.0, "{worst_bias}");
}
