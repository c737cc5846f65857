//! The reverse path against known truth: records of a 2-DOF rig with nonlinear elements, the
//! displacement prescribed and the force computed exactly (`common/nonlinear_records.rs`), 2 %
//! noise on force and displacement channels.
//!
//! Bounds: each coefficient within [`SIGMAS`] of its own jackknife standard deviation of the
//! truth, and that standard deviation itself small ([`MAX_RELATIVE_STD`] of the value), so a
//! test cannot pass on a wide error bar. The linear-only fit of the same data must be off by
//! many of its standard deviations.

use crate::common::nonlinear_records;

use crate::common::block_errors;
use bearing_ident::nonlinear::{Differentiation, Regressor, ReversePath, Term};
use bearing_ident::{Error, Record, Response};
use nonlinear_records::rig;

/// Coefficients must lie within this many jackknife standard deviations of the truth.
const SIGMAS: f64 = 4.0;
/// A jackknife standard deviation must be below this fraction of the coefficient.
const MAX_RELATIVE_STD: f64 = 0.03;
/// The identification band (Hz), inside the prescribed 5–80 Hz.
const BAND: (f64, f64) = (10.0, 60.0);

fn coulomb(dof: usize) -> Term {
    Term {
        regressor: Regressor::Coulomb,
        dof: Some(dof),
    }
}

fn term(regressor: Regressor, dof: usize) -> Term {
    Term {
        regressor,
        dof: Some(dof),
    }
}

/// Checks every term and M, C, K against the truth; returns the relative errors of the terms.
fn assert_recovered(
    id: &bearing_ident::nonlinear::NonlinearIdentification,
    truth: &[(Term, f64)],
    system: &bearing_ident::Coefficients,
) -> Vec<f64> {
    assert_eq!(id.terms().len(), truth.len());
    let mut errors = Vec::new();
    for (est, (t, value)) in id.terms().iter().zip(truth) {
        assert_eq!(est.term, *t);
        let std = est.std.expect("jackknife std");
        let err = est.value - value;
        eprintln!(
            "{}: {:.6e} ± {:.2e} (truth {:.6e}, {:+.3} %)",
            t.label(),
            est.value,
            std,
            value,
            100.0 * err / value
        );
        assert!(
            std < MAX_RELATIVE_STD * value.abs(),
            "{}: std {std:e}",
            t.label()
        );
        assert!(
            err.abs() < SIGMAS * std,
            "{}: error {err:e} vs std {std:e}",
            t.label()
        );
        errors.push(err / value);
    }
    let got = id.coefficients();
    let std = id.std_dev().expect("jackknife std of M, C, K");
    fn blocks(c: &bearing_ident::Coefficients) -> [faer::MatRef<'_, f64>; 3] {
        [c.mass(), c.damping(), c.stiffness()]
    }
    for ((g, s), t) in blocks(got).iter().zip(blocks(std)).zip(blocks(system)) {
        for i in 0..2 {
            for j in 0..2 {
                let err = g[(i, j)] - t[(i, j)];
                assert!(
                    err.abs() < SIGMAS * s[(i, j)] + 1e-3 * t.norm_l2(),
                    "({i},{j}): {} vs {} ± {}",
                    g[(i, j)],
                    t[(i, j)],
                    s[(i, j)]
                );
            }
        }
    }
    eprintln!("M, C, K block errors: {:?}", block_errors(got, system));
    for check in id.checks() {
        assert!(!check.misfit, "{check:?}");
    }
    assert!(
        id.warnings().iter().all(|w| w.kind() != "nonlinear_misfit"),
        "{:?}",
        id.warnings()
    );
    errors
}

#[test]
fn coulomb_friction_per_dof_is_recovered_with_m_c_k() {
    let truth = vec![(coulomb(0), 0.8), (coulomb(1), 0.5)];
    let test = rig(truth.clone());
    let records = test.run();
    let id = ReversePath::new(BAND.0, BAND.1, &[Regressor::Coulomb])
        .identify(&records)
        .unwrap();
    assert_recovered(&id, &truth, &test.system);
    assert_eq!(id.velocity().differentiation, Differentiation::Wiener);
    assert_eq!(id.velocity().sources, [Response::Displacement]);
    assert!(id.min_output_coherence() > 0.9);
    eprintln!("timings: {:?}", id.timings());
}

#[test]
fn planar_friction_is_recovered() {
    let planar = Term {
        regressor: Regressor::CoulombPlanar,
        dof: None,
    };
    let truth = vec![(planar, 0.8)];
    let test = rig(truth.clone());
    let id = ReversePath::new(BAND.0, BAND.1, &[Regressor::CoulombPlanar])
        .identify(&test.run())
        .unwrap();
    assert_recovered(&id, &truth, &test.system);
}

#[test]
fn cubic_stiffness_is_recovered() {
    let truth = vec![
        (term(Regressor::Cubic, 0), 1.0e14),
        (term(Regressor::Cubic, 1), 0.6e14),
    ];
    let test = rig(truth.clone());
    let id = ReversePath::new(BAND.0, BAND.1, &[Regressor::Cubic])
        .identify(&test.run())
        .unwrap();
    assert_recovered(&id, &truth, &test.system);
}

#[test]
fn quadratic_damping_is_recovered() {
    let truth = vec![
        (term(Regressor::QuadraticDamping, 0), 1.5e4),
        (term(Regressor::QuadraticDamping, 1), 1.0e4),
    ];
    let test = rig(truth.clone());
    let id = ReversePath::new(BAND.0, BAND.1, &[Regressor::QuadraticDamping])
        .identify(&test.run())
        .unwrap();
    assert_recovered(&id, &truth, &test.system);
}

#[test]
fn measured_velocities_are_used_directly() {
    let truth = vec![(coulomb(0), 0.8), (coulomb(1), 0.5)];
    let test = rig(truth.clone());
    // The same kind of motion, recorded by velocity probes (v exact for the multisine).
    let mut rng = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(77);
    let velocity_records: Vec<Record> = (0..test.records)
        .map(|r| {
            let clean = test.clean_record(&format!("v-{r}"), &mut rng);
            let n = clean.dofs();
            // v from the displacement's own spectrum (exact for the multisine).
            let v: Vec<Vec<f64>> = (0..n)
                .map(|i| exact_derivative(clean.displacement(i), clean.sample_rate()))
                .collect();
            let forces = (0..n).map(|i| clean.force(i).to_vec()).collect();
            let rec = Record::new(clean.label(), clean.sample_rate(), forces, v)
                .unwrap()
                .with_responses(vec![Response::Velocity; n])
                .unwrap();
            bearing_ident::simulate::add_noise(&rec, 0.02, &mut rng).unwrap()
        })
        .collect();
    let id = ReversePath::new(BAND.0, BAND.1, &[Regressor::Coulomb])
        .identify(&velocity_records)
        .unwrap();
    assert_eq!(id.velocity().sources, [Response::Velocity]);
    assert_recovered(&id, &truth, &test.system);
}

/// The derivative of a periodic band-limited signal by its DFT (exact for the multisines).
fn exact_derivative(x: &[f64], fs: f64) -> Vec<f64> {
    use faer::c64;
    let n = x.len();
    let mut planner = realfft::RealFftPlanner::<f64>::new();
    let (fwd, inv) = (planner.plan_fft_forward(n), planner.plan_fft_inverse(n));
    let mut input = x.to_vec();
    let mut spec = fwd.make_output_vec();
    fwd.process(&mut input, &mut spec).unwrap();
    let dw = std::f64::consts::TAU * fs / n as f64;
    for (k, s) in spec.iter_mut().enumerate() {
        *s = *s * c64::new(0.0, dw * k as f64) / n as f64;
    }
    spec[0] = c64::new(0.0, 0.0);
    spec[n / 2] = c64::new(0.0, 0.0);
    let mut out = vec![0.0; n];
    inv.process(&mut spec, &mut out).unwrap();
    out
}

#[test]
fn the_linear_only_fit_of_friction_data_is_biased() {
    let truth = vec![(coulomb(0), 0.8), (coulomb(1), 0.5)];
    let test = rig(truth.clone());
    let records = test.run();
    let linear = ReversePath::new(BAND.0, BAND.1, &[])
        .identify(&records)
        .unwrap();
    let full = ReversePath::new(BAND.0, BAND.1, &[Regressor::Coulomb])
        .identify(&records)
        .unwrap();
    let c_true = test.system.damping();
    let k_true = test.system.stiffness();
    for i in 0..2 {
        let c_lin = linear.coefficients().damping()[(i, i)];
        let c_std = linear.std_dev().unwrap().damping()[(i, i)];
        let c_full = full.coefficients().damping()[(i, i)];
        let k_lin = linear.coefficients().stiffness()[(i, i)];
        let k_full = full.coefficients().stiffness()[(i, i)];
        eprintln!(
            "C[{i}{i}]: linear-only {:+.1} %, with coulomb {:+.2} %; K[{i}{i}]: linear-only {:+.2} %, with coulomb {:+.3} %",
            100.0 * (c_lin / c_true[(i, i)] - 1.0),
            100.0 * (c_full / c_true[(i, i)] - 1.0),
            100.0 * (k_lin / k_true[(i, i)] - 1.0),
            100.0 * (k_full / k_true[(i, i)] - 1.0),
        );
        // Friction looks like extra damping: C high by many standard deviations.
        assert!(
            c_lin - c_true[(i, i)] > 10.0 * c_std,
            "C[{i}{i}] {c_lin} ± {c_std}"
        );
        assert!((c_lin - c_true[(i, i)]).abs() > 5.0 * (c_full - c_true[(i, i)]).abs());
    }
}

#[test]
fn a_wrong_regressor_is_flagged_by_the_check() {
    let truth = vec![(coulomb(0), 0.8), (coulomb(1), 0.5)];
    let records = rig(truth).run();
    let id = ReversePath::new(BAND.0, BAND.1, &[Regressor::Cubic])
        .identify(&records)
        .unwrap();
    for (t, c) in id.terms().iter().zip(id.checks()) {
        eprintln!(
            "{}: {:.4e}, Im/Re {:.3} ({:.1} σ), slope {:.3} ({:.1} σ), input coherence {:.3}",
            t.term.label(),
            t.value,
            c.imaginary_ratio,
            c.imaginary_sigmas,
            c.slope,
            c.slope_sigmas,
            c.input_coherence
        );
    }
    assert!(id.checks().iter().all(|c| c.misfit), "{:?}", id.checks());
    let misfits = id
        .warnings()
        .iter()
        .filter(|w| w.kind() == "nonlinear_misfit")
        .count();
    assert_eq!(misfits, 2, "{:?}", id.warnings());
}

#[test]
fn too_few_averages_is_a_typed_error() {
    let mut test = rig(vec![(coulomb(0), 0.8)]);
    test.records = 1;
    test.len = 4096;
    let records = test.run();
    // 4096 samples in 1024-sample segments: 7 averages for 2 + 2 inputs, 8 needed.
    let e = ReversePath::new(BAND.0, BAND.1, &[Regressor::Coulomb])
        .segment_len(1024)
        .identify(&records)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::TooFewAverages {
                averages: 7,
                inputs: 4,
                required: 8
            }
        ),
        "{e:?}"
    );
    assert_eq!(e.kind(), "record_too_short");
    let e = ReversePath::new(BAND.0, BAND.1, &[])
        .identify(&[])
        .unwrap_err();
    assert_eq!(e, Error::NoRecords);
}

#[test]
fn planar_friction_needs_two_dofs() {
    let mut test = rig(vec![]);
    test.system = bearing_ident::Coefficients::new(
        faer::mat![[4.7]],
        faer::mat![[220.0]],
        faer::mat![[146.3e3]],
    )
    .unwrap();
    test.len = 8192;
    let e = ReversePath::new(BAND.0, BAND.1, &[Regressor::CoulombPlanar])
        .identify(&test.run())
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::InvalidParameter {
                name: bearing_ident::Parameter::DegreesOfFreedomForCoulombPlanar,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn nan_and_overflow_never_reach_a_result() {
    let mut test = rig(vec![]);
    test.len = 8192;
    let records = test.run();
    // A NaN band, a NaN cutoff.
    let e = ReversePath::new(f64::NAN, 60.0, &[Regressor::Cubic])
        .identify(&records)
        .unwrap_err();
    assert_eq!(e.kind(), "bad_band");
    let e = ReversePath::new(10.0, 60.0, &[Regressor::Coulomb])
        .differentiation(Differentiation::Cutoff(f64::NAN))
        .identify(&records)
        .unwrap_err();
    assert_eq!(e.kind(), "invalid_argument");
    // A NaN sample is refused by the record itself.
    let mut x = records[0].displacement(0).to_vec();
    x[100] = f64::NAN;
    let e = Record::new(
        "nan",
        1024.0,
        vec![records[0].force(0).to_vec(), records[0].force(1).to_vec()],
        vec![x, records[0].displacement(1).to_vec()],
    )
    .unwrap_err();
    assert_eq!(e.kind(), "non_finite");
    // Displacements in nanometres of 1e110 m: finite samples whose cubes are not.
    let huge: Vec<Record> = records
        .iter()
        .map(|r| {
            Record::new(
                r.label(),
                r.sample_rate(),
                (0..2).map(|i| r.force(i).to_vec()).collect(),
                (0..2)
                    .map(|i| r.displacement(i).iter().map(|v| v * 1e115).collect())
                    .collect(),
            )
            .unwrap()
        })
        .collect();
    let e = ReversePath::new(10.0, 60.0, &[Regressor::Cubic])
        .identify(&huge)
        .unwrap_err();
    assert!(
        matches!(&e, Error::NonFiniteRegressor { record, term, .. } if record == "nl-0" && term == "cubic[0]"),
        "{e:?}"
    );
    assert_eq!(e.kind(), "non_finite");
}
