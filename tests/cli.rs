//! The command-line tool end to end: simulate → identify round trips, and one crafted bad input
//! per error kind, checking exit status 2, the one-line stderr and the JSON `error` kind.
#![cfg(feature = "cli")]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bearing-ident"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn csv_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path().display().to_string())
        .filter(|p| p.ends_with(".csv"))
        .collect();
    v.sort();
    v
}

fn simulate(dir: &Path, extra: &[&str]) -> Vec<String> {
    let out = run(&[&["simulate", "--out", dir.to_str().unwrap()], extra].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    csv_files(dir)
}

fn identify_json(args: &[&str], files: &[String]) -> Value {
    let file_refs: Vec<&str> = files.iter().map(String::as_str).collect();
    let out = run(&[&["identify", "--json"], args, &file_refs].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

fn matrix(v: &Value, key: &str) -> Vec<Vec<f64>> {
    v[key]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect()
}

/// Largest error relative to the block's Frobenius norm, as in `common::block_relative_error`.
fn block_error(got: &[Vec<f64>], truth: &[Vec<f64>]) -> f64 {
    let norm: f64 = truth.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    got.iter()
        .flatten()
        .zip(truth.iter().flatten())
        .map(|(g, t)| (g - t).abs() / norm)
        .fold(0.0, f64::max)
}

fn expect_failure(args: &[&str], kind: &str) {
    let out = run(args);
    assert_eq!(out.status.code(), Some(2), "args {args:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "one line on stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let v: Value = serde_json::from_slice(&out.stdout).expect("JSON error object");
    assert_eq!(v["error"], kind, "{v}");
    assert!(v["message"].as_str().unwrap().len() > 10);
}

#[test]
fn round_trip_two_dof_noise_free_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "2"]);
    assert_eq!(files.len(), 4);
    let v = identify_json(&["--band", "8,49", "--method", "ivf"], &files);
    let truth = bearing_ident::simulate::seed_rig();
    let rows = |m: faer::MatRef<'_, f64>| -> Vec<Vec<f64>> {
        (0..2)
            .map(|i| (0..2).map(|j| m[(i, j)]).collect())
            .collect()
    };
    for (key, t) in [
        ("M", truth.mass()),
        ("C", truth.damping()),
        ("K", truth.stiffness()),
    ] {
        let err = block_error(&matrix(&v, key), &rows(t));
        println!("n = 2 round trip {key}: {err:.3e}");
        assert!(err < common::EXACT, "{key}: {err:e}");
    }
    for key in [
        "method",
        "excitation",
        "estimator",
        "n",
        "fs",
        "n_records",
        "band_used_hz",
        "n_freq",
        "iterations",
        "converged",
        "condition_number",
        "fit",
        "natural_frequencies_hz",
        "damping_ratios",
        "warnings",
        "compute_ms",
    ] {
        assert!(!v[key].is_null(), "missing {key}");
    }
    assert_eq!(v["excitation"], "impact");
    assert_eq!(v["n_records"], 4);
    assert_eq!(v["n_freq"], 49);
    assert!((v["fs"].as_f64().unwrap() - 6700.0).abs() < 1e-6);
}

#[test]
fn round_trip_three_dof_with_noise_is_within_error_bars() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(
        dir.path(),
        &[
            "--mass",
            "2,0.1,0;0.1,2.5,0.2;0,0.2,3",
            "--damping",
            "60,8,-3;-5,70,4;2,-6,80",
            "--stiffness",
            "4e4,6e3,-1e3;2e3,6e4,5e3;-2e3,1e3,9e4",
            "--impacts",
            "3",
            "--noise",
            "0.05",
            "--seed",
            "7",
            "--rate",
            "2000",
        ],
    );
    assert_eq!(files.len(), 9);
    let v = identify_json(
        // The 6σ̂ bound below is derived for the sandwich (normal, many lines); a jackknife
        // over 3 sets has a t(2) distribution, far too wide-tailed for it.
        &[
            "--band",
            "3,60",
            "--force",
            "fx,fy,fz",
            "--disp",
            "x,y,z",
            "--uncertainty",
            "sandwich",
        ],
        &files,
    );
    let truth = [
        ("M", [[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]]),
        (
            "C",
            [[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
        ),
        ("K", [[4e4, 6e3, -1e3], [2e3, 6e4, 5e3], [-2e3, 1e3, 9e4]]),
    ];
    for (key, t) in truth {
        let (got, std) = (matrix(&v, key), matrix(&v, &format!("{key}_std")));
        for i in 0..3 {
            let err = (got[i][i] - t[i][i]).abs();
            println!(
                "n = 3 {key}{i}{i}: error {:.2e} relative, {:.2} σ̂",
                err / t[i][i],
                err / std[i][i]
            );
            // 6 σ̂: see tests/properties.rs for the derivation.
            assert!(err < 6.0 * std[i][i], "{key}{i}{i}");
        }
    }
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p: PathBuf = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// A small valid record text with `rows` samples at 100 samples/s.
fn good_text(rows: usize) -> String {
    let mut s = String::from("t,fx,fy,x,y\n");
    for m in 0..rows {
        let f = if m == 3 { 1.0 } else { 0.0 };
        s += &format!(
            "{},{f},0,{},{}\n",
            m as f64 * 0.01,
            1e-6 * (m % 7) as f64,
            1e-7 * (m % 5) as f64
        );
    }
    s
}

#[test]
fn every_error_kind_exits_2_with_its_kind() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = write(d, "good.csv", &good_text(64));
    let ragged = write(
        d,
        "ragged.csv",
        &good_text(64).replace("0.05,0,0,", "0.05,0,"),
    );
    let text = write(
        d,
        "text.csv",
        &good_text(64).replace("0.06,0,0", "0.06,zero,0"),
    );
    let nocol = write(
        d,
        "nocol.csv",
        &good_text(64).replace("t,fx,fy,x,y", "t,fx,fy,x,z"),
    );
    let nan = write(
        d,
        "nan.csv",
        &good_text(64).replace("0.07,0,0,", "0.07,0,inf,"),
    );
    let jitter = write(d, "jitter.csv", &good_text(64).replace("0.08,", "0.0815,"));
    let short = write(d, "short.csv", &good_text(32));
    let band = ["identify", "--json", "--band", "1,40"];
    expect_failure(&[&band[..], &[&ragged]].concat(), "malformed_csv");
    expect_failure(&[&band[..], &[&text]].concat(), "malformed_csv");
    expect_failure(&[&band[..], &[&nocol]].concat(), "missing_column");
    expect_failure(&[&band[..], &[&nan]].concat(), "non_finite");
    expect_failure(&[&band[..], &[&jitter]].concat(), "nonuniform_time");
    expect_failure(
        &[&band[..], &[&good, &short]].concat(),
        "inconsistent_records",
    );
    expect_failure(
        &["identify", "--json", "--band", "8,500", &good],
        "bad_band",
    );
    expect_failure(
        &["identify", "--json", "--band", "eight,49", &good],
        "bad_band",
    );

    // Rank-deficient: impacts in x only.
    let sim = tempfile::tempdir().unwrap();
    let files = simulate(sim.path(), &["--impacts", "2", "--noise", "0.3"]);
    let x_only: Vec<&str> = files
        .iter()
        .filter(|f| f.contains("dof0"))
        .map(String::as_str)
        .collect();
    expect_failure(
        &[&["identify", "--json", "--band", "8,49"][..], &x_only].concat(),
        "rank_deficient",
    );
    // Not converged: noisy records and a single IVF iteration.
    let all: Vec<&str> = files.iter().map(String::as_str).collect();
    expect_failure(
        &[
            &[
                "identify",
                "--json",
                "--band",
                "8,49",
                "--max-iterations",
                "1",
            ][..],
            &all,
        ]
        .concat(),
        "not_converged",
    );
    // The same with --allow-unconverged succeeds and says so.
    let v = identify_json(
        &[
            "--band",
            "8,49",
            "--max-iterations",
            "1",
            "--allow-unconverged",
        ],
        &files,
    );
    assert_eq!(v["converged"], false);
    assert!(v["warnings"][0].as_str().unwrap().contains("not converged"));
}

#[test]
fn errors_name_file_and_line_in_plain_mode() {
    let dir = tempfile::tempdir().unwrap();
    let ragged = write(
        dir.path(),
        "ragged.csv",
        &good_text(64).replace("0.05,0,0,", "0.05,0,"),
    );
    let out = run(&["identify", "--band", "1,40", &ragged]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("ragged.csv") && stderr.contains("line 7"),
        "{stderr}"
    );
}

#[test]
fn random_excitation_is_detected_and_uses_h1() {
    // White-noise forcing in both directions at once, recorded as one long record.
    use bearing_ident::simulate::{AntiAlias, Simulator};
    let truth = bearing_ident::simulate::seed_rig();
    let fs = 1000.0;
    let n = 40_000;
    let mut sim = Simulator::new(&truth, fs, n, AntiAlias::default()).unwrap();
    let rec = sim.random_record("random", 100.0, 11).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let layout = bearing_ident::io::CsvLayout::default();
    let path = dir.path().join("random.csv");
    bearing_ident::io::write_record(&path, &rec, &layout).unwrap();
    let v = identify_json(&["--band", "8,49"], &[path.display().to_string()]);
    assert_eq!(v["excitation"], "random");
    assert_eq!(v["excitation_auto"], true);
    assert_eq!(v["estimator"], "h1");
    let k = matrix(&v, "K");
    let k_std = matrix(&v, "K_std");
    assert!(
        (k[0][0] - 146.3e3).abs() < 6.0 * k_std[0][0],
        "{k:?} ± {k_std:?}"
    );
}

#[test]
fn exponential_window_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "1"]);
    let v = identify_json(&["--band", "8,49", "--window", "exp:0.01"], &files);
    assert_eq!(v["window"], "exp");
    // a = −ln(0.01)/1.2 s (the seed's figure).
    assert!((v["window_decay_per_s"].as_f64().unwrap() - 3.8376).abs() < 1e-4);
    let k = matrix(&v, "K");
    assert!(
        (k[0][0] / 146.3e3 - 1.0).abs() < 1e-6,
        "corrected K_xx {}",
        k[0][0]
    );
    expect_failure(
        &[
            &["identify", "--json", "--band", "8,49", "--window", "exp:2"][..],
            &[files[0].as_str()],
        ]
        .concat(),
        "invalid_argument",
    );
}

#[test]
fn demo_runs() {
    let out = run(&["demo", "--noise", "0.0"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("K xx (N/m)") && text.contains("natural frequency"));
}
