//! Nonlinear identification end to end, through the command line as a user runs it:
//! `simulate` a rig with dry friction, cubic stiffness or quadratic damping under random forces
//! on both axes at once (2 % noise), then `identify --nonlinear TERMS`. Each coefficient and
//! the linear M, C, K come back; a linear-only fit of the same records is biased; a wrong
//! regressor list is flagged by the model check (`nonlinear_misfit`).
//!
//! The quick cases run 2 × 32 s at 1024 samples/s; the reference case of
//! `docs/method.md` section 4 (2 × 60 s
//! at 2048 samples/s, 8 s segments) is `#[ignore]`d and runs in release:
//! `cargo test --release --all-features --test nonlinear end_to_end:: -- --include-ignored`.
#![cfg(feature = "cli")]

use crate::common::{self, run};
use std::path::Path;
use std::sync::OnceLock;

use serde_json::Value;

/// `simulate` into `dir` with the common forcing and `extra`; the CSV files written.
fn simulate(dir: &Path, forcing: &[&str], extra: &[&str]) -> Vec<String> {
    let out = run(&[
        &["simulate", "--out", dir.to_str().unwrap()],
        forcing,
        extra,
    ]
    .concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    common::csv_files(dir)
}

/// `identify --json ARGS FILES`, its JSON.
fn identify(args: &[&str], files: &[String]) -> Value {
    let files: Vec<&str> = files.iter().map(String::as_str).collect();
    let out = run(&[&["identify", "--json"], args, &files].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON")
}

/// The seed rig's M, C, K (the `simulate` default system).
fn truth() -> [[[f64; 2]; 2]; 3] {
    let rig = bearing_ident::simulate::seed_rig();
    let block = |m: faer::MatRef<'_, f64>| [[m[(0, 0)], m[(0, 1)]], [m[(1, 0)], m[(1, 1)]]];
    [
        block(rig.mass()),
        block(rig.damping()),
        block(rig.stiffness()),
    ]
}

/// Largest relative error of the diagonal of `key` (`"M"`, `"C"`, `"K"`), signed.
fn diagonal_errors(v: &Value, key: &str, truth: &[[f64; 2]; 2]) -> [f64; 2] {
    let got = |i: usize| v[key][i][i].as_f64().unwrap();
    [got(0) / truth[0][0] - 1.0, got(1) / truth[1][1] - 1.0]
}

/// Largest error of a block relative to its Frobenius norm, cross terms included
/// ([`common::relative_error`]).
fn block_error(v: &Value, key: &str, truth: &[[f64; 2]; 2]) -> f64 {
    common::json_relative_error(&v[key], truth)
}

/// The identified coefficient of `term` on `dof` (`None`: planar) and its standard deviation.
fn coefficient(v: &Value, term: &str, dof: Option<u64>) -> (f64, f64) {
    let entry = v["nonlinear"]
        .as_array()
        .expect("a `nonlinear` array")
        .iter()
        .find(|e| e["term"] == term && e["dof"].as_u64() == dof)
        .unwrap_or_else(|| panic!("no {term} on {dof:?} in {}", v["nonlinear"]));
    (
        entry["value"].as_f64().unwrap(),
        entry["std"].as_f64().unwrap(),
    )
}

fn warned_misfit(v: &Value) -> bool {
    warned(v, "nonlinear_misfit")
}

/// Quick forcing: 50 N RMS band-limited (8–49 Hz) on both axes at once, 2 % noise.
const QUICK: [&str; 14] = [
    "--excitation",
    "random",
    "--freqs",
    "8,49",
    "--rate",
    "1024",
    "--duration",
    "32",
    "--records",
    "2",
    "--noise",
    "0.02",
    "--seed",
    "7",
];

const QUICK_ID: [&str; 6] = [
    "--band",
    "8,49",
    "--excitation",
    "random",
    "--nperseg",
    "4096",
];

/// One case: simulate with `terms`, identify with and without `--nonlinear kinds`, and return
/// both results.
fn case(name: &str, terms: &[&str], kinds: &str) -> (Value, Value) {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(&dir.path().join(name), &QUICK, terms);
    both(&files, kinds)
}

/// `files` identified with and without `--nonlinear kinds`.
fn both(files: &[String], kinds: &str) -> (Value, Value) {
    let with = identify(&[&QUICK_ID[..], &["--nonlinear", kinds]].concat(), files);
    let without = identify(&QUICK_ID, files);
    (with, without)
}

/// The dry-friction records (`--coulomb 20,15` under the quick forcing), simulated once for
/// the two tests that read them: a friction simulation resolves every stick in substeps and
/// is the slowest step of this suite.
fn coulomb_files() -> &'static [String] {
    static FILES: OnceLock<Vec<String>> = OnceLock::new();
    FILES.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("nonlinear-coulomb");
        // Records of an earlier run (perhaps of an earlier simulator) are not reused.
        let _ = std::fs::remove_dir_all(&dir);
        simulate(&dir, &QUICK, &["--coulomb", "20,15"])
    })
}

#[test]
fn dry_friction_is_recovered_and_removes_the_equivalent_damping() {
    let t = truth();
    let (with, without) = both(coulomb_files(), "coulomb");
    for (dof, f) in [(0, 20.0), (1, 15.0)] {
        let (value, std) = coefficient(&with, "coulomb", Some(dof));
        eprintln!("coulomb[{dof}] {value:.3} ± {std:.3} N (truth {f})");
        assert!((value / f - 1.0).abs() < 0.05, "coulomb[{dof}] = {value}");
        assert!(std > 0.0 && (value - f).abs() < 4.0 * std + 0.01 * f);
    }
    for (k, key) in ["M", "C", "K"].iter().enumerate() {
        let err = block_error(&with, key, &t[k]);
        eprintln!("with coulomb: {key} {err:.2e}");
        assert!(err < 0.03, "{key}: {err}");
    }
    // A linear-only fit turns the friction into damping: C too high by a lot.
    let c_bias = diagonal_errors(&without, "C", &t[1]);
    eprintln!("linear only: C diagonal {c_bias:?}");
    assert!(c_bias.iter().all(|&b| b > 0.08), "{c_bias:?}");
    // The guide's nonlinear chapter (docs/guide/07-nonlinear.md) quotes this run (its commands
    // are this case's): linear C +120 % / +88 %; with the term, friction 0.8 % / 0.8 % low and
    // C within 1.5 %.
    assert!(
        (1.15..1.25).contains(&c_bias[0]) && (0.83..0.93).contains(&c_bias[1]),
        "guide figures: {c_bias:?}"
    );
    let friction_low =
        [(0, 20.0), (1, 15.0)].map(|(d, f)| 1.0 - coefficient(&with, "coulomb", Some(d)).0 / f);
    assert!(
        (0.004..0.013).contains(&friction_low[0]) && (0.004..0.013).contains(&friction_low[1]),
        "guide figures: {friction_low:?}"
    );
    let c_with = diagonal_errors(&with, "C", &t[1]);
    assert!(
        c_with.iter().all(|b| b.abs() < 0.015),
        "guide figures: {c_with:?}"
    );
    assert!(!warned_misfit(&with), "{}", with["nonlinear_check"]);
}

#[test]
fn cubic_stiffness_is_recovered_and_biases_a_linear_k() {
    let t = truth();
    let (with, without) = case("cubic", &["--cubic", "2e11,1.5e11"], "cubic");
    for (dof, k3) in [(0, 2e11), (1, 1.5e11)] {
        let (value, std) = coefficient(&with, "cubic", Some(dof));
        eprintln!("cubic[{dof}] {value:.4e} ± {std:.2e} N/m³");
        assert!((value / k3 - 1.0).abs() < 0.02, "cubic[{dof}] = {value}");
    }
    for (k, key) in ["M", "C", "K"].iter().enumerate() {
        let err = block_error(&with, key, &t[k]);
        assert!(err < 0.02, "{key}: {err}");
    }
    let k_bias = diagonal_errors(&without, "K", &t[2]);
    eprintln!("linear only: K diagonal {k_bias:?}");
    assert!(k_bias.iter().all(|&b| b > 0.05), "{k_bias:?}");
}

#[test]
fn quadratic_damping_and_planar_friction_are_recovered() {
    let t = truth();
    let (qd, _) = case(
        "qd",
        &["--quadratic-damping", "2000,1500"],
        "quadratic-damping",
    );
    for (dof, q) in [(0, 2000.0), (1, 1500.0)] {
        let (value, _) = coefficient(&qd, "quadratic-damping", Some(dof));
        eprintln!("quadratic-damping[{dof}] {value:.1}");
        assert!((value / q - 1.0).abs() < 0.05, "qd[{dof}] = {value}");
    }
    let (planar, _) = case("planar", &["--coulomb-planar", "20"], "coulomb-planar");
    let (value, _) = coefficient(&planar, "coulomb-planar", None);
    eprintln!("coulomb-planar {value:.3}");
    assert!((value / 20.0 - 1.0).abs() < 0.05, "planar = {value}");
    for v in [&qd, &planar] {
        for (k, key) in ["M", "C", "K"].iter().enumerate() {
            let err = block_error(v, key, &t[k]);
            assert!(err < 0.03, "{key}: {err}");
        }
    }
}

fn warned(v: &Value, kind: &str) -> bool {
    v["warning_kinds"]
        .as_array()
        .is_some_and(|k| k.iter().any(|k| k == kind))
}

#[test]
fn a_wrong_regressor_is_flagged() {
    // Friction in the records, cubic stiffness in the model: Â is far from real and flat.
    let wrong = identify(
        &[&QUICK_ID[..], &["--nonlinear", "cubic"]].concat(),
        coulomb_files(),
    );
    eprintln!("check: {}", wrong["nonlinear_check"]);
    assert!(warned_misfit(&wrong), "{}", wrong["warning_kinds"]);
    // Quadratic damping in the records, friction in the model: both are odd in the velocity,
    // the linear damping takes up the difference and Â stays nearly real and flat; the
    // friction comes out negative, which no dry contact does.
    let (swapped, _) = case("swapped", &["--quadratic-damping", "2000,1500"], "coulomb");
    eprintln!("swapped: {}", swapped["nonlinear"]);
    assert!(
        warned(&swapped, "negative_dissipation"),
        "{}",
        swapped["warning_kinds"]
    );
}

/// One regressor of the reference case: its name, the `simulate` flags, the coefficients
/// expected per DOF, the relative tolerance.
struct Reference {
    term: &'static str,
    flags: &'static [&'static str],
    expected: &'static [(Option<u64>, f64)],
    tolerance: f64,
}

/// The reference case of `docs/method.md` section 4: two records of 60 s at 2048 samples/s, 50 N RMS on both
/// axes at once in 8–49 Hz, 2 % noise, 8 s Welch segments, every regressor at once in turn.
#[test]
#[ignore = "release only: cargo test --release --all-features --test nonlinear end_to_end:: -- --include-ignored"]
fn method_reference_case() {
    let forcing = [
        "--excitation",
        "random",
        "--freqs",
        "8,49",
        "--rate",
        "2048",
        "--duration",
        "60",
        "--records",
        "2",
        "--noise",
        "0.02",
    ];
    let id = [
        "--band",
        "8,49",
        "--excitation",
        "random",
        "--nperseg",
        "16384",
    ];
    let t = truth();
    let cases = [
        Reference {
            term: "coulomb",
            flags: &["--coulomb", "20,15"],
            expected: &[(Some(0), 20.0), (Some(1), 15.0)],
            tolerance: 0.03,
        },
        Reference {
            term: "coulomb-planar",
            flags: &["--coulomb-planar", "20"],
            expected: &[(None, 20.0)],
            tolerance: 0.03,
        },
        Reference {
            term: "cubic",
            flags: &["--cubic", "2e11,1.5e11"],
            expected: &[(Some(0), 2e11), (Some(1), 1.5e11)],
            tolerance: 0.005,
        },
        Reference {
            term: "quadratic-damping",
            flags: &["--quadratic-damping", "2000,1500"],
            expected: &[(Some(0), 2000.0), (Some(1), 1500.0)],
            tolerance: 0.02,
        },
    ];
    let dir = tempfile::tempdir().unwrap();
    for Reference {
        term: name,
        flags,
        expected,
        tolerance,
    } in cases
    {
        let start = std::time::Instant::now();
        let files = simulate(&dir.path().join(name), &forcing, flags);
        let simulated = start.elapsed().as_secs_f64();
        let with = identify(&[&id[..], &["--nonlinear", name]].concat(), &files);
        let without = identify(&id, &files);
        for &(dof, value) in expected {
            let (got, std) = coefficient(&with, name, dof);
            eprintln!(
                "{name}[{dof:?}]: {:+.3} % (± {:.3} %)",
                100.0 * (got / value - 1.0),
                100.0 * std / value
            );
            assert!((got / value - 1.0).abs() < tolerance, "{name}: {got}");
        }
        for (k, key) in ["M", "C", "K"].iter().enumerate() {
            let err = block_error(&with, key, &t[k]);
            eprintln!("{name}: {key} {:.3} % of the block", 100.0 * err);
            assert!(err < 0.01, "{name}: {key} {err}");
        }
        let (c, k) = (
            diagonal_errors(&without, "C", &t[1]),
            diagonal_errors(&without, "K", &t[2]),
        );
        eprintln!("{name}: linear only C {c:?}, K {k:?}; simulated in {simulated:.1} s");
        assert!(!warned_misfit(&with), "{name}: {}", with["nonlinear_check"]);
    }
}

/// Dry friction's bias over 6 seeds, in its own standard deviations: the quick forcing with
/// 2 % noise. Taking the sign of a noisy velocity flips it near zero crossings, which biased the
/// friction low by 2.0–3.4 % (dof 0), −4.9 σ on average; the regressor is now the sign's
/// expectation given the noisy velocity (`gather::sign_noise`), measured at −0.4 to −1.2 %,
/// −2.5 σ of the random error on average. What is left comes from the velocity dwelling near
/// zero (sticking) more than a Gaussian velocity would, which the correction does not model:
/// the predicted sign bias is carried as the term's `model_std` (in `std`) and named by
/// `friction_bias`. Measured against the combined σ: −0.66 to −1.42 σ, every 95 % interval
/// covering.
#[test]
#[ignore = "release only, 6 simulations: cargo test --release --all-features --test nonlinear end_to_end::friction_bias -- --include-ignored"]
fn friction_bias_over_seeds() {
    let dir = tempfile::tempdir().unwrap();
    let mut in_sigma = Vec::new();
    for seed in 1..=6 {
        let seed = seed.to_string();
        let forcing = [
            "--excitation",
            "random",
            "--freqs",
            "8,49",
            "--rate",
            "1024",
            "--duration",
            "32",
            "--records",
            "2",
            "--noise",
            "0.02",
            "--seed",
            &seed,
        ];
        let files = simulate(
            &dir.path().join(format!("friction-{seed}")),
            &forcing,
            &["--coulomb", "20,15"],
        );
        let with = identify(
            &[&QUICK_ID[..], &["--nonlinear", "coulomb"]].concat(),
            &files,
        );
        for (dof, f) in [(0, 20.0), (1, 15.0)] {
            let (value, std) = coefficient(&with, "coulomb", Some(dof));
            let entry = with["nonlinear"]
                .as_array()
                .unwrap()
                .iter()
                .find(|e| e["term"] == "coulomb" && e["dof"].as_u64() == Some(dof))
                .unwrap();
            let model = entry["model_std"].as_f64().unwrap();
            let random = (std * std - model * model).sqrt();
            assert!(model > 0.0, "seed {seed} dof {dof}: no predicted sign bias");
            if model > 0.5 * random {
                assert!(warned(&with, "friction_bias"), "seed {seed} dof {dof}");
            }
            assert!(
                ((value - f) / std).abs() < 1.96,
                "seed {seed} dof {dof}: {value} ± {std} (truth {f})"
            );
            eprintln!(
                "seed {seed} dof {dof}: {:+.3} % ± {:.3} %, {:+.2} σ",
                100.0 * (value / f - 1.0),
                100.0 * std / f,
                (value - f) / std
            );
            in_sigma.push((value - f) / std);
        }
    }
    let mean = in_sigma.iter().sum::<f64>() / in_sigma.len() as f64;
    eprintln!("mean bias {mean:+.2} combined σ");
    assert!(mean.abs() < 1.5, "{mean}");
}
