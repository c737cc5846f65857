//! Criterion benches of every stage, grouped over sizes, setup outside the timed closures.
//!
//! `cargo bench -p bearing-ident-benches --bench identify` runs every group; `… -- ivf_iteration`
//! picks one. Groups:
//! - `spectra`: one channel through the planned estimator, 2¹⁰ … 2²⁰ samples;
//! - `frf`: impedance/flexibility assembly on the seed's rig (paired sets and H1), from
//!   records (FFTs included) and from gathered spectra (`finish` only);
//! - `ivf_iteration`, `ivf_solve`: one allocation-free IVF iteration and a whole IVF fit, for
//!   n ∈ {2, 4, 8, 16, 32} and N ∈ {50, 500, 5000} lines;
//! - `matmul`: faer's dense `Wᵀ A` product on the IVF shapes of n = 16, 32, the reference for
//!   the IVF iteration's GFLOP/s (the IVF counts the flops it performs, `ivf_flops`);
//! - `seed_rig`: end to end (16 impact records of 8040 samples, 2 DOF, 8–49 Hz, IVF) beside
//!   the FFTs of all its channels alone, the floor;
//! - `batch`: one record set, and 8 sets through `identify_batch` (compare with and without
//!   `--features rayon`);
//! - `csv`: parsing throughput of a record file;
//! - `conditioning`: condition numbers of 2766 complex n × n matrices (the paired-set force
//!   matrices of a 3-DOF impact test: 6 sets × 461 lines), one at a time and four per SIMD
//!   register (`Conditioner::condition_numbers`), n ∈ {3, 4, 6}.

#[path = "../tests/common/mod.rs"]
mod common;

// The crate's private dense kernels, compiled into the bench (they use only faer).
#[path = "../src/linalg/mod.rs"]
#[allow(dead_code, unused_imports)]
mod linalg;

use std::hint::black_box;

use bearing_ident::frf::{Assignment, Band, Estimator, Frf, FrfBuilder};
use bearing_ident::io::{CsvLayout, read_record, write_record};
use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::solve::{self, IvfOptions, IvfSolver, Method};
use bearing_ident::spectra::{Segmentation, SpectralEstimator, Window};
use bearing_ident::{Identifier, Record};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par, c64};

fn spectra(c: &mut Criterion) {
    let mut group = c.benchmark_group("spectra");
    for p in [10, 12, 14, 16, 18, 20] {
        let len = 1usize << p;
        let signal: Vec<f64> = (0..len)
            .map(|m| ((m * 7919) % 1000) as f64 * 1e-3)
            .collect();
        let mut est = SpectralEstimator::new(len, 1.0e4, Window::Rectangular).expect("valid plan");
        group.throughput(Throughput::Elements(len as u64));
        group.bench_with_input(BenchmarkId::from_parameter(len), &signal, |b, s| {
            b.iter(|| black_box(est.transform(s)[1]))
        });
    }
    group.finish();
}

fn seed_records() -> Vec<Record> {
    ImpactTest {
        noise: 0.05,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap()
}

fn frf(c: &mut Criterion) {
    let records = seed_records();
    let band = Band::new(8.0, 49.0).unwrap();
    let mut group = c.benchmark_group("frf");
    for (name, estimator, window) in [
        ("paired", Estimator::PairedSets, Window::Rectangular),
        ("h1", Estimator::H1, Window::Rectangular),
        ("h2", Estimator::H2, Window::Rectangular),
        ("hv", Estimator::Hv, Window::Rectangular),
    ] {
        let new = || FrfBuilder::new(estimator, band, Segmentation::WholeRecord, window);
        group.bench_function(format!("{name}_from_records"), |b| {
            b.iter(|| {
                let mut builder = new();
                builder.push_all(&records).unwrap();
                black_box(builder.finish(&Assignment::DominantForce).unwrap())
            })
        });
        let mut filled = new();
        filled.push_all(&records).unwrap();
        group.bench_function(format!("{name}_finish"), |b| {
            b.iter(|| black_box(filled.finish(&Assignment::DominantForce).unwrap()))
        });
    }
    group.finish();
}

fn synthetic_frf(n: usize, lines: usize) -> Frf {
    common::perturbed_frf(n, lines, 0.01)
}

/// `(n, N)`. At n = 32, 50 lines are too few for the 96 unknowns per column
/// (`solve::required_lines(32)` = 51), so that size is left out.
const SIZES: [(usize, usize); 14] = [
    (2, 50),
    (2, 500),
    (2, 5000),
    (4, 50),
    (4, 500),
    (4, 5000),
    (8, 50),
    (8, 500),
    (8, 5000),
    (16, 50),
    (16, 500),
    (16, 5000),
    (32, 500),
    (32, 5000),
];

/// Real flops of one IVF iteration as `IvfSolver::iterate` performs them (a complex
/// multiply-add counted as 8 real flops). Per line: the model impedance inverted (`8n³`,
/// Gauss–Jordan), `(G_mᴴ G)ᵀ` (`8n³`), the eight weighted `n × n` sums (`16n²`),
/// `(G H(Θ))ᵀ` for the residual (`8n³`), the two impedances and the residual's norm (`10n²`);
/// per iteration: the `3n × 3n` LU (`18n³`) and its solve for `n` columns (`18n³`). The
/// matmul reference counts its `2 · (3n)² · 2nN = 36n³N`.
fn ivf_flops(n: usize, lines: usize) -> u64 {
    ((24 * n * n * n + 26 * n * n) * lines + 36 * n * n * n) as u64
}

fn ivf_iteration(c: &mut Criterion) {
    let mut group = c.benchmark_group("ivf_iteration");
    group.sample_size(10);
    for (n, lines) in SIZES {
        let frf = synthetic_frf(n, lines);
        let mut solver = IvfSolver::new(&frf, IvfOptions::default()).unwrap();
        group.throughput(Throughput::Elements(ivf_flops(n, lines)));
        group.bench_function(BenchmarkId::new(format!("n{n}"), lines), |b| {
            b.iter(|| black_box(solver.iterate()))
        });
    }
    group.finish();
}

fn ivf_solve(c: &mut Criterion) {
    let mut group = c.benchmark_group("ivf_solve");
    group.sample_size(10);
    for (n, lines) in SIZES {
        let frf = synthetic_frf(n, lines);
        group.bench_function(BenchmarkId::new(format!("n{n}"), lines), |b| {
            b.iter(|| black_box(solve::fit(&frf, Method::Ivf, &IvfOptions::default()).unwrap()))
        });
    }
    group.finish();
}

fn matmul_reference(c: &mut Criterion) {
    let mut group = c.benchmark_group("matmul");
    group.sample_size(10);
    for (n, lines) in [(16, 500), (16, 5000), (32, 500), (32, 5000)] {
        let (rows, cols) = (2 * n * lines, 3 * n);
        let w = Mat::<f64>::from_fn(rows, cols, |i, j| ((i * 31 + j * 17) % 97) as f64 * 1e-2);
        let a = Mat::<f64>::from_fn(rows, cols, |i, j| ((i * 13 + j * 7) % 89) as f64 * 1e-2);
        let mut out = Mat::<f64>::zeros(cols, cols);
        group.throughput(Throughput::Elements((36 * n * n * n * lines) as u64));
        group.bench_function(BenchmarkId::new(format!("wta_n{n}"), lines), |b| {
            b.iter(|| {
                matmul(
                    out.as_mut(),
                    Accum::Replace,
                    w.transpose(),
                    a.as_ref(),
                    1.0,
                    Par::Seq,
                );
                black_box(out[(0, 0)])
            })
        });
    }
    group.finish();
}

fn seed_rig_end_to_end(c: &mut Criterion) {
    let records = seed_records();
    let mut group = c.benchmark_group("seed_rig");
    group.bench_function("identify_ivf", |b| {
        let id = Identifier::new(8.0, 49.0);
        b.iter(|| black_box(id.identify(&records).unwrap()))
    });
    group.bench_function("fft_only", |b| {
        let mut est =
            SpectralEstimator::new(8040, 6700.0, Window::Rectangular).expect("valid plan");
        b.iter(|| {
            let mut acc = c64::new(0.0, 0.0);
            for r in &records {
                for ch in 0..2 {
                    acc += est.transform(r.force(ch))[10];
                    acc += est.transform(r.displacement(ch))[10];
                }
            }
            black_box(acc)
        })
    });
    group.finish();
}

/// Many test conditions at once (`identify_batch`): 8 record sets of the seed's rig. Run with
/// and without `--features rayon` for the multicore speed-up.
fn batch(c: &mut Criterion) {
    let sets: Vec<Vec<Record>> = (0..8)
        .map(|seed| {
            ImpactTest {
                noise: 0.05,
                seed,
                ..ImpactTest::seed_rig()
            }
            .run(&seed_rig())
            .unwrap()
        })
        .collect();
    let id = Identifier::new(8.0, 49.0);
    let mut group = c.benchmark_group("batch");
    group.sample_size(20);
    group.bench_function("identify_one_set", |b| {
        b.iter(|| black_box(id.identify(&sets[0]).unwrap()))
    });
    group.bench_function("identify_batch_8_sets", |b| {
        b.iter(|| black_box(id.identify_batch(&sets)))
    });
    group.finish();
}

fn csv(c: &mut Criterion) {
    let rows = 200_000;
    let dir = std::env::temp_dir().join(format!("bearing-ident-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("record.csv");
    let channel = |k: f64| {
        (0..rows)
            .map(|m| (m as f64 * k).sin() * 1e-5)
            .collect::<Vec<f64>>()
    };
    let record = Record::new(
        "bench",
        1.0e4,
        vec![channel(0.01), channel(0.02)],
        vec![channel(0.03), channel(0.04)],
    )
    .unwrap();
    let layout = CsvLayout::default();
    write_record(&path, &record, &layout).unwrap();
    let bytes = std::fs::metadata(&path).unwrap().len();
    let mut group = c.benchmark_group("csv");
    group.sample_size(10);
    group.throughput(Throughput::Bytes(bytes));
    group.bench_function(format!("parse_{rows}_rows"), |b| {
        b.iter(|| black_box(read_record(&path, &layout).unwrap().len()))
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

/// `count` complex `n × n` force matrices as a paired-sets impact test gives them, column
/// `j` the forces of the set that excites direction `j`: the dominant force on the diagonal,
/// cross-axis forces of about 30 % with random phase, each set's level varying.
fn force_matrices(n: usize, count: usize) -> Vec<c64> {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(12);
    let mut a = Vec::with_capacity(count * n * n);
    for _ in 0..count {
        for j in 0..n {
            let level = 0.5 + rng.random::<f64>();
            for i in 0..n {
                let modulus = if i == j {
                    1.0
                } else {
                    0.3 * rng.random::<f64>()
                };
                let phase = std::f64::consts::TAU * rng.random::<f64>();
                a.push(c64::from_polar(level * modulus, phase));
            }
        }
    }
    a
}

fn conditioning(c: &mut Criterion) {
    let count = 2766;
    let mut group = c.benchmark_group("conditioning");
    group.throughput(Throughput::Elements(count as u64));
    for n in [3, 4, 6] {
        let a = force_matrices(n, count);
        let mut conditioner = linalg::Conditioner::new(n);
        let (mut one, mut batched) = (vec![0.0; count], vec![0.0; count]);
        group.bench_function(format!("n{n}_one_by_one"), |b| {
            b.iter(|| {
                for (m, o) in one.iter_mut().enumerate() {
                    *o = conditioner.condition_number(&a[m * n * n..(m + 1) * n * n]);
                }
                black_box(one[count - 1])
            })
        });
        group.bench_function(format!("n{n}_batched"), |b| {
            b.iter(|| {
                conditioner.condition_numbers(&a, &mut batched);
                black_box(batched[count - 1])
            })
        });
        assert!(
            one.iter()
                .zip(&batched)
                .all(|(x, y)| x.to_bits() == y.to_bits())
        );
    }
    group.finish();
}

criterion_group!(
    benches,
    spectra,
    frf,
    ivf_iteration,
    ivf_solve,
    matmul_reference,
    seed_rig_end_to_end,
    batch,
    csv,
    conditioning
);
criterion_main!(benches);
