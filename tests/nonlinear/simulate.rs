//! The nonlinear simulator against known truth: the exact linear simulator when every
//! coefficient is zero, the exact Coulomb free decay, the exact Duffing period (elliptic
//! integral), the energy balance of quadratic damping, and typed errors for bad inputs.

use std::f64::consts::PI;

use bearing_ident::Choice;
use bearing_ident::model::Coefficients;
use bearing_ident::nonlinear::{Regressor, Term};
use bearing_ident::records::Response;
use bearing_ident::simulate::{AntiAlias, NonlinearSimulator, Simulator, band_noise, seed_rig};
use bearing_ident::{Error, Record};
use faer::mat;

fn term(regressor: Regressor, dof: Option<usize>) -> Term {
    Term { regressor, dof }
}

fn sdof(m: f64, c: f64, k: f64) -> Coefficients {
    Coefficients::new(mat![[m]], mat![[c]], mat![[k]]).unwrap()
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// Largest difference of all channels of `a` and `b`, relative to each channel's RMS in `b`.
fn relative_difference(a: &Record, b: &Record) -> f64 {
    (0..a.dofs())
        .flat_map(|c| {
            [
                (a.force(c), b.force(c)),
                (a.displacement(c), b.displacement(c)),
            ]
        })
        .map(|(x, y)| {
            let scale = rms(y);
            x.iter()
                .zip(y)
                .map(|(p, q)| (p - q).abs() / scale)
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// Relative difference from the exact linear simulator, for the seed rig under band-limited
/// and white (staircase) forces on both axes, with zero nonlinear coefficients.
fn difference_from_linear(kinds: &[Response], white: bool, oversampling: usize) -> f64 {
    let (fs, samples) = (2048.0, 4096);
    let rig = seed_rig();
    let forces: Vec<Vec<f64>> = (0..2)
        .map(|d| {
            if white {
                // White staircase: power up to Nyquist, the filters' hardest case.
                band_noise(1.0, 1023.0, 50.0, fs, samples, 40 + d).unwrap()
            } else {
                band_noise(8.0, 49.0, 50.0, fs, samples, 20 + d).unwrap()
            }
        })
        .collect();
    let mut linear = Simulator::new(&rig, fs, samples, AntiAlias::default())
        .unwrap()
        .responding(kinds)
        .unwrap();
    let exact = linear.held_record("linear", &forces).unwrap();
    let mut nonlinear = NonlinearSimulator::new(&rig, fs, samples, AntiAlias::default())
        .unwrap()
        .responding(kinds)
        .unwrap()
        .with_oversampling(oversampling)
        .unwrap();
    for t in Regressor::expand(Regressor::ALL, 2).unwrap() {
        nonlinear = nonlinear.with_term(t, 0.0).unwrap();
    }
    let rec = nonlinear.held_record("nonlinear", &forces).unwrap();
    assert_eq!(rec.responses(), exact.responses());
    relative_difference(&rec, &exact)
}

#[test]
fn with_zero_coefficients_it_is_the_exact_linear_simulator() {
    // RK4 against the matrix exponential, both through the same 8th-order Butterworth
    // anti-alias filter. Measured at 16 steps per sample, band-limited 8–49 Hz forces:
    // displacement 4.5e-10, velocity 6.0e-9, acceleration 9.2e-8 (the held force's jumps pass
    // straight into it); white forces (power up to Nyquist): displacement 4.3e-8 at 16 steps,
    // 2.8e-9 at 32 — RK4's h⁴ —, acceleration 5.2e-7 at 32.
    for (kinds, white, steps, tolerance) in [
        (vec![], false, 16, 1e-9),
        (vec![Response::Velocity], false, 16, 1e-8),
        (vec![], true, 16, 1e-7),
        (vec![], true, 32, 5e-9),
        (vec![Response::Acceleration], false, 16, 2e-7),
        (vec![Response::Acceleration], true, 32, 1e-6),
    ] {
        let diff = difference_from_linear(&kinds, white, steps);
        eprintln!("{kinds:?}, white {white}, {steps} steps: {diff:.3e}");
        assert!(diff < tolerance, "{kinds:?}, white {white}: {diff:.3e}");
    }
}

/// The exact free decay of `m ẍ + k x + F sign(ẋ) = 0` from rest at `x0 > 0`: every half
/// period `π/ω` the motion turns and the amplitude has dropped by `2F/k`.
fn coulomb_decay(m: f64, k: f64, friction: f64, x0: f64, t: f64) -> f64 {
    let w = (k / m).sqrt();
    let half = (t * w / PI).floor();
    let mut x = x0;
    for _ in 0..half as usize {
        x = -x + 2.0 * friction / k * x.signum();
    }
    // Moving away from x towards −x: the friction pushes towards x's side.
    let offset = friction / k * x.signum();
    offset + (x - offset) * (w * (t - half * PI / w)).cos()
}

#[test]
fn coulomb_free_decay_loses_4f_over_k_per_cycle() {
    let (m, k, friction, x0, fs) = (1.0, 4.0e4, 2.0, 1e-3, 2000.0);
    // Four cycles (ω = 200 rad/s): the amplitude falls from 1 mm to 0.2 mm, above F/k = 0.05 mm.
    let samples = 250;
    let coulomb = term(Regressor::Coulomb, Some(0));
    let decay = |smoothing: f64| {
        let mut sim = NonlinearSimulator::new(&sdof(m, 0.0, k), fs, samples, AntiAlias::None)
            .unwrap()
            .with_term(coulomb, friction)
            .unwrap()
            .with_smoothing(smoothing)
            .unwrap();
        let rec = sim.free_decay("decay", &[x0], &[0.0]).unwrap();
        let err = rec
            .displacement(0)
            .iter()
            .enumerate()
            .map(|(s, x)| (x - coulomb_decay(m, k, friction, x0, s as f64 / fs)).abs() / x0)
            .fold(0.0, f64::max);
        (rec, err)
    };
    // The only departure from the exact law is the smoothing's, in proportion to v_s
    // (measured 5.05e-6, 5.05e-7, 5.05e-8 of the amplitude for v_s = 1e-5, 1e-6, 1e-7 m/s,
    // the same at 64 or 256 steps per sample): the integration resolves the band.
    let (rec, err) = decay(1e-6);
    assert!(err < 1e-6, "largest error {err:.3e} of the amplitude");
    let (_, coarse) = decay(1e-5);
    let (_, fine) = decay(1e-7);
    assert!(coarse < 1e-5, "default smoothing: {coarse:.3e}");
    for ratio in [coarse / err, err / fine] {
        assert!((ratio / 10.0 - 1.0).abs() < 0.05, "not ∝ v_s: {ratio}");
    }
    // The same motion along x with planar friction (y never moves): the planar law is the
    // per-axis law on a straight line.
    let rig = Coefficients::new(
        mat![[m, 0.0], [0.0, m]],
        mat![[0.0, 0.0], [0.0, 0.0]],
        mat![[k, 0.0], [0.0, k]],
    )
    .unwrap();
    let mut planar = NonlinearSimulator::new(&rig, fs, samples, AntiAlias::None)
        .unwrap()
        .with_term(term(Regressor::CoulombPlanar, None), friction)
        .unwrap()
        .with_smoothing(1e-6)
        .unwrap();
    let rec2 = planar
        .free_decay("planar", &[x0, 0.0], &[0.0, 0.0])
        .unwrap();
    let diff = rec2
        .displacement(0)
        .iter()
        .zip(rec.displacement(0))
        .map(|(a, b)| (a - b).abs() / x0)
        .fold(0.0, f64::max);
    assert!(diff < 1e-9, "planar vs per-axis {diff:.3e}");
    assert!(rec2.displacement(1).iter().all(|y| y.abs() < 1e-15));
}

/// Complete elliptic integral of the first kind `K(μ)` (parameter `μ = k²`), by the AGM.
fn elliptic_k(mu: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - mu).sqrt());
    while (a - b).abs() > 1e-16 * a {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

#[test]
fn duffing_period_follows_the_elliptic_backbone() {
    // ẍ + ω₀² x + ε x³ = 0 from rest at A: x = A cn(Ωt, μ), Ω² = ω₀² + εA², μ = εA²/(2Ω²),
    // period 4K(μ)/Ω.
    let (m, f0, amplitude, fs) = (1.0, 20.0, 1e-3, 10_000.0);
    let k = m * (2.0 * PI * f0).powi(2);
    let k3 = 0.5 * k / (amplitude * amplitude); // εA² = ω₀²/2: a 17 % frequency shift
    let samples = 25_000;
    let mut sim = NonlinearSimulator::new(&sdof(m, 0.0, k), fs, samples, AntiAlias::None)
        .unwrap()
        .with_term(term(Regressor::Cubic, Some(0)), k3)
        .unwrap();
    let rec = sim.free_decay("duffing", &[amplitude], &[0.0]).unwrap();
    let x = rec.displacement(0);
    // Upward zero crossings, linearly interpolated (x'' = 0 there: the error is O(Δt³)).
    let crossings: Vec<f64> = (1..samples)
        .filter(|&s| x[s - 1] < 0.0 && x[s] >= 0.0)
        .map(|s| (s as f64 - 1.0 + x[s - 1] / (x[s - 1] - x[s])) / fs)
        .collect();
    let periods = (crossings.len() - 1) as f64;
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / periods;
    let w0 = (k / m).sqrt();
    let big_omega = (w0 * w0 + k3 / m * amplitude * amplitude).sqrt();
    let mu = k3 / m * amplitude * amplitude / (2.0 * big_omega * big_omega);
    let exact = 4.0 * elliptic_k(mu) / big_omega;
    let err = (measured / exact - 1.0).abs();
    assert!(periods >= 40.0);
    eprintln!("Duffing period error {err:.3e}");
    // Measured 7.6e-11.
    assert!(err < 1e-9, "period {measured} vs {exact}: {err:.3e}");
    // The shift itself is large: a linear model would be 17 % off.
    assert!((2.0 * PI / w0 / exact - 1.0) > 0.15);
    // The amplitude is conserved (no damping): the sampled maxima reach A to within sampling.
    let peak = x[samples / 2..].iter().cloned().fold(f64::MIN, f64::max);
    assert!((peak / amplitude - 1.0).abs() < 1e-4, "peak {peak}");
}

#[test]
fn quadratic_damping_dissipates_the_energy_lost() {
    // E = ½mv² + ½kx² falls by ∫ q|v|³ dt; both records from the same start.
    let (m, k, q, fs) = (1.0, (2.0 * PI * 20.0_f64).powi(2), 50.0, 20_000.0);
    let samples = 4001; // 0.2 s, four cycles, even number of Simpson intervals
    let qd = term(Regressor::QuadraticDamping, Some(0));
    let make = |kind| {
        NonlinearSimulator::new(&sdof(m, 0.0, k), fs, samples, AntiAlias::None)
            .unwrap()
            .with_term(qd, q)
            .unwrap()
            .responding(&[kind])
            .unwrap()
            .free_decay("qd", &[1e-3], &[0.0])
            .unwrap()
    };
    let (xr, vr) = (make(Response::Displacement), make(Response::Velocity));
    let (x, v) = (xr.displacement(0), vr.displacement(0));
    let energy = |s: usize| 0.5 * m * v[s] * v[s] + 0.5 * k * x[s] * x[s];
    let power: Vec<f64> = v.iter().map(|v| q * v.abs().powi(3)).collect();
    let h = 1.0 / fs;
    let mut dissipated = 0.0;
    let mut worst = 0.0_f64;
    for s in (2..samples).step_by(2) {
        dissipated += h / 3.0 * (power[s - 2] + 4.0 * power[s - 1] + power[s]);
        worst = worst.max((energy(0) - energy(s) - dissipated).abs() / energy(0));
    }
    let lost = 1.0 - energy(samples - 1) / energy(0);
    assert!(lost > 0.2, "the damping matters: {lost}");
    eprintln!("energy balance {worst:.3e} of E₀, lost {lost:.3}");
    // Measured 2.2e-11.
    assert!(worst < 1e-9, "energy balance off by {worst:.3e} of E₀");
}

#[test]
fn bad_inputs_are_typed_errors() {
    let rig = seed_rig();
    let mut sim = NonlinearSimulator::new(&rig, 1000.0, 100, AntiAlias::None).unwrap();
    let ok = vec![0.0; 100];
    assert!(matches!(
        sim.held_record("r", std::slice::from_ref(&ok)),
        Err(Error::InvalidParameter {
            name: bearing_ident::Parameter::HeldForceChannels,
            ..
        })
    ));
    assert!(matches!(
        sim.held_record("r", &[ok.clone(), vec![0.0; 99]]),
        Err(Error::InvalidParameter {
            name: bearing_ident::Parameter::HeldForceLength,
            ..
        })
    ));
    let mut nan = ok.clone();
    nan[7] = f64::NAN;
    let e = sim.held_record("r", &[ok.clone(), nan]).unwrap_err();
    assert!(
        matches!(&e, Error::NonFinite { record, sample: 7, .. } if record == "r"),
        "{e}"
    );
    assert_eq!(e.kind(), "non_finite");
    assert!(sim.free_decay("r", &[0.0], &[0.0, 0.0]).is_err());
    assert!(sim.free_decay("r", &[f64::NAN, 0.0], &[0.0, 0.0]).is_err());
    // Too few RK4 steps per sample for a stiff system (|λ| = 1e5 rad/s at 1000 samples/s).
    let stiff = NonlinearSimulator::new(&sdof(1.0, 0.0, 1e10), 1000.0, 100, AntiAlias::None);
    let mut coarse = stiff.unwrap().with_oversampling(16).unwrap();
    assert!(matches!(
        coarse.held_record("r", std::slice::from_ref(&ok)),
        Err(Error::InvalidParameter {
            name: bearing_ident::Parameter::Oversampling,
            ..
        })
    ));
    // A softening spring past its turning point runs away: a typed error naming the record.
    let soft = term(Regressor::Cubic, Some(0));
    let mut runaway = NonlinearSimulator::new(&sdof(1.0, 0.0, 1e4), 1000.0, 1000, AntiAlias::None)
        .unwrap()
        .with_term(soft, -1e10)
        .unwrap();
    let e = runaway.free_decay("runaway", &[2e-3], &[0.0]).unwrap_err();
    assert!(
        matches!(&e, Error::SimulationDiverged { record, .. } if record == "runaway"),
        "{e}"
    );
    assert_eq!(e.kind(), "non_finite");
    assert!(e.to_string().contains("runaway"));
    // Records so long that the fine steps pass the limit.
    let long = NonlinearSimulator::new(&rig, 1000.0, 1 << 24, AntiAlias::None)
        .unwrap()
        .with_oversampling(4096)
        .unwrap();
    assert!(matches!(long.oversampling(), Err(Error::TooLarge { .. })));
}
