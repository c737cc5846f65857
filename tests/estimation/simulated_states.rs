//! Records of a system whose element has internal states (`simulate::ElementStates`,
//! `Simulator::with_states`, the `states` option of `Setup`) against independent references:
//! the steady-state response to a sine against `X = H(iω)⁻¹ F` of the closed form, an impulse
//! response against a fine RK4 integration of the ODE, states that do nothing against records
//! without them; and impact records of such an element identified with `--model auto`.

use std::f64::consts::PI;

use bearing_ident::element::{Family, ModelSpec};
use bearing_ident::model::Coefficients;
use bearing_ident::simulate::{
    AntiAlias, ElementStates, Impact, Kind, Setup, Simulator, seed_rig, sine, slowest_decay,
};
use bearing_ident::{Error, Identifier, Parameter, Response};
use faer::{c64, mat};

use crate::common::EXACT;

/// Two states on the seed's rig, at 12 and 35 Hz, with residues that couple the directions.
fn two_states() -> ElementStates {
    ElementStates::new(
        vec![12.0, 35.0],
        vec![
            mat![[3.0e4, 5.0e3], [2.0e3, 2.5e4]],
            mat![[2.0e4, -4.0e3], [1.0e3, 1.5e4]],
        ],
    )
    .unwrap()
}

/// `H(iω) = K + iωC − ω²M + Σ A_j iω/(iω + p_j)` of a 2-DOF system, entry by entry.
fn impedance(
    system: &Coefficients,
    poles_hz: &[f64],
    residues: &[faer::Mat<f64>],
    f: f64,
) -> [[c64; 2]; 2] {
    let s = c64::new(0.0, 2.0 * PI * f);
    let mut h = [[c64::new(0.0, 0.0); 2]; 2];
    for (i, row) in h.iter_mut().enumerate() {
        for (j, hij) in row.iter_mut().enumerate() {
            *hij = system.stiffness()[(i, j)]
                + s * system.damping()[(i, j)]
                + s * s * system.mass()[(i, j)];
            for (p, a) in poles_hz.iter().zip(residues) {
                *hij += a[(i, j)] * s / (s + 2.0 * PI * p);
            }
        }
    }
    h
}

/// `(2/N) Σ y_m e^{−iω t_m}` over `y`, sampled at `rate` from `t = 0`.
fn phasor(y: &[f64], f: f64, rate: f64) -> c64 {
    let sum: c64 = y
        .iter()
        .enumerate()
        .map(|(m, &v)| v * c64::cis(-2.0 * PI * f * m as f64 / rate))
        .sum();
    sum * (2.0 / y.len() as f64)
}

/// Driven by a sine on one direction at a time, the seed's rig with two states settles to
/// `X = H(iω)⁻¹ F` of the closed form, in displacement, velocity (`iω X`) and acceleration
/// (`−ω² X`). The force is the recorded (filtered) one, so the anti-alias filter cancels; its
/// 16th order leaves the aliases of the held staircase at `4⁻¹⁶ ≈ 2·10⁻¹⁰`. After 2 s of
/// settling the start transient (slowest decay 23 /s with the states) is `e⁻⁴⁶`; the phasors
/// are taken over 1 s, a whole number of periods.
#[test]
fn sine_response_matches_the_closed_form_impedance() {
    let (rig, states) = (seed_rig(), two_states());
    let (rate, settle, kept) = (2000.0, 4000, 2000);
    let filter = AntiAlias::Butterworth {
        order: 16,
        cutoff_ratio: 0.25,
    };
    let mut worst: f64 = 0.0;
    for response in [
        Response::Displacement,
        Response::Velocity,
        Response::Acceleration,
    ] {
        let mut sim = Simulator::with_states(&rig, &states, rate, settle + kept, filter)
            .unwrap()
            .responding(&[response])
            .unwrap();
        for f in [12.0, 28.0, 35.0, 50.0] {
            let h = impedance(&rig, states.poles_hz(), states.residues(), f);
            let s = c64::new(0.0, 2.0 * PI * f);
            let derivative = match response {
                Response::Displacement => c64::new(1.0, 0.0),
                Response::Velocity => s,
                _ => s * s,
            };
            for d in 0..2 {
                let mut forces = vec![vec![0.0; settle + kept]; 2];
                forces[d] = sine(f, 100.0, rate, settle + kept).unwrap();
                let rec = sim.held_record(format!("{f}-{d}"), &forces).unwrap();
                let at = |y: &[f64]| phasor(&y[settle..], f, rate);
                let force = [at(rec.force(0)), at(rec.force(1))];
                let got = [at(rec.displacement(0)), at(rec.displacement(1))];
                // X = H⁻¹ F for the 2 × 2 H.
                let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
                let x = [
                    (h[1][1] * force[0] - h[0][1] * force[1]) / det,
                    (h[0][0] * force[1] - h[1][0] * force[0]) / det,
                ];
                let expected = [x[0] * derivative, x[1] * derivative];
                let error = ((got[0] - expected[0]).norm().powi(2)
                    + (got[1] - expected[1]).norm().powi(2))
                .sqrt()
                    / (expected[0].norm().powi(2) + expected[1].norm().powi(2)).sqrt();
                assert!(
                    error < EXACT,
                    "{response:?} {f} Hz, direction {d}: {error:e}"
                );
                worst = worst.max(error);
            }
        }
    }
    println!("worst relative error against H(iω)⁻¹ F: {worst:.1e}");
}

/// The impulse response of a 1-DOF system with one state, `m ẍ + c ẋ + k x + A w = f`,
/// `ẇ = ẋ − p w`, sampled without a filter, against classical RK4 on the same ODE with steps of
/// 1 µs (a 200th of a sample; the pulse's edges on the grid), whose own error is of order
/// `(ωh)⁴ ≈ 6·10⁻¹²` for the pulse's `ω = π/2 ms`; without states the records are
/// [`Simulator::new`]'s, bit for bit.
#[test]
fn impulse_response_matches_rk4_of_the_ode() {
    let (m, c, k) = (4.7, 130.0, 1.5e5);
    let (pole_hz, a) = (20.0, 4.0e4);
    let system = Coefficients::new(mat![[m]], mat![[c]], mat![[k]]).unwrap();
    let states = ElementStates::new(vec![pole_hz], vec![mat![[a]]]).unwrap();
    let (rate, samples) = (5000.0, 3000);
    let hit = Impact {
        direction: vec![1.0],
        peak_n: 500.0,
        duration_s: 0.002,
        start_s: 0.01,
    };
    let mut sim = Simulator::with_states(&system, &states, rate, samples, AntiAlias::None).unwrap();
    let rec = sim.record("hit", std::slice::from_ref(&hit)).unwrap();

    let p = 2.0 * PI * pole_hz;
    let force = |t: f64| {
        let u = t - hit.start_s;
        if (0.0..=hit.duration_s).contains(&u) {
            hit.peak_n * (PI * u / hit.duration_s).sin()
        } else {
            0.0
        }
    };
    let rhs = |t: f64, y: [f64; 3]| {
        let [x, v, w] = y;
        [v, (force(t) - c * v - k * x - a * w) / m, v - p * w]
    };
    let steps = 200;
    let h = 1.0 / (rate * steps as f64);
    let mut y = [0.0; 3];
    let mut reference = Vec::with_capacity(samples);
    for n in 0..samples {
        reference.push(y[0]);
        for s in 0..steps {
            let t = (n * steps + s) as f64 * h;
            let add = |y: [f64; 3], k: [f64; 3], f: f64| {
                [y[0] + f * k[0], y[1] + f * k[1], y[2] + f * k[2]]
            };
            let k1 = rhs(t, y);
            let k2 = rhs(t + h / 2.0, add(y, k1, h / 2.0));
            let k3 = rhs(t + h / 2.0, add(y, k2, h / 2.0));
            let k4 = rhs(t + h, add(y, k3, h));
            for i in 0..3 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
    }
    let peak = reference.iter().fold(0.0_f64, |p, v| p.max(v.abs()));
    let worst = rec
        .displacement(0)
        .iter()
        .zip(&reference)
        .fold(0.0_f64, |e, (x, r)| e.max((x - r).abs()))
        / peak;
    println!("impulse response against RK4: worst {worst:.1e} of the peak {peak:.3e} m");
    assert!(worst < 1e-10, "{worst:e}");
    // The state matters: without it the response differs by far more than that.
    let mut plain = Simulator::new(&system, rate, samples, AntiAlias::None).unwrap();
    let without = plain.record("hit", std::slice::from_ref(&hit)).unwrap();
    // No states is `Simulator::new`, bit for bit.
    let mut none = Simulator::with_states(
        &system,
        &ElementStates::default(),
        rate,
        samples,
        AntiAlias::None,
    )
    .unwrap();
    assert_eq!(none.record("hit", &[hit]).unwrap(), without);
    let apart = without
        .displacement(0)
        .iter()
        .zip(&reference)
        .fold(0.0_f64, |e, (x, r)| e.max((x - r).abs()))
        / peak;
    assert!(apart > 0.1, "{apart}");
}

/// States whose residues are zero leave every kind of record as it is without them (to
/// round-off: the simulator's state is larger, so its matrix exponential rounds differently),
/// acceleration responses included; the same states with residues change them.
#[test]
fn zero_residues_change_no_record_kind() {
    let rig = seed_rig();
    let cases: [(Kind, &[(&str, &str)]); 4] = [
        (
            Kind::Impact,
            &[("impacts", "1"), ("response", "acceleration")],
        ),
        (
            Kind::Random,
            &[("records", "1"), ("duration", "1"), ("rate", "1000")],
        ),
        (Kind::SteppedSine, &[("freqs", "20,30,2"), ("rate", "1000")]),
        (
            Kind::Sweep,
            &[("records", "1"), ("rate", "1000"), ("response", "velocity")],
        ),
    ];
    for (kind, options) in cases {
        let setup = |states: &str| {
            let mut s = Setup::default();
            s.kind = kind;
            for (name, value) in options {
                s.set(name, value).unwrap();
            }
            s.set("states", states).unwrap();
            s.run(&rig).unwrap()
        };
        let plain = setup("");
        let zero = setup("20:0,0;0,0|35:0,0;0,0");
        let seal = setup("20:4e4,0;0,3e4|35:0,0;0,0");
        assert_eq!(plain.duration_s, zero.duration_s, "{kind}");
        let mut worst: f64 = 0.0;
        let mut changed: f64 = 0.0;
        for ((p, z), s) in plain.records.iter().zip(&zero.records).zip(&seal.records) {
            for c in 0..2 {
                let (a, b) = (p.displacement(c), z.displacement(c));
                let peak = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                let n = a.len().min(s.len());
                let diff = |x: &[f64], y: &[f64]| {
                    x[..n]
                        .iter()
                        .zip(&y[..n])
                        .fold(0.0_f64, |m, (u, v)| m.max((u - v).abs()))
                        / peak
                };
                worst = worst.max(diff(a, b));
                changed = changed.max(diff(a, s.displacement(c)));
                assert_eq!(p.force(c), z.force(c), "{kind}: the forcing is the same");
            }
        }
        assert!(worst < 1e-12, "{kind}: {worst:e}");
        assert!(changed > 1e-2, "{kind}: {changed:e}");
    }
}

/// A slow state sets the impact records' default length: the response has decayed to `10⁻⁷`
/// of its peak by the end, where the length the system alone would get leaves far more.
#[test]
fn impact_records_last_until_the_states_decay() {
    let rig = seed_rig();
    let mut setup = Setup::default();
    setup.set("impacts", "1").unwrap();
    setup.set("states", "0.5:2e4,0;0,2e4").unwrap();
    let slow = setup.run(&rig).unwrap();
    let alone = 0.022 + 16.2 / slowest_decay(&rig).unwrap();
    let with_states = 0.022 + 16.2 / setup.states.slowest_decay(&rig).unwrap();
    assert!(
        with_states > 3.0 * alone,
        "{with_states} s against {alone} s"
    );
    assert!((slow.duration_s - (with_states * 10.0).ceil() / 10.0).abs() < 1e-12);
    let rate = setup.rate;
    for rec in &slow.records {
        for c in 0..2 {
            let x = rec.displacement(c);
            let peak = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let end = x[x.len() - 1].abs();
            assert!(end < 1e-7 * peak, "{}: {end:e} of {peak:e}", rec.label());
            let early = x[(alone * rate) as usize].abs();
            assert!(
                early > 1e-5 * peak,
                "{}: {early:e} of {peak:e}",
                rec.label()
            );
        }
    }
}

/// Bad states are refused with the parameter or option named: residues of the wrong size for
/// the system, a system that the states leave without decay, states with nonlinear terms.
#[test]
fn bad_states_are_refused() {
    let rig = seed_rig();
    let named = |r: Result<Simulator, Error>| match r {
        Err(Error::InvalidParameter { name, .. }) => name,
        other => panic!("{other:?}"),
    };
    let sdof: ElementStates = "20:4e4".parse().unwrap();
    assert_eq!(
        named(Simulator::with_states(
            &rig,
            &sdof,
            1000.0,
            100,
            AntiAlias::None
        )),
        Parameter::StateResidueSize
    );
    let driving: ElementStates = "20:-6e4,0;0,-6e4".parse().unwrap();
    assert_eq!(
        named(Simulator::with_states(
            &rig,
            &driving,
            1000.0,
            100,
            AntiAlias::None
        )),
        Parameter::StateDecay
    );
    for kind in ["impact", "random"] {
        let mut setup = Setup::default();
        setup.set("kind", kind).unwrap();
        setup.set("states", "20:-6e4,0;0,-6e4").unwrap();
        assert!(matches!(
            setup.run(&rig),
            Err(Error::InvalidParameter {
                name: Parameter::StateDecay,
                ..
            })
        ));
    }
    let mut setup = Setup::default();
    setup.set("kind", "random").unwrap();
    setup.set("cubic", "1e9").unwrap();
    setup.set("states", "20:4e4,0;0,3e4").unwrap();
    assert!(matches!(
        setup.run(&rig),
        Err(Error::InvalidOption {
            option: "states",
            ..
        })
    ));
    assert!(matches!(
        setup.set("states", "20:4e4,0"),
        Err(Error::InvalidOption {
            option: "states",
            ..
        })
    ));
    assert!(matches!(
        setup.set("states", "20:4e4,0;0,nan"),
        Err(Error::InvalidParameter {
            name: Parameter::StateResidue,
            ..
        })
    ));
}

/// Impact records of the seed's rig whose element has one state at 20 Hz,
/// `A = diag(4e4, 3e4)` N/m, with 2 % noise: [`ModelSpec::Auto`] chooses `states:1` and
/// recovers the pole and the residues' diagonal within three of their standard deviations;
/// with the default `kcm` the records are a misfit and the `frequency_dependent` warning names
/// the family that fits.
#[test]
fn impacts_of_an_element_with_a_state_are_identified_as_states_1() {
    let (pole_hz, residue) = (20.0, [4.0e4, 3.0e4]);
    let mut setup = Setup::default();
    setup.set("noise", "0.02").unwrap();
    setup.set("states", "20:4e4,0;0,3e4").unwrap();
    let records = setup.run(&seed_rig()).unwrap().records;
    let identifier = || Identifier::new(8.0, 49.0);

    let id = identifier()
        .model(ModelSpec::Auto)
        .identify(&records)
        .unwrap();
    let model = id.model().expect("an element model");
    let tried: Vec<String> = model
        .selection()
        .iter()
        .map(|c| format!("{} {} p={:?}", c.family, c.verdict, c.p_value))
        .collect();
    println!("tried: {tried:?}");
    assert_eq!(model.family(), Family::States { poles: 1 }, "{tried:?}");
    let (pole, pole_std) = (model.poles_hz()[0], model.poles_hz_std().unwrap()[0]);
    let z = (pole - pole_hz) / pole_std;
    println!("pole {pole:.3} ± {pole_std:.3} Hz ({z:+.2} σ)");
    assert!(z.abs() < 3.0, "pole {pole} ± {pole_std} Hz");
    let (a, a_std) = (model.fit().matrix(3), model.fit().matrix_std(3).unwrap());
    for (i, truth) in residue.iter().enumerate() {
        let z = (a[(i, i)] - truth) / a_std[(i, i)];
        println!(
            "A[{i}][{i}] {:.4e} ± {:.2e} N/m ({z:+.2} σ)",
            a[(i, i)],
            a_std[(i, i)]
        );
        assert!(
            z.abs() < 3.0,
            "A[{i}][{i}] {} ± {}",
            a[(i, i)],
            a_std[(i, i)]
        );
    }

    let kcm = identifier().identify(&records).unwrap();
    let kinds: Vec<&str> = kcm.warnings().iter().map(|w| w.kind()).collect();
    let hint = kcm
        .warnings()
        .iter()
        .find(|w| w.kind() == "frequency_dependent")
        .unwrap_or_else(|| panic!("no frequency_dependent warning: {kinds:?}"));
    assert!(hint.to_string().contains("states:1"), "{hint}");
}
