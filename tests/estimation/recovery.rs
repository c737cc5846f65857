//! Noise-free recovery of M, C, K from simulated time records, through the real DFT path, and
//! closed forms of the impedance.

use crate::common;

use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{Coefficients, Estimator, Identifier, Method};
use common::{EXACT, block_relative_error};
use faer::{c64, mat};
use std::f64::consts::PI;

/// A 3-DOF system with a full, non-symmetric cross-coupling in K and C.
fn three_dof() -> Coefficients {
    Coefficients::new(
        mat![[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]],
        mat![[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
        mat![
            [4.0e4, 6.0e3, -1.0e3],
            [2.0e3, 6.0e4, 5.0e3],
            [-2.0e3, 1.0e3, 9.0e4]
        ],
    )
    .unwrap()
}

fn small_test() -> ImpactTest {
    ImpactTest {
        per_direction: 2,
        sample_rate: 2000.0,
        duration_s: 2.0,
        pulse_s: 0.003,
        ..ImpactTest::seed_rig()
    }
}

#[test]
fn coordinate_transform_of_a_rigid_shaft() {
    // Coefficients at two sensor planes z1 = 0, z2 = 0.2 m; the bearing at zb = 0.1 m sees the
    // mean motion. With x = T q for q = (x_B, tilt), T = [[1, −0.1], [1, 0.1]].
    let t = mat![[1.0, -0.1], [1.0, 0.1]];
    let sensors = Coefficients::new(
        mat![[2.0, 0.0], [0.0, 3.0]],
        mat![[10.0, 0.0], [0.0, 20.0]],
        mat![[1.0e4, 0.0], [0.0, 2.0e4]],
    )
    .unwrap();
    let q = sensors.transform(t.as_ref()).unwrap();
    // Translation: M_qq = Σ m = 5; tilt: Σ m z² = 2·0.01 + 3·0.01; coupling Σ m z = −0.2 + 0.3.
    assert!((q.mass()[(0, 0)] - 5.0).abs() < 1e-12);
    assert!((q.mass()[(1, 1)] - 0.05).abs() < 1e-12);
    assert!((q.mass()[(0, 1)] - 0.1).abs() < 1e-12);
    assert!((q.stiffness()[(0, 0)] - 3.0e4).abs() < 1e-9);
    // The record-level helpers agree with x_B = (x1 + x2)/2 here.
    let xb = bearing_ident::records::two_plane_to_bearing(&[1.0], &[3.0], 0.0, 0.2, 0.1).unwrap();
    assert!((xb[0] - 2.0).abs() < 1e-15);
}

#[test]
fn sdof_impedance_closed_form() {
    let (m, c, k) = (4.7, 132.0, 146.3e3);
    let sdof = Coefficients::new(mat![[m]], mat![[c]], mat![[k]]).unwrap();
    for f in [1.0, 28.08, 49.0] {
        let w = 2.0 * PI * f;
        let h = sdof.impedance_at(f)[(0, 0)];
        assert!((h - c64::new(k - w * w * m, w * c)).norm() < 1e-9);
        let g = sdof.flexibility_at(f).unwrap()[(0, 0)];
        assert!((g * c64::new(k - w * w * m, w * c) - c64::new(1.0, 0.0)).norm() < 1e-12);
    }
}

#[test]
fn two_dof_flexibility_closed_form() {
    // G = adj(H)/det(H) (seed eq. 11).
    let sys = seed_rig();
    let f = 29.0;
    let h = sys.impedance_at(f);
    let det = h[(0, 0)] * h[(1, 1)] - h[(0, 1)] * h[(1, 0)];
    let g = sys.flexibility_at(f).unwrap();
    assert!((g[(0, 0)] - h[(1, 1)] / det).norm() < 1e-12 * g[(0, 0)].norm());
    assert!((g[(0, 1)] + h[(0, 1)] / det).norm() < 1e-12 * g[(0, 0)].norm());
    assert!((g[(1, 0)] + h[(1, 0)] / det).norm() < 1e-12 * g[(0, 0)].norm());
    assert!((g[(1, 1)] - h[(0, 0)] / det).norm() < 1e-12 * g[(0, 0)].norm());
}

#[test]
fn measured_flexibility_of_simulated_records_matches_the_model() {
    let truth = seed_rig();
    let records = ImpactTest {
        per_direction: 1,
        ..ImpactTest::seed_rig()
    }
    .run(&truth)
    .unwrap();
    let id = Identifier::new(8.0, 49.0)
        .method(Method::LeastSquares)
        .identify(&records)
        .unwrap();
    let frf = id.frf();
    for k in 0..frf.line_count() {
        let model = truth.flexibility_at(frf.freqs_hz()[k]).unwrap();
        let scale = model.norm_l2();
        for i in 0..2 {
            for j in 0..2 {
                let err = (frf.flexibility(k)[(i, j)] - model[(i, j)]).norm() / scale;
                assert!(err < EXACT, "line {k} G[{i}{j}] error {err:e}");
            }
        }
    }
}

#[test]
fn noise_free_seed_rig_by_every_method_and_estimator() {
    let truth = seed_rig();
    let records = ImpactTest::seed_rig().run(&truth).unwrap();
    for estimator in [Estimator::PairedSets, Estimator::H1] {
        for method in [Method::Direct, Method::LeastSquares, Method::Ivf] {
            let id = Identifier::new(8.0, 49.0)
                .estimator(estimator)
                .method(method)
                .identify(&records)
                .unwrap();
            let err = block_relative_error(id.coefficients(), &truth);
            println!("{estimator:?} {method}: {err:.3e}");
            assert!(err < EXACT, "{estimator:?} {method}: {err:e}");
            assert!(id.converged());
            assert!(id.warnings().is_empty(), "{:?}", id.warnings());
        }
    }
}

#[test]
fn noise_free_three_dof_cross_coupled() {
    let truth = three_dof();
    let records = small_test().run(&truth).unwrap();
    for method in [Method::LeastSquares, Method::Ivf] {
        let id = Identifier::new(3.0, 60.0)
            .method(method)
            .identify(&records)
            .unwrap();
        let err = block_relative_error(id.coefficients(), &truth);
        println!("3-DOF {method}: {err:.3e}");
        assert!(err < EXACT, "{method}: {err:e}");
        let r2 = id.fit_r2();
        for i in 0..3 {
            for j in 0..3 {
                assert!(r2[(i, j)] > 1.0 - 1e-9, "r2[{i}{j}] = {}", r2[(i, j)]);
            }
        }
    }
}

#[test]
fn modes_of_the_identified_system_match_the_truth() {
    let truth = seed_rig();
    let records = ImpactTest {
        per_direction: 1,
        ..ImpactTest::seed_rig()
    }
    .run(&truth)
    .unwrap();
    let id = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    for (a, b) in id.modes().unwrap().iter().zip(truth.modes().unwrap()) {
        assert!((a.natural_frequency_hz / b.natural_frequency_hz - 1.0).abs() < EXACT);
        assert!((a.damping_ratio / b.damping_ratio - 1.0).abs() < EXACT);
    }
}

#[test]
fn baseline_subtraction_recovers_the_bearing() {
    // Dry structure alone (lightly damped: records of 6.5 s so that it decays), then structure
    // plus a squeeze-film damper with cross-coupled stiffness; the difference is the bearing.
    let dry = Coefficients::new(
        mat![[4.7, 0.0], [0.0, 4.8]],
        mat![[22.3, 0.0], [0.0, 22.3]],
        mat![[146.3e3, 0.0], [0.0, 169.1e3]],
    )
    .unwrap();
    let bearing = Coefficients::new(
        mat![[0.3, 0.0], [0.0, 0.3]],
        mat![[109.68, 3.0], [-3.0, 109.68]],
        mat![[5.0e3, 2.0e3], [-2.0e3, 5.0e3]],
    )
    .unwrap();
    let add = |a: faer::MatRef<'_, f64>, b: faer::MatRef<'_, f64>| a + b;
    let lubricated = Coefficients::new(
        add(dry.mass(), bearing.mass()),
        add(dry.damping(), bearing.damping()),
        add(dry.stiffness(), bearing.stiffness()),
    )
    .unwrap();
    let test = ImpactTest {
        per_direction: 1,
        duration_s: 6.5,
        ..ImpactTest::seed_rig()
    };
    let identify = |sys: &Coefficients| {
        let records = test.run(sys).unwrap();
        Identifier::new(8.0, 49.0)
            .identify(&records)
            .unwrap()
            .coefficients()
            .clone()
    };
    let found = identify(&lubricated).subtract(&identify(&dry)).unwrap();
    // The same through the identifications, which check that both were processed alike.
    let full = |sys: &Coefficients| {
        Identifier::new(8.0, 49.0)
            .identify(&test.run(sys).unwrap())
            .unwrap()
    };
    let (via_ids, _) = full(&lubricated).subtract_baseline(&full(&dry)).unwrap();
    assert_eq!(via_ids, found);
    let other_band = Identifier::new(8.0, 45.0)
        .identify(&test.run(&dry).unwrap())
        .unwrap();
    assert_eq!(
        full(&lubricated)
            .subtract_baseline(&other_band)
            .unwrap_err(),
        bearing_ident::Error::BaselineMismatch {
            what: bearing_ident::error::BaselineField::Band
        }
    );
    // Errors scale with the system identified, so each block is judged against the
    // lubricated system's block norm.
    let scale = common::blocks(&lubricated).map(|b| b.norm_l2());
    for ((g, t), s) in common::blocks(&found)
        .iter()
        .zip(common::blocks(&bearing))
        .zip(scale)
    {
        for i in 0..2 {
            for j in 0..2 {
                let err = (g[(i, j)] - t[(i, j)]).abs() / s;
                assert!(err < EXACT, "element ({i},{j}): {err:e}");
            }
        }
    }
}
