//! The fit gate on the faults of issue 11: settings that leave the fit nothing to work with and
//! records passed twice all used to return confident numbers with no warning. Each case here
//! reproduces one on simulated impact records of the seed's rig and checks the warning, and
//! that a sound identification of the same records raises none.

use bearing_ident::gate::FitGate;
use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::spectra::ForceGate;
use bearing_ident::{Identification, Identifier, Record, Segmentation, Uncertainty, Window};

fn records() -> Vec<Record> {
    ImpactTest {
        noise: 0.05,
        seed: 11,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap()
}

fn kinds(id: &Identification) -> Vec<&'static str> {
    id.warnings().iter().map(|w| w.kind()).collect()
}

#[test]
fn a_sound_identification_passes_the_gate() {
    let id = Identifier::new(8.0, 49.0)
        .uncertainty(Uncertainty::Jackknife)
        .identify(&records())
        .unwrap();
    assert!(id.warnings().is_empty(), "{:?}", id.warnings());
    // A reasonable exponential window and force gate pass too.
    let id = Identifier::new(8.0, 49.0)
        .window(Window::exponential_to(0.01, 1.2))
        .force_gate(ForceGate::new(0.035, 0.007).unwrap())
        .identify(&records())
        .unwrap();
    assert!(id.warnings().is_empty(), "{:?}", id.warnings());
}

#[test]
fn a_window_that_leaves_nothing_of_the_record_is_flagged() {
    let id = Identifier::new(8.0, 49.0)
        .window(Window::exponential_to(1e-300, 1.2))
        .identify(&records())
        .unwrap();
    let k = kinds(&id);
    assert!(k.contains(&"window_too_short"), "{k:?}");
    println!(
        "exp:1e-300: M_xx = {:.4} kg, warnings {:?}",
        id.coefficients().mass()[(0, 0)],
        id.warnings()
    );
}

#[test]
fn a_force_gate_shorter_than_the_pulse_is_flagged() {
    let id = Identifier::new(8.0, 49.0)
        .force_gate(ForceGate::new(1e-9, 2e-10).unwrap())
        .identify(&records())
        .unwrap();
    let k = kinds(&id);
    assert!(k.contains(&"force_gate_short"), "{k:?}");
    // What the gate leaves is no force at all: the fit cannot explain the data.
    assert!(k.contains(&"poor_fit"), "{k:?}");
    let m = id.coefficients().mass()[(0, 0)];
    println!(
        "force gate 1 ns: M_xx = {m:.4} kg, warnings {:?}",
        id.warnings()
    );
}

#[test]
fn welch_segments_on_impact_records_are_flagged() {
    let id = Identifier::new(8.0, 49.0)
        .estimator(bearing_ident::Estimator::H1)
        .segmentation(Segmentation::Welch { len: 1000 })
        .window(Window::Hann)
        .identify(&records())
        .unwrap();
    let k = kinds(&id);
    assert!(k.contains(&"coarse_resolution"), "{k:?}");
    assert!(k.contains(&"few_lines"), "{k:?}");
    println!(
        "Welch 1000 on impacts: K_xx = {:.4e}, warnings {:?}",
        id.coefficients().stiffness()[(0, 0)],
        id.warnings()
    );
}

#[test]
fn records_passed_several_times_are_flagged() {
    let all = records();
    // Two files, each passed eight times: the first x hit and the first y hit.
    let (x, y) = (all[0].clone(), all[8].clone());
    let mut twice = vec![x; 8];
    twice.extend(vec![y; 8]);
    let id = Identifier::new(8.0, 49.0)
        .uncertainty(Uncertainty::Jackknife)
        .identify(&twice)
        .unwrap();
    assert!(
        id.warnings()
            .contains(&bearing_ident::Warning::DependentReplicates {
                replicates: 8,
                distinct: 1
            }),
        "{:?}",
        id.warnings()
    );
    // Three sets of eight repeated: the spread is not zero but the replicates are dependent.
    let mut some = all.clone();
    some[1] = some[0].clone();
    some[9] = some[8].clone();
    let id = Identifier::new(8.0, 49.0)
        .uncertainty(Uncertainty::Jackknife)
        .identify(&some)
        .unwrap();
    assert!(
        id.warnings()
            .contains(&bearing_ident::Warning::DependentReplicates {
                replicates: 8,
                distinct: 7
            }),
        "{:?}",
        id.warnings()
    );
    // The bootstrap of the all-duplicate set has zero spread.
    let id = Identifier::new(8.0, 49.0)
        .uncertainty(Uncertainty::BOOTSTRAP)
        .identify(&twice)
        .unwrap();
    assert!(kinds(&id).contains(&"zero_spread"), "{:?}", id.warnings());
}

#[test]
fn the_r2_threshold_is_a_setting() {
    let strict = Identifier::new(8.0, 49.0)
        .fit_gate(FitGate { min_r2: 1.0 })
        .identify(&records())
        .unwrap();
    assert!(kinds(&strict).contains(&"poor_fit"));
    assert!(
        Identifier::new(8.0, 49.0)
            .fit_gate(FitGate { min_r2: f64::NAN })
            .identify(&records())
            .is_err()
    );
}
