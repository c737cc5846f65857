//! Impact quality checks on simulated records: clean hits pass, double hits and clipping are
//! found where they were put, random forcing is not mistaken for a double hit.
//!
//! The references are the simulation's own inputs (pulse times and peaks, the saturation level
//! applied) and plain counts over the unclipped samples.

use bearing_ident::quality::{ImpactChecks, ImpactIssue, check_record};
use bearing_ident::simulate::{AntiAlias, Impact, ImpactTest, Simulator, add_noise, seed_rig};
use bearing_ident::{Channel, Record};
use rand::SeedableRng;
use rand::rngs::StdRng;

const FS: f64 = 6700.0;
const SAMPLES: usize = 8040;
const PULSE_S: f64 = 0.002;

fn hit(dof: usize, peak_n: f64, start_s: f64) -> Impact {
    let mut direction = vec![0.0, 0.0];
    direction[dof] = 1.0;
    direction[1 - dof] = 0.05;
    Impact {
        direction,
        peak_n,
        duration_s: PULSE_S,
        start_s,
    }
}

fn simulate(impacts: &[Impact]) -> Record {
    Simulator::new(&seed_rig(), FS, SAMPLES, AntiAlias::default())
        .unwrap()
        .record("sim", impacts)
        .unwrap()
}

fn noisy(record: &Record, level: f64, seed: u64) -> Record {
    add_noise(record, level, &mut StdRng::seed_from_u64(seed)).unwrap()
}

/// Longest run of consecutive samples meeting `cond`, and the index where it starts.
fn longest_run(x: &[f64], cond: impl Fn(f64) -> bool) -> (usize, usize) {
    let (mut best, mut best_start, mut cur) = (0, 0, 0);
    for (i, &v) in x.iter().enumerate() {
        cur = if cond(v) { cur + 1 } else { 0 };
        if cur > best {
            (best, best_start) = (cur, i + 1 - cur);
        }
    }
    (best, best_start)
}

fn replace_channel(record: &Record, channel: Channel, samples: Vec<f64>) -> Record {
    let n = record.dofs();
    let mut forces: Vec<Vec<f64>> = (0..n).map(|c| record.force(c).to_vec()).collect();
    let mut displacements: Vec<Vec<f64>> =
        (0..n).map(|c| record.displacement(c).to_vec()).collect();
    match channel {
        Channel::Force(c) => forces[c] = samples,
        Channel::Displacement(c) => displacements[c] = samples,
    }
    Record::new(record.label(), record.sample_rate(), forces, displacements).unwrap()
}

#[test]
fn clean_impacts_have_no_issue() {
    let checks = ImpactChecks::default();
    let clean = ImpactTest::seed_rig().run_clean(&seed_rig()).unwrap();
    assert_eq!(clean.len(), 16);
    for r in &clean {
        assert_eq!(check_record(r, &checks), vec![], "{}", r.label());
    }
    // Without the anti-alias filter the force is exactly zero outside the pulse: zero is the
    // channel's minimum for thousands of samples, and it is the resting level, not clipping.
    let raw = ImpactTest {
        anti_alias: AntiAlias::None,
        per_direction: 2,
        ..ImpactTest::seed_rig()
    }
    .run_clean(&seed_rig())
    .unwrap();
    for r in &raw {
        let f = r.force(r.dominant_force());
        let f_min = f.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(f_min.abs() < 1e-300, "minimum {f_min}");
        assert_eq!(check_record(r, &checks), vec![], "{}", r.label());
    }
}

#[test]
fn clean_impacts_with_five_percent_noise_have_no_issue() {
    let checks = ImpactChecks::default();
    for seed in 1..=4 {
        let records = ImpactTest {
            noise: 0.05,
            seed,
            ..ImpactTest::seed_rig()
        }
        .run(&seed_rig())
        .unwrap();
        for r in &records {
            assert_eq!(
                check_record(r, &checks),
                vec![],
                "seed {seed}, {}",
                r.label()
            );
        }
    }
}

#[test]
fn heavy_noise_is_not_a_double_hit() {
    // Noise 2.5 × the force RMS (pooled over both force channels), σ ≈ 25 N or 5 % of the
    // peak: about a hundred noise samples per record exceed 10 % of the peak, so the ratio
    // alone would report a double hit on every record; the MAD noise floor must not.
    let clean = simulate(&[hit(0, 500.0, 0.02)]);
    for seed in 1..=4 {
        let r = noisy(&clean, 2.5, seed);
        let f = r.force(0);
        let later_spikes = f[200..].iter().filter(|&&v| v > 50.0).count();
        assert!(later_spikes > 50, "seed {seed}: {later_spikes} spikes");
        assert_eq!(
            check_record(&r, &ImpactChecks::default()),
            vec![],
            "seed {seed}"
        );
    }
}

#[test]
fn double_hit_is_found_where_it_was_put() {
    let checks = ImpactChecks::default();
    for dof in 0..2 {
        let clean = simulate(&[hit(dof, 500.0, 0.02), hit(dof, 150.0, 0.05)]);
        let cases = [(clean.clone(), "clean")]
            .into_iter()
            .chain((1..=3).map(|s| (noisy(&clean, 0.05, s), "noisy")));
        for (r, what) in cases {
            let issues = check_record(&r, &checks);
            let [
                ImpactIssue::DoubleHit {
                    channel,
                    first_s,
                    second_s,
                    ratio,
                },
            ] = issues[..]
            else {
                panic!("dof {dof}, {what}: {issues:?}");
            };
            assert_eq!(channel, dof);
            // Peaks at mid-pulse: 21 ms and 51 ms.
            assert!((first_s - 0.021).abs() < PULSE_S, "{first_s}");
            assert!((second_s - 0.051).abs() < PULSE_S, "{second_s}");
            assert!((ratio - 0.3).abs() < 0.05, "{ratio}");
        }
    }
}

#[test]
fn double_hit_before_the_main_hit_is_found() {
    // A light touch 30 ms before the real hit.
    let r = simulate(&[hit(1, 200.0, 0.02), hit(1, 500.0, 0.05)]);
    let issues = check_record(&r, &ImpactChecks::default());
    assert!(
        matches!(
            issues[..],
            [ImpactIssue::DoubleHit { channel: 1, first_s, second_s, ratio }]
                if (first_s - 0.051).abs() < PULSE_S
                    && (second_s - 0.021).abs() < PULSE_S
                    && (ratio - 0.4).abs() < 0.05
        ),
        "{issues:?}"
    );
}

#[test]
fn clipped_force_channel_is_named() {
    let clean = simulate(&[hit(0, 500.0, 0.02)]);
    let f = clean.force(0);
    let peak = f.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let limit = 0.7 * peak;
    let r = replace_channel(
        &clean,
        Channel::Force(0),
        f.iter().map(|v| v.min(limit)).collect(),
    );
    let (run, start) = longest_run(f, |v| v >= limit);
    assert!(run >= 3, "{run}");
    let issues = check_record(&r, &ImpactChecks::default());
    assert_eq!(
        issues,
        vec![ImpactIssue::Clipped {
            channel: Channel::Force(0),
            value: limit,
            run,
            at_s: start as f64 / FS,
        }]
    );
}

#[test]
fn clipped_displacement_channel_is_named() {
    // A y hit, its displacement saturating on the negative side at 70 % of the largest swing.
    let clean = simulate(&[hit(1, 500.0, 0.02)]);
    let x = clean.displacement(1);
    let trough = x.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(trough < 0.0);
    let limit = 0.7 * trough;
    let r = replace_channel(
        &clean,
        Channel::Displacement(1),
        x.iter().map(|v| v.max(limit)).collect(),
    );
    let (run, start) = longest_run(x, |v| v <= limit);
    assert!(run >= 3, "{run}");
    let issues = check_record(&r, &ImpactChecks::default());
    assert_eq!(
        issues,
        vec![ImpactIssue::Clipped {
            channel: Channel::Displacement(1),
            value: limit,
            run,
            at_s: start as f64 / FS,
        }]
    );
}

#[test]
fn random_forcing_is_not_a_double_hit() {
    let mut sim = Simulator::new(&seed_rig(), FS, SAMPLES, AntiAlias::default()).unwrap();
    for seed in 1..=3 {
        let r = sim.random_record("shaker", 20.0, seed).unwrap();
        let f = r.force(r.dominant_force());
        let mean = f.iter().sum::<f64>() / f.len() as f64;
        let peak = f.iter().map(|v| (v - mean).abs()).fold(0.0, f64::max);
        let rms = (f.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / f.len() as f64).sqrt();
        assert!(peak / rms < 8.0, "crest factor {}", peak / rms);
        assert_eq!(
            check_record(&r, &ImpactChecks::default()),
            vec![],
            "seed {seed}"
        );
    }
}

#[test]
fn million_sample_record_is_checked_exactly() {
    // 10⁶ samples at 10 kHz: a hit at 10 s, a bounce at 60 s with 25 % of its force, and a
    // displacement held at its maximum for 7 samples at 20 s.
    const N: usize = 1_000_000;
    let fs = 10_000.0;
    let mut f = vec![0.0; N];
    for (k, w) in [0.5, 1.0, 0.5].into_iter().enumerate() {
        f[100_000 + k - 1] = 400.0 * w;
        f[600_000 + k - 1] = 100.0 * w;
    }
    let mut x: Vec<f64> = (0..N).map(|m| 1e-5 * (0.001 * m as f64).sin()).collect();
    for v in &mut x[200_000..200_007] {
        *v = 2e-5;
    }
    let r = Record::new("long", fs, vec![f], vec![x]).unwrap();
    let t = std::time::Instant::now();
    let issues = check_record(&r, &ImpactChecks::default());
    eprintln!("check_record on 10⁶ samples: {:?}", t.elapsed());
    assert_eq!(
        issues,
        vec![
            ImpactIssue::DoubleHit {
                channel: 0,
                first_s: 10.0,
                second_s: 60.0,
                ratio: 0.25
            },
            ImpactIssue::Clipped {
                channel: Channel::Displacement(0),
                value: 2e-5,
                run: 7,
                at_s: 20.0
            },
        ]
    );
}
