//! The cross-spectral estimators H1, H2 and Hv on simulated random-excitation records, each
//! under the noise it is meant for; plus periodic (multisine) excitation over whole periods,
//! the force gate, per-frequency coefficients and record screening.

use crate::common;
use bearing_ident::Choice;

use bearing_ident::frf::{Assignment, Band, ForceNoise, FrfBuilder};
use bearing_ident::per_frequency::PerFrequency;
use bearing_ident::records::Record;
use bearing_ident::simulate::{AntiAlias, Simulator, seed_rig};
use bearing_ident::{Coefficients, Estimator, Identification, Identifier, Segmentation, Window};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

/// `record` with white noise of `level_f` × the pooled force RMS on the forces and `level_x` ×
/// the pooled displacement RMS on the displacements.
fn noisy(record: &Record, level_f: f64, level_x: f64, seed: u64) -> Record {
    let mut rng = StdRng::seed_from_u64(seed);
    let n = record.dofs();
    let rms = |chs: Vec<&[f64]>| {
        let total: f64 = chs.iter().flat_map(|c| c.iter()).map(|v| v * v).sum();
        (total / (n * record.len()) as f64).sqrt()
    };
    let sf = level_f * rms((0..n).map(|c| record.force(c)).collect());
    let sx = level_x * rms((0..n).map(|c| record.displacement(c)).collect());
    let mut add = |ch: &[f64], s: f64| -> Vec<f64> {
        if s == 0.0 {
            return ch.to_vec();
        }
        let d = Normal::new(0.0, s).unwrap();
        ch.iter().map(|v| v + d.sample(&mut rng)).collect()
    };
    let forces = (0..n).map(|c| add(record.force(c), sf)).collect();
    let disps = (0..n).map(|c| add(record.displacement(c), sx)).collect();
    Record::new(record.label(), record.sample_rate(), forces, disps).unwrap()
}

/// One 60 s record of the seed rig under independent random forces on both axes, 1000 S/s.
fn random_record() -> Record {
    let mut sim = Simulator::new(&seed_rig(), 1000.0, 240_000, AntiAlias::default()).unwrap();
    sim.random_record("shaker", 20.0, 11).unwrap()
}

fn diag_errors(got: &Coefficients, truth: &Coefficients) -> [f64; 6] {
    let (g, t) = (common::blocks(got), common::blocks(truth));
    let mut out = [0.0; 6];
    for b in 0..3 {
        for i in 0..2 {
            out[2 * b + i] = g[b][(i, i)] / t[b][(i, i)] - 1.0;
        }
    }
    out
}

/// The estimator alone: its FRF (no noise compensation) fitted as a ready-made FRF.
fn identify(record: &Record, estimator: Estimator) -> Coefficients {
    let mut builder = FrfBuilder::new(
        estimator,
        Band::new(8.0, 49.0).unwrap(),
        Segmentation::Welch { len: 8000 },
        Window::Hann,
    );
    builder.push(record).unwrap();
    let frf = builder.finish(&Assignment::DominantForce).unwrap();
    Identifier::new(8.0, 49.0)
        .identify_frf(frf)
        .unwrap()
        .coefficients()
        .clone()
}

/// The identification of the records by H1, the segments' force-side noise taken for what
/// `force_noise` says.
fn identified(record: &Record, force_noise: ForceNoise) -> Identification {
    Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Welch { len: 8000 })
        .window(Window::Hann)
        .force_noise(force_noise)
        .identify(std::slice::from_ref(record))
        .unwrap()
}

/// Errors (relative, diagonal M, C, K) measured on one seed, 240 s at 1000 S/s, Welch 8000
/// samples (0.125 Hz) with Hann, band 8–49 Hz, IVF; in %:
///
/// | noise (force, disp) | H1                          | H2                          | Hv                         |
/// |---------------------|-----------------------------|-----------------------------|----------------------------|
/// | 0, 0                | −0.01 −0.01 +0.11 +0.07 …   | −0.02 −0.02 +0.04 +0.03 …   | −0.01 −0.02 +0.07 +0.04 …  |
/// | 0.3, 0              | +4.29 +4.28 +5.13 +3.30 +4.20 +4.18 | +0.09 −0.00 +0.74 −0.85 +0.00 −0.13 | +2.15 … |
/// | 0, 0.3              | +0.28 −0.09 +0.08 +0.15 +0.28 −0.08 | −4.52 −4.57 −0.47 −1.26 −4.16 −4.34 | −2.01 … |
/// | 0.3, 0.3            | +4.42 +4.28 … +4.35 +4.13   | −4.42 −4.67 … −4.16 −4.59   | +0.04 −0.21 +2.60 +0.56 +0.13 −0.25 |
///
/// Force noise of 0.3 × the force RMS is white to Nyquist (500 Hz) while the force itself is
/// filtered at 250 Hz, so per line it is 0.3² × 500/250 ≈ 4.5 % of the force power: H1's
/// predicted bias on `M` and `K` is +4.5 %, as measured. Hv scales each output to the forces'
/// power, which matches equal noise-to-signal ratios on the two sides.
#[test]
fn each_estimator_is_unbiased_under_its_noise() {
    let truth = seed_rig();
    let clean = random_record();
    let errors = |lf: f64, lx: f64, e: Estimator| {
        diag_errors(&identify(&noisy(&clean, lf, lx, 5), e), &truth)
    };
    // M and K entries of the diagonal error vector (C is noisier and less affected).
    let mk = |e: [f64; 6]| [e[0], e[1], e[4], e[5]];
    for e in [Estimator::H1, Estimator::H2, Estimator::Hv] {
        let err = errors(0.0, 0.0, e);
        assert!(err.iter().all(|v| v.abs() < 2e-3), "{}: {err:?}", e.name());
    }
    // Force noise: H1 biased high as predicted, H2 unbiased.
    assert!(
        mk(errors(0.3, 0.0, Estimator::H1))
            .iter()
            .all(|&v| (0.03..0.06).contains(&v))
    );
    let h2 = errors(0.3, 0.0, Estimator::H2);
    assert!(mk(h2).iter().all(|v| v.abs() < 5e-3), "{h2:?}");
    // Displacement noise: H1 unbiased, H2 biased low.
    let h1 = errors(0.0, 0.3, Estimator::H1);
    assert!(mk(h1).iter().all(|v| v.abs() < 5e-3), "{h1:?}");
    assert!(
        mk(errors(0.0, 0.3, Estimator::H2))
            .iter()
            .all(|&v| (-0.06..-0.03).contains(&v))
    );
    // Both: Hv nearly unbiased while H1 and H2 are off by more than 3 % either way.
    let hv = errors(0.3, 0.3, Estimator::Hv);
    assert!(mk(hv).iter().all(|v| v.abs() < 5e-3), "{hv:?}");
    assert!(
        mk(errors(0.3, 0.3, Estimator::H1))
            .iter()
            .all(|&v| v > 0.03)
    );
    assert!(
        mk(errors(0.3, 0.3, Estimator::H2))
            .iter()
            .all(|&v| v < -0.03)
    );
    // Told that the force-side noise is the load cell's, the identification compensates H1
    // for what the segments show: unbiased under force noise, response noise and both.
    for (lf, lx) in [(0.3, 0.0), (0.0, 0.3), (0.3, 0.3)] {
        let id = identified(&noisy(&clean, lf, lx, 5), ForceNoise::Measurement);
        let err = diag_errors(id.coefficients(), &truth);
        eprintln!("compensated H1, noise ({lf}, {lx}): {err:+.4?}");
        assert!(
            mk(err).iter().all(|v| v.abs() < 5e-3),
            "({lf}, {lx}): {err:?}"
        );
    }
    // By default it does not (the segments cannot tell the load cell's noise from an
    // unmeasured excitation): H1 as it is, what compensation would change carried in the
    // error bars, which cover the bias.
    let id = identified(&noisy(&clean, 0.3, 0.0, 5), ForceNoise::Auto);
    assert!(!id.noise_floor().unwrap().compensated());
    let (k, sd) = (
        id.coefficients().stiffness(),
        id.std_dev().unwrap().stiffness(),
    );
    for i in 0..2 {
        let t = truth.stiffness()[(i, i)];
        assert!(k[(i, i)] / t - 1.0 > 0.03, "{}", k[(i, i)]);
        assert!(
            (k[(i, i)] - t).abs() < 1.96 * sd[(i, i)],
            "{} ± {}",
            k[(i, i)],
            sd[(i, i)]
        );
    }
    assert!(id.warnings().iter().any(|w| w.kind() == "noise_bias"));
}

/// Per-frequency `K(ω)`, `C(ω)` under displacement noise (H1, unbiased): the error bars from
/// the FRF variance cover the constant truth on about 95 % of the lines, and are not inflated
/// (the median of |error|/σ of a normal variable is 0.674).
///
/// Measured (329 lines × 4 elements): K within 1.96σ on 95.2 %, C on 94.5 %; median |z|
/// 0.70 (K) and 0.65 (C). With the fitted `M` instead of the true one, K covers 90.5 %
/// (median |z| 0.78): `M`'s own error, reported with `M`, shifts all lines together.
#[test]
fn per_frequency_error_bars_cover_the_truth() {
    let truth = seed_rig();
    let record = noisy(&random_record(), 0.0, 0.3, 6);
    let id = Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Welch { len: 8000 })
        .window(Window::Hann)
        .identify(std::slice::from_ref(&record))
        .unwrap();
    // With the true M the check isolates the FRF variance; with the fitted M (what
    // `Identification::per_frequency` uses) every line's K(ω) also moves by ω² δM together.
    let pf = PerFrequency::new(id.frf(), truth.mass(), 0.0).unwrap();
    let fitted = id.per_frequency().unwrap();
    assert_eq!(fitted.freqs_hz(), pf.freqs_hz());
    coverage_of_error_bars(&pf, &truth, (0.90, 0.99));
}

/// The per-line error bars of `pf` against the constant truth: the fraction of line-elements
/// within 1.96σ lies in `range`, and the median |error|/σ is that of a normal variable
/// (0.674) within 0.55–0.80.
fn coverage_of_error_bars(pf: &PerFrequency, truth: &Coefficients, range: (f64, f64)) {
    let mut z = [Vec::new(), Vec::new()];
    for k in 0..pf.freqs_hz().len() {
        let (ks, cs) = (pf.stiffness_std(k).unwrap(), pf.damping_std(k).unwrap());
        for i in 0..2 {
            for j in 0..2 {
                z[0].push((pf.stiffness(k)[(i, j)] - truth.stiffness()[(i, j)]) / ks[(i, j)]);
                z[1].push((pf.damping(k)[(i, j)] - truth.damping()[(i, j)]) / cs[(i, j)]);
            }
        }
    }
    for (name, z) in ["K", "C"].iter().zip(&mut z) {
        let covered = z.iter().filter(|v| v.abs() <= 1.96).count() as f64 / z.len() as f64;
        z.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
        let median = z[z.len() / 2].abs();
        println!(
            "{name}: covered {covered:.3} of {}, median |z| {median:.3}",
            z.len()
        );
        assert!((range.0..=range.1).contains(&covered), "{name}: {covered}");
        assert!((0.55..=0.80).contains(&median), "{name}: {median}");
    }
}

/// Per-frequency error bars of paired sets come from the scatter of the per-set impedances
/// (8 sets: Student-t(7) tails make 1.96σ cover about 91 %, not 95 %). Measured (noise 0.5,
/// 49 lines × 4 elements): K covered 0.918 with median |z| 0.71, C 0.918 with median 0.75.
#[test]
fn per_frequency_error_bars_of_paired_sets() {
    use bearing_ident::simulate::{ImpactTest, add_noise};
    let truth = seed_rig();
    let mut rng = StdRng::seed_from_u64(17);
    let records: Vec<Record> = ImpactTest::seed_rig()
        .run_clean(&truth)
        .unwrap()
        .iter()
        .map(|r| add_noise(r, 0.5, &mut rng).unwrap())
        .collect();
    let id = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    let pf = PerFrequency::new(id.frf(), truth.mass(), 0.0).unwrap();
    coverage_of_error_bars(&pf, &truth, (0.85, 0.99));
}

/// Multisine excitation over whole periods: one record per direction, 2 s settled then 8
/// periods of 2 s at 1000 S/s (0.5 Hz grid), lines 8–49 Hz excited; band 5–60 Hz asked for.
/// `Segmentation::Periods` averages the periods and leaves out the 28 band lines the
/// multisine does not drive. Measured (5 % noise): largest diagonal error 0.06 % (M), 0.3 %
/// (C), 0.05 % (K); noise-free below 1e-7.
#[test]
fn multisine_over_whole_periods_uses_the_excited_lines_only() {
    use bearing_ident::simulate::{add_noise, multisine};
    let truth = seed_rig();
    let (period, settle, periods) = (2000, 2000, 8);
    let total = settle + periods * period;
    let mut sim = Simulator::new(&truth, 1000.0, total, AntiAlias::default()).unwrap();
    let records: Vec<Record> = (0..2)
        .map(|d| {
            let drive = multisine(period, 16..=98, 30.0, total, 40 + d as u64).unwrap();
            let mut forces = vec![vec![0.0; total]; 2];
            forces[d] = drive;
            sim.held_record(format!("multisine-{d}"), &forces)
                .unwrap()
                .trimmed(settle..total)
                .unwrap()
        })
        .collect();
    let identifier = Identifier::new(5.0, 60.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Periods { len: period });
    let clean = identifier.identify(&records).unwrap();
    assert_eq!(clean.frf().unexcited_hz().len(), 28);
    assert_eq!(clean.freqs_hz().len(), 83);
    assert_eq!(clean.frf().averages(), 16);
    assert!(common::block_relative_error(clean.coefficients(), &truth) < common::EXACT);

    let mut rng = StdRng::seed_from_u64(3);
    let noisy: Vec<Record> = records
        .iter()
        .map(|r| add_noise(r, 0.05, &mut rng).unwrap())
        .collect();
    let id = identifier.identify(&noisy).unwrap();
    let err = diag_errors(id.coefficients(), &truth);
    println!("multisine 5 %: {err:?}");
    assert!(err.iter().all(|v| v.abs() < 5e-3), "{err:?}");
    assert_eq!(id.frf().unexcited_hz().len(), 28);
}

/// Impacts with noise on the force channel only: after the 2 ms pulse the force record holds
/// nothing but noise, which the gate (open 30 ms, 5 ms taper, 235 of 8040 samples) keeps out
/// of the spectra. The per-line impedance error then falls by about √(8040/235) ≈ 5.8.
///
/// Measured (noise 1.0 × the force RMS, 8 hits per direction, seed 5000): RMS relative
/// impedance error over the 49 lines and 4 elements 0.088 → 0.015 (6.0×). The fitted coefficients gain much
/// less (IVF worst diagonal 2.3 % either way): the noise left inside the short gate has a
/// spectrum smooth over ~1/35 ms ≈ 28 Hz, so its errors are correlated across the band and do
/// not average out over lines, while white noise over the whole record does. The gate is worth
/// most for per-line results (coherence, `K(ω)`, `C(ω)`) and for long, ringing records.
#[test]
fn force_gate_removes_the_quiet_force_noise() {
    use bearing_ident::simulate::ImpactTest;
    use bearing_ident::spectra::ForceGate;
    let truth = seed_rig();
    let clean = ImpactTest::seed_rig().run_clean(&truth).unwrap();
    let records: Vec<Record> = clean
        .iter()
        .enumerate()
        .map(|(k, r)| noisy(r, 1.0, 0.0, 5000 + k as u64))
        .collect();
    let rms_error = |id: &bearing_ident::Identification| {
        let frf = id.frf();
        let mut e = 0.0;
        for k in 0..frf.line_count() {
            let (h, m) = (truth.impedance_at(frf.freqs_hz()[k]), frf.impedance(k));
            for i in 0..2 {
                for j in 0..2 {
                    e += (m[(i, j)] - h[(i, j)]).norm_sqr() / h[(i, i)].norm_sqr();
                }
            }
        }
        (e / (4 * frf.line_count()) as f64).sqrt()
    };
    let gate = ForceGate::new(0.03, 0.005).unwrap();
    let plain = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    let gated = Identifier::new(8.0, 49.0)
        .force_gate(gate)
        .identify(&records)
        .unwrap();
    let (a, b) = (rms_error(&plain), rms_error(&gated));
    println!("RMS impedance error: rectangular {a:.4}, gated {b:.4}");
    assert!(b < a / 4.0, "{a} {b}");
    let worst = diag_errors(gated.coefficients(), &truth)
        .iter()
        .fold(0.0_f64, |a, v| a.max(v.abs()));
    assert!(worst < 0.03, "{worst}");
    // Noise-free, the gate changes nothing: the force is zero where it closes.
    let exact = Identifier::new(8.0, 49.0)
        .force_gate(gate)
        .identify(&clean)
        .unwrap();
    assert!(common::block_relative_error(exact.coefficients(), &truth) < common::EXACT);
}

/// Screening: a double hit is reported and kept under `Warn`, left out under `Reject`.
#[test]
fn screening_warns_or_rejects_a_double_hit() {
    use bearing_ident::Screening;
    use bearing_ident::quality::ImpactChecks;
    use bearing_ident::simulate::{Impact, ImpactTest};
    let truth = seed_rig();
    let test = ImpactTest {
        per_direction: 3,
        ..ImpactTest::seed_rig()
    };
    let mut records = test.run_clean(&truth).unwrap();
    let mut sim = Simulator::new(&truth, 6700.0, 8040, AntiAlias::default()).unwrap();
    let hit = |start_s: f64, peak_n: f64| Impact {
        direction: vec![1.0, 0.0],
        peak_n,
        duration_s: 0.002,
        start_s,
    };
    records[0] = sim
        .record("bounced", &[hit(0.02, 500.0), hit(0.05, 150.0)])
        .unwrap();
    let checks = ImpactChecks::default();
    let warned = Identifier::new(8.0, 49.0)
        .screening(Screening::Warn(checks.into()))
        .identify(&records)
        .unwrap();
    let text: Vec<String> = warned.warnings().iter().map(|w| w.to_string()).collect();
    assert!(
        text.iter()
            .any(|w| w.contains("`bounced`") && w.contains("double hit")),
        "{text:?}"
    );
    assert_eq!(warned.excitations().len(), 6);
    // A double hit is still a valid excitation: the result stays exact.
    assert!(common::block_relative_error(warned.coefficients(), &truth) < common::EXACT);
    let rejected = Identifier::new(8.0, 49.0)
        .screening(Screening::Reject(checks.into()))
        .identify(&records)
        .unwrap();
    assert_eq!(rejected.excitations().len(), 5);
    let text: Vec<String> = rejected.warnings().iter().map(|w| w.to_string()).collect();
    assert!(
        text.iter().any(|w| w.contains("`bounced` rejected")),
        "{text:?}"
    );
}
