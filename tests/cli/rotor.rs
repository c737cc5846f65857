//! `identify --clearance --load --speed`: the dimensionless coefficients and the stability of
//! a rigid rotor on the element, in the JSON and the table; bad conditions refused.

use crate::common::run;
use serde_json::Value;

/// Impact records of the seed rig's element with a destabilising cross-coupled stiffness
/// (`K_xy = −K_yx = 1.5·10⁴ N/m`).
fn cross_coupled(dir: &std::path::Path) -> Vec<String> {
    let out = dir.join("records");
    let status = crate::common::bin()
        .args(["simulate", "--out"])
        .arg(&out)
        .args(["--impacts", "2", "--noise", "0.02"])
        .args(["--mass", "4.7,0;0,4.8", "--damping", "131.98,0;0,131.98"])
        .args(["--stiffness", "1.463e5,1.5e4;-1.5e4,1.691e5"])
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    let mut files: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path().display().to_string())
        .collect();
    files.sort();
    files
}

fn identify(extra: &[&str], files: &[String]) -> std::process::Output {
    let mut args = vec!["identify", "--band", "8,49"];
    args.extend(extra);
    args.extend(files.iter().map(String::as_str));
    run(&args)
}

fn matrix(v: &Value) -> Vec<Vec<f64>> {
    serde_json::from_value(v.clone()).unwrap()
}

/// The JSON's `dimensionless` is its own `K`, `C`, `M` and their σ scaled by `c/W`,
/// `Ωc/W`, `Ω²c/W` (c = 100 µm, W = 500 N, Ω = 3000 rpm); its `stability` is Lund's closed
/// form on its own `K`, `C`: `K_eq = (K_xx C_yy + K_yy C_xx − K_xy C_yx − K_yx C_xy)/(C_xx +
/// C_yy)`, `ν² = ((K_xx − K_eq)(K_yy − K_eq) − K_xy K_yx)/(C_xx C_yy − C_xy C_yx)`, `γ = ν/Ω`,
/// `Ω_th = √(K_eq g/W)/γ`, and the crossover `(K_xy − K_yx)/(C_xx + C_yy)/2π`, each with a σ.
/// The table shows them.
#[test]
fn cli_dimensionless_and_stability_follow_the_closed_forms() {
    let dir = tempfile::tempdir().unwrap();
    let files = cross_coupled(dir.path());
    let conditions = [
        "--clearance",
        "100um",
        "--load",
        "500N",
        "--speed",
        "3000rpm",
    ];
    let out = identify(&[&["--json"][..], &conditions].concat(), &files);
    assert!(out.status.success(), "{out:?}");
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let d = &v["dimensionless"];
    let pi = std::f64::consts::PI;
    let (c, w, omega) = (100e-6, 500.0, 100.0 * pi);
    for (key, factor) in [
        ("K", c / w),
        ("C", omega * c / w),
        ("M", omega * omega * c / w),
    ] {
        for (ours, theirs) in [
            (key.to_owned(), key.to_owned()),
            (format!("{key}_std"), format!("{key}_std")),
        ] {
            let (dim, raw) = (matrix(&d[&ours]), matrix(&v[&theirs]));
            for i in 0..2 {
                for j in 0..2 {
                    let expected = raw[i][j] * factor;
                    assert!(
                        (dim[i][j] - expected).abs() <= 1e-12 * expected.abs(),
                        "{ours}"
                    );
                }
            }
        }
    }
    assert_eq!(d["clearance_m"], 100e-6);
    assert_eq!(d["load_n"], 500.0);
    assert!((d["speed_rpm"].as_f64().unwrap() - 3000.0).abs() < 1e-9);
    let (k, cc) = (matrix(&v["K"]), matrix(&v["C"]));
    let k_eq = (k[0][0] * cc[1][1] + k[1][1] * cc[0][0] - k[0][1] * cc[1][0] - k[1][0] * cc[0][1])
        / (cc[0][0] + cc[1][1]);
    let nu2 = ((k[0][0] - k_eq) * (k[1][1] - k_eq) - k[0][1] * k[1][0])
        / (cc[0][0] * cc[1][1] - cc[0][1] * cc[1][0]);
    let gamma = nu2.sqrt() / omega;
    let threshold_rpm = (k_eq * 9.80665 / w).sqrt() / gamma * 30.0 / pi;
    let crossover = (k[0][1] - k[1][0]) / (cc[0][0] + cc[1][1]) / (2.0 * pi);
    let s = &v["stability"];
    for (key, expected) in [
        ("whirl_frequency_ratio", gamma),
        ("threshold_speed_rpm", threshold_rpm),
        ("c_eff_crossover_hz", crossover),
    ] {
        let got = s[key].as_f64().unwrap();
        assert!(
            (got / expected - 1.0).abs() < 1e-12,
            "{key}: {got} vs {expected}"
        );
        let std = s[format!("{key}_std")].as_f64().unwrap();
        assert!(std > 0.0 && std < 0.2 * got, "{key}_std {std}");
    }
    // The element simulated: γ = √(2.25·10⁸ − 1.14²·10⁸)/131.98/(100π) = 0.235.
    assert!((gamma - 0.235).abs() < 0.03, "{gamma}");
    assert_eq!(s["reason"], Value::Null);
    let table = identify(&conditions, &files);
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(
        text.contains("Dimensionless (c = 100.0 µm, W = 500.0 N, Ω = 3000.0 rpm"),
        "{text}"
    );
    assert!(text.contains("whirl-frequency ratio 0.2"), "{text}");
    assert!(text.contains("threshold speed"), "{text}");
    // The HTML report says it under its heading.
    let report = dir.path().join("report");
    let report_arg = report.display().to_string();
    let out = identify(
        &[&conditions[..], &["--plot", &report_arg]].concat(),
        &files,
    );
    assert!(out.status.success(), "{out:?}");
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(
        html.contains("(Lund): whirl-frequency ratio 0.2"),
        "stability line"
    );
    // Without conditions, both are null.
    let plain: Value = serde_json::from_slice(&identify(&["--json"], &files).stdout).unwrap();
    assert_eq!(plain["dimensionless"], Value::Null);
    assert_eq!(plain["stability"], Value::Null);
}

/// A clearance or load ≤ 0, a value without its unit, a clearance without the load and speed
/// it needs: `invalid_argument` naming the option, exit status 2, never a panic.
#[test]
fn cli_refuses_bad_conditions_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let files = cross_coupled(dir.path());
    for (args, option) in [
        (
            &["--clearance", "0um", "--load", "1N", "--speed", "1Hz"][..],
            "--clearance",
        ),
        (&["--load", "-5N"][..], "--load"),
        (&["--speed", "3000"][..], "--speed"),
        (
            &["--clearance", "100um", "--speed", "3000rpm"][..],
            "--load",
        ),
        (&["--clearance", "100um", "--load", "1kN"][..], "--speed"),
    ] {
        let out = identify(&[&["--json"][..], args].concat(), &files);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["error"], "invalid_argument", "{v}");
        assert!(v["message"].as_str().unwrap().contains(option), "{v}");
    }
}

/// `--ross-samples N FILE.csv`: N rows of `sample,kxx,…,myy`, the same for the same
/// `--ross-seed`, each near the fitted value; a count of 0 or a seed that is not a whole
/// number refused naming the option.
#[test]
fn cli_writes_ross_samples() {
    let dir = tempfile::tempdir().unwrap();
    let files = cross_coupled(dir.path());
    let csv = dir.path().join("samples.csv");
    let csv_arg = csv.display().to_string();
    let out = identify(
        &[
            "--json",
            "--ross-samples",
            "50",
            &csv_arg,
            "--ross-seed",
            "9",
        ],
        &files,
    );
    assert!(out.status.success(), "{out:?}");
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "sample,kxx,kxy,kyx,kyy,cxx,cxy,cyx,cyy,mxx,mxy,myx,myy"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 50);
    let (k, k_std) = (matrix(&v["K"]), matrix(&v["K_std"]));
    assert!(
        rows.iter()
            .all(|r| (r[2] - k[0][1]).abs() < 6.0 * k_std[0][1])
    );
    assert!(rows.iter().any(|r| r[1] != k[0][0]));
    let again = dir.path().join("again.csv");
    let again_arg = again.display().to_string();
    let out = identify(
        &["--ross-samples", "50", &again_arg, "--ross-seed", "9"],
        &files,
    );
    assert!(out.status.success());
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);
    for (args, option) in [
        (&["--ross-samples", "0", &csv_arg][..], "--ross-samples"),
        (&["--ross-samples", "x", &csv_arg][..], "--ross-samples"),
        (
            &["--ross-samples", "5", &csv_arg, "--ross-seed", "abc"][..],
            "--ross-seed",
        ),
        (
            &["--ross-samples", "5", &csv_arg, "--ross-seed", "-1"][..],
            "--ross-seed",
        ),
    ] {
        let out = identify(&[&["--json"][..], args].concat(), &files);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["error"], "invalid_argument", "{v}");
        assert!(v["message"].as_str().unwrap().contains(option), "{v}");
    }
}
