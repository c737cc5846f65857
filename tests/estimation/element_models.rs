//! Frequency-dependent element models over seeds: records of the seed's rig with an element
//! of one or two internal states (and of none), impacts and random forcing, 3 % noise, 10
//! seeds each, identified as `identify --model auto` does ([`Job`]): the family and order
//! chosen, and every coefficient, residue and pole against its 95 % interval.
//!
//! `#[ignore]`d Monte-Carlo tests, run in release by `.ci/run`
//! (`cargo test --release --all-features --test estimation -- --include-ignored element_models::`).
#![cfg(feature = "job")]

use bearing_ident::element::Family;
use bearing_ident::job::{Channels, Job, Options};
use bearing_ident::simulate::{Setup, seed_rig};
use bearing_ident::{Identification, Record};

const SEEDS: u64 = 10;

/// An element: its states (`simulate --states` form), the poles (Hz, increasing) and the
/// residues' diagonals in the same order.
struct Element {
    states: &'static str,
    poles_hz: &'static [f64],
    residues: &'static [[f64; 2]],
}

const NONE: Element = Element {
    states: "",
    poles_hz: &[],
    residues: &[],
};
const ONE: Element = Element {
    states: "20:4e4,0;0,3e4",
    poles_hz: &[20.0],
    residues: &[[4e4, 3e4]],
};
const TWO: Element = Element {
    states: "12:3e4,0;0,2.5e4|35:6e4,0;0,5e4",
    poles_hz: &[12.0, 35.0],
    residues: &[[3e4, 2.5e4], [6e4, 5e4]],
};

/// Records of `kind` (`impact`, `random`) of the rig with `element`, 3 % noise, seed `seed`.
fn records(kind: &str, element: &Element, seed: u64) -> Vec<Record> {
    let mut setup = Setup::default();
    for (name, value) in [
        ("kind", kind),
        ("noise", "0.03"),
        ("seed", &seed.to_string()),
    ] {
        setup.set(name, value).unwrap();
    }
    if kind == "random" {
        for (name, value) in [("rate", "1000"), ("duration", "60"), ("records", "4")] {
            setup.set(name, value).unwrap();
        }
    } else {
        setup.set("impacts", "4").unwrap();
    }
    if !element.states.is_empty() {
        setup.set("states", element.states).unwrap();
    }
    setup.run(&seed_rig()).unwrap().records
}

/// `records` identified over 8–49 Hz with `--model auto`, the rest at the defaults.
fn identify(records: Vec<Record>) -> Identification {
    let mut o = Options::new(8.0, 49.0);
    o.set("model", "auto").unwrap();
    Job::new(o, Channels::default())
        .run_records(records)
        .unwrap()
        .identification()
        .clone()
}

/// The `z` of every term with a truth: the diagonals of `K`, `C`, `M` (the seed's rig plus
/// nothing: the element's constant part is in its residues' limits), the off-diagonals (zero),
/// each residue's diagonal, each pole.
fn z_scores(id: &Identification, element: &Element) -> Vec<(String, f64)> {
    let model = id.model().unwrap();
    let fit = model.fit();
    let rig = seed_rig();
    let mut z = Vec::new();
    let truths = [rig.stiffness(), rig.damping(), rig.mass()];
    for (b, (name, truth)) in ["K", "C", "M"].iter().zip(truths).enumerate() {
        let (v, s) = (fit.matrix(b), fit.matrix_std(b).unwrap());
        for i in 0..2 {
            for j in 0..2 {
                z.push((
                    format!("{name}{i}{j}"),
                    (v[(i, j)] - truth[(i, j)]) / s[(i, j)],
                ));
            }
        }
    }
    // The model's poles in increasing order, with their residues.
    let poles = model.poles_hz();
    let poles_std = model.poles_hz_std().unwrap();
    let mut order: Vec<usize> = (0..poles.len()).collect();
    order.sort_by(|&a, &b| poles[a].total_cmp(&poles[b]));
    for (k, &j) in order.iter().enumerate() {
        z.push((
            format!("p{k}"),
            (poles[j] - element.poles_hz[k]) / poles_std[j],
        ));
        let (a, sa) = (fit.matrix(3 + j), fit.matrix_std(3 + j).unwrap());
        for i in 0..2 {
            z.push((
                format!("A{k}_{i}{i}"),
                (a[(i, i)] - element.residues[k][i]) / sa[(i, i)],
            ));
        }
    }
    z
}

/// Over 10 seeds of `kind` records of `element`: `auto` chooses the element's family in at
/// least 9, and of the terms of the seeds that chose it at least 90 % lie within their 95 %
/// intervals.
fn recovered(kind: &str, element: &Element) {
    let truth = match element.poles_hz.len() {
        0 => Family::Kcm,
        poles => Family::States { poles },
    };
    let (mut right, mut inside, mut terms) = (0, 0, 0);
    let mut worst = (String::new(), 0.0_f64);
    let mut chosen = Vec::new();
    for seed in 1..=SEEDS {
        let id = identify(records(kind, element, seed));
        let family = id.model().unwrap().family();
        chosen.push(family.to_string());
        if family != truth {
            continue;
        }
        right += 1;
        for (name, z) in z_scores(&id, element) {
            terms += 1;
            inside += usize::from(z.abs() < 1.96);
            if z.abs() > worst.1.abs() {
                worst = (format!("seed {seed} {name}"), z);
            }
        }
    }
    let coverage = inside as f64 / terms.max(1) as f64;
    println!(
        "{kind}, {truth}: chose {right}/{SEEDS} ({chosen:?}); coverage {coverage:.3} of \
         {terms} terms; worst {} {:+.2} σ",
        worst.0, worst.1
    );
    assert!(right >= 9, "{kind} {truth}: chose {chosen:?}");
    assert!(coverage >= 0.90, "{kind} {truth}: coverage {coverage}");
}

#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn one_state_from_impacts() {
    recovered("impact", &ONE);
}

#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn two_states_from_impacts() {
    recovered("impact", &TWO);
}

#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn one_state_from_random_records() {
    recovered("random", &ONE);
}

#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn two_states_from_random_records() {
    recovered("random", &TWO);
}

#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn constant_coefficients_are_kept_constant() {
    recovered("impact", &NONE);
    recovered("random", &NONE);
}
