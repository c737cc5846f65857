//! Error kinds that say the cause (issue 11, item 4): an empty or too narrow band is `bad_band`
//! with its line spacing, overflowing spectra are `non_finite` naming the record and channel, a
//! dead record is `dead_channel`, and sampling rates that the CSV reader accepts agree.

#[cfg(feature = "csv")]
use bearing_ident::io::{CsvLayout, read_record_from};
use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{Channel, Error, Estimator, Identifier, Method, NonConvergence, Record};

fn records(per_direction: usize) -> Vec<Record> {
    ImpactTest {
        per_direction,
        off_axis: 0.05,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap()
}

/// `record` with its forces multiplied by `factor` (and its label kept).
fn scaled_forces(record: &Record, factor: f64) -> Record {
    let n = record.dofs();
    Record::new(
        record.label(),
        record.sample_rate(),
        (0..n)
            .map(|c| record.force(c).iter().map(|f| f * factor).collect())
            .collect(),
        (0..n).map(|c| record.displacement(c).to_vec()).collect(),
    )
    .unwrap()
}

/// The records with their forces scaled so that the largest is `peak` (N), and the factor.
fn forces_peaking_at(records: &[Record], peak: f64) -> (Vec<Record>, f64) {
    let largest = records
        .iter()
        .flat_map(|r| (0..r.dofs()).flat_map(move |c| r.force(c).iter()))
        .fold(0.0, |m: f64, f| m.max(f.abs()));
    let factor = peak / largest;
    let scaled = records.iter().map(|r| scaled_forces(r, factor)).collect();
    (scaled, factor)
}

#[test]
fn a_band_without_lines_is_bad_band_with_the_spacing() {
    // 6700 samples/s × 1.2 s: lines every 0.8333 Hz, none in 10.01–10.02 Hz.
    let recs = records(1);
    for estimator in [Estimator::PairedSets, Estimator::H1] {
        let e = Identifier::new(10.01, 10.02)
            .estimator(estimator)
            .identify(&recs)
            .unwrap_err();
        assert_eq!(e.kind(), "bad_band", "{e}");
        match e {
            Error::TooFewLines {
                lines: 0,
                required: 6,
                resolution_hz: Some(df),
            } => assert!((df - 6700.0 / 8040.0).abs() < 1e-12),
            e => panic!("{estimator:?}: {e:?}"),
        }
    }
}

#[test]
fn a_single_line_gives_the_spacing_not_nan() {
    let recs = records(1);
    let e = Identifier::new(10.0, 10.2).identify(&recs).unwrap_err();
    let message = e.to_string();
    assert!(
        matches!(
            e,
            Error::TooFewLines {
                lines: 1,
                required: 6,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(!message.contains("NaN"), "{message}");
    assert!(message.contains("line spacing 0.83333"), "{message}");
}

#[test]
fn huge_forces_are_non_finite_naming_record_and_channel() {
    let recs = records(1);
    for estimator in [Estimator::PairedSets, Estimator::H1, Estimator::H2] {
        let (big, _) = forces_peaking_at(&recs, 1e308);
        let e = Identifier::new(8.0, 49.0)
            .estimator(estimator)
            .identify(&big)
            .unwrap_err();
        assert_eq!(e.kind(), "non_finite", "{estimator:?}: {e}");
        match e {
            Error::SpectrumOverflow {
                record, channel, ..
            } => {
                assert_eq!(record, "impact-dof0-0");
                assert_eq!(channel, Channel::Force(0));
            }
            e => panic!("{estimator:?}: {e:?}"),
        }
    }
}

/// The class: whatever the level, never a misleading rank or band error.
fn fits_or_says_non_finite(scales: &[f64], estimators: &[Estimator]) {
    let recs = records(1);
    for &scale in scales {
        for &estimator in estimators {
            let (scaled, factor) = forces_peaking_at(&recs, scale);
            match Identifier::new(8.0, 49.0)
                .estimator(estimator)
                .identify(&scaled)
            {
                Ok(id) => {
                    let k = id.coefficients().stiffness()[(0, 0)];
                    assert!(
                        (k / (146.3e3 * factor) - 1.0).abs() < 1e-3,
                        "{scale:e} {estimator:?}: K = {k:e}"
                    );
                }
                Err(e) => assert_eq!(e.kind(), "non_finite", "{scale:e} {estimator:?}: {e}"),
            }
        }
    }
}

#[test]
fn any_force_scale_fits_or_says_non_finite() {
    let scales = [1e308, 1e300, 1e250, 1e200, 1e160, 1e150, 1e100, 1e-100];
    fits_or_says_non_finite(&scales, &[Estimator::PairedSets, Estimator::H1]);
}

#[test]
fn a_dead_record_that_stops_the_run_is_named() {
    // One record per direction; the x hit did not register: no x excitation is left.
    let mut recs = records(1);
    recs[0] = scaled_forces(&recs[0], 0.0);
    for estimator in [Estimator::PairedSets, Estimator::H1] {
        let e = Identifier::new(8.0, 49.0)
            .estimator(estimator)
            .identify(&recs)
            .unwrap_err();
        assert_eq!(e.kind(), "dead_channel", "{estimator:?}: {e}");
        assert_eq!(
            e,
            Error::DeadChannel {
                record: "impact-dof0-0".into(),
                channel: Channel::Force(0),
                value: 0.0
            }
        );
        assert!(e.to_string().contains("impact-dof0-0"));
    }
    // A band too narrow is still the band's fault, dead record or not.
    let e = Identifier::new(10.0, 10.2).identify(&recs).unwrap_err();
    assert_eq!(e.kind(), "bad_band", "{e}");
}

/// A CSV text of `len` samples at 100 Hz whose first and last time stamps sit `shift` steps
/// off the grid in opposite directions.
#[cfg(feature = "csv")]
fn jittered_csv(len: usize, shift: f64) -> String {
    let mut text = String::from("t,fx,fy,x,y\n");
    for m in 0..len {
        let off = match m {
            0 => -shift,
            m if m == len - 1 => shift,
            _ => 0.0,
        };
        let t = (m as f64 + off) / 100.0;
        let f = if m == 3 { 1.0 } else { 0.0 };
        let x = (m as f64 * 0.7).sin() * 1e-6;
        text.push_str(&format!("{t},{f},{},{x},{}\n", 0.5 * f, 2.0 * x));
    }
    text
}

#[test]
#[cfg(feature = "csv")]
fn rates_that_the_reader_accepts_agree() {
    let layout = CsvLayout::for_dofs(2);
    for len in [8, 12, 100, 1000] {
        // Just inside the reader's tolerance in each file, one stretched and one squeezed.
        let shift = 0.0099 * (len as f64 - 1.0) / (len as f64 - 3.0);
        let a = read_record_from(jittered_csv(len, shift).as_bytes(), "a.csv", &layout).unwrap();
        let b = read_record_from(jittered_csv(len, -shift).as_bytes(), "b.csv", &layout).unwrap();
        assert!(
            (a.sample_rate() / b.sample_rate() - 1.0).abs() > 1e-6,
            "{len}"
        );
        bearing_ident::frf::common_shape(&[a, b], None)
            .unwrap_or_else(|e| panic!("{len} samples: {e}"));
    }
    // A rate that differs by more than any accepted jitter is still refused.
    let a = read_record_from(jittered_csv(1000, 0.0).as_bytes(), "a.csv", &layout).unwrap();
    let faster = Record::new(
        "faster.csv",
        a.sample_rate() * 1.001,
        vec![a.force(0).to_vec(), a.force(1).to_vec()],
        vec![a.displacement(0).to_vec(), a.displacement(1).to_vec()],
    )
    .unwrap();
    let e = bearing_ident::frf::common_shape(&[a, faster], None).unwrap_err();
    assert_eq!(e.kind(), "inconsistent_records");
}

/// `record` with its forces multiplied by `force` and its responses by `response`.
fn scaled(record: &Record, force: f64, response: f64) -> Record {
    let n = record.dofs();
    let times = |v: &[f64], k: f64| v.iter().map(|x| x * k).collect::<Vec<f64>>();
    Record::new(
        record.label(),
        record.sample_rate(),
        (0..n).map(|c| times(record.force(c), force)).collect(),
        (0..n)
            .map(|c| times(record.displacement(c), response))
            .collect(),
    )
    .unwrap()
}

/// Every response × 1e-310 (subnormal samples) or × 1e-300, or every force × 1e-300, or
/// responses × 1e300: the record and channel whose levels leave f64 are named (before:
/// `rank_deficient` "span 1 of 2 directions", `not_converged` "in 0 iterations (last relative
/// change NaN)" or "the coherence … is not finite" naming nothing).
#[test]
fn levels_that_leave_f64_name_the_record_and_channel() {
    let recs = records(1);
    for (force, response, forces, subnormal) in [
        (1.0, 1e-310, false, true),
        (1.0, 1e-300, false, false),
        (1e-300, 1.0, true, false),
        (1.0, 1e300, false, false),
    ] {
        let all: Vec<Record> = recs.iter().map(|r| scaled(r, force, response)).collect();
        for estimator in [Estimator::PairedSets, Estimator::H1] {
            let e = Identifier::new(8.0, 49.0)
                .estimator(estimator)
                .on_non_convergence(NonConvergence::Fail)
                .identify(&all)
                .unwrap_err();
            let case = format!("{force:e} {response:e} {estimator:?}: {e}");
            assert_eq!(e.kind(), "non_finite", "{case}");
            // An overflow can meet a cross-spectrum first: named there, as before.
            match &e {
                Error::LevelOutOfRange {
                    record, channel, ..
                }
                | Error::SpectrumOverflow {
                    record, channel, ..
                } => {
                    assert_eq!(record, "impact-dof0-0", "{case}");
                    assert_eq!(matches!(channel, Channel::Force(_)), forces, "{case}");
                }
                _ => panic!("{case}"),
            }
            assert_eq!(e.to_string().contains("subnormal"), subnormal, "{case}");
        }
    }
}

/// Forces and responses scaled 1e200 apart (|H| about 1e205 or 1e-195 N/m): the impedance's
/// level is named with the advice to rescale, for IVF and ML (before: `not_converged` "in 0
/// iterations (last relative change NaN)"); 1e150 apart still fits, K scaled exactly.
#[test]
fn an_impedance_far_from_one_names_the_units() {
    let recs = records(2);
    for (force, response, level) in [(1e100, 1e-100, 205.0), (1e-100, 1e100, -195.0)] {
        let all: Vec<Record> = recs.iter().map(|r| scaled(r, force, response)).collect();
        for method in [Method::Ivf, Method::Ml] {
            let e = Identifier::new(8.0, 49.0)
                .method(method)
                .on_non_convergence(NonConvergence::Fail)
                .identify(&all)
                .unwrap_err();
            let case = format!("{force:e} {method:?}: {e}");
            assert_eq!(e.kind(), "non_finite", "{case}");
            match e {
                Error::ImpedanceScale { magnitude } => {
                    assert!((magnitude.log10() - level).abs() < 1.0, "{case}")
                }
                _ => panic!("{case}"),
            }
        }
    }
    let all: Vec<Record> = recs.iter().map(|r| scaled(r, 1e75, 1e-75)).collect();
    let id = Identifier::new(8.0, 49.0)
        .on_non_convergence(NonConvergence::Fail)
        .identify(&all)
        .unwrap();
    let k = id.coefficients().stiffness()[(0, 0)];
    assert!((k / 146.3e153 - 1.0).abs() < 1e-2, "K = {k:e}");
}
