//! Field identification against known truth: a two-disk beam rotor (six degrees of freedom per
//! node, as ROSS builds them) on speed-dependent, cross-coupled bearings; imbalance responses
//! simulated by the forward problem; bearings recovered noise-free to 1e-6 relative with probes
//! at the bearings and one node inboard, with noise inside their error bars, and the singular
//! cases refused or warned about.

use crate::common::field_rig;
use bearing_ident::error::FieldError;

use bearing_ident::field::{
    self, BearingCoefficients, FieldIdentification, FieldTests, RotorModel,
};
use bearing_ident::{Error, Warning};
use field_rig::{at, bearings, isotropic, probes, rotor, runs};

/// Largest relative error of any element of K and C, any bearing, any speed.
fn worst_error(id: &FieldIdentification, law: impl Fn(usize, f64) -> BearingCoefficients) -> f64 {
    let mut worst: f64 = 0.0;
    for (b, brg) in id.bearings().iter().enumerate() {
        for (s, &w) in id.speeds_rad_s().iter().enumerate() {
            let c = brg.coefficients[s].expect("identified");
            let truth = law(b, w);
            for i in 0..2 {
                for j in 0..2 {
                    worst = worst
                        .max((c.stiffness[i][j] / truth.stiffness[i][j] - 1.0).abs())
                        .max((c.damping[i][j] / truth.damping[i][j] - 1.0).abs());
                }
            }
        }
    }
    worst
}

#[test]
fn recovers_bearings_noise_free_with_probes_at_the_bearings() {
    let rotor = rotor();
    let tests = runs([0, 7], 0.0, 1).simulate(&rotor, bearings).unwrap();
    let id = field::identify(&rotor, &tests).unwrap();
    let worst = worst_error(&id, bearings);
    eprintln!("probes at the bearings: worst relative error {worst:.3e}");
    assert!(worst < 1e-6, "{worst:e}");
    assert_eq!(id.speeds_rad_s().len(), 14);
    assert!(id.model_residual().iter().all(|r| r.unwrap() < 1e-10));
    for b in id.bearings() {
        assert!(b.condition_number.iter().all(|&c| (1.0..30.0).contains(&c)));
    }
    // Only the speeds next to the pinned critical speeds (397.9, 416.3 rad/s) are flagged.
    assert!(
        id.warnings().iter().all(|w| match w {
            Warning::NearPinnedCritical { speed_rad_s, .. } => [400.0, 425.0].contains(speed_rad_s),
            Warning::HighNoiseGain { speeds_rad_s, .. } => speeds_rad_s == &[400.0],
            _ => false,
        }),
        "{:?}",
        id.warnings()
    );
}

#[test]
fn recovers_bearings_noise_free_with_probes_one_node_inboard() {
    let rotor = rotor();
    let tests = runs([1, 6], 0.0, 1).simulate(&rotor, bearings).unwrap();
    let id = field::identify(&rotor, &tests).unwrap();
    let worst = worst_error(&id, bearings);
    eprintln!("probes one node inboard: worst relative error {worst:.3e}");
    assert!(worst < 1e-6, "{worst:e}");
    // Inboard probes recover the bearing force through the stiff shaft end: noise costs more.
    let at_bearings = field::identify(
        &rotor,
        &runs([0, 7], 0.0, 1).simulate(&rotor, bearings).unwrap(),
    )
    .unwrap();
    let median_gain = |id: &FieldIdentification| {
        let mut g: Vec<f64> = id.bearings()[1]
            .coefficients
            .iter()
            .map(|c| c.unwrap().noise_gain)
            .collect();
        g.sort_by(f64::total_cmp);
        g[g.len() / 2]
    };
    let (inboard, at) = (median_gain(&id), median_gain(&at_bearings));
    eprintln!("median noise gain: {at:.1} at the bearings, {inboard:.1} one node inboard");
    assert!(inboard > 3.0 * at, "{inboard} vs {at}");
    // At the bearings, the gain peaks at 400 rad/s, next to the pinned critical speed 397.9.
    let gain = |s: usize| {
        at_bearings.bearings()[0].coefficients[s]
            .unwrap()
            .noise_gain
    };
    assert!(gain(2) > 10.0 * gain(6), "{} vs {}", gain(2), gain(6));
    assert!(
        at_bearings
            .warnings()
            .iter()
            .any(|w| w.kind() == "high_noise_gain")
    );
}

#[test]
fn extra_probes_give_a_residual_that_sees_a_wrong_model() {
    let rotor = rotor();
    let mut plan = runs([0, 7], 0.0, 1);
    plan.probes.extend(probes([3, 4]));
    let tests = plan.simulate(&rotor, bearings).unwrap();
    let id = field::identify(&rotor, &tests).unwrap();
    assert!(worst_error(&id, bearings) < 1e-6);
    assert!(id.model_residual().iter().all(|r| r.unwrap() < 1e-10));
    // The same responses against a rotor 5 % stiffer: the residual says so.
    let stiff = RotorModel::new(
        6,
        field::DOF_NAMES.iter().map(|s| (*s).to_owned()).collect(),
        rotor.mass().clone(),
        rotor.stiffness() * 1.05,
        rotor.gyroscopic().clone(),
        None,
        rotor.bearings().to_vec(),
    )
    .unwrap();
    let wrong = field::identify(&stiff, &tests).unwrap();
    eprintln!(
        "residuals against a 5 % stiffer rotor: {:?}",
        wrong.model_residual()
    );
    assert!(wrong.model_residual().iter().all(|r| r.unwrap() > 1e-6));
}

/// With redundant probes and stated noise, the residual is judged against the noise: about 1
/// when the rotor model fits, far above when it does not (`model_residual`).
#[test]
fn the_residual_is_judged_against_the_stated_noise() {
    let rotor = rotor();
    let mut plan = runs([0, 7], 0.01, 5);
    plan.probes.extend(probes([3, 4]));
    let tests = plan.simulate(&rotor, bearings).unwrap();
    let id = field::identify(&rotor, &tests).unwrap();
    let ratios: Vec<f64> = id.residual_ratio().iter().map(|r| r.unwrap()).collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    eprintln!("residual / expected, right model: mean {mean:.3}, {ratios:.3?}");
    assert!((0.7..1.3).contains(&mean), "{mean}");
    let kinds: Vec<&str> = id.warnings().iter().map(Warning::kind).collect();
    assert!(!kinds.contains(&"model_residual"), "{kinds:?}");
    // A 5 % stiffness error in the model leaves a residual of 4e-5 (noise-free, the test above),
    // far below what 1 % noise leaves: not visible, and not called a misfit.
    // Responses written with the opposite phase convention, x = Re(q e^{−iΩt}), are: the
    // conjugates satisfy no rotor model with gyroscopic terms and damping.
    let mut conjugated = tests.clone();
    for r in &mut conjugated.responses {
        r.value = r.value.conj();
    }
    let wrong = field::identify(&rotor, &conjugated).unwrap();
    let worst = wrong
        .residual_ratio()
        .iter()
        .map(|r| r.unwrap())
        .fold(0.0, f64::max);
    eprintln!("conjugated responses: worst ratio {worst:.3e}");
    let kinds: Vec<&str> = wrong.warnings().iter().map(Warning::kind).collect();
    assert!(kinds.contains(&"model_residual"), "{kinds:?}");
    // Without redundant probes the residual is zero whatever the model: no ratio.
    let square = runs([0, 7], 0.01, 5).simulate(&rotor, bearings).unwrap();
    let id = field::identify(&rotor, &square).unwrap();
    assert!(id.residual_ratio().iter().all(Option::is_none));
}

#[test]
fn one_percent_noise_lies_within_the_error_bars() {
    let rotor = rotor();
    let tests = runs([0, 7], 0.01, 7).simulate(&rotor, bearings).unwrap();
    let id = field::identify(&rotor, &tests).unwrap();
    let (mut inside, mut total, mut worst_z) = (0, 0, 0.0f64);
    for (b, brg) in id.bearings().iter().enumerate() {
        for (s, &w) in id.speeds_rad_s().iter().enumerate() {
            let c = brg.coefficients[s].unwrap();
            let (sk, sc) = (c.stiffness_std.unwrap(), c.damping_std.unwrap());
            let t = bearings(b, w);
            for i in 0..2 {
                for j in 0..2 {
                    for z in [
                        (c.stiffness[i][j] - t.stiffness[i][j]) / sk[i][j],
                        (c.damping[i][j] - t.damping[i][j]) / sc[i][j],
                    ] {
                        worst_z = worst_z.max(z.abs());
                        total += 1;
                        inside += usize::from(z.abs() < 1.96);
                    }
                }
            }
        }
    }
    let coverage = inside as f64 / total as f64;
    eprintln!("one draw: coverage {coverage:.3} of {total}, worst |z| {worst_z:.2}");
    assert!(worst_z < 5.0, "{worst_z}");
    assert!(coverage > 0.85, "{coverage}");
}

#[test]
fn repeats_give_error_bars_without_stated_noise() {
    let rotor = rotor();
    let mut plan = runs([0, 7], 0.01, 3);
    plan.repeats = 4;
    let mut tests = plan.simulate(&rotor, bearings).unwrap();
    for r in &mut tests.responses {
        r.std = None;
    }
    let id = field::identify(&rotor, &tests).unwrap();
    let c = id.bearings()[0].coefficients[5].unwrap();
    let truth = bearings(0, 475.0);
    let sk = c.stiffness_std.unwrap();
    assert!(sk[0][0] > 0.0 && ((c.stiffness[0][0] - truth.stiffness[0][0]) / sk[0][0]).abs() < 5.0);
    // Without repeats or stated noise, no error bars.
    let mut plan = runs([0, 7], 0.01, 3);
    plan.repeats = 1;
    let mut tests = plan.simulate(&rotor, bearings).unwrap();
    tests.responses.iter_mut().for_each(|r| r.std = None);
    let id = field::identify(&rotor, &tests).unwrap();
    assert!(
        id.bearings()[0].coefficients[5]
            .unwrap()
            .stiffness_std
            .is_none()
    );
}

/// Release only: coverage of the first-order 95 % intervals over 400 draws: 1 % response noise
/// with probes at the bearings; 0.1 % with probes one node inboard, where the recovery of the
/// bearing force through the stiff shaft end (about 100 × the bearing's stiffness) raises the
/// noise gain from about 5 to 20–290, so that 1 % noise leaves the first-order regime
/// (relative errors of tens of percent).
#[test]
#[ignore = "release only: 400 Monte-Carlo draws"]
fn error_bars_cover_at_their_nominal_rate() {
    let rotor = rotor();
    for (probe_nodes, noise) in [([0, 7], 0.01), ([1, 6], 0.001)] {
        let (mut inside, mut total) = (0usize, 0usize);
        for seed in 0..400 {
            let tests = runs(probe_nodes, noise, 1000 + seed)
                .simulate(&rotor, bearings)
                .unwrap();
            let id = field::identify(&rotor, &tests).unwrap();
            for (b, brg) in id.bearings().iter().enumerate() {
                for (s, &w) in id.speeds_rad_s().iter().enumerate() {
                    let c = brg.coefficients[s].unwrap();
                    let (sk, sc) = (c.stiffness_std.unwrap(), c.damping_std.unwrap());
                    let t = bearings(b, w);
                    for i in 0..2 {
                        for j in 0..2 {
                            for z in [
                                (c.stiffness[i][j] - t.stiffness[i][j]) / sk[i][j],
                                (c.damping[i][j] - t.damping[i][j]) / sc[i][j],
                            ] {
                                total += 1;
                                inside += usize::from(z.abs() < 1.959964);
                            }
                        }
                    }
                }
            }
        }
        let coverage = inside as f64 / total as f64;
        eprintln!(
            "probes at nodes {probe_nodes:?}, noise {noise}: coverage {coverage:.4} of {total}"
        );
        assert!((0.93..=0.97).contains(&coverage), "{coverage}");
    }
}

#[test]
fn masses_in_one_plane_are_rank_deficient_or_warned() {
    let rotor = rotor();
    let mut plan = runs([0, 7], 0.0, 1);
    plan.added = [at(2, 1e-4, 0.0), at(2, 2e-4, 1.2)];
    let tests = plan.simulate(&rotor, bearings).unwrap();
    let e = field::identify(&rotor, &tests).unwrap_err();
    assert_eq!(e.kind(), "rank_deficient", "{e}");
    // The error says why: the forces are proportional, and angles do not help.
    assert!(
        matches!(
            e,
            Error::Field(FieldError::RankDeficient {
                dependent_tests: true,
                ..
            })
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("another plane"), "{e}");
    // With noise the pair is merely ill-conditioned: the tests are flagged dependent.
    plan.noise = 0.01;
    let tests = plan.simulate(&rotor, bearings).unwrap();
    let id = field::identify(&rotor, &tests).unwrap();
    let kinds: Vec<&str> = id.warnings().iter().map(Warning::kind).collect();
    assert!(kinds.contains(&"dependent_tests"), "{kinds:?}");
    assert!(kinds.contains(&"ill_conditioned_pair"), "{kinds:?}");
}

#[test]
fn isotropic_supports_give_circular_orbits_and_rank_deficient() {
    let rotor = rotor();
    let tests = runs([0, 7], 0.0, 1).simulate(&rotor, isotropic).unwrap();
    let e = field::identify(&rotor, &tests).unwrap_err();
    assert!(
        matches!(
            e,
            Error::Field(FieldError::RankDeficient {
                dependent_tests: false,
                ..
            })
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("circular"), "{e}");
}

#[test]
fn a_speed_near_a_pinned_critical_speed_is_warned() {
    let rotor = rotor();
    let id = field::identify(
        &rotor,
        &runs([0, 7], 0.0, 1).simulate(&rotor, bearings).unwrap(),
    )
    .unwrap();
    let critical = id.pinned_critical_speeds()[0];
    eprintln!(
        "pinned critical speeds: {:?}",
        &id.pinned_critical_speeds()[..4]
    );
    let mut plan = runs([0, 7], 0.0, 1);
    plan.speeds_rad_s = vec![0.5 * critical, 1.01 * critical];
    let id = field::identify(&rotor, &plan.simulate(&rotor, bearings).unwrap()).unwrap();
    let near: Vec<f64> = id
        .warnings()
        .iter()
        .filter_map(|w| match w {
            Warning::NearPinnedCritical { speed_rad_s, .. } => Some(*speed_rad_s),
            _ => None,
        })
        .collect();
    assert_eq!(near, vec![1.01 * critical]);
}

#[test]
fn too_few_probes_and_missing_responses_are_refused() {
    let rotor = rotor();
    let mut plan = runs([0, 7], 0.0, 1);
    plan.probes.truncate(3);
    let e = field::identify(&rotor, &plan.simulate(&rotor, bearings).unwrap()).unwrap_err();
    assert_eq!(e.kind(), "underdetermined", "{e}");
    let mut tests: FieldTests = runs([0, 7], 0.0, 1).simulate(&rotor, bearings).unwrap();
    tests.responses.remove(17);
    let e = field::identify(&rotor, &tests).unwrap_err();
    assert_eq!(e.kind(), "missing_response", "{e}");
    let mut tests = runs([0, 7], 0.0, 1).simulate(&rotor, bearings).unwrap();
    tests.responses[3].value.im = f64::NAN;
    assert_eq!(
        field::identify(&rotor, &tests).unwrap_err().kind(),
        "non_finite"
    );
}

#[test]
fn constant_fit_over_speeds_summarises_the_trends() {
    let rotor = rotor();
    let tests = runs([0, 7], 0.0, 1).simulate(&rotor, bearings).unwrap();
    let fits = field::fit_constant(&field::identify(&rotor, &tests).unwrap());
    let fit = fits[1].unwrap();
    // Damping c_yy = 0.7 · 7.5e3 at every speed: the mean is exact.
    assert!((fit.damping[1][1] / 5.25e3 - 1.0).abs() < 1e-9);
    assert_eq!(fit.speeds, 14);
}

/// Bearings that are a constant K, C, M: the fit over speeds returns them, and its error bars
/// (from the per-speed ones) cover them at 1 % response noise.
#[test]
fn constant_fit_recovers_k_c_m_within_its_error_bars() {
    let rotor = rotor();
    let mass = [[2.0, 0.4], [-0.3, 3.0]];
    let law = |b: usize, w: f64| {
        let base = bearings(b, 0.0);
        BearingCoefficients {
            stiffness: std::array::from_fn(|i| {
                std::array::from_fn(|j| base.stiffness[i][j] - w * w * mass[i][j])
            }),
            damping: base.damping,
        }
    };
    // Noise-free: exact.
    let tests = runs([0, 7], 0.0, 1).simulate(&rotor, law).unwrap();
    let fit = field::fit_constant(&field::identify(&rotor, &tests).unwrap())[0].unwrap();
    assert!((fit.mass[1][1] / 3.0 - 1.0).abs() < 1e-6, "{:?}", fit.mass);
    let (mut inside, mut total) = (0, 0);
    for seed in 0..40 {
        let tests = runs([0, 7], 0.01, 100 + seed)
            .simulate(&rotor, law)
            .unwrap();
        let fits = field::fit_constant(&field::identify(&rotor, &tests).unwrap());
        for (b, fit) in fits.iter().enumerate() {
            let fit = fit.unwrap();
            let truth = bearings(b, 0.0);
            for k in 0..4 {
                let (i, j) = (k / 2, k % 2);
                for (value, std, t) in [
                    (
                        fit.stiffness[i][j],
                        fit.stiffness_std[i][j],
                        truth.stiffness[i][j],
                    ),
                    (
                        fit.damping[i][j],
                        fit.damping_std[i][j],
                        truth.damping[i][j],
                    ),
                    (fit.mass[i][j], fit.mass_std[i][j], mass[i][j]),
                ] {
                    total += 1;
                    if (value - t).abs() <= 1.96 * std {
                        inside += 1;
                    }
                }
            }
        }
    }
    let coverage = inside as f64 / total as f64;
    eprintln!("constant fit: coverage {coverage:.3} of {total}");
    assert!((0.93..=0.99).contains(&coverage), "{coverage}");
}

/// A rotor built with ROSS 3.1.0 (Timoshenko shaft, `M0`, `K0`, `G0`, `C0`) and ROSS's own
/// unbalance responses (`examples/field/generate.py`): the bearings come back to 1e-6,
/// which checks the JSON form, the DOF order, the force convention and the gyroscopic sign
/// against an independent code.
#[cfg(feature = "json")]
#[test]
fn recovers_the_bearings_of_a_rotor_built_with_ross() {
    let rotor = RotorModel::from_json(include_str!("../../examples/field/ROTOR.json")).unwrap();
    assert_eq!(rotor.dofs(), 48);
    let truth = |b: usize, _w: f64| match b {
        0 => BearingCoefficients {
            stiffness: [[5e6, 3e6], [-3.6e6, 2e7]],
            damping: [[5e3, 500.0], [-350.0, 7.5e3]],
        },
        _ => BearingCoefficients {
            stiffness: [[3.5e6, 2.1e6], [-2.52e6, 1.4e7]],
            damping: [[3.5e3, 500.0], [-245.0, 5.25e3]],
        },
    };
    for text in [
        include_str!("../../examples/field/TESTS_bearings.json"),
        include_str!("../../examples/field/TESTS_inboard.json"),
    ] {
        let tests = FieldTests::from_json(text).unwrap();
        let id = field::identify(&rotor, &tests).unwrap();
        let worst = worst_error(&id, truth);
        eprintln!("ROSS rotor: worst relative error {worst:.2e}");
        assert!(worst < 1e-6, "{worst:e}");
    }
}

/// The mass-sum check on a rotor whose truth is known, at 1 % response noise: bearings with a
/// constant added mass of 1 kg (x) and 1.5 kg (y) each sum to 2 and 3 kg, within 3σ, and the
/// check is quiet against the 58.3 kg rotor; the speed-dependent bearings (whose trend the
/// constant fit's `M` takes) stay quiet too; the same responses read with a model whose 20 kg
/// disk is written as 5 kg give a sum of −175 ± 54 kg in y and warn.
#[test]
fn mass_sum_is_quiet_on_the_true_rotor_and_warns_on_a_wrong_mass() {
    use bearing_ident::field::{BeamRotor, BearingSite, Disk};
    let beam = |disk_mass: f64| {
        BeamRotor {
            element_lengths: vec![0.15; 7],
            diameter: 0.06,
            density: 7850.0,
            young: 2.1e11,
            poisson: 0.3,
            disks: vec![
                Disk {
                    node: 2,
                    mass: disk_mass,
                    polar: 0.25,
                    diametral: 0.13,
                },
                Disk {
                    node: 5,
                    mass: 15.0,
                    polar: 0.2,
                    diametral: 0.1,
                },
            ],
            bearings: vec![BearingSite::new("brg0", 0), BearingSite::new("brg1", 7)],
        }
        .model()
        .unwrap()
    };
    let truth = beam(20.0);
    assert_eq!(truth, rotor());
    let added = [[1.0, 0.0], [0.0, 1.5]];
    let law = |b: usize, w: f64| {
        let base = bearings(b, 0.0);
        BearingCoefficients {
            stiffness: std::array::from_fn(|i| {
                std::array::from_fn(|j| base.stiffness[i][j] - w * w * added[i][j])
            }),
            damping: base.damping,
        }
    };
    let kinds = |id: &FieldIdentification| -> Vec<&str> {
        id.warnings().iter().map(|w| w.kind()).collect()
    };
    let tests = runs([0, 7], 0.01, 300).simulate(&truth, law).unwrap();
    let right = field::identify(&truth, &tests).unwrap();
    let sum = *right.mass_sum().unwrap();
    assert!((sum.rotor_mass[0] - 58.305).abs() < 1e-3, "{sum:?}");
    for (d, t) in [(0, 2.0), (1, 3.0)] {
        assert!((sum.sum[d] - t).abs() < 3.0 * sum.sum_std[d], "{sum:?}");
    }
    assert!(
        !kinds(&right).contains(&"mass_sum"),
        "{:?}",
        right.warnings()
    );
    let trend = runs([0, 7], 0.01, 1).simulate(&truth, bearings).unwrap();
    let trend = field::identify(&truth, &trend).unwrap();
    assert!(
        !kinds(&trend).contains(&"mass_sum"),
        "{:?}",
        trend.warnings()
    );
    let wrong = field::identify(&beam(5.0), &tests).unwrap();
    let sum = *wrong.mass_sum().unwrap();
    assert!((sum.rotor_mass[1] - 43.305).abs() < 1e-3, "{sum:?}");
    let warned: Vec<_> = wrong
        .warnings()
        .iter()
        .filter_map(|w| match w {
            Warning::MassSum {
                direction, sum_kg, ..
            } => Some((*direction, *sum_kg)),
            _ => None,
        })
        .collect();
    assert_eq!(warned.len(), 1, "{sum:?}");
    assert_eq!(warned[0].0, "y");
    assert!(warned[0].1 < -100.0, "{sum:?}");
}
