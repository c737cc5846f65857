//! Criterion benches of the element model selection (`--model auto`) against the default
//! `kcm` fit on the same records, with the ratio of their median identify times printed after
//! each group (the target: `auto` at most 3× `kcm`).
//!
//! `cargo bench -p bearing-ident-benches --bench element` runs both; `… -- random` one.
//! - `seed_rig`: the seed's 16 impact records × 8040 samples, 2 DOF, 8–49 Hz, 5 % noise;
//! - `random`: 2 random-excitation records × 40 000 samples on the seed's rig, H1 with Welch
//!   segments (Hann, 50 % overlap), 5–60 Hz.
//!
//! On constant-coefficient records `auto` fits `kc`, then `kcm`, which the model check
//! accepts: the selection stops there.

mod common;
use common::median;

use std::hint::black_box;

use bearing_ident::element::ModelSpec;
use bearing_ident::excitation::welch_len;
use bearing_ident::simulate::{AntiAlias, ImpactTest, Simulator, add_noise, seed_rig};
use bearing_ident::spectra::{Segmentation, Window};
use bearing_ident::{Estimator, Identifier, Record};
use criterion::{Criterion, criterion_group, criterion_main};
use rand::SeedableRng;
use rand::rngs::StdRng;

/// Benches `kcm` and `auto` on `records` and prints their medians and ratio.
fn pair(c: &mut Criterion, name: &str, kcm: Identifier, records: &[Record]) {
    let auto = kcm.clone().model(ModelSpec::Auto);
    let chosen = auto.identify(records).expect("identifies");
    let family = chosen.model().expect("a model").family();
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    group.bench_function("kcm", |b| {
        b.iter(|| black_box(kcm.identify(records).unwrap()))
    });
    group.bench_function("auto", |b| {
        b.iter(|| black_box(auto.identify(records).unwrap()))
    });
    group.finish();
    const RUNS: usize = 15;
    let t_kcm = median(RUNS, || {
        black_box(kcm.identify(records).unwrap());
    });
    let t_auto = median(RUNS, || {
        black_box(auto.identify(records).unwrap());
    });
    eprintln!(
        "{name}: kcm {:.3} ms, auto {:.3} ms (chose {family}), ratio {:.2}",
        t_kcm.as_secs_f64() * 1e3,
        t_auto.as_secs_f64() * 1e3,
        t_auto.as_secs_f64() / t_kcm.as_secs_f64()
    );
}

fn seed(c: &mut Criterion) {
    let records = ImpactTest {
        noise: 0.05,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .expect("simulated");
    pair(c, "seed_rig", Identifier::new(8.0, 49.0), &records);
}

fn random(c: &mut Criterion) {
    let mut sim =
        Simulator::new(&seed_rig(), 6700.0, 40_000, AntiAlias::default()).expect("simulator");
    let mut rng = StdRng::seed_from_u64(9);
    let records: Vec<Record> = (0..2)
        .map(|r| {
            let clean = sim
                .random_record(format!("random-{r}"), 50.0, r)
                .expect("record");
            add_noise(&clean, 0.02, &mut rng).expect("noise")
        })
        .collect();
    let kcm = Identifier::new(5.0, 60.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Welch {
            len: welch_len(40_000),
        })
        .window(Window::Hann);
    pair(c, "random", kcm, &records);
}

criterion_group!(benches, seed, random);
criterion_main!(benches);
