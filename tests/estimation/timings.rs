//! Stage timings: present, finite, non-negative, and the total covers its parts — in the
//! library ([`Identification::timings`]) and in the CLI's JSON (`timings_ms`) and table
//! (`--timings`). The values themselves are never asserted.

use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::{Estimator, Identifier, Uncertainty};

#[test]
fn library_timings_cover_every_stage() {
    let records = ImpactTest {
        per_direction: 3,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap();
    for identifier in [
        Identifier::new(8.0, 49.0),
        Identifier::new(8.0, 49.0).uncertainty(Uncertainty::Jackknife),
        Identifier::new(8.0, 49.0).estimator(Estimator::H1),
    ] {
        let batch = identifier.identify(&records).unwrap().timings();
        let stream = identifier
            .identify_stream(records.clone().into_iter().map(Ok))
            .unwrap()
            .timings();
        for t in [batch, stream] {
            let names: Vec<&str> = t.stages().iter().map(|(n, _)| *n).collect();
            assert_eq!(
                names,
                [
                    "screen",
                    "spectra",
                    "noise",
                    "frf",
                    "conditioning",
                    "solve",
                    "model_check",
                    "uncertainty",
                    "bias"
                ]
            );
            let parts: std::time::Duration = t.stages().iter().map(|(_, d)| *d).sum();
            assert!(t.total >= parts, "{t:?}");
            assert_eq!(
                parts,
                t.screen
                    + t.spectra
                    + t.noise
                    + t.frf
                    + t.conditioning
                    + t.solve
                    + t.model_check
                    + t.uncertainty
                    + t.bias
            );
        }
    }
}

#[test]
fn timings_do_not_enter_equality() {
    let records = ImpactTest {
        per_direction: 1,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap();
    let a = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    let b = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    assert_eq!(a, b);
}

#[cfg(feature = "cli")]
mod cli {

    const STAGES: [&str; 11] = [
        "read",
        "detect",
        "welch_choice",
        "screen",
        "spectra",
        "frf",
        "conditioning",
        "solve",
        "uncertainty",
        "baseline",
        "total",
    ];

    use crate::common::{bin, csv_files};
    fn files() -> (tempfile::TempDir, Vec<String>) {
        let dir = tempfile::tempdir().unwrap();
        let out = bin()
            .args(["simulate", "--out", dir.path().to_str().unwrap()])
            .output()
            .unwrap();
        assert!(out.status.success());
        let files = csv_files(dir.path());
        (dir, files)
    }

    #[test]
    fn json_carries_timings_ms() {
        let (_dir, files) = files();
        let out = bin()
            .args(["identify", "--json", "--band", "8,49"])
            .args(&files)
            .output()
            .unwrap();
        assert!(out.status.success());
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let t = &v["timings_ms"];
        let ms = |k: &str| {
            let x = t[k]
                .as_f64()
                .unwrap_or_else(|| panic!("timings_ms.{k}: {t}"));
            assert!(x.is_finite() && x >= 0.0, "{k}: {x}");
            x
        };
        let parts: f64 = STAGES[..10].iter().map(|k| ms(k)).sum();
        // Sums of rounded milliseconds: allow the rounding of ten terms.
        assert!(ms("total") >= parts - 1e-6, "{t}");
        let compute = v["compute_ms"].as_f64().unwrap();
        assert!(compute.is_finite() && compute >= 0.0);
    }

    #[test]
    fn table_prints_timings_on_request() {
        let (_dir, files) = files();
        let with = bin()
            .args(["identify", "--timings", "--band", "8,49"])
            .args(&files)
            .output()
            .unwrap();
        assert!(with.status.success());
        let text = String::from_utf8(with.stdout).unwrap();
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with("timings (ms):"))
            .unwrap_or_else(|| panic!("{text}"));
        for stage in STAGES {
            assert!(line.contains(stage), "{stage}: {line}");
        }
        let without = bin()
            .args(["identify", "--band", "8,49"])
            .args(&files)
            .output()
            .unwrap();
        assert!(
            !String::from_utf8(without.stdout)
                .unwrap()
                .contains("timings (ms)")
        );
    }
}
