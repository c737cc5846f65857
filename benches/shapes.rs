//! Criterion benches of the shapes users have, each beside its FFT-only floor measured in the
//! same run (the same FFTs through [`SpectralEstimator`] alone), with the ratio and the stage
//! timings ([`Identification::timings`](bearing_ident::Identification::timings)) printed
//! after each group.
//!
//! `cargo bench -p bearing-ident-benches --bench shapes` runs all three; `… -- three_dof` one.
//! - `seed_rig`: the seed's 16 impact records × 8040 samples, 2 DOF, 8–49 Hz, IVF, sandwich
//!   error bars (the library's defaults), for the stage timings beside the other shapes;
//! - `three_dof`: 18 impact records × 8192 samples at 4096 samples/s, 3 DOF (6 channels),
//!   20–250 Hz (461 lines), IVF with 4 iterations, without error bars and with the jackknife;
//! - `random`: 2 random-excitation records × 40 000 samples on the seed's rig, H1 with Welch
//!   segments of 4096 samples (Hann, 50 % overlap), 5–60 Hz;
//! - `random_job`: the same records as the `identify` command takes them with nothing but the
//!   band given ([`Job::run_records`]: excitation detected, Welch length chosen from a first
//!   fit), beside the FFTs of every channel at the length the job ends up using, with the
//!   job's own stages ([`Outcome::timings`](bearing_ident::job::Outcome::timings));
//! - `random_files`: the same records written as two CSV files and identified from them
//!   ([`Job::run_files`], the `identify` command's path), beside the floor of reading them (the
//!   files parsed on two threads, as the job reads them) plus those FFTs.
//!
//! Each report also prints the sum of the stages over `total` (the bookkeeping between
//! stages is the rest).

mod common;
use common::median;

use std::hint::black_box;
use std::time::Duration;

use bearing_ident::excitation::welch_len;
use bearing_ident::io::{CsvLayout, write_record};
use bearing_ident::job::{Channels, Job, Options, read_file};
use bearing_ident::model::Coefficients;
use bearing_ident::simulate::{AntiAlias, ImpactTest, Simulator, add_noise, seed_rig};
use bearing_ident::spectra::{Segmentation, SpectralEstimator, Window};
use bearing_ident::{Estimator, Identifier, Record, Screening, Uncertainty};
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use faer::{c64, mat};
use rand::SeedableRng;
use rand::rngs::StdRng;

/// A 3-DOF bearing with natural frequencies near 70–90 Hz, cross-coupled in every block.
fn three_dof_system() -> Coefficients {
    Coefficients::new(
        mat![[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]],
        mat![[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
        mat![[4e5, 6e4, -1e4], [2e4, 6e5, 5e4], [-2e4, 1e4, 9e5]],
    )
    .expect("valid system")
}

fn three_dof_records() -> Vec<Record> {
    ImpactTest {
        per_direction: 6,
        sample_rate: 4096.0,
        duration_s: 2.0,
        noise: 0.03,
        seed: 5,
        ..ImpactTest::seed_rig()
    }
    .run(&three_dof_system())
    .expect("simulated")
}

fn random_records() -> Vec<Record> {
    let mut sim =
        Simulator::new(&seed_rig(), 6700.0, 40_000, AntiAlias::default()).expect("simulator");
    let mut rng = StdRng::seed_from_u64(9);
    (0..2)
        .map(|r| {
            let clean = sim
                .random_record(format!("random-{r}"), 50.0, r)
                .expect("record");
            add_noise(&clean, 0.02, &mut rng).expect("noise")
        })
        .collect()
}

/// The FFTs of every channel of every record, segment by segment, through one planned
/// estimator: what the identification cannot go below.
fn fft_floor(est: &mut SpectralEstimator, records: &[Record], segmentation: Segmentation) -> c64 {
    let len = est.len();
    let mut acc = c64::new(0.0, 0.0);
    for r in records {
        for ch in 0..r.dofs() {
            for s in segmentation.starts(r.len()) {
                acc += est.transform_force(&r.force(ch)[s..s + len])[3];
                acc += est.transform(&r.displacement(ch)[s..s + len])[3];
            }
        }
    }
    acc
}

/// Prints the median identify time, the floor, their ratio, and the median of each stage.
fn report(name: &str, id: &Identifier, records: &[Record], floor: &mut dyn FnMut()) {
    let identify = median(RUNS, || {
        black_box(id.identify(records).expect("identifies"));
    });
    let fft = median(RUNS, floor);
    let stages: Vec<Vec<(&str, Duration)>> = (0..RUNS)
        .map(|_| {
            let t = id.identify(records).expect("identifies").timings();
            let mut row = t.stages().to_vec();
            row.push(("total", t.total));
            row
        })
        .collect();
    print_report(name, "identify", identify, "FFT floor", fft, &stages);
}

/// Repetitions behind each median of a report.
const RUNS: usize = 15;

/// Prints the median `what` time, the floor `fft`, their ratio, the median of each stage
/// (`stages`: one row per run, `total` last), `total` over `spectra` and the stages' sum over
/// `total`.
fn print_report(
    name: &str,
    what: &str,
    time: Duration,
    floor_name: &str,
    fft: Duration,
    stages: &[Vec<(&str, Duration)>],
) {
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let runs = stages.len();
    let medians: Vec<(&str, f64)> = (0..stages[0].len())
        .map(|k| {
            let mut v: Vec<Duration> = stages.iter().map(|row| row[k].1).collect();
            v.sort();
            (stages[0][k].0, ms(v[runs / 2]))
        })
        .collect();
    let stage = |name: &str| {
        medians
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(0.0, |m| m.1)
    };
    // The sum of the stages over the total, per run, its median.
    let mut covered: Vec<f64> = stages
        .iter()
        .map(|row| {
            let (total, parts) = row.split_last().expect("total last");
            parts.iter().map(|p| ms(p.1)).sum::<f64>() / ms(total.1)
        })
        .collect();
    covered.sort_by(f64::total_cmp);
    let stage_medians: Vec<String> = medians
        .iter()
        .map(|(name, ms)| format!("{name} {ms:.3}"))
        .collect();
    eprintln!(
        "{name}: {what} {:.3} ms, {floor_name} {:.3} ms, ratio {:.2}; total / spectra {:.2}; \
         stages / total {:.3}; stages (ms, medians): {}",
        ms(time),
        ms(fft),
        time.as_secs_f64() / fft.as_secs_f64(),
        stage("total") / stage("spectra"),
        covered[runs / 2],
        stage_medians.join(", ")
    );
}

fn three_dof(c: &mut Criterion) {
    let records = three_dof_records();
    let plain = Identifier::new(20.0, 250.0)
        .max_iterations(4)
        .uncertainty(Uncertainty::None);
    let jackknife = plain.clone().uncertainty(Uncertainty::Jackknife);
    let id = plain.identify(&records).expect("identifies");
    assert_eq!(id.freqs_hz().len(), 461);
    let mut est = SpectralEstimator::new(8192, 4096.0, Window::Rectangular).expect("plan");
    let mut group = c.benchmark_group("three_dof");
    group.sample_size(10);
    group.bench_function("identify", |b| {
        b.iter(|| black_box(plain.identify(&records).unwrap()))
    });
    group.bench_function("identify_jackknife", |b| {
        b.iter(|| black_box(jackknife.identify(&records).unwrap()))
    });
    group.bench_function("fft_only", |b| {
        b.iter(|| black_box(fft_floor(&mut est, &records, Segmentation::WholeRecord)))
    });
    group.finish();
    let mut floor = || {
        black_box(fft_floor(&mut est, &records, Segmentation::WholeRecord));
    };
    report("three_dof (no error bars)", &plain, &records, &mut floor);
    // The computation the speed targets were first set on, before the screening existed.
    let unscreened = plain.clone().screening(Screening::Off);
    report(
        "three_dof (no screening)",
        &unscreened,
        &records,
        &mut floor,
    );
    report("three_dof (jackknife)", &jackknife, &records, &mut floor);
}

fn random(c: &mut Criterion) {
    let records = random_records();
    let len = welch_len(40_000);
    let segmentation = Segmentation::Welch { len };
    let id = Identifier::new(5.0, 60.0)
        .estimator(Estimator::H1)
        .segmentation(segmentation)
        .window(Window::Hann);
    id.identify(&records).expect("identifies");
    let mut est = SpectralEstimator::new(len, 6700.0, Window::Hann).expect("plan");
    let mut group = c.benchmark_group("random");
    group.sample_size(10);
    group.bench_function("identify", |b| {
        b.iter(|| black_box(id.identify(&records).unwrap()))
    });
    group.bench_function("fft_only", |b| {
        b.iter(|| black_box(fft_floor(&mut est, &records, segmentation)))
    });
    group.finish();
    let mut floor = || {
        black_box(fft_floor(&mut est, &records, segmentation));
    };
    report("random (H1, Welch)", &id, &records, &mut floor);
}

fn random_job(c: &mut Criterion) {
    let records = random_records();
    let job = Job::new(Options::new(5.0, 60.0), Channels::default());
    let outcome = job.run_records(records.clone()).expect("identifies");
    let len = outcome.segment_len().expect("cut into Welch segments");
    let segmentation = Segmentation::Welch { len };
    let mut est = SpectralEstimator::new(len, 6700.0, Window::Hann).expect("plan");
    let mut group = c.benchmark_group("random_job");
    group.sample_size(10);
    group.bench_function("run_records", |b| {
        b.iter_batched(
            || records.clone(),
            |r| black_box(job.run_records(r).unwrap()),
            BatchSize::LargeInput,
        )
    });
    group.bench_function("fft_only", |b| {
        b.iter(|| black_box(fft_floor(&mut est, &records, segmentation)))
    });
    group.finish();
    let runs: Vec<_> = (0..RUNS)
        .map(|_| job.run_records(records.clone()).expect("identifies"))
        .collect();
    let mut compute: Vec<Duration> = runs.iter().map(|o| o.compute_time()).collect();
    compute.sort();
    let fft = median(RUNS, || {
        black_box(fft_floor(&mut est, &records, segmentation));
    });
    let stages: Vec<Vec<(&str, Duration)>> = runs
        .iter()
        .map(|o| {
            let t = o.timings();
            let mut row = t.stages();
            row.push(("total", t.total()));
            row
        })
        .collect();
    let name = format!(
        "random_job (auto, {len} samples per segment{})",
        if outcome.welch_choice().is_some_and(|c| c.record_limited) {
            ", record-limited"
        } else {
            ""
        }
    );
    print_report(
        &name,
        "compute",
        compute[RUNS / 2],
        "FFT floor",
        fft,
        &stages,
    );
}

fn random_files(c: &mut Criterion) {
    let records = random_records();
    let dir = tempfile::tempdir().expect("temporary directory");
    let files: Vec<std::path::PathBuf> = records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let path = dir.path().join(format!("random-{i}.csv"));
            write_record(&path, r, &CsvLayout::for_dofs(2)).expect("written");
            path
        })
        .collect();
    let job = Job::new(Options::new(5.0, 60.0), Channels::default());
    let len = job
        .run_files(&files)
        .expect("identifies")
        .segment_len()
        .expect("cut into Welch segments");
    let segmentation = Segmentation::Welch { len };
    let mut est = SpectralEstimator::new(len, 6700.0, Window::Hann).expect("plan");
    // The files parsed on two threads, as the job reads them, and the FFTs of what they hold.
    let mut floor = || {
        let read: Vec<Record> = std::thread::scope(|scope| {
            let workers: Vec<_> = files
                .iter()
                .map(|f| scope.spawn(move || read_file(f, &Channels::default()).expect("read")))
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().expect("reader"))
                .collect()
        });
        black_box(fft_floor(&mut est, &read, segmentation));
    };
    let mut group = c.benchmark_group("random_files");
    group.sample_size(10);
    group.bench_function("run_files", |b| {
        b.iter(|| black_box(job.run_files(&files).unwrap()))
    });
    group.bench_function("read_and_fft", |b| b.iter(&mut floor));
    group.finish();
    let runs: Vec<_> = (0..RUNS)
        .map(|_| {
            let start = std::time::Instant::now();
            let outcome = job.run_files(&files).expect("identifies");
            (start.elapsed(), outcome)
        })
        .collect();
    let mut wall: Vec<Duration> = runs.iter().map(|r| r.0).collect();
    wall.sort();
    let fft = median(RUNS, &mut floor);
    let stages: Vec<Vec<(&str, Duration)>> = runs
        .iter()
        .map(|(_, o)| {
            let t = o.timings();
            let mut row = t.stages();
            row.push(("total", t.total()));
            row
        })
        .collect();
    print_report(
        &format!("random_files (auto, {len} samples per segment)"),
        "run_files",
        wall[RUNS / 2],
        "read + FFT floor",
        fft,
        &stages,
    );
}

fn seed(c: &mut Criterion) {
    let records = ImpactTest {
        noise: 0.05,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .expect("simulated");
    let id = Identifier::new(8.0, 49.0);
    let mut est = SpectralEstimator::new(8040, 6700.0, Window::Rectangular).expect("plan");
    let mut group = c.benchmark_group("seed_rig");
    group.sample_size(10);
    group.bench_function("identify", |b| {
        b.iter(|| black_box(id.identify(&records).unwrap()))
    });
    group.bench_function("fft_only", |b| {
        b.iter(|| black_box(fft_floor(&mut est, &records, Segmentation::WholeRecord)))
    });
    group.finish();
    let mut floor = || {
        black_box(fft_floor(&mut est, &records, Segmentation::WholeRecord));
    };
    report("seed_rig (sandwich)", &id, &records, &mut floor);
}

criterion_group!(benches, seed, three_dof, random, random_job, random_files);
criterion_main!(benches);
