//! The element model families against an independent physics model: a hole-pattern gas seal and
//! a magnetic bearing whose coefficients ROSS 3.1.0 computed over whirl frequency
//! (`tests/element_tables/`, written by `ross_tables.py` there; ROSS is not needed here), each
//! added to the seed rig. Periodic multisine records are synthesised exactly in the frequency
//! domain, `X = (H_rig(ω) + H_element(ω))⁻¹ F` at the excited lines and inverse-transformed (no
//! transient), with white noise on every channel; they are identified with `--model auto` and
//! with `--model kcm` as `identify` does ([`Job`]). The chosen model's `K(ω)`, `C(ω)` less the
//! rig's must agree with ROSS's within 3 of the curve's standard deviations on 95 % of lines and
//! elements, and `kcm` must be flagged `model_misfit`.
//!
//! The comparison is made in the curve's own convention, `K(ω) = Re H(ω) + ω²M` with `M` the
//! model's constant mass: the element's `K(ω)` is the curve's less `K_rig` and less
//! `ω²(M − M_rig)`, so that the real parts of the impedances are compared and the mass term
//! cancels; `C(ω) = Im H(ω)/ω` needs no convention.
//!
//! `tests/element_tables/cli_check.py` makes the same records with numpy and runs the release
//! CLI on them.
#![cfg(feature = "job")]

use bearing_ident::element::{ElementModel, Family};
use bearing_ident::job::{Channels, Job, Options};
use bearing_ident::simulate::{add_noise, seed_rig};
use bearing_ident::{Identification, Record};
use faer::{Mat, c64};
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Uniform};
use realfft::RealFftPlanner;
use std::f64::consts::TAU;

const SEAL: &str = include_str!("../element_tables/hole_pattern_seal.csv");
const MAGNETIC_BEARING: &str = include_str!("../element_tables/magnetic_bearing.csv");

const SAMPLE_RATE: f64 = 4000.0;
/// Samples per period: lines every 20 Hz, the tables' grid.
const PERIOD: usize = 200;
const PERIODS: usize = 40;
const PER_DIRECTION: usize = 3;
/// The band: the tables' 20 … 1000 Hz.
const BAND: (f64, f64) = (15.0, 1005.0);

/// An element's impedance `H(ω) = k − ω²m + iωc` per line of a ROSS table, times `scale`.
struct Element {
    freqs_hz: Vec<f64>,
    impedance: Vec<Mat<c64>>,
}

impl Element {
    /// The table `text` (`frequency_hz`, then `k`, `c`, `m` for `xx, xy, yx, yy`).
    fn from_table(text: &str, scale: f64) -> Element {
        let mut element = Element {
            freqs_hz: Vec::new(),
            impedance: Vec::new(),
        };
        for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
            let v: Vec<f64> = line.split(',').map(|x| x.trim().parse().unwrap()).collect();
            assert_eq!(v.len(), 13, "{line}");
            let w = TAU * v[0];
            let at = |kind: usize, e: usize| v[1 + 4 * kind + e];
            element.freqs_hz.push(v[0]);
            element.impedance.push(Mat::from_fn(2, 2, |i, j| {
                let e = 2 * i + j;
                c64::new(at(0, e) - w * w * at(2, e), w * at(1, e)) * scale
            }));
        }
        element
    }

    /// The element's `K(ω) = Re H`, `C(ω) = Im H/ω` at `f_hz`, a line of the table.
    fn coefficients_at(&self, f_hz: f64) -> (Mat<f64>, Mat<f64>) {
        let k = self
            .freqs_hz
            .iter()
            .position(|&f| (f - f_hz).abs() < 1e-6)
            .unwrap_or_else(|| panic!("{f_hz} Hz is not a line of the table"));
        let h = &self.impedance[k];
        let w = TAU * f_hz;
        (
            Mat::from_fn(2, 2, |i, j| h[(i, j)].re),
            Mat::from_fn(2, 2, |i, j| h[(i, j)].im / w),
        )
    }
}

/// Noise-free periodic records of the seed rig with `element`: unit multisines at the table's
/// lines, random phases, one direction per record, `PER_DIRECTION` records each.
fn clean_records(element: &Element, seed: u64) -> Vec<Record> {
    let rig = seed_rig();
    let df = SAMPLE_RATE / PERIOD as f64;
    let lines: Vec<usize> = element
        .freqs_hz
        .iter()
        .map(|f| (f / df).round() as usize)
        .collect();
    let flexibility: Vec<Mat<c64>> = element
        .freqs_hz
        .iter()
        .zip(&element.impedance)
        .map(|(&f, h)| inverse(&(rig.impedance_at(f) + h)))
        .collect();
    let phase = Uniform::new(0.0, TAU).unwrap();
    let mut rng = StdRng::seed_from_u64(seed);
    let inverse_fft = RealFftPlanner::<f64>::new().plan_fft_inverse(PERIOD);
    let to_time = |spectrum: &[c64]| {
        let mut spectrum = spectrum.to_vec();
        let mut period = vec![0.0; PERIOD];
        inverse_fft.process(&mut spectrum, &mut period).unwrap();
        period.repeat(PERIODS)
    };
    let mut records = Vec::new();
    for direction in 0..2 {
        for r in 0..PER_DIRECTION {
            let mut f = vec![vec![c64::new(0.0, 0.0); PERIOD / 2 + 1]; 2];
            let mut x = f.clone();
            for (&line, g) in lines.iter().zip(&flexibility) {
                let p = phase.sample(&mut rng);
                f[direction][line] = c64::new(p.cos(), p.sin());
                for (dof, x) in x.iter_mut().enumerate() {
                    x[line] = g[(dof, direction)] * f[direction][line];
                }
            }
            records.push(
                Record::new(
                    format!("d{direction}r{r}"),
                    SAMPLE_RATE,
                    f.iter().map(|s| to_time(s)).collect(),
                    x.iter().map(|s| to_time(s)).collect(),
                )
                .unwrap(),
            );
        }
    }
    records
}

fn inverse(h: &Mat<c64>) -> Mat<c64> {
    let det = h[(0, 0)] * h[(1, 1)] - h[(0, 1)] * h[(1, 0)];
    let mut g = Mat::zeros(2, 2);
    g[(0, 0)] = h[(1, 1)] / det;
    g[(1, 1)] = h[(0, 0)] / det;
    g[(0, 1)] = -h[(0, 1)] / det;
    g[(1, 0)] = -h[(1, 0)] / det;
    g
}

/// `records` identified over [`BAND`] as periodic records with `--model model`.
fn identify(records: Vec<Record>, model: &str) -> Identification {
    let mut o = Options::new(BAND.0, BAND.1);
    o.set("excitation", "periodic").unwrap();
    o.set("period", &(PERIOD as f64 / SAMPLE_RATE).to_string())
        .unwrap();
    o.set("model", model).unwrap();
    Job::new(o, Channels::default())
        .run_records(records)
        .unwrap()
        .identification()
        .clone()
}

/// The model's `K(ω)`, `C(ω)` less the rig's against `element`'s, in units of the curve's
/// standard deviations: one `z` per line and element of `K` and of `C`.
fn z_scores(model: &ElementModel, element: &Element) -> Vec<f64> {
    let rig = seed_rig();
    let mass = model.constant_part().unwrap().mass().to_owned();
    let curve = model.curve();
    let mut z = Vec::new();
    for (line, &f) in curve.frequency_hz.iter().enumerate() {
        let w2 = (TAU * f).powi(2);
        let (k_true, c_true) = element.coefficients_at(f);
        for i in 0..2 {
            for j in 0..2 {
                let k = curve.stiffness[line][(i, j)]
                    - rig.stiffness()[(i, j)]
                    - w2 * (mass[(i, j)] - rig.mass()[(i, j)]);
                let c = curve.damping[line][(i, j)] - rig.damping()[(i, j)];
                z.push((k - k_true[(i, j)]) / curve.stiffness_std[line][(i, j)]);
                z.push((c - c_true[(i, j)]) / curve.damping_std[line][(i, j)]);
            }
        }
    }
    z
}

fn misfit(id: &Identification) -> bool {
    id.warnings().iter().any(|w| w.kind() == "model_misfit")
}

/// The fraction of `z` within `limit` in absolute value (NaN counts as outside).
fn within(z: &[f64], limit: f64) -> f64 {
    z.iter().filter(|z| z.abs() <= limit).count() as f64 / z.len() as f64
}

/// What one set of records of `element` on the seed rig, `noise` × each channel's RMS, shows:
/// `Ok` with a summary when `auto` chooses a frequency-dependent family (`family` when given)
/// that the check accepts and whose `K(ω)`, `C(ω)` agree with ROSS's (3σ on 95 % of lines and
/// elements), and `kcm` is a misfit; `Err` saying what failed otherwise.
fn against_ross(
    element: &Element,
    family: Option<Family>,
    noise: f64,
    seed: u64,
) -> Result<String, String> {
    let clean = clean_records(element, seed);
    let mut rng = StdRng::seed_from_u64(seed ^ 0x5eed);
    let records: Vec<Record> = clean
        .iter()
        .map(|r| add_noise(r, noise, &mut rng).unwrap())
        .collect();

    let auto = identify(records.clone(), "auto");
    let model = auto.model().expect("an element model with --model auto");
    let z = z_scores(model, element);
    let worst = z.iter().fold(0.0f64, |a, z| a.max(z.abs()));
    let summary = format!(
        "noise {noise}, seed {seed}: auto chose {} (poles {:.1?} Hz), {} lines; within 2σ \
         {:.3}, within 3σ {:.3}, worst |z| {worst:.2}",
        model.family(),
        model.poles_hz(),
        model.curve().frequency_hz.len(),
        within(&z, 2.0),
        within(&z, 3.0),
    );
    let kcm = identify(records, "kcm");
    let frequency_dependent = !matches!(model.family(), Family::Kc | Family::Kcm);
    let mut failed = Vec::new();
    if !frequency_dependent || family.is_some_and(|f| f != model.family()) {
        failed.push("not the family expected");
    }
    if misfit(&auto) {
        failed.push("the chosen model is a misfit");
    }
    if within(&z, 3.0) < 0.95 {
        failed.push("fewer than 95 % within 3σ");
    }
    if !misfit(&kcm) {
        failed.push("kcm is not a misfit");
    }
    if failed.is_empty() {
        Ok(summary)
    } else {
        Err(format!("{summary}: {}", failed.join("; ")))
    }
}

/// [`against_ross`] for every seed of `seeds` and noise level of `noises`: panics naming every
/// failure.
fn check_against_ross(
    family: Option<Family>,
    name: &str,
    element: &Element,
    noises: &[f64],
    seeds: std::ops::RangeInclusive<u64>,
) {
    let mut failures = Vec::new();
    for &noise in noises {
        for seed in seeds.clone() {
            match against_ross(element, family, noise, seed) {
                Ok(summary) => eprintln!("{name}, {summary}"),
                Err(failure) => failures.push(failure),
            }
        }
    }
    assert!(failures.is_empty(), "{name}:\n{}", failures.join("\n"));
}

/// ROSS's `HolePatternSeal` (its docstring example, 8000 rpm) ten times over, so that it is most
/// of the rig's impedance below 200 Hz: over 20–1000 Hz direct stiffness 7.4 → 14.5 MN/m,
/// cross-coupled 1.8 → 0.29 MN/m, direct damping 2.4 → 1.5 kN·s/m, cross-coupled −470 → −150
/// N·s/m; 2 % and 3 % noise, five seeds each.
#[test]
fn hole_pattern_seal_from_ross() {
    let seal = Element::from_table(SEAL, 10.0);
    check_against_ross(None, "hole-pattern seal", &seal, &[0.02, 0.03], 1..=5);
}

/// The seal at 5 % noise, five seeds: `auto` chooses a family whose curve agrees with ROSS's.
#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn hole_pattern_seal_from_ross_at_five_percent() {
    let seal = Element::from_table(SEAL, 10.0);
    check_against_ross(None, "hole-pattern seal", &seal, &[0.05], 1..=5);
}

/// ROSS's `MagneticBearingElement` under `pid(4000, 0, 4, n_f = 2π·600) · low_pass(2π·400)`,
/// thirty times over (the same actuator with 30 × its pole area × turns², which scales both
/// `k_s` and `k_i`): its impedance is exactly a `states:2` model (poles 400 and 600 Hz, residues
/// +1.46 and −1.68 MN/m per unit scale), `K(ω)` 2.9 → 9.2 → 3.4 MN/m and `C(ω)` 4.0 → −1.4
/// kN·s/m over the band, the rig with it stable (modes near 210 Hz, 25 % damping); 2 % and 3 %
/// noise, ten seeds each.
///
/// Two poles of nearly opposite residues are close to a double pole: in some seeds the data
/// fit the two poles merged as well as apart, and `auto` refuses that `states:2` (its poles not
/// told apart, or not determined) and falls back on `states:1`, which the check calls a misfit.
/// So: in every seed either the chosen model agrees with ROSS's curve or the result says
/// `model_misfit` (never a silent wrong curve); `states:2` is found and agrees in at least 8 of
/// 10 seeds at 2 % and 5 of 10 at 3 % (measured: 9 and 6); `kcm` is always a misfit.
#[test]
#[ignore = "Monte-Carlo: run in release by .ci/run"]
fn magnetic_bearing_from_ross() {
    let bearing = Element::from_table(MAGNETIC_BEARING, 30.0);
    let states_2 = Some(Family::States { poles: 2 });
    let mut silent = Vec::new();
    for (noise, least) in [(0.02, 8), (0.03, 5)] {
        let mut found = 0;
        for seed in 1..=10 {
            match against_ross(&bearing, states_2, noise, seed) {
                Ok(summary) => {
                    eprintln!("magnetic bearing, {summary}");
                    found += 1;
                }
                Err(failure) if failure.contains("the chosen model is a misfit") => {
                    eprintln!("magnetic bearing, said misfit: {failure}");
                }
                Err(failure) => silent.push(failure),
            }
        }
        eprintln!("magnetic bearing, noise {noise}: states:2 found and agreeing in {found} of 10");
        assert!(found >= least, "noise {noise}: {found} of 10");
    }
    assert!(silent.is_empty(), "{}", silent.join("\n"));
}
