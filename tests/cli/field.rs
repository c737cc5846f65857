//! `bearing-ident field`: the command-line contract of issue 16 (used as is by external
//! checks), on JSON files written from a simulated two-disk rotor.
#![cfg(feature = "cli")]

use crate::common::field_rig;
use crate::common::run;

use std::path::{Path, PathBuf};
use std::process::Output;

use bearing_ident::field::{FieldTests, RotorModel};
use field_rig::{bearings, isotropic, rotor, runs};
use serde_json::{Value, json};

fn rows(m: &bearing_ident::faer::Mat<f64>) -> Value {
    json!(
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect::<Vec<f64>>())
            .collect::<Vec<_>>()
    )
}

fn rotor_json(rotor: &RotorModel) -> String {
    let bearings: Vec<Value> = rotor
        .bearings()
        .iter()
        .map(|b| json!({"tag": b.tag, "node": b.node}))
        .collect();
    json!({
        "dof_per_node": rotor.dof_per_node(),
        "dof_names": rotor.dof_names(),
        "M": rows(rotor.mass()),
        "K": rows(rotor.stiffness()),
        "G": rows(rotor.gyroscopic()),
        "C": null,
        "bearings": bearings,
    })
    .to_string()
}

fn tests_json(tests: &FieldTests) -> Value {
    let set = |t: usize| -> Vec<Value> {
        tests.imbalances[t]
            .iter()
            .map(|u| json!({"node": u.node, "magnitude_kg_m": u.magnitude_kg_m, "phase_rad": u.phase_rad}))
            .collect()
    };
    let responses: Vec<Value> = tests
        .responses
        .iter()
        .map(|r| {
            let mut v = json!({
                "speed_rad_s": r.speed_rad_s,
                "test": r.run.name(),
                "node": r.probe.node,
                "dir": r.probe.dir.name(),
                "re": r.value.re,
                "im": r.value.im,
            });
            if let Some(s) = r.std {
                v["std"] = json!(s);
            }
            v
        })
        .collect();
    json!({"imbalances": {"1": set(0), "2": set(1)}, "responses": responses})
}

/// Writes ROTOR.json and TESTS.json into `dir`; returns their paths.
fn write(dir: &Path, rotor: &RotorModel, tests: &Value) -> (PathBuf, PathBuf) {
    let (r, t) = (dir.join("ROTOR.json"), dir.join("TESTS.json"));
    std::fs::write(&r, rotor_json(rotor)).unwrap();
    std::fs::write(&t, tests.to_string()).unwrap();
    (r, t)
}

fn field(r: &Path, t: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "field",
        "--json",
        "--rotor",
        r.to_str().unwrap(),
        "--tests",
        t.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    run(&args)
}

fn json_of(out: &Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "{e}: stdout {}, stderr {}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

fn error_kind(out: &Output) -> String {
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    json_of(out)["error"].as_str().unwrap().to_owned()
}

#[test]
fn json_contract_recovers_the_bearings() {
    let dir = tempfile::tempdir().unwrap();
    let rotor = rotor();
    for probe_nodes in [[0, 7], [1, 6]] {
        let tests = runs(probe_nodes, 0.0, 1)
            .simulate(&rotor, bearings)
            .unwrap();
        let (r, t) = write(dir.path(), &rotor, &tests_json(&tests));
        let out = field(&r, &t, &[]);
        assert!(out.status.success(), "{out:?}");
        let v = json_of(&out);
        let speeds: Vec<f64> = v["speeds_rad_s"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s.as_f64().unwrap())
            .collect();
        assert_eq!(speeds.len(), 14);
        assert!(speeds.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(v["measured"].as_array().unwrap().len(), 4);
        assert_eq!(
            v["measured"][0],
            json!({"node": probe_nodes[0], "dir": "x"})
        );
        assert_eq!(v["model_residual"].as_array().unwrap().len(), 14);
        // Noise-free and no redundant probe: nothing to judge the residual against.
        let ratios = v["residual_ratio"].as_array().unwrap();
        assert!(
            ratios.len() == 14 && ratios.iter().all(Value::is_null),
            "{ratios:?}"
        );
        assert!(v["compute_ms"].as_f64().unwrap() >= 0.0);
        let mut worst: f64 = 0.0;
        for (b, brg) in v["bearings"].as_array().unwrap().iter().enumerate() {
            assert_eq!(brg["tag"], format!("brg{b}"));
            assert_eq!(brg["condition_number"].as_array().unwrap().len(), 14);
            for (s, &w) in speeds.iter().enumerate() {
                let truth = bearings(b, w);
                for i in 0..2 {
                    for j in 0..2 {
                        let k = brg["K"][s][i][j].as_f64().unwrap();
                        let c = brg["C"][s][i][j].as_f64().unwrap();
                        worst = worst
                            .max((k / truth.stiffness[i][j] - 1.0).abs())
                            .max((c / truth.damping[i][j] - 1.0).abs());
                    }
                }
            }
        }
        assert!(worst < 1e-6, "probes at {probe_nodes:?}: {worst:e}");
    }
}

#[test]
fn noisy_responses_carry_error_bars_and_the_table_and_report_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let rotor = rotor();
    let tests = runs([0, 7], 0.01, 5).simulate(&rotor, bearings).unwrap();
    let (r, t) = write(dir.path(), &rotor, &tests_json(&tests));
    let v = json_of(&field(&r, &t, &[]));
    let sd = v["bearings"][0]["K_std"][3][0][0].as_f64().unwrap();
    // The constant fit over the speeds carries its own error bars.
    let fit = &v["bearings"][0]["fit"];
    for key in ["K_std", "C_std", "M_std"] {
        assert!(fit[key][0][0].as_f64().unwrap() > 0.0, "{fit}");
    }
    let k = v["bearings"][0]["K"][3][0][0].as_f64().unwrap();
    let truth = bearings(0, 425.0).stiffness[0][0];
    assert!(
        sd > 0.0 && ((k - truth) / sd).abs() < 4.0,
        "{k} ± {sd} vs {truth}"
    );
    let report = dir.path().join("report");
    let out = run(&[
        "field",
        "--rotor",
        r.to_str().unwrap(),
        "--tests",
        t.to_str().unwrap(),
        "--plot",
        report.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.contains("bearing brg1 (node 7)") && table.contains('±'),
        "{table}"
    );
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(html.contains("<img src=\"field.svg\"") && html.contains("Bearing brg0"));
    let svg = std::fs::read_to_string(report.join("field.svg")).unwrap();
    assert_eq!(svg.matches("class=\"series\"").count(), 2 * 9);
}

#[test]
fn errors_have_their_kinds_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let rotor = rotor();
    let tests = runs([0, 7], 0.0, 1).simulate(&rotor, bearings).unwrap();
    let good = tests_json(&tests);
    let (r, t) = write(dir.path(), &rotor, &good);

    std::fs::write(&t, "{\"imbalances\": [").unwrap();
    assert_eq!(error_kind(&field(&r, &t, &[])), "invalid_input");

    let mut v = good.clone();
    v["responses"][5]["re"] = Value::Null;
    std::fs::write(&t, v.to_string()).unwrap();
    assert_eq!(error_kind(&field(&r, &t, &[])), "non_finite");
    // A NaN literal, as Python's json module writes it.
    let text = good.to_string().replacen("\"im\":", "\"im\":NaN,\"x\":", 1);
    std::fs::write(&t, text).unwrap();
    assert_eq!(error_kind(&field(&r, &t, &[])), "non_finite");

    let mut v = good.clone();
    v["responses"].as_array_mut().unwrap().remove(9);
    std::fs::write(&t, v.to_string()).unwrap();
    let out = field(&r, &t, &[]);
    assert_eq!(error_kind(&out), "missing_response");

    let mut v = good.clone();
    v["responses"]
        .as_array_mut()
        .unwrap()
        .retain(|r| !(r["node"] == 7 && r["dir"] == "y"));
    std::fs::write(&t, v.to_string()).unwrap();
    assert_eq!(error_kind(&field(&r, &t, &[])), "underdetermined");

    let mut v = good.clone();
    v["imbalances"]["3"] = json!([]);
    std::fs::write(&t, v.to_string()).unwrap();
    assert_eq!(error_kind(&field(&r, &t, &[])), "invalid_input");

    let iso = runs([0, 7], 0.0, 1).simulate(&rotor, isotropic).unwrap();
    std::fs::write(&t, tests_json(&iso).to_string()).unwrap();
    assert_eq!(error_kind(&field(&r, &t, &[])), "rank_deficient");

    // A response of 1e308 m (a test's, so that the pair it enters is not dependent): named
    // with its test and entry; before, a "dependent tests" warning with K, C left out there.
    let mut v = good.clone();
    let entry = v["responses"]
        .as_array()
        .unwrap()
        .iter()
        .position(|r| r["test"] == "1")
        .unwrap();
    v["responses"][entry]["re"] = json!(1e308);
    std::fs::write(&t, v.to_string()).unwrap();
    let out = field(&r, &t, &[]);
    assert_eq!(error_kind(&out), "invalid_input");
    let message = json_of(&out)["message"].as_str().unwrap().to_owned();
    assert!(
        message.starts_with(&format!("response {entry} (speed "))
            && message.contains("test `1`")
            && message.contains("value 1e308 m is past 1e150"),
        "{message}"
    );

    // A malformed rotor: K of the wrong size.
    std::fs::write(&t, good.to_string()).unwrap();
    let mut rv: Value = serde_json::from_str(&rotor_json(&rotor)).unwrap();
    rv["K"] = json!([[1.0]]);
    std::fs::write(&r, rv.to_string()).unwrap();
    assert_eq!(error_kind(&field(&r, &t, &[])), "invalid_input");
}

/// The text table on the example rotor (`examples/field/`, as the README runs it): every value
/// ends in the column of its header (the `gain` column is filled, so K and C sit under their
/// headers), and the gain is the JSON's `noise_gain` to the three digits printed.
#[test]
fn table_columns_sit_under_their_headers_on_the_example_rotor() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/field");
    let (rotor, tests) = (root.join("ROTOR.json"), root.join("TESTS_bearings.json"));
    let args = |json: bool| {
        let mut a = vec![
            "field",
            "--rotor",
            rotor.to_str().unwrap(),
            "--tests",
            tests.to_str().unwrap(),
        ];
        if json {
            a.push("--json");
        }
        run(&a)
    };
    let out = args(false);
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8(out.stdout).unwrap();
    let v = json_of(&args(true));
    // Column ends, in characters: where each right-aligned header or value stops.
    let ends = |line: &str, labels: &[String]| -> Vec<usize> {
        let mut from = 0;
        labels
            .iter()
            .map(|l| {
                let at = line[from..].find(l.as_str()).unwrap() + from;
                from = at + l.len();
                line[..from].chars().count()
            })
            .collect()
    };
    let mut headers = vec!["Ω rad/s".to_owned(), "cond".into(), "gain".into()];
    for block in ["K", "C"] {
        let unit = if block == "K" { "N/m" } else { "N·s/m" };
        headers.extend(["xx", "xy", "yx", "yy"].map(|n| format!("{block}_{n} {unit}")));
    }
    let lines: Vec<&str> = text.lines().collect();
    let mut rows_seen = 0;
    for (b, bearing) in v["bearings"].as_array().unwrap().iter().enumerate() {
        let at = lines
            .iter()
            .position(|l| l.starts_with(&format!("bearing {}", bearing["tag"].as_str().unwrap())))
            .unwrap_or_else(|| panic!("bearing {b} in\n{text}"));
        let header = lines[at + 1];
        let want = ends(header, &headers);
        for (s, row) in lines[at + 2..]
            .iter()
            .take_while(|l| !l.is_empty())
            .enumerate()
        {
            let values: Vec<String> = row.split_whitespace().map(str::to_owned).collect();
            assert_eq!(values.len(), headers.len(), "{row}");
            assert_eq!(ends(row, &values), want, "\n{header}\n{row}");
            let gain: f64 = values[2].parse().unwrap();
            let json_gain = bearing["noise_gain"][s].as_f64().unwrap();
            assert!(
                (gain / json_gain - 1.0).abs() < 5e-3,
                "{gain} vs {json_gain}"
            );
            rows_seen += 1;
        }
    }
    assert_eq!(
        rows_seen,
        2 * v["speeds_rad_s"].as_array().unwrap().len(),
        "{text}"
    );
}
