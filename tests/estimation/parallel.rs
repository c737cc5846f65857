//! With the `rayon` feature, records are transformed in parallel and test conditions identified
//! in parallel; the results must be bit for bit those of the sequential paths (`push` one
//! record at a time, one set after another), which are what a build without `rayon` runs.

use bearing_ident::simulate::{AntiAlias, ImpactTest, Simulator, seed_rig};
use bearing_ident::{Estimator, Identification, Identifier, Record, Segmentation, Window};

fn bits(id: &Identification) -> Vec<u64> {
    id.coefficients()
        .stacked()
        .col_iter()
        .flat_map(|c| c.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
        .chain(id.condition_numbers().iter().map(|v| v.to_bits()))
        .collect()
}

fn impacts() -> Vec<Record> {
    ImpactTest {
        per_direction: 4,
        noise: 0.05,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap()
}

#[test]
fn parallel_and_sequential_paired_sets_agree_bit_for_bit() {
    let records = impacts();
    let id = Identifier::new(8.0, 49.0);
    let parallel = id.identify(&records).unwrap();
    let sequential = id.identify_stream(records.iter().cloned().map(Ok)).unwrap();
    assert_eq!(bits(&parallel), bits(&sequential));
}

#[test]
fn parallel_and_sequential_h1_agree_bit_for_bit() {
    let mut sim = Simulator::new(&seed_rig(), 1000.0, 16_384, AntiAlias::default()).unwrap();
    let records: Vec<Record> = (0..4)
        .map(|s| sim.random_record(format!("random-{s}"), 50.0, s).unwrap())
        .collect();
    let id = Identifier::new(8.0, 49.0)
        .estimator(Estimator::H1)
        .segmentation(Segmentation::Welch { len: 2048 })
        .window(Window::Hann);
    let parallel = id.identify(&records).unwrap();
    let sequential = id.identify_stream(records.iter().cloned().map(Ok)).unwrap();
    assert_eq!(bits(&parallel), bits(&sequential));
}

#[test]
fn batch_equals_one_by_one() {
    let sets: Vec<Vec<Record>> = (0..3)
        .map(|seed| {
            ImpactTest {
                per_direction: 2,
                noise: 0.05,
                seed,
                ..ImpactTest::seed_rig()
            }
            .run(&seed_rig())
            .unwrap()
        })
        .collect();
    let id = Identifier::new(8.0, 49.0);
    let batch = id.identify_batch(&sets);
    for (set, result) in sets.iter().zip(&batch) {
        let one = id.identify(set).unwrap();
        assert_eq!(bits(result.as_ref().unwrap()), bits(&one));
    }
}
