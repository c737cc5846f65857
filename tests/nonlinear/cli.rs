//! `identify --nonlinear`: the command-line contract used by external checks, on CSV records
//! of a 2-DOF rig with dry friction (displacement prescribed, 2 % noise).
#![cfg(feature = "cli")]

use crate::common::nonlinear_records;
use crate::common::run;

use std::path::Path;
use std::process::Output;

use bearing_ident::io::{CsvLayout, write_record};
use bearing_ident::nonlinear::{Regressor, Term};
use serde_json::Value;

/// Friction records (0.8 N on x, 0.5 N on y) written as CSV into `dir`.
fn friction_files(dir: &Path) -> Vec<String> {
    let coulomb = |dof| Term {
        regressor: Regressor::Coulomb,
        dof: Some(dof),
    };
    let test = nonlinear_records::rig(vec![(coulomb(0), 0.8), (coulomb(1), 0.5)]);
    test.run()
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let path = dir.join(format!("friction-{i}.csv"));
            write_record(&path, r, &CsvLayout::default()).unwrap();
            path.display().to_string()
        })
        .collect()
}

fn json_of(out: &Output) -> Value {
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

#[test]
fn the_json_carries_terms_checks_and_velocity() {
    let dir = tempfile::tempdir().unwrap();
    let files = friction_files(dir.path());
    let mut args = vec![
        "identify",
        "--json",
        "--band",
        "10,60",
        "--excitation",
        "random",
        "--nonlinear",
        "coulomb",
    ];
    args.extend(files.iter().map(String::as_str));
    let out = run(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json_of(&out);
    let terms = v["nonlinear"].as_array().unwrap();
    assert_eq!(terms.len(), 2);
    for (t, (dof, truth)) in terms.iter().zip([(0, 0.8), (1, 0.5)]) {
        assert_eq!(t["term"], "coulomb");
        assert_eq!(t["dof"], dof);
        assert_eq!(t["unit"], "N");
        let (value, std) = (t["value"].as_f64().unwrap(), t["std"].as_f64().unwrap());
        assert!(
            (value - truth).abs() < 4.0 * std && std < 0.03 * truth,
            "{t}"
        );
    }
    // M, C, K as the linear identification writes them.
    for key in ["M", "C", "K", "M_std", "C_std", "K_std"] {
        let rows = v[key].as_array().unwrap();
        assert_eq!(rows.len(), 2, "{key}");
        assert!(
            rows.iter().all(|r| r.as_array().unwrap().len() == 2),
            "{key}"
        );
    }
    let k = v["K"][0][0].as_f64().unwrap();
    assert!((k / 146.3e3 - 1.0).abs() < 0.01, "{k}");
    assert_eq!(v["velocity"]["method"], "wiener");
    assert!(v["velocity"]["cutoff_hz"].is_null());
    assert_eq!(v["velocity"]["sources"][0], "displacement");
    let checks = v["nonlinear_check"].as_array().unwrap();
    assert_eq!(checks.len(), 2);
    assert!(
        checks
            .iter()
            .all(|c| c["misfit"] == false && c["imaginary_ratio"].is_f64())
    );
    assert_eq!(v["n_records"], 2);
    // The one warning: the friction's predicted sign bias, carried in its error bar.
    let kinds = v["warning_kinds"].as_array().unwrap();
    assert!(
        kinds.iter().all(|k| k == "friction_bias"),
        "{}",
        v["warnings"]
    );
    for t in terms {
        let (model, std) = (t["model_std"].as_f64().unwrap(), t["std"].as_f64().unwrap());
        assert!(model > 0.0 && model < std, "{t}");
    }
}

#[test]
fn planar_friction_has_a_null_dof_and_the_cutoff_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let files = friction_files(dir.path());
    let mut args = vec![
        "identify",
        "--json",
        "--band",
        "10,60",
        "--excitation",
        "random",
        "--nonlinear",
        "coulomb-planar,cubic",
        "--vel-cutoff",
        "100",
    ];
    args.extend(files.iter().map(String::as_str));
    let out = run(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json_of(&out);
    let terms = v["nonlinear"].as_array().unwrap();
    assert_eq!(terms.len(), 3);
    assert_eq!(terms[0]["term"], "coulomb-planar");
    assert!(terms[0]["dof"].is_null());
    assert_eq!(terms[1]["term"], "cubic");
    assert_eq!(terms[1]["unit"], "N/m³");
    assert_eq!(v["velocity"]["method"], "cutoff");
    assert_eq!(v["velocity"]["cutoff_hz"], 100.0);
}

#[test]
fn the_table_and_the_report_show_the_terms() {
    let dir = tempfile::tempdir().unwrap();
    let files = friction_files(dir.path());
    let plot = dir.path().join("plot");
    let mut args = vec![
        "identify",
        "--band",
        "10,60",
        "--excitation",
        "random",
        "--nonlinear",
        "coulomb",
        "--plot",
        plot.to_str().unwrap(),
    ];
    args.extend(files.iter().map(String::as_str));
    let out = run(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.contains("Nonlinear terms") && table.contains("coulomb[0]"),
        "{table}"
    );
    let html = std::fs::read_to_string(plot.join("index.html")).unwrap();
    assert!(html.contains("coulomb[1]") && html.contains("<img src=\"nonlinear.svg\""));
    let svg = std::fs::read_to_string(plot.join("nonlinear.svg")).unwrap();
    assert_eq!(svg.matches("class=\"series\"").count(), 2 * 4);
}

#[test]
fn bad_terms_and_misuse_are_invalid_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let files = friction_files(dir.path());
    for extra in [
        &["--nonlinear", "friction"][..],
        &["--vel-cutoff", "50"][..],
        &["--nonlinear", "coulomb", "--vel-cutoff", "-3"][..],
        &["--nonlinear", "coulomb", "--excitation", "impact"][..],
        &["--nonlinear", "coulomb", "--calibration", "force=1%"][..],
        &["--nonlinear", "coulomb", "--delay", "x=0.25ms"][..],
        &["--nonlinear", "coulomb", "--highpass", "x=3Hz"][..],
    ] {
        let mut args = vec!["identify", "--json", "--band", "10,60"];
        if !extra.contains(&"--excitation") {
            args.extend(["--excitation", "random"]);
        }
        args.extend(extra);
        args.extend(files.iter().map(String::as_str));
        let out = run(&args);
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        assert_eq!(json_of(&out)["error"], "invalid_argument", "{extra:?}");
    }
    // Too few Welch averages: one record of 32768 samples in 8192-sample segments gives 7 for
    // 2 + 2 inputs, 8 needed.
    let args = vec![
        "identify",
        "--json",
        "--band",
        "10,60",
        "--excitation",
        "random",
        "--nonlinear",
        "coulomb",
        "--nperseg",
        "8192",
        files[0].as_str(),
    ];
    let out = run(&args);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(json_of(&out)["error"], "record_too_short");
}
