//! `bearing-ident simulate` with nonlinear terms: the flags reach the simulator (zero
//! coefficients give the linear records, friction lowers the response), forcing on several
//! directions at once, and typed failures for bad flags.
#![cfg(feature = "cli")]

use crate::common::{csv_files, run};
use std::path::Path;

use bearing_ident::Record;
use bearing_ident::io::{CsvLayout, read_record};
use serde_json::Value;

/// Runs `simulate --json --out DIR ARGS`, returns its JSON and the records written, by name.
fn simulate(dir: &Path, args: &[&str]) -> (Value, Vec<Record>) {
    let out = run(&[
        &["simulate", "--json", "--out", dir.to_str().unwrap()],
        args,
    ]
    .concat());
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let files = csv_files(dir);
    let layout = CsvLayout::for_dofs(2);
    let records = files
        .iter()
        .map(|p| read_record(p, &layout).unwrap())
        .collect();
    (v, records)
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

const RANDOM: [&str; 10] = [
    "--excitation",
    "random",
    "--freqs",
    "8,49",
    "--rate",
    "1024",
    "--duration",
    "4",
    "--records",
    "2",
];

#[test]
fn zero_coefficients_give_the_linear_records_and_friction_lowers_the_response() {
    let dir = tempfile::tempdir().unwrap();
    let (_, linear) = simulate(&dir.path().join("linear"), &RANDOM);
    let (v, zero) = simulate(
        &dir.path().join("zero"),
        &[&RANDOM[..], &["--cubic", "0", "--coulomb", "0,0"]].concat(),
    );
    assert_eq!(v["records"], 2);
    let terms = v["nonlinear"]["terms"].as_array().unwrap();
    let names: Vec<(&str, Value)> = terms
        .iter()
        .map(|t| (t["term"].as_str().unwrap(), t["dof"].clone()))
        .collect();
    assert_eq!(
        names,
        [
            ("coulomb", Value::from(0)),
            ("coulomb", Value::from(1)),
            ("cubic", Value::from(0)),
            ("cubic", Value::from(1)),
        ]
    );
    assert_eq!(terms[0]["unit"], "N");
    assert!((v["nonlinear"]["smoothing"].as_f64().unwrap() - 1e-5).abs() < 1e-20);
    assert!(v["nonlinear"]["oversampling"].as_u64().unwrap() >= 16);
    assert_eq!(linear.len(), 2);
    for (a, b) in zero.iter().zip(&linear) {
        assert_eq!(
            Path::new(a.label()).file_name(),
            Path::new(b.label()).file_name()
        );
        for c in 0..2 {
            // The same band-limited forces through the same filter (to rounding); RK4 against
            // the exact linear simulator for the displacements.
            let worst = |x: &[f64], y: &[f64]| {
                let scale = rms(y);
                x.iter()
                    .zip(y)
                    .map(|(p, q)| (p - q).abs() / scale)
                    .fold(0.0, f64::max)
            };
            let (df, dx) = (
                worst(a.force(c), b.force(c)),
                worst(a.displacement(c), b.displacement(c)),
            );
            assert!(df < 1e-12, "{} force {c}: {df:.3e}", a.label());
            assert!(dx < 1e-8, "{} displacement {c}: {dx:.3e}", a.label());
        }
    }
    // 20 N of friction against 50 N RMS forces: the motion is clearly smaller.
    let (_, dry) = simulate(
        &dir.path().join("dry"),
        &[&RANDOM[..], &["--coulomb", "20"]].concat(),
    );
    for (a, b) in dry.iter().zip(&linear) {
        let ratio = rms(a.displacement(0)) / rms(b.displacement(0));
        assert!(ratio < 0.95, "{ratio}");
    }
    // The band-limited forces carry their RMS.
    assert!((rms(linear[0].force(0)) / 50.0 - 1.0).abs() < 0.01);
}

#[test]
fn multisine_drives_every_direction_at_once_with_simultaneous() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "--excitation",
        "multisine",
        "--rate",
        "512",
        "--periods",
        "1",
        "--records",
        "2",
        "--quadratic-damping",
        "100",
    ];
    let (v, both) = simulate(
        &dir.path().join("both"),
        &[&common[..], &["--simultaneous"]].concat(),
    );
    assert_eq!(v["records"], 2);
    for r in &both {
        assert!(
            rms(r.force(0)) > 10.0 && rms(r.force(1)) > 10.0,
            "{}",
            r.label()
        );
    }
    // Independent phases: the two forces differ.
    assert!((both[0].force(0)[10] - both[0].force(1)[10]).abs() > 1e-3);
    let (v, one) = simulate(&dir.path().join("one"), &common);
    assert_eq!(v["records"], 4);
    for r in &one {
        let quiet = rms(r.force(0)).min(rms(r.force(1)));
        assert!(quiet < 1e-6, "{}: {quiet}", r.label());
    }
}

#[test]
fn bad_nonlinear_flags_are_typed_failures() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let head = ["simulate", "--json", "--out", out];
    let cases: Vec<(Vec<&str>, &str, &str)> = vec![
        (
            vec!["--excitation", "random", "--coulomb", "1,2,3"],
            "invalid_argument",
            "3 values for 2 degrees of freedom",
        ),
        (vec!["--coulomb", "5"], "invalid_argument", "forced test"),
        (
            // ω = 1.46e4 rad/s at 6700 samples/s: one RK4 step per sample is unstable.
            vec![
                "--excitation",
                "random",
                "--mass=4.7,0;0,4.7",
                "--damping=100,0;0,100",
                "--stiffness=1e9,0;0,1e9",
                "--cubic",
                "1e9",
                "--oversampling",
                "1",
            ],
            "invalid_argument",
            "oversampling",
        ),
        (
            vec![
                "--excitation",
                "random",
                "--coulomb",
                "5",
                "--smoothing",
                "0",
            ],
            "invalid_argument",
            "smoothing",
        ),
        (
            vec!["--excitation", "random", "--coulomb", "nan"],
            "invalid_argument",
            "coefficient",
        ),
        (
            vec!["--excitation", "sweep", "--simultaneous"],
            "invalid_argument",
            "--simultaneous",
        ),
        (
            // A softening spring that turns at 12 µm, under 50 N RMS forces: it runs away.
            vec![
                "--excitation",
                "random",
                "--duration",
                "1",
                "--records",
                "1",
                "--cubic=-1e15",
            ],
            "non_finite",
            "diverged",
        ),
    ];
    for (extra, kind, says) in cases {
        let args = [&head[..], &extra[..]].concat();
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        let v: Value = serde_json::from_slice(&o.stdout).expect("JSON error");
        assert_eq!(v["error"], kind, "{extra:?}: {v}");
        let message = v["message"].as_str().unwrap();
        assert!(message.contains(says), "{extra:?}: {message}");
        assert_eq!(String::from_utf8_lossy(&o.stderr).lines().count(), 1);
    }
}
