//! Every way a user's data can make an identification fail returns a typed error.

use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{
    Assignment, ConditionLimits, Error, Estimator, Identifier, NonConvergence, Record, Warning,
};

fn records(per_direction: usize, off_axis: f64, noise: f64) -> Vec<Record> {
    ImpactTest {
        per_direction,
        off_axis,
        noise,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap()
}

#[test]
fn impacts_all_in_one_direction_are_rank_deficient() {
    let recs = records(2, 0.05, 0.01);
    let x_only: Vec<Record> = recs
        .into_iter()
        .filter(|r| r.dominant_force() == 0)
        .collect();
    let e = Identifier::new(8.0, 49.0).identify(&x_only).unwrap_err();
    assert_eq!(e, Error::RankDeficient { rank: 1, dofs: 2 });
}

#[test]
fn proportional_forcing_is_rank_deficient_for_h1() {
    let recs = records(2, 0.0, 0.0);
    let x_only: Vec<Record> = recs
        .into_iter()
        .filter(|r| r.dominant_force() == 0)
        .collect();
    let e = Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .identify(&x_only)
        .unwrap_err();
    assert_eq!(e, Error::RankDeficient { rank: 1, dofs: 2 });
}

#[test]
fn forced_pairing_of_one_direction_is_refused() {
    // An explicit assignment that pairs two x impacts as if one were a y impact.
    let recs = records(2, 0.0, 0.0);
    let x_only: Vec<Record> = recs
        .into_iter()
        .filter(|r| r.dominant_force() == 0)
        .collect();
    let e = Identifier::new(8.0, 49.0)
        .assignment(Assignment::Explicit(vec![0, 1]))
        .identify(&x_only)
        .unwrap_err();
    assert!(matches!(e, Error::RankDeficient { .. }), "{e:?}");
}

#[test]
fn band_errors() {
    let recs = records(1, 0.05, 0.0);
    assert!(matches!(
        Identifier::new(49.0, 8.0).identify(&recs),
        Err(Error::InvalidBand { .. })
    ));
    assert!(matches!(
        Identifier::new(8.0, 4000.0).identify(&recs),
        Err(Error::BandAboveNyquist { nyquist_hz, .. }) if nyquist_hz == 3350.0
    ));
    let e = Identifier::new(8.0, 10.0).identify(&recs);
    assert!(
        matches!(
            e,
            Err(Error::TooFewLines {
                lines: 3,
                required: 6,
                ..
            })
        ),
        "{e:?}"
    ); // 8.33, 9.17, 10.00 Hz
}

#[test]
fn record_set_errors_name_the_record() {
    let recs = records(1, 0.05, 0.0);
    assert_eq!(
        Identifier::new(8.0, 49.0).identify(&[]).unwrap_err(),
        Error::NoRecords
    );
    match Identifier::new(8.0, 49.0)
        .dofs(3)
        .identify(&recs)
        .unwrap_err()
    {
        Error::DofMismatch {
            record,
            expected: 3,
            actual: 2,
        } => assert_eq!(record, "impact-dof0-0"),
        e => panic!("{e:?}"),
    }
    let short = Record::new(
        "short.csv",
        6700.0,
        (0..2).map(|c| recs[1].force(c)[..4000].to_vec()).collect(),
        (0..2)
            .map(|c| recs[1].displacement(c)[..4000].to_vec())
            .collect(),
    )
    .unwrap();
    let e = Identifier::new(8.0, 49.0)
        .identify(&[recs[0].clone(), short])
        .unwrap_err();
    assert_eq!(
        e,
        Error::RecordLengthMismatch {
            record: "short.csv".into(),
            expected: 8040,
            actual: 4000
        }
    );
}

#[test]
fn settings_out_of_range_are_refused() {
    let recs = records(1, 0.05, 0.0);
    assert!(matches!(
        Identifier::new(8.0, 49.0).tolerance(0.0).identify(&recs),
        Err(Error::InvalidParameter {
            name: bearing_ident::Parameter::IvfTolerance,
            ..
        })
    ));
    let limits = ConditionLimits {
        warn: 10.0,
        refuse: 1.0,
    };
    assert!(matches!(
        Identifier::new(8.0, 49.0)
            .condition_limits(limits)
            .identify(&recs),
        Err(Error::InvalidParameter {
            name: bearing_ident::Parameter::ConditionLimits,
            ..
        })
    ));
}

#[test]
fn non_convergence_warns_or_fails_as_asked() {
    let recs = records(2, 0.05, 0.3);
    let id = Identifier::new(8.0, 49.0)
        .max_iterations(1)
        .identify(&recs)
        .unwrap();
    assert!(!id.converged());
    assert!(matches!(
        id.warnings(),
        [Warning::NotConverged { iterations: 1, .. }]
    ));
    let e = Identifier::new(8.0, 49.0)
        .max_iterations(1)
        .on_non_convergence(NonConvergence::Fail)
        .identify(&recs)
        .unwrap_err();
    assert!(matches!(
        e,
        Error::NotConverged {
            method: bearing_ident::Method::Ivf,
            iterations: 1,
            ..
        }
    ));
}

#[test]
fn unequal_directions_leave_records_unpaired_with_a_warning() {
    let mut recs = records(2, 0.05, 0.0);
    recs.pop(); // one y impact fewer
    let id = Identifier::new(8.0, 49.0).identify(&recs).unwrap();
    assert_eq!(id.frf().averages(), 1);
    assert!(
        matches!(&id.warnings()[0], Warning::UnpairedRecords { records } if records == &["impact-dof0-1".to_string()])
    );
}

#[test]
fn low_coherence_lines_are_dropped_and_reported() {
    let recs = records(4, 0.05, 0.5);
    let all = Identifier::new(8.0, 49.0).identify(&recs).unwrap();
    let c_min = all.min_coherence().unwrap();
    assert!(c_min < 1.0);
    // A threshold between the smallest and the median coherence drops some lines, not all.
    let mut per_line: Vec<f64> = (0..all.frf().line_count())
        .map(|k| {
            all.frf()
                .multiple_coherence(k)
                .unwrap()
                .iter()
                .cloned()
                .fold(1.0, f64::min)
        })
        .collect();
    per_line.sort_by(f64::total_cmp);
    let threshold = per_line[per_line.len() / 4];
    let some = Identifier::new(8.0, 49.0)
        .min_coherence(threshold)
        .identify(&recs)
        .unwrap();
    let dropped = (0..all.frf().line_count()).filter(|&k| {
        all.frf()
            .multiple_coherence(k)
            .unwrap()
            .iter()
            .any(|&g| g < threshold)
    });
    let dropped = dropped.count();
    assert!(dropped > 0);
    assert_eq!(some.frf().line_count(), all.frf().line_count() - dropped);
    assert!(some.min_coherence().unwrap() >= threshold);
    assert!(matches!(some.warnings()[0], Warning::LowCoherence { lines, .. } if lines == dropped));
    assert!(matches!(
        Identifier::new(8.0, 49.0)
            .min_coherence(1.5)
            .identify(&recs),
        Err(Error::InvalidParameter {
            name: bearing_ident::Parameter::MinimumCoherence,
            ..
        })
    ));
}

#[test]
fn ill_conditioned_lines_warn() {
    let recs = records(1, 0.05, 0.0);
    let limits = ConditionLimits {
        warn: 1.5,
        refuse: 1e8,
    };
    let id = Identifier::new(8.0, 49.0)
        .condition_limits(limits)
        .identify(&recs)
        .unwrap();
    assert!(
        matches!(id.warnings()[0], Warning::IllConditioned { threshold, .. } if threshold == 1.5)
    );
}
