//! Criterion benches of the pipeline's stages, setup outside the timed closures.
//!
//! `cargo bench` runs them all; `cargo bench -- ivf` picks a group.

use std::hint::black_box;

use bearing_ident::frf::{self, Band, Frf};
use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::solve::{self, IvfOptions, Method};
use bearing_ident::spectra::{SpectralEstimator, Window};
use bearing_ident::{Coefficients, Identifier};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use faer::{Mat, c64};

/// The spectral estimator on one channel, record lengths 2¹⁰ … 2²⁰.
fn spectra(c: &mut Criterion) {
    let mut group = c.benchmark_group("spectra");
    for p in [10, 14, 17, 20] {
        let len = 1usize << p;
        let signal: Vec<f64> = (0..len)
            .map(|m| ((m * 7919) % 1000) as f64 * 1e-3)
            .collect();
        let mut est = SpectralEstimator::new(len, 1.0e4, Window::Rectangular);
        group.throughput(Throughput::Elements(len as u64));
        group.bench_with_input(BenchmarkId::from_parameter(len), &signal, |b, s| {
            b.iter(|| black_box(est.transform(s)[1]))
        });
    }
    group.finish();
}

/// A diagonal-dominant n-DOF system with modes spread over 10–40 Hz and its exact flexibility
/// on `lines` lines with 1 % deterministic perturbation (so IVF iterates).
fn synthetic_frf(n: usize, lines: usize) -> Frf {
    let m = Mat::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.05 });
    let k = Mat::from_fn(n, n, |i, j| {
        let w = 2.0 * std::f64::consts::PI * (10.0 + 30.0 * i as f64 / n.max(2) as f64);
        if i == j {
            2.0 * w * w
        } else {
            100.0 * (i as f64 - j as f64)
        }
    });
    let c = Mat::from_fn(n, n, |i, j| if i == j { 40.0 } else { 1.0 });
    let sys = Coefficients::new(m, c, k).unwrap();
    let freqs: Vec<f64> = (0..lines)
        .map(|l| 5.0 + 40.0 * l as f64 / lines as f64)
        .collect();
    let g: Vec<Mat<c64>> = freqs
        .iter()
        .enumerate()
        .map(|(l, &f)| {
            let g = sys.flexibility_at(f).unwrap();
            let e = 0.01 * (((l * 7919) % 101) as f64 / 50.0 - 1.0);
            Mat::from_fn(n, n, |i, j| g[(i, j)] * c64::new(1.0 + e, -e))
        })
        .collect();
    Frf::from_flexibility(freqs, &g).unwrap()
}

/// Whole fits (least squares, IVF) over n DOF and N lines.
fn fits(c: &mut Criterion) {
    let mut group = c.benchmark_group("fit");
    group.sample_size(20);
    for n in [2, 4, 8] {
        for lines in [50, 500] {
            let frf = synthetic_frf(n, lines);
            for method in [Method::LeastSquares, Method::Ivf] {
                let id = BenchmarkId::new(method.name(), format!("n{n}-N{lines}"));
                group.bench_with_input(id, &frf, |b, frf| {
                    b.iter(|| black_box(solve::fit(frf, method, &IvfOptions::default()).unwrap()))
                });
            }
        }
    }
    group.finish();
}

/// The seed's rig end to end: 16 impact records of 8040 samples, 2 DOF, 8–49 Hz.
fn end_to_end(c: &mut Criterion) {
    let records = ImpactTest {
        noise: 0.05,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap();
    let mut group = c.benchmark_group("seed_rig");
    group.bench_function("paired_frf", |b| {
        let excitation: Vec<usize> = records.iter().map(|r| r.dominant_force()).collect();
        let band = Band::new(8.0, 49.0).unwrap();
        b.iter(|| {
            black_box(frf::paired_sets(&records, &excitation, band, Window::Rectangular).unwrap())
        })
    });
    group.bench_function("identify_ivf", |b| {
        let id = Identifier::new(8.0, 49.0);
        b.iter(|| black_box(id.identify(&records).unwrap()))
    });
    group.bench_function("fft_only", |b| {
        let mut est = SpectralEstimator::new(8040, 6700.0, Window::Rectangular);
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

criterion_group!(benches, spectra, fits, end_to_end);
criterion_main!(benches);
