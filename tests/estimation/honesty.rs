//! Quiet when right, loud when wrong, and error bars of the right size, at the settings a user
//! gets without asking (the path `identify` takes, [`Job`]):
//!
//! - the model check's false alarms on right models of two and three degrees of freedom,
//!   impacts, random and multisine forcing, 2–5 % noise (low-coherence lines included: the
//!   3-DOF system's responses fall to a third of their noise near its anti-resonances), and
//!   its power on a cubic spring fitted linearly;
//! - the stated standard deviations against the scatter of the estimates over seeds, and the
//!   95 % intervals' coverage, on periodic and random records with noise on the forces only,
//!   the responses only, and both, at 2 % and 30 %;
//! - no warning on clean records of any excitation kind.
//!
//! The Monte-Carlo tests are `#[ignore]`d and run in release by `.ci/run`
//! (`cargo test --release --all-features --test estimation -- --include-ignored honesty::`).
#![cfg(feature = "job")]

use bearing_ident::job::{Channels, Job, Options};
use bearing_ident::simulate::{ImpactTest, Setup, add_noise, seed_rig};
use bearing_ident::{Coefficients, Identification, Record};
use faer::mat;
use rand::SeedableRng;
use rand::rngs::StdRng;

/// Where the measurement noise is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Side {
    Forces,
    Responses,
    Both,
}

/// `records` with white noise of `level` × each kind's RMS on the channels of `side`.
fn noisy(records: &[Record], level: f64, side: Side, seed: u64) -> Vec<Record> {
    let mut rng = StdRng::seed_from_u64(seed ^ 0x5eed);
    records
        .iter()
        .map(|clean| {
            let noisy = add_noise(clean, level, &mut rng).unwrap();
            let (f, x) = match side {
                Side::Forces => (&noisy, clean),
                Side::Responses => (clean, &noisy),
                Side::Both => (&noisy, &noisy),
            };
            let n = clean.dofs();
            Record::new(
                clean.label(),
                clean.sample_rate(),
                (0..n).map(|c| f.force(c).to_vec()).collect(),
                (0..n).map(|c| x.displacement(c).to_vec()).collect(),
            )
            .unwrap()
        })
        .collect()
}

/// A 3-DOF bearing with natural frequencies near 70–90 Hz, cross-coupled in every block.
fn three_dof() -> Coefficients {
    Coefficients::new(
        mat![[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]],
        mat![[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
        mat![[4e5, 6e4, -1e4], [2e4, 6e5, 5e4], [-2e4, 1e4, 9e5]],
    )
    .unwrap()
}

/// The clean records of a `simulate` kind on the seed's rig, by the library's `Setup`.
fn simulated(kind: &str, seed: u64, options: &[(&str, &str)]) -> Vec<Record> {
    let mut setup = Setup::default();
    setup.set("kind", kind).unwrap();
    setup.set("seed", &seed.to_string()).unwrap();
    for (name, value) in options {
        setup.set(name, value).unwrap();
    }
    setup.run(&seed_rig()).unwrap().records
}

/// `records` identified over `band` as `identify` does, with `options` by name.
fn identify(records: Vec<Record>, band: (f64, f64), options: &[(&str, &str)]) -> Identification {
    let mut o = Options::new(band.0, band.1);
    for (name, value) in options {
        o.set(name, value).unwrap();
    }
    Job::new(o, Channels::default())
        .run_records(records)
        .unwrap()
        .identification()
        .clone()
}

fn misfit(id: &Identification) -> bool {
    id.warnings().iter().any(|w| w.kind() == "model_misfit")
}

/// One right-model case: the records of seed `s`, and the band.
type Case = (&'static str, Box<dyn Fn(u64) -> Vec<Record>>, (f64, f64));

fn right_models() -> Vec<Case> {
    let impacts = |per_direction, noise, seed| ImpactTest {
        per_direction,
        noise,
        seed,
        ..ImpactTest::seed_rig()
    };
    let three = |seed: u64, side: Side| {
        let clean = ImpactTest {
            per_direction: 6,
            sample_rate: 4096.0,
            duration_s: 2.0,
            seed,
            ..ImpactTest::seed_rig()
        }
        .run(&three_dof())
        .unwrap();
        noisy(&clean, 0.02, side, seed)
    };
    let random = |noise: f64| {
        move |s: u64| {
            let clean = simulated(
                "random",
                s,
                &[("rate", "1000"), ("duration", "60"), ("records", "4")],
            );
            noisy(&clean, noise, Side::Both, s)
        }
    };
    let multisine = |noise: f64| {
        move |s: u64| {
            noisy(
                &simulated("multisine", s, &[("periods", "16")]),
                noise,
                Side::Both,
                s,
            )
        }
    };
    vec![
        (
            "2-DOF impacts, 5 %",
            Box::new(move |s| impacts(4, 0.05, s).run(&seed_rig()).unwrap()),
            (8.0, 49.0),
        ),
        (
            "3-DOF impacts, 2 % on every channel",
            Box::new(move |s| three(s, Side::Both)),
            (20.0, 250.0),
        ),
        (
            "3-DOF impacts, 2 % on the responses",
            Box::new(move |s| three(s, Side::Responses)),
            (20.0, 250.0),
        ),
        ("2-DOF random, 2 %", Box::new(random(0.02)), (8.0, 49.0)),
        ("2-DOF random, 5 %", Box::new(random(0.05)), (8.0, 49.0)),
        (
            "2-DOF multisine, 2 %",
            Box::new(multisine(0.02)),
            (8.0, 49.0),
        ),
        (
            "2-DOF multisine, 5 %",
            Box::new(multisine(0.05)),
            (8.0, 49.0),
        ),
    ]
}

/// Right models are called misfits in at most 1 of 20 seeds over all cases together, and in
/// no case more than 2 of 20.
#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn right_models_are_rarely_called_misfits() {
    let (mut total, mut runs) = (0, 0);
    for (name, records, band) in right_models() {
        let mut flagged = Vec::new();
        let mut ratios = Vec::new();
        for seed in 1..=20 {
            let id = identify(records(seed), band, &[]);
            ratios.push(id.model_check().ratio().unwrap_or(f64::NAN));
            if misfit(&id) {
                flagged.push(seed);
            }
        }
        let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
        eprintln!(
            "{name}: model_misfit on {} of 20 seeds {flagged:?}, mean χ²/expected {mean:.3}",
            flagged.len()
        );
        assert!(flagged.len() <= 2, "{name}: {flagged:?}");
        total += flagged.len();
        runs += 20;
    }
    eprintln!("all cases: {total} of {runs}");
    assert!(20 * total <= runs, "{total} false alarms in {runs} runs");
}

/// A cubic spring (1.5·10¹¹ N/m³ on each axis) driven by random forces and fitted linearly:
/// its stiffness comes out 64 % high and more, and the model check calls it a misfit in at least 19
/// of 20 seeds.
#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn a_cubic_spring_fitted_linearly_is_a_misfit() {
    let truth = seed_rig();
    let (mut flagged, mut worst) = (0, f64::INFINITY);
    for seed in 1..=20 {
        let records = noisy(
            &simulated(
                "random",
                seed,
                &[
                    ("freqs", "8,49"),
                    ("rate", "2048"),
                    ("duration", "60"),
                    ("records", "2"),
                    ("cubic", "1.5e11,1.5e11"),
                ],
            ),
            0.02,
            Side::Both,
            seed,
        );
        let id = identify(records, (8.0, 49.0), &[]);
        let k = id.coefficients().stiffness()[(1, 1)] / truth.stiffness()[(1, 1)] - 1.0;
        eprintln!(
            "seed {seed}: K_yy {:+.0} %, χ²/expected {:.2}, misfit {}",
            100.0 * k,
            id.model_check().ratio().unwrap_or(f64::NAN),
            misfit(&id)
        );
        assert!(k > 0.3, "{k}");
        worst = worst.min(k);
        flagged += usize::from(misfit(&id));
    }
    eprintln!(
        "misfit on {flagged} of 20 seeds; K_yy at least {:+.0} %",
        100.0 * worst
    );
    assert!(flagged >= 19, "{flagged}/20");
}

/// Over the seeds of `runs`: per diagonal coefficient, the RMS of the stated standard deviations over the
/// scatter of the estimates, and the share of 95 % intervals that hold the truth.
fn interval_statistics(runs: &[Identification], truth: &Coefficients) -> (Vec<f64>, f64) {
    let n = truth.dofs();
    let t = truth.stacked();
    let entries: Vec<(usize, usize)> = (0..3)
        .flat_map(|b| (0..n).map(move |i| (b * n + i, i)))
        .collect();
    let mut covered = 0usize;
    let ratios = entries
        .iter()
        .map(|&(r, c)| {
            let errors: Vec<f64> = runs
                .iter()
                .map(|id| id.coefficients().stacked()[(r, c)] - t[(r, c)])
                .collect();
            let k = errors.len() as f64;
            let mean = errors.iter().sum::<f64>() / k;
            let scatter =
                (errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
            let stated = (runs
                .iter()
                .map(|id| id.std_dev().unwrap().stacked()[(r, c)].powi(2))
                .sum::<f64>()
                / k)
                .sqrt();
            covered += runs
                .iter()
                .zip(&errors)
                .filter(|(id, e)| e.abs() <= id.interval_95().unwrap().stacked()[(r, c)])
                .count();
            stated / scatter
        })
        .collect();
    (ratios, covered as f64 / (entries.len() * runs.len()) as f64)
}

/// Periodic and random records with noise on the forces, the responses or both, at 2 % and
/// 30 %: the stated standard deviation of each diagonal coefficient is within 0.7–1.5 × the
/// scatter over 40 seeds (the median over the six; each within 0.55–1.8, which leaves room for
/// the sampling spread of a scatter from 40 seeds, 11 %), and the 95 % intervals cover the
/// truth in 90–99 % of the cases.
///
/// Random records: the force-side noise of Welch segments cannot be told from an unmeasured
/// excitation, so with noise on the forces the load cell is declared the noisy channel
/// (`force-noise = measurement`, as a lab that knows it would); without that the force
/// noise's effect is carried, and the intervals cover (checked too).
#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn error_bars_match_the_scatter_over_seeds() {
    let truth = seed_rig();
    for kind in ["multisine", "random"] {
        for level in [0.02, 0.3] {
            for side in [Side::Forces, Side::Responses, Side::Both] {
                let options: &[(&str, &str)] = match (kind, side) {
                    ("random", Side::Forces | Side::Both) => &[("force-noise", "measurement")],
                    _ => &[],
                };
                let runs: Vec<Identification> = (1..=40)
                    .map(|seed| {
                        let clean = match kind {
                            "multisine" => simulated(kind, seed, &[("periods", "16")]),
                            _ => simulated(
                                kind,
                                seed,
                                &[("rate", "1000"), ("duration", "60"), ("records", "4")],
                            ),
                        };
                        identify(noisy(&clean, level, side, seed), (8.0, 49.0), options)
                    })
                    .collect();
                let (ratios, coverage) = interval_statistics(&runs, &truth);
                let mut sorted = ratios.clone();
                sorted.sort_by(f64::total_cmp);
                let median = 0.5 * (sorted[2] + sorted[3]);
                eprintln!(
                    "{kind}, {side:?} {level}: stated/scatter {ratios:.2?} (median {median:.2}), \
                     coverage {coverage:.3}"
                );
                assert!(
                    (0.7..=1.5).contains(&median),
                    "{kind} {side:?} {level}: {ratios:?}"
                );
                assert!(
                    ratios.iter().all(|r| (0.55..=1.8).contains(r)),
                    "{kind} {side:?} {level}: {ratios:?}"
                );
                assert!(
                    (0.90..=0.99).contains(&coverage),
                    "{kind} {side:?} {level}: {coverage}"
                );
            }
        }
    }
    // Random records, noise on the forces, nothing declared: the force-side noise is carried.
    let runs: Vec<Identification> = (1..=20)
        .map(|seed| {
            let clean = simulated(
                "random",
                seed,
                &[("rate", "1000"), ("duration", "60"), ("records", "4")],
            );
            identify(noisy(&clean, 0.3, Side::Forces, seed), (8.0, 49.0), &[])
        })
        .collect();
    let (ratios, coverage) = interval_statistics(&runs, &truth);
    eprintln!("random, forces 0.3, auto: stated/scatter {ratios:.2?}, coverage {coverage:.3}");
    assert!(coverage >= 0.95, "{coverage}");
    assert!(runs.iter().all(|id| {
        id.noise_floor().is_some_and(|n| !n.compensated())
            && id.warnings().iter().any(|w| w.kind() == "noise_bias")
    }));
}

/// Clean, well-conducted records of every excitation kind the tool simulates (2 % noise on
/// every channel; for random forcing a load cell of 0.2 %, since the force-side noise of Welch
/// segments is news when it moves H1 by more than its error bars), default settings, the
/// excitation detected: no warning at all.
#[test]
fn clean_records_of_every_kind_raise_no_warning() {
    let cases: [(&str, &[(&str, &str)]); 5] = [
        ("impact", &[("impacts", "4")]),
        (
            "random",
            &[("rate", "1000"), ("duration", "60"), ("records", "4")],
        ),
        ("multisine", &[]),
        ("stepped-sine", &[]),
        ("sweep", &[("records", "2")]),
    ];
    for (kind, options) in cases {
        for seed in [1, 2] {
            let clean = simulated(kind, seed, options);
            let records = match kind {
                "random" => {
                    let probes = noisy(&clean, 0.02, Side::Responses, seed);
                    noisy(&probes, 0.002, Side::Forces, seed + 100)
                }
                _ => noisy(&clean, 0.02, Side::Both, seed),
            };
            let id = identify(records, (8.0, 49.0), &[]);
            let kinds: Vec<&str> = id.warnings().iter().map(|w| w.kind()).collect();
            assert!(kinds.is_empty(), "{kind} seed {seed}: {:?}", id.warnings());
        }
    }
}
