//! The command-line tool end to end: simulate → identify round trips, and one crafted bad input
//! per error kind, checking exit status 2, the one-line stderr and the JSON `error` kind.
#![cfg(feature = "cli")]

use crate::common;
use crate::common::{bin, csv_files, run};

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;

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

pub(crate) fn matrix(v: &Value, key: &str) -> Vec<Vec<f64>> {
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

/// Largest error relative to the block's Frobenius norm ([`common::relative_error`]).
pub(crate) fn block_error(got: &[Vec<f64>], truth: &[Vec<f64>]) -> f64 {
    common::relative_error(
        got.iter().flatten().copied(),
        truth.iter().flatten().copied(),
    )
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
    // Parsed ahead on worker threads, the files are identified in the order given.
    let listed: Vec<&str> = v["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert_eq!(listed, files);
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
            // 6 σ̂: see tests/estimation/properties.rs for the derivation.
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
    // a = −ln(0.01)/1.2 s (the seed's figure), in the window's string form too.
    let a = v["window_decay_per_s"].as_f64().unwrap();
    assert!((a - 3.8376).abs() < 1e-4);
    assert_eq!(v["window"], format!("exp:{a}/s"));
    // The same decay stated in 1/s gives the same window and the same coefficients.
    let fixed = identify_json(
        &["--band", "8,49", "--window", &format!("exp:{a}/s")],
        &files,
    );
    assert_eq!(fixed["window"], v["window"]);
    assert_eq!(fixed["K"], v["K"]);
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
    assert!(text.contains("K_xx (N/m)") && text.contains("natural frequency"));
}

/// The seed rig's matrices, rows as in the JSON.
fn seed_truth() -> [Vec<Vec<f64>>; 3] {
    let t = bearing_ident::simulate::seed_rig();
    let rows = bearing_ident::model::rows;
    [rows(t.mass()), rows(t.damping()), rows(t.stiffness())]
}

/// Every excitation kind through `simulate` and `identify`, noise-free: the coefficients come
/// back to within the simulation's floor (measured: multisine 1.9e-8, stepped sine 1.1e-7,
/// sweep 2.7e-7 of each block's norm, worst block).
#[test]
fn every_excitation_kind_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str], &[&str]); 3] = [
        (
            "multisine",
            &[
                "--kind",
                "multisine",
                "--records",
                "1",
                "--rate",
                "1000",
                "--periods",
                "2",
            ],
            &[
                "--band",
                "5,60",
                "--excitation",
                "periodic",
                "--period",
                "1",
            ],
        ),
        (
            "stepped",
            &[
                "--kind",
                "stepped-sine",
                "--rate",
                "2000",
                "--freqs",
                "10,48,8",
            ],
            &["--band", "8,49", "--excitation", "stepped-sine"],
        ),
        (
            "sweep",
            &["--kind", "sweep", "--records", "1", "--rate", "2000"],
            &["--band", "8,49", "--excitation", "sweep"],
        ),
    ];
    let truth = seed_truth();
    for (name, sim, id) in cases {
        let files = simulate(&dir.path().join(name), sim);
        let v = identify_json(id, &files);
        let worst = ["M", "C", "K"]
            .iter()
            .zip(&truth)
            .map(|(k, t)| block_error(&matrix(&v, k), t))
            .fold(0.0, f64::max);
        assert!(worst < common::EXACT, "{name}: {worst}");
        let kind = match name {
            "multisine" => "periodic",
            "stepped" => "stepped-sine",
            other => other,
        };
        assert_eq!(v["excitation"], kind);
    }
    // The periodic run left the unexcited band lines out: 5–7 Hz and 50–60 Hz at 1 Hz.
    let files = csv_files(&dir.path().join("multisine"));
    let v = identify_json(
        &[
            "--band",
            "5,60",
            "--excitation",
            "periodic",
            "--period",
            "1",
        ],
        &files,
    );
    assert_eq!(v["unexcited_lines"], 14);
    assert_eq!(v["segmentation"], "periods");
    // Without `--excitation` or `--period`, the records are found to repeat (two periods
    // each, the least that shows it) and their period is found: the same fit.
    let auto = identify_json(&["--band", "5,60"], &files);
    assert_eq!(auto["excitation"], "periodic");
    assert_eq!(auto["period"], 1.0);
    for key in ["M", "C", "K"] {
        assert_eq!(auto[key], v[key], "{key}");
    }
    // Random records have no period to find.
    let random = simulate(
        &dir.path().join("random"),
        &["--kind", "random", "--records", "1", "--rate", "1000"],
    );
    expect_failure(
        &[
            &[
                "identify",
                "--json",
                "--band",
                "5,60",
                "--excitation",
                "periodic",
            ],
            &random.iter().map(String::as_str).collect::<Vec<_>>()[..],
        ]
        .concat(),
        "invalid_argument",
    );
}

/// `--baseline` from a directory and from a saved JSON result give the same bearing; the
/// bearing is the difference of the two systems within its error bars; `--per-frequency`,
/// `--force-gate`, `--estimator h2|hv` and `--uncertainty bootstrap` reach the JSON.
#[test]
fn baseline_per_frequency_gate_and_bootstrap_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let common_args = [
        "--impacts",
        "4",
        "--noise",
        "0.02",
        "--duration",
        "4.5",
        "--rate",
        "2000",
    ];
    let wet = simulate(&dir.path().join("wet"), &common_args);
    let dry_dir = dir.path().join("dry");
    simulate(
        &dry_dir,
        &[
            &common_args[..],
            &[
                "--seed",
                "7",
                "--mass",
                "4.0,0;0,4.1",
                "--damping",
                "30,0;0,30",
            ],
            &["--stiffness", "100e3,0;0,110e3"],
        ]
        .concat(),
    );
    let dry = identify_json(&["--band", "8,49"], &csv_files(&dry_dir));
    let json_path = dir.path().join("dry.json");
    std::fs::write(&json_path, dry.to_string()).unwrap();
    let from_dir = identify_json(
        &["--band", "8,49", "--baseline", dry_dir.to_str().unwrap()],
        &wet,
    );
    let from_json = identify_json(
        &[
            "--band",
            "8,49",
            "--baseline",
            json_path.to_str().unwrap(),
            "--per-frequency",
        ],
        &wet,
    );
    // The same up to the JSON's decimal round trip of the baseline.
    for key in ["M", "C", "K"] {
        let (a, b) = (
            matrix(&from_dir["bearing"], key),
            matrix(&from_json["bearing"], key),
        );
        let scale = a.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (x, y) in a.iter().flatten().zip(b.iter().flatten()) {
            assert!((x - y).abs() <= 1e-12 * scale, "{key}: {x} vs {y}");
        }
    }
    // Truth: seed rig minus the dry structure.
    let expected = [
        ("M", [[0.7, 0.0], [0.0, 0.7]]),
        ("C", [[101.98, 0.0], [0.0, 101.98]]),
        ("K", [[46.3e3, 22.3e3], [11.5e3, 59.1e3]]),
    ];
    let bearing = &from_json["bearing"];
    for (key, truth) in expected {
        let (got, std) = (matrix(bearing, key), matrix(bearing, &format!("{key}_std")));
        for i in 0..2 {
            for j in 0..2 {
                let z = (got[i][j] - truth[i][j]) / std[i][j];
                assert!(z.abs() < 6.0, "{key}[{i}][{j}]: {} ({z:.1} σ)", got[i][j]);
            }
        }
    }
    let lines = from_json["per_frequency"].as_array().unwrap();
    assert_eq!(lines.len(), from_json["n_freq"].as_u64().unwrap() as usize);
    for key in ["freq_hz", "K", "C", "K_std", "C_std", "K_eff", "C_eff"] {
        assert!(!lines[0][key].is_null(), "{key}");
    }
    // A baseline processed differently is refused.
    let wet_refs: Vec<&str> = wet.iter().map(String::as_str).collect();
    let dry_path = dry_dir.to_str().unwrap();
    expect_failure(
        &[
            &["identify", "--json", "--band", "8,40", "--baseline"],
            &[json_path.to_str().unwrap()][..],
            &wet_refs,
        ]
        .concat(),
        "baseline_mismatch",
    );
    let empty = dir.path().join("empty.json");
    std::fs::write(&empty, "{}").unwrap();
    expect_failure(
        &[
            &["identify", "--json", "--band", "8,49", "--baseline"],
            &[empty.to_str().unwrap()][..],
            &wet_refs,
        ]
        .concat(),
        "bad_baseline",
    );
    let gated = identify_json(
        &[
            "--band",
            "8,49",
            "--force-gate",
            "0.03",
            "--uncertainty",
            "bootstrap",
            "--bootstrap-draws",
            "50",
        ],
        &wet,
    );
    assert_eq!(gated["force_gate_s"], 0.03);
    assert_eq!(gated["uncertainty"], "bootstrap");
    for estimator in ["h2", "hv"] {
        let v = identify_json(
            &[
                "--band",
                "8,49",
                "--estimator",
                estimator,
                "--baseline",
                dry_path,
            ],
            &wet,
        );
        assert_eq!(v["estimator"], estimator);
        assert!(block_error(&matrix(&v, "K"), &seed_truth()[2]) < 0.01);
    }
}

/// `--method ml` on periodic records: the JSON carries the likelihood report, the error bars
/// are the inverse Fisher information, and every diagonal coefficient lies within 6 of them of
/// the truth (measured: within 2.24 σ). Cut into Welch segments, the residual noise model is
/// used; with fewer than 3 periods it is refused.
#[test]
fn maximum_likelihood_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(
        &dir.path().join("ms"),
        &[
            "--kind",
            "multisine",
            "--records",
            "1",
            "--rate",
            "1000",
            "--periods",
            "8",
            "--noise",
            "0.3",
        ],
    );
    let v = identify_json(
        &[
            "--band",
            "8,49",
            "--excitation",
            "periodic",
            "--period",
            "1",
            "--method",
            "ml",
        ],
        &files,
    );
    assert_eq!(v["method"], "ml");
    assert_eq!(v["uncertainty"], "fisher");
    assert!(v["ml"]["fell_back"].is_null());
    let ratio = v["ml"]["cost_ratio"].as_f64().unwrap();
    assert!((0.7..1.5).contains(&ratio), "{ratio}");
    let truth = seed_truth();
    let mut worst: f64 = 0.0;
    for (b, key) in ["M", "C", "K"].iter().enumerate() {
        let (got, std) = (matrix(&v, key), matrix(&v, &format!("{key}_std")));
        for i in 0..2 {
            worst = worst.max((got[i][i] - truth[b][i][i]).abs() / std[i][i]);
        }
    }
    println!("worst |error| / σ: {worst:.2}");
    assert!(worst < 6.0, "{worst}");
    assert_eq!(v["ml"]["noise_model"], "periodic_repeats");
    // Cut into Welch segments instead, the residual noise model takes over.
    let welch = identify_json(
        &["--band", "8,49", "--excitation", "random", "--method", "ml"],
        &files,
    );
    assert_eq!(welch["ml"]["noise_model"], "welch_residuals");
    assert!(welch["ml"]["fell_back"].is_null());
    // Periodic with fewer than 3 periods per record: refused.
    let refs: Vec<&str> = files.iter().map(String::as_str).collect();
    expect_failure(
        &[
            &[
                "identify",
                "--json",
                "--band",
                "8,49",
                "--excitation",
                "periodic",
                "--period",
                "3",
                "--method",
                "ml",
            ],
            &refs[..],
        ]
        .concat(),
        "ml_needs_repeats",
    );
}

/// `--method ml` on impact and random records: the residual noise models, named in the JSON
/// (`ml.noise_model`); random records without `--nperseg` get a Welch length chosen from a
/// first fit (`welch_choice`), and `--nperseg` overrides it.
#[test]
fn maximum_likelihood_on_impact_and_random_records() {
    let dir = tempfile::tempdir().unwrap();
    let impacts = simulate(
        &dir.path().join("hits"),
        &["--impacts", "4", "--noise", "0.2"],
    );
    let v = identify_json(&["--band", "8,49", "--method", "ml"], &impacts);
    assert_eq!(v["excitation"], "impact");
    assert_eq!(v["ml"]["noise_model"], "impact_residuals");
    assert!(v["ml"]["fell_back"].is_null());
    assert!(v["welch_choice"].is_null());
    assert!(block_error(&matrix(&v, "K"), &seed_truth()[2]) < 0.02);
    let random = simulate(
        &dir.path().join("random"),
        &[
            "--kind",
            "random",
            "--records",
            "2",
            "--noise",
            "0.2",
            "--rate",
            "1000",
            "--duration",
            "40",
        ],
    );
    let v = identify_json(
        &["--band", "8,49", "--excitation", "random", "--method", "ml"],
        &random,
    );
    assert_eq!(v["ml"]["noise_model"], "welch_residuals");
    let choice = &v["welch_choice"];
    assert_eq!(v["nperseg"], choice["nperseg"]);
    assert!(
        choice["predicted_bias"].as_f64().unwrap() < 0.01,
        "{choice}"
    );
    assert!(block_error(&matrix(&v, "K"), &seed_truth()[2]) < 0.02);
    let v = identify_json(
        &[
            "--band",
            "8,49",
            "--excitation",
            "random",
            "--nperseg",
            "1024",
        ],
        &random,
    );
    assert_eq!(v["nperseg"], 1024);
    assert!(v["welch_choice"].is_null());
}

#[test]
fn identify_plot_writes_figures_and_a_static_report() {
    let dir = tempfile::tempdir().unwrap();
    let records = dir.path().join("records");
    let files = simulate(&records, &["--impacts", "2", "--noise", "0.02"]);
    let report = dir.path().join("report");
    let file_refs: Vec<&str> = files.iter().map(String::as_str).collect();
    let out = run(&[
        &[
            "identify",
            "--band",
            "8,49",
            "--plot",
            report.to_str().unwrap(),
        ],
        &file_refs[..],
    ]
    .concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    for stem in [
        "flexibility",
        "impedance",
        "coherence",
        "per_frequency",
        "records",
        "convergence",
        "residual",
    ] {
        assert!(report.join(format!("{stem}.svg")).is_file(), "{stem}");
        assert!(html.contains(&format!("href=\"{stem}.svg\"")), "{stem}");
    }
    // The axis names come from --disp; the text table is folded in.
    assert!(html.contains("<td>K_xy (N/m)</td>") && html.contains("<summary>Text report"));
    assert!(!html.contains("<script"));
    // The plain-text table still goes to stdout.
    assert!(String::from_utf8_lossy(&out.stdout).contains("Coefficients"));
}

#[test]
fn identify_reports_the_fit_gate_in_json() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "3", "--noise", "0.05"]);
    // A force gate of 1 ns closes before the 2 ms pulse: the fit explains nothing.
    let v = identify_json(
        &["--band", "8,49", "--force-gate=1e-9", "--allow-unconverged"],
        &files,
    );
    let kinds: Vec<&str> = v["warning_kinds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| k.as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"force_gate_short"), "{kinds:?}");
    assert!(kinds.contains(&"poor_fit"), "{kinds:?}");
    assert_eq!(kinds.len(), v["warnings"].as_array().unwrap().len());
    // The threshold is a setting; sound records pass it.
    let v = identify_json(&["--band", "8,49", "--min-r2", "0.5"], &files);
    assert_eq!(
        v["warning_kinds"],
        serde_json::json!([]),
        "{}",
        v["warnings"]
    );
}

/// Sets the named columns of a CSV record to zero (a channel that did not register).
fn zero_columns(path: &str, columns: &[&str]) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let zeroed: Vec<usize> = header
        .split(',')
        .enumerate()
        .filter(|(_, name)| columns.contains(name))
        .map(|(i, _)| i)
        .collect();
    assert_eq!(zeroed.len(), columns.len(), "{header}");
    let mut out = format!("{header}\n");
    for line in lines {
        let fields: Vec<&str> = line
            .split(',')
            .enumerate()
            .map(|(i, v)| if zeroed.contains(&i) { "0" } else { v })
            .collect();
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    std::fs::write(path, out).unwrap();
}

/// Screening on by default: a hammer hit that did not register (`fx`, `fy` zero in one x-hit
/// file of sixteen) is named in the table and the JSON; `--reject-bad-records` (and its
/// hidden alias `--reject-bad-impacts`) leaves it out and M comes back.
#[test]
fn dead_force_channel_is_screened_and_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "8", "--noise", "0.05"]);
    assert_eq!(files.len(), 16);
    let dead = files
        .iter()
        .find(|f| f.ends_with("impact-dof0-2.csv"))
        .unwrap();
    zero_columns(dead, &["fx", "fy"]);

    let v = identify_json(&["--band", "8,49"], &files);
    let warnings: Vec<&str> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    println!("{warnings:#?}");
    for channel in ["force channel 0 is flat", "force channel 1 is flat"] {
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("impact-dof0-2") && w.contains(channel)),
            "{warnings:?}"
        );
    }
    let kinds = v["warning_kinds"].as_array().unwrap();
    assert!(kinds.iter().any(|k| k == "flat_channel"), "{kinds:?}");
    assert!(kinds.iter().any(|k| k == "outlier_set"), "{kinds:?}");
    let m = matrix(&v, "M")[0][0];
    assert!((m / 4.7 - 0.875).abs() < 0.02, "{m}");

    let file_refs: Vec<&str> = files.iter().map(String::as_str).collect();
    let out = run(&[&["identify", "--band", "8,49"], &file_refs[..]].concat());
    assert!(out.status.success());
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.lines().any(|l| l.contains("warning:")
            && l.contains("impact-dof0-2")
            && l.contains("force channel 0")),
        "{table}"
    );

    for flag in ["--reject-bad-records", "--reject-bad-impacts"] {
        let v = identify_json(&["--band", "8,49", flag], &files);
        let warnings = v["warnings"].as_array().unwrap();
        assert!(
            warnings.iter().any(|w| {
                let w = w.as_str().unwrap();
                w.contains("impact-dof0-2") && w.contains("rejected: force channel 0 flat")
            }),
            "{warnings:?}"
        );
        let (m, m_std) = (matrix(&v, "M")[0][0], matrix(&v, "M_std")[0][0]);
        println!("{flag}: M_xx {m:.4} ± {m_std:.4} kg");
        assert!((m - 4.7).abs() < 6.0 * m_std, "{m} ± {m_std}");
    }
}

/// `simulate` refuses sizes past its documented limits with a typed error instead of
/// panicking, aborting or running without end; a mass that is not positive definite, or a
/// system that does not decay, is named.
#[test]
fn simulate_refuses_sizes_past_its_limits() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let head = ["simulate", "--json", "--out", out];
    let seed_k = "146.3e3,22.3e3;11.5e3,169.1e3";
    let cases: Vec<(Vec<&str>, &str, &str)> = vec![
        (
            vec!["--duration", "1e30"],
            "too_large",
            "samples per record",
        ),
        (vec!["--duration", "1e9"], "too_large", "samples per record"),
        (vec!["--rate", "1e12"], "too_large", "slowest mode"),
        (
            vec!["--records", "18446744073709551615", "--kind", "random"],
            "too_large",
            "records",
        ),
        (
            vec!["--impacts", "18446744073709551615"],
            "too_large",
            "records",
        ),
        (
            vec!["--kind", "stepped-sine", "--freqs", "10,48,1e9"],
            "too_large",
            "records",
        ),
        (
            vec!["--kind", "multisine", "--period", "1e6"],
            "too_large",
            "samples per record",
        ),
        (
            vec!["--kind", "sweep", "--freqs", "5,inf"],
            "invalid_argument",
            "--freqs",
        ),
        (
            vec![
                "--mass=-4.7,0;0,4.8",
                "--damping=131.98,0;0,131.98",
                "--stiffness",
                seed_k,
            ],
            "invalid_argument",
            "mass matrix",
        ),
        (
            vec![
                "--mass=4.7,0;0,4.8",
                "--damping=1e-9,0;0,1e-9",
                "--stiffness",
                seed_k,
            ],
            "too_large",
            "slowest mode",
        ),
        (
            vec![
                "--mass=4.7,0;0,4.8",
                "--damping=0,0;0,0",
                "--stiffness",
                seed_k,
                "--kind",
                "random",
            ],
            "invalid_argument",
            "damping matrix",
        ),
    ];
    for (extra, kind, says) in cases {
        let args = [&head[..], &extra[..]].concat();
        let start = std::time::Instant::now();
        let o = run(&args);
        assert!(
            start.elapsed().as_secs_f64() < 20.0,
            "{extra:?} took too long"
        );
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        let v: Value = serde_json::from_slice(&o.stdout).expect("JSON error");
        assert_eq!(v["error"], kind, "{extra:?}: {v}");
        let message = v["message"].as_str().unwrap();
        assert!(message.contains(says), "{extra:?}: {message}");
    }
    // Within the limits, --json says what was written.
    let o = run(&[&head[..], &["--impacts", "1", "--duration", "1.2"]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["records"], 2);
    assert_eq!(v["samples"], 8040);
    // Counts from the user that once sized allocations (bootstrap draws, IVF iterations).
    let files = simulate(dir.path(), &["--impacts", "3", "--noise", "0.05"]);
    let files: Vec<&str> = files.iter().map(String::as_str).collect();
    let head = ["identify", "--json", "--band", "8,49"];
    let huge = "18446744073709551615";
    let o = run(&[
        &head[..],
        &["--uncertainty", "bootstrap", "--bootstrap-draws", huge],
        &files,
    ]
    .concat());
    assert_eq!(o.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["error"], "too_large", "{v}");
    // A baseline file that never ends is read only up to its limit.
    let o = run(&[&head[..], &["--baseline", "/dev/zero"], &files].concat());
    assert_eq!(o.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["error"], "too_large", "{v}");
    let o = run(&[&head[..], &["--max-iterations", huge], &files].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Argument errors (clap's and the tool's own) print `{"error": "invalid_argument", …}` on
/// stdout and exit 2 when `--json` is given, for every subcommand; the input they quote is
/// bounded.
#[test]
fn argument_errors_are_json_with_json() {
    let long = "9".repeat(100_000);
    let cases: Vec<Vec<&str>> = vec![
        vec!["identify", "--json", "--band", "8,49", "--bogus", "f.csv"],
        vec![
            "identify", "--json", "--band", "8,49", "--method", "magic", "f.csv",
        ],
        vec!["identify", "--json", "f.csv"],
        vec![
            "identify", "--json", "--band", "8,49", "--window", &long, "f.csv",
        ],
        vec!["demo", "--json", "--noise", "abc"],
        vec!["demo", "--json", "--noise", &long[..]],
        vec!["simulate", "--json", "--out", "x", "--rate", "fast"],
        vec!["simulate", "--json"],
        vec!["--json"],
    ];
    for args in cases {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let v: Value = serde_json::from_slice(&o.stdout).expect("JSON on stdout");
        let shown: Vec<&str> = args.iter().map(|a| &a[..a.len().min(20)]).collect();
        assert!(
            v["error"] == "invalid_argument" || v["error"] == "io_error",
            "{shown:?}: {v}"
        );
        let message = v["message"].as_str().unwrap();
        assert!(message.len() < 500, "{shown:?}: {} bytes", message.len());
        assert!(
            o.stderr.len() < 600,
            "{shown:?}: stderr {} bytes",
            o.stderr.len()
        );
    }
    // Without --json clap's own text (with its tip) remains.
    let o = run(&["demo", "--noise", "abc"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stdout.is_empty());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--help"));
}

/// A record file with no newline, or a huge header, is quoted by at most 80 characters in the
/// error (stderr and JSON), and `/dev/zero` stops at the line limit.
#[test]
fn huge_lines_are_not_echoed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let no_newline = write(d, "one-line.csv", &"t,fx,fy,x,y,".repeat(40_000));
    let wide = write(
        d,
        "wide.csv",
        &format!("t,fx,fy,x,{}\n0,0,0,0,0\n", "q".repeat(500_000)),
    );
    for file in [no_newline.as_str(), wide.as_str(), "/dev/zero"] {
        let o = run(&["identify", "--json", "--band", "8,49", file]);
        assert_eq!(o.status.code(), Some(2), "{file}");
        let v: Value = serde_json::from_slice(&o.stdout).expect("JSON");
        let message = v["message"].as_str().unwrap();
        assert!(message.len() < 400, "{file}: {} bytes", message.len());
        assert!(
            o.stderr.len() < 500,
            "{file}: stderr {} bytes",
            o.stderr.len()
        );
        assert!(
            v["error"] == "too_large" || v["error"] == "missing_column",
            "{file}: {v}"
        );
    }
}

/// `text` of a simulated record with both force columns set to zero.
fn without_force(text: &str) -> String {
    let mut lines = text.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        out.push_str(&format!("{},0,0,{}\n", fields[0], fields[3..].join(",")));
    }
    out
}

#[test]
fn a_dead_force_in_the_first_file_is_not_a_band_error() {
    // Auto detection used to read the first file only: a flat force has no crest, so impacts
    // were taken for random excitation and Welch segments left too few lines (`bad_band`).
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "2"]);
    let dead = without_force(&std::fs::read_to_string(&files[0]).unwrap());
    std::fs::write(&files[0], dead).unwrap();
    let v = identify_json(&["--band", "8,49"], &files);
    assert_eq!(v["excitation"], "impact", "{v}");
    assert_eq!(v["n_records"], 4);
    // With every force dead, the error names the first record and its force channel.
    for f in &files[1..] {
        let dead = without_force(&std::fs::read_to_string(f).unwrap());
        std::fs::write(f, dead).unwrap();
    }
    let refs: Vec<&str> = files.iter().map(String::as_str).collect();
    expect_failure(
        &[&["identify", "--json", "--band", "8,49"], &refs[..]].concat(),
        "dead_channel",
    );
    let out = run(&[&["identify", "--band", "8,49"], &refs[..]].concat());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&files[0]) && stderr.contains("force channel 0"),
        "{stderr}"
    );
}

/// A reader of stdout that goes away before the result is written (`bearing-ident … | head
/// -1`) ends the tool quietly: status 0, no panic and nothing on stderr, for the table and the
/// JSON alike.
#[test]
fn a_closed_stdout_is_a_quiet_success() {
    for args in [&["demo"][..], &["demo", "--json"][..]] {
        let mut child = bin()
            .args(args)
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("the binary runs");
        // Close the read end at once: the demo simulates and identifies before it writes.
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("the binary ends");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(stderr.is_empty(), "{args:?}: {stderr}");
        assert!(out.status.success(), "{args:?}: {:?}", out.status);
    }
}

/// The record files of `dir` written again as Universal Files (one record, load case 0, per
/// file: its time histories, force data type 13, displacement 8), in the same order.
fn as_uff(csv: &[String], dofs: usize) -> Vec<String> {
    use bearing_ident::uff::{self, Function};
    let layout = bearing_ident::io::CsvLayout::for_dofs(dofs);
    csv.iter()
        .map(|path| {
            let r = bearing_ident::io::read_record(path, &layout).unwrap();
            let dt = 1.0 / r.sample_rate();
            let mut functions = Vec::new();
            for i in 0..dofs {
                let dir = i as i64 + 1;
                functions.push(Function::time_response(
                    1,
                    dir,
                    13,
                    0.0,
                    dt,
                    r.force(i).to_vec(),
                ));
                let x = r.displacement(i).to_vec();
                functions.push(Function::time_response(1, dir, 8, 0.0, dt, x));
            }
            let out = path.replace(".csv", ".uff");
            let mut bytes = Vec::new();
            uff::write_binary(&mut bytes, &functions, uff::ByteOrder::Little).unwrap();
            std::fs::write(&out, bytes).unwrap();
            out
        })
        .collect()
}

/// No path may lose or reorder a record: for every excitation kind, `identify` on 1–8 files
/// (CSV, then the same records as Universal Files), given in an order that is not sorted,
/// reports `files` equal to the list given and `n_records` its length. Fewer files than a
/// kind needs to span its directions or lines are refused (never answered with fewer).
fn every_file_kept_in_order(
    kind: &str,
    simulate_args: &[&str],
    identify_args: &[&str],
    least: usize,
) {
    let dir = tempfile::tempdir().unwrap();
    let csv = simulate(dir.path(), &[&["--kind", kind], simulate_args].concat());
    assert_eq!(csv.len(), 8, "{kind}: {csv:?}");
    let dofs = if simulate_args.contains(&"--mass") {
        1
    } else {
        2
    };
    let uff = as_uff(&csv, dofs);
    // An order that is neither sorted nor reversed, with both directions in its first two.
    let order = [7, 0, 5, 2, 3, 4, 1, 6];
    // CSV files need their columns named for one degree of freedom; Universal Files do not.
    let csv_only: &[&str] = if dofs == 1 {
        &["--force", "fx", "--disp", "x"]
    } else {
        &[]
    };
    for (files, extra) in [(&csv, csv_only), (&uff, &[][..])] {
        for n in 1..=8 {
            let given: Vec<String> = order[..n].iter().map(|&i| files[i].clone()).collect();
            let refs: Vec<&str> = given.iter().map(String::as_str).collect();
            let head = ["identify", "--json", "--band", "8,49"];
            let out = run(&[&head[..], identify_args, extra, &refs].concat());
            let v: Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
            if !out.status.success() {
                assert!(n < least, "{kind}, {n} files: {v}");
                continue;
            }
            assert_eq!(v["n_records"], n, "{kind}, {n} files: {v}");
            let reported: Vec<&str> = v["files"]
                .as_array()
                .unwrap()
                .iter()
                .map(|f| f.as_str().unwrap())
                .collect();
            assert_eq!(reported, refs, "{kind}, {n} files");
        }
    }
}

#[test]
fn impact_files_are_all_kept_in_order() {
    every_file_kept_in_order("impact", &["--impacts", "4", "--rate", "1000"], &[], 2);
}

#[test]
fn random_files_are_all_kept_in_order() {
    every_file_kept_in_order(
        "random",
        &["--records", "8", "--rate", "256", "--duration", "32"],
        &[],
        1,
    );
}

#[test]
fn multisine_files_are_all_kept_in_order() {
    let sim = [
        "--records",
        "4",
        "--rate",
        "256",
        "--period",
        "1",
        "--periods",
        "4",
    ];
    let sim = [&sim[..], &["--freqs", "8,49"]].concat();
    every_file_kept_in_order(
        "multisine",
        &sim,
        &["--excitation", "periodic", "--period", "1"],
        4,
    );
}

#[test]
fn stepped_sine_files_are_all_kept_in_order() {
    // One degree of freedom: each file is one line of the fit.
    let sim = ["--freqs", "8,49,8", "--rate", "256", "--duration", "1"];
    let one_dof = ["--mass", "4.7", "--damping", "30", "--stiffness", "146e3"];
    let identify = ["--excitation", "stepped-sine"];
    every_file_kept_in_order("stepped-sine", &[&sim[..], &one_dof].concat(), &identify, 5);
}

#[test]
fn sweep_files_are_all_kept_in_order() {
    let sim = ["--records", "4", "--rate", "256", "--freqs", "5,60"];
    every_file_kept_in_order("sweep", &sim, &["--excitation", "sweep"], 2);
}

/// A stderr that cannot be written (`2>/dev/full`) changes nothing but what stderr shows: an
/// error still exits 2 (never the 101 of a panic) and, under `--json`, still prints its object
/// on stdout; `--plot`'s "wrote N figures" line and argument errors alike.
#[test]
fn a_full_stderr_neither_panics_nor_loses_the_json() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        println!("skipped: /dev/full is absent on this system");
        return;
    };
    let with_full_stderr = |args: &[&str]| -> Output {
        bin()
            .args(args)
            .stderr(full.try_clone().unwrap())
            .output()
            .expect("the binary runs")
    };
    let missing = "/nonexistent/bearing-ident/r.csv";
    let out = with_full_stderr(&["identify", "--band", "8,49", missing]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let out = with_full_stderr(&["identify", "--json", "--band", "8,49", missing]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let v: Value = serde_json::from_slice(&out.stdout).expect("the error object on stdout");
    assert_eq!(v["error"], "io_error", "{v}");
    for args in [
        &["identify", "--no-such-flag"][..],
        &["identify", "--json"][..],
    ] {
        let out = with_full_stderr(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {out:?}");
    }
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("plot");
    let out = with_full_stderr(&["demo", "--plot", plot.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(plot.join("index.html").is_file());
}

/// An output pointed at an input (`--uff`, `--ross`, `--plot`, also through another spelling
/// of its path) is refused before anything is written: before, `--uff` overwrote the record.
/// `--plot` into a path that is a file says so, not "File exists (os error 17)".
#[test]
fn outputs_never_overwrite_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "2"]);
    let before = std::fs::read(&files[1]).unwrap();
    let other_spelling = format!(
        "{}/./{}",
        dir.path().display(),
        Path::new(&files[1]).file_name().unwrap().to_str().unwrap()
    );
    for (flag, out) in [
        ("--uff", files[1].as_str()),
        ("--ross", other_spelling.as_str()),
        ("--plot", files[0].as_str()),
    ] {
        let o = run(&[
            "identify", "--json", "--band", "8,49", flag, out, &files[0], &files[1],
        ]);
        assert_eq!(o.status.code(), Some(2), "{flag}");
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["error"], "invalid_argument", "{flag}: {v}");
        let m = v["message"].as_str().unwrap();
        let says = if flag == "--plot" {
            "is a file, not a folder"
        } else {
            "is one of the input files"
        };
        assert!(m.starts_with(flag) && m.contains(says), "{m}");
    }
    assert_eq!(std::fs::read(&files[1]).unwrap(), before);
    // A file where `demo --plot` wants its folder: named as such.
    let o = run(&["demo", "--json", "--plot", &files[0]]);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(
        v["message"]
            .as_str()
            .unwrap()
            .contains("is a file, not a folder"),
        "{v}"
    );
}

/// Messages name their cause and quote safely: a missing required argument is named in the
/// JSON message (before, cut at "were not provided:"); counts of 0 and a NaN rate are refused
/// naming the flag (before: exit 0 with nothing written, or `too_large`); a negative Coulomb
/// force is refused; a 309-digit number, a 4000-character path and an ESC byte of a CSV header
/// are never echoed raw.
#[test]
fn messages_name_the_cause_and_quote_safely() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    let json_error = |args: &[&str]| -> (String, String) {
        let o = run(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let v: Value = serde_json::from_slice(&o.stdout).expect("JSON on stdout");
        assert!(!o.stderr.contains(&0x1b), "{args:?}");
        (
            v["error"].as_str().unwrap().to_owned(),
            v["message"].as_str().unwrap().to_owned(),
        )
    };
    let (kind, m) = json_error(&["simulate", "--json"]);
    assert_eq!(kind, "invalid_argument");
    assert!(m.contains("--out"), "{m}");
    for (extra, says) in [
        (&["--rate", "nan"][..], "--rate NaN"),
        (&["--impacts", "0"][..], "--impacts 0"),
        (&["--kind", "random", "--records", "0"][..], "--records 0"),
        (
            &["--kind", "multisine", "--periods", "0"][..],
            "--periods 0",
        ),
        (&["--kind", "random", "--coulomb=-5"][..], "--coulomb -5"),
    ] {
        let (kind, m) = json_error(&[&["simulate", "--json", "--out", out], extra].concat());
        assert_eq!(kind, "invalid_argument", "{extra:?}: {m}");
        assert!(m.starts_with(says), "{extra:?}: {m}");
    }
    assert!(!Path::new(out).exists(), "nothing is written");
    let huge = format!("{}", 1e308);
    let band = format!("8,{huge}");
    let long_path = format!("{}/{}.csv", dir.path().display(), "p".repeat(4000));
    let header = write(dir.path(), "esc.csv", "t,f\u{1b}[31mx,x\n0,0,0\n0.1,1,1\n");
    for args in [
        vec!["identify", "--json", "--band", &band, &header],
        vec!["identify", "--json", &long_path],
        vec![
            "identify", "--json", "--force", "fx", "--disp", "x", &header,
        ],
    ] {
        let (_, m) = json_error(&args);
        let longest = m.split(' ').map(|w| w.chars().count()).max().unwrap_or(0);
        assert!(longest <= 100 && !m.contains(&huge), "{m}");
        assert!(!m.contains('\u{1b}'), "{m}");
    }
}

/// `--calibration`: the stated force gain uncertainty enters `budget.calibration` exactly
/// (`|P| · u`), the combined `*_std` hold the three components in quadrature, the model check
/// and the modes' error bars are in the JSON; bad values and unknown channels are refused.
#[test]
fn calibration_enters_the_budget_and_bad_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "4", "--noise", "0.05"]);
    let v = identify_json(
        &["--band", "8,49", "--calibration", "force=2%,x=1%"],
        &files,
    );
    let (k, cal) = (
        matrix(&v, "K"),
        matrix(&v["budget"]["calibration"], "K_std"),
    );
    // Row x: 2 % force and 1 % response x; row y: 2 % force and response y unstated (0).
    assert!((cal[0][0] - k[0][0].abs() * 0.02f64.hypot(0.01)).abs() < 1e-9 * k[0][0]);
    assert!((cal[1][1] - k[1][1].abs() * 0.02).abs() < 1e-9 * k[1][1]);
    let (random, model) = (
        matrix(&v["budget"]["random"], "K_std"),
        matrix(&v["budget"]["model"], "K_std"),
    );
    let combined = matrix(&v, "K_std");
    let quadrature = (random[0][0].powi(2) + model[0][0].powi(2) + cal[0][0].powi(2)).sqrt();
    assert!((combined[0][0] - quadrature).abs() < 1e-9 * combined[0][0]);
    assert_eq!(v["model_check"]["verdict"], "fits", "{}", v["model_check"]);
    assert!(v["model_check"]["p_value"].as_f64().unwrap() > 0.01);
    assert_eq!(v["natural_frequencies_hz_std"].as_array().unwrap().len(), 2);
    assert!(v["damping_ratios_std"][0].as_f64().unwrap() > 0.0);
    let file = files[0].as_str();
    for (spec, kind) in [
        ("force=-1%", "invalid_argument"),
        ("force=nan", "invalid_argument"),
        ("z=1%", "invalid_argument"),
    ] {
        expect_failure(
            &[
                "identify",
                "--json",
                "--band",
                "8,49",
                "--calibration",
                spec,
                file,
            ],
            kind,
        );
    }
}

/// `--delay x=0.1ms±5us`: the stated uncertainty of the delay enters `budget.calibration` on
/// the coefficients of response column x (and the combined `*_std` with it); `+-` reads the
/// same; without it the calibration part is zero; a negative uncertainty is refused.
#[test]
fn a_stated_delay_uncertainty_enters_the_budget() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "4", "--noise", "0.05"]);
    let cal = |delay: &str| {
        let v = identify_json(&["--band", "8,49", "--delay", delay], &files);
        (
            matrix(&v["budget"]["calibration"], "C_std"),
            matrix(&v["budget"]["random"], "C_std"),
            matrix(&v, "C_std"),
        )
    };
    let (stated, random, combined) = cal("x=0.1ms±5us");
    assert!(stated[0][0] > 0.0 && stated[1][0] > 0.0, "{stated:?}");
    // Column y is not delayed: what moves there is the weighting's coupling alone.
    assert!(stated[1][1] < 1e-2 * stated[0][0], "{stated:?}");
    assert!(combined[0][0] >= random[0][0].hypot(stated[0][0]) * (1.0 - 1e-12));
    let plus_minus = cal("x=0.1ms+-0.005ms").0;
    for (a, b) in plus_minus.iter().flatten().zip(stated.iter().flatten()) {
        assert!(
            (a - b).abs() <= 1e-9 * stated[0][0],
            "{plus_minus:?} vs {stated:?}"
        );
    }
    assert_eq!(cal("x=0.1ms").0, [[0.0, 0.0], [0.0, 0.0]]);
    let file = files[0].as_str();
    expect_failure(
        &[
            "identify",
            "--json",
            "--band",
            "8,49",
            "--delay",
            "x=0.1ms±-5us",
            file,
        ],
        "invalid_argument",
    );
}

/// Three multisine records, one driving x and two driving y, with `--excitation periodic` and
/// the jackknife asked for (periodic records take the sandwich by default): before, the run
/// failed as `bad_band` "the band holds 0 usable frequency lines" — the cause was the
/// jackknife, whose refit without the lone x record has no excitation in x. Now the fit is
/// given with sandwich error bars and the `jackknife_unavailable` warning.
#[test]
fn a_direction_excited_by_one_record_falls_back_to_the_sandwich() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--kind", "multisine", "--records", "2"]);
    let chosen: Vec<String> = files
        .iter()
        .filter(|f| !f.ends_with("d0-1.csv"))
        .cloned()
        .collect();
    assert_eq!(chosen.len(), 3, "{files:?}");
    let v = identify_json(
        &[
            "--band",
            "8,49",
            "--excitation",
            "periodic",
            "--period",
            "1",
            "--uncertainty",
            "jackknife",
        ],
        &chosen,
    );
    assert_eq!(v["uncertainty"], "sandwich", "{v}");
    let kinds: Vec<&str> = v["warning_kinds"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert!(kinds.contains(&"jackknife_unavailable"), "{kinds:?}");
    let c = matrix(&v, "C");
    assert!((c[0][0] / 131.98 - 1.0).abs() < 1e-3, "{c:?}");
}

/// A `--min-coherence` the records never reach leaves no lines: the error names the minimum
/// (`invalid_argument`), not the excitations (before: `rank_deficient` "span 1 of 2
/// directions") or the band.
#[test]
fn a_coherence_minimum_too_high_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &["--impacts", "2", "--noise", "0.05"]);
    let refs: Vec<&str> = files.iter().map(String::as_str).collect();
    let o = run(&[
        &[
            "identify",
            "--json",
            "--band",
            "8,49",
            "--min-coherence",
            "0.9999999",
        ],
        &refs[..],
    ]
    .concat());
    assert_eq!(o.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["error"], "invalid_argument", "{v}");
    assert!(
        v["message"].as_str().unwrap().contains("min_coherence"),
        "{v}"
    );
}

/// One column named as both force and response (or twice) is refused before any file is read,
/// naming it (before: `not_converged` after the whole run); exchanged force and response
/// columns are suggested as such: not read as two transfer FRFs (random records, where a fit
/// comes out), and named as a likely cause when impacts so read fail.
#[test]
fn a_column_named_twice_is_refused_and_swapped_columns_are_suggested() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("not-read.csv");
    let missing = missing.to_str().unwrap();
    for (force, disp, says) in [
        (
            "fx,fy",
            "fx,y",
            "channel `fx` is named in --force and in --disp",
        ),
        ("fx,fx", "x,y", "channel `fx` is named twice in --force"),
        (
            "t,fy",
            "x,y",
            "channel `t` is named in --time and in --force",
        ),
    ] {
        let o = run(&[
            "identify", "--json", "--band", "8,49", "--force", force, "--disp", disp, missing,
        ]);
        assert_eq!(o.status.code(), Some(2), "{force} {disp}");
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["error"], "invalid_argument", "{v}");
        let m = v["message"].as_str().unwrap();
        assert!(m.starts_with(says), "{m}");
    }
    let files = simulate(dir.path(), &["--kind", "random", "--records", "2"]);
    let o = run(&[
        &[
            "identify", "--json", "--band", "8,49", "--force", "x,y", "--disp", "fx,fy",
        ][..],
        &files.iter().map(String::as_str).collect::<Vec<_>>(),
    ]
    .concat());
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let kinds: Vec<&str> = v["warning_kinds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| k.as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"swapped_channels"), "{kinds:?}");
    assert!(!kinds.contains(&"transfer_frf"), "{kinds:?}");
    // Impacts read the wrong way round are taken for random records and fail; the message
    // asks whether the columns are exchanged (before: "the band holds 3 usable frequency
    // lines" alone).
    let hits = dir.path().join("hits");
    let files = simulate(&hits, &["--impacts", "2"]);
    let o = run(&[
        &[
            "identify", "--json", "--band", "8,49", "--force", "x,y", "--disp", "fx,fy",
        ][..],
        &files.iter().map(String::as_str).collect::<Vec<_>>(),
    ]
    .concat());
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let m = v["message"].as_str().unwrap();
    assert!(
        m.ends_with("are the columns of --force and --disp exchanged?"),
        "{m}"
    );
    // Read the right way round, the same records fit.
    let o = run(&[
        &["identify", "--json", "--band", "8,49"][..],
        &files.iter().map(String::as_str).collect::<Vec<_>>(),
    ]
    .concat());
    assert_eq!(o.status.code(), Some(0), "{o:?}");
}

/// A right model's multisine records cut into Welch segments (as `--excitation random` reads
/// them): leakage inflates the replicates' scatter (residuals at a few per cent of it) and
/// shapes those small residuals over frequency. That is no misfit: the check says the model
/// fits and no `model_misfit` is raised. (The runs test counts only residuals of at least half
/// the pure error; on these 50 lines, taken three apart under Hann, it has too few to count.)
#[test]
fn leakage_patterns_in_small_residuals_are_no_misfit() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(
        dir.path(),
        &[
            "--excitation",
            "multisine",
            "--records",
            "2",
            "--periods",
            "4",
            "--seed",
            "5",
            "--noise",
            "0.01",
        ],
    );
    let v = identify_json(&["--band", "8,49", "--excitation", "random"], &files);
    let check = &v["model_check"];
    assert!(check["statistic"].as_f64().unwrap() < 0.5 * check["expected"].as_f64().unwrap());
    assert_eq!(check["verdict"], "fits", "{check}");
    let kinds = v["warning_kinds"].as_array().unwrap();
    assert!(!kinds.iter().any(|k| k == "model_misfit"), "{kinds:?}");
}

/// A folder given where record files are expected is refused, naming the files to give.
#[test]
fn a_folder_of_records_is_refused_naming_its_files() {
    let tmp = tempfile::tempdir().unwrap();
    let records = tmp.path().join("records");
    simulate(&records, &["--impacts", "1"]);
    let out = run(&["identify", "--band", "8,49", records.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let want = format!(
        "a folder, not a file: give its files: {}",
        records.join("*.csv").display()
    );
    assert!(err.contains(&want), "{err}");
    assert!(!err.contains("os error"), "{err}");
    expect_failure(
        &[
            "identify",
            "--json",
            "--band",
            "8,49",
            records.to_str().unwrap(),
        ],
        "io_error",
    );
}

/// A report folder that holds another command's report is refused, and left as it was; the
/// same command writes its report there again.
#[test]
fn a_report_folder_of_another_command_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let files = simulate(&tmp.path().join("records"), &["--impacts", "2"]);
    let report = tmp.path().join("report");
    let identify = || {
        let mut args = vec![
            "identify",
            "--band",
            "8,49",
            "--plot",
            report.to_str().unwrap(),
        ];
        args.extend(files.iter().map(String::as_str));
        run(&args)
    };
    assert!(identify().status.success());
    assert!(identify().status.success(), "the same kind again");
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    let mark = "<meta name=\"generator\" content=\"bearing-ident identification report\">";
    assert!(page.contains(mark));
    let field = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/field");
    let out = run(&[
        "field",
        "--rotor",
        field.join("ROTOR.json").to_str().unwrap(),
        "--tests",
        field.join("TESTS_bearings.json").to_str().unwrap(),
        "--plot",
        report.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(
            "holds an identification report; give the field identification report another \
             folder, or empty this one"
        ),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(report.join("index.html")).unwrap(),
        page
    );
    assert!(!report.join("field.svg").exists());
    // A page this tool did not write is not overwritten either.
    let other = tmp.path().join("site");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("index.html"), "<html>mine</html>").unwrap();
    let mut args = vec![
        "identify",
        "--band",
        "8,49",
        "--plot",
        other.to_str().unwrap(),
    ];
    args.extend(files.iter().map(String::as_str));
    let out = run(&args);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a report of this tool"));
}

/// The text tables are at most 120 characters wide: the identification's (3 DOF, per
/// frequency), the demo's and the field table; sentences (warnings) aside.
#[test]
fn text_tables_are_at_most_120_characters_wide() {
    let tmp = tempfile::tempdir().unwrap();
    let files = simulate(
        &tmp.path().join("r3"),
        &[
            "--impacts",
            "2",
            "--noise",
            "0.02",
            "--mass",
            "4,0,0;0,4.5,0;0,0,5",
            "--damping",
            "40,0,0;0,45,0;0,0,50",
            "--stiffness",
            "1.5e5,0,0;0,1.6e5,0;0,0,1.7e5",
        ],
    );
    let mut args = vec![
        "identify",
        "--band",
        "8,49",
        "--per-frequency",
        "--force",
        "fx,fy,fz",
        "--disp",
        "x,y,z",
    ];
    args.extend(files.iter().map(String::as_str));
    let field = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/field");
    let (rotor, tests) = (field.join("ROTOR.json"), field.join("TESTS_inboard.json"));
    let field_args = [
        "field",
        "--rotor",
        rotor.to_str().unwrap(),
        "--tests",
        tests.to_str().unwrap(),
    ];
    for (what, args) in [
        ("identify", args.as_slice()),
        ("demo", &["demo"][..]),
        ("field", &field_args[..]),
    ] {
        let out = run(args);
        assert!(out.status.success(), "{what}: {out:?}");
        let text = String::from_utf8(out.stdout).unwrap();
        let wide: Vec<&str> = text
            .lines()
            .filter(|l| !l.trim_start().starts_with("warning: "))
            .filter(|l| l.chars().count() > bearing_ident::text::TABLE_WIDTH)
            .collect();
        assert!(wide.is_empty(), "{what}: {wide:#?}\n{text}");
        if what == "identify" {
            assert!(
                text.contains("K_zz (N/m)") && text.contains("C_xx (N·s/m)"),
                "{text}"
            );
        }
    }
}
