//! `identify` and `inspect` on MAT-files written by SciPy (`tests/mat/make_fixtures.py`): the
//! same result, bit for bit, as from the CSV of the same data.

use std::path::Path;

use serde_json::Value;

use crate::common::run;

fn fixture(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/mat/fixtures")
        .join(name)
        .display()
        .to_string()
}

fn identify(args: &[&str]) -> Value {
    let out = run(&[&["identify", "--json", "--band", "10,100"], args].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

/// What the identification found, without what names the files or times the stages.
fn result(v: &Value) -> Vec<(&'static str, Value)> {
    [
        "M", "C", "K", "M_std", "C_std", "K_std", "fs", "n", "freqs_hz", "warnings",
    ]
    .into_iter()
    .map(|k| (k, v[k].clone()))
    .collect()
}

#[test]
fn identify_gives_the_csv_result_bit_for_bit_from_each_mat_layout() {
    let csv = result(&identify(&[&fixture("a.csv")]));
    let plain = identify(&[&fixture("plain.mat")]);
    assert_eq!(result(&plain), csv);
    assert_eq!(result(&identify(&[&fixture("compressed.mat")])), csv);
    let columns = [
        "--force",
        "data:2,data:3",
        "--disp",
        "data:4,data:5",
        "--time",
        "data:1",
    ];
    let matrix = identify(&[&columns[..], &[&fixture("matrix.mat")]].concat());
    assert_eq!(result(&matrix), csv);
    // Two records of a struct array against the two CSV files (the rate from `dt`: the same
    // to 1e-12, so the coefficients agree to rounding).
    let two_csv = identify(&[&fixture("a.csv"), &fixture("b.csv")]);
    let fields = ["--force", "recs.fx,recs.fy", "--disp", "recs.x,recs.y"];
    let two_mat = identify(&[&fields[..], &[&fixture("struct_array.mat")]].concat());
    assert_eq!(two_mat["n_records"], 2);
    for key in ["M", "C", "K"] {
        let flat = |v: &Value| -> Vec<f64> {
            v[key]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
                .collect()
        };
        let scale = flat(&two_csv).iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (a, b) in flat(&two_mat).iter().zip(flat(&two_csv)) {
            assert!((a - b).abs() <= 1e-9 * scale, "{key}: {a} vs {b}");
        }
    }
}

#[test]
fn inspect_lists_variables_fields_class_and_size() {
    let out = run(&[
        "inspect",
        &fixture("struct_array.mat"),
        &fixture("cell.mat"),
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("struct_array.mat: 2 MAT-file variables"),
        "{text}"
    );
    for line in [
        "recs                     struct     1×2",
        "recs.fx                  double     512×1",
        "hits.Fs                  double     1×1",
    ] {
        assert!(text.contains(line), "{line}\n{text}");
    }
    let out = run(&["inspect", "--json", &fixture("wrong_classes.mat")]);
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let fx = &v["variables"][1];
    assert_eq!(fx["name"], "fx");
    assert_eq!(fx["class"], "char");
    assert_eq!(fx["size"], serde_json::json!([1, 12]));
}

#[test]
fn a_bad_mat_file_exits_2_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.mat");
    let data = std::fs::read(fixture("compressed.mat")).unwrap();
    std::fs::write(&path, &data[..1000]).unwrap();
    let out = run(&[
        "identify",
        "--json",
        "--band",
        "10,100",
        path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["error"], "malformed_mat", "{v}");
    assert!(
        v["message"].as_str().unwrap().contains("cut.mat, byte 128"),
        "{v}"
    );
}

#[test]
fn a_campaign_point_reads_matrix_columns_at_a_given_rate() {
    let dir = tempfile::tempdir().unwrap();
    let plan = dir.path().join("plan.toml");
    std::fs::write(
        &plan,
        format!(
            "[identify]\nband = [10.0, 100.0]\nforce = \"data:2,data:3\"\n\
             disp = \"data:4,data:5\"\nrate = 1000.0\n\
             [[point]]\nname = \"m\"\nfiles = {:?}\n",
            fixture("matrix.mat")
        ),
    )
    .unwrap();
    let out = run(&["campaign", plan.to_str().unwrap(), "--json"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let point = &v["points"][0];
    let direct = identify(&[
        "--force",
        "data:2,data:3",
        "--disp",
        "data:4,data:5",
        "--rate",
        "1000",
        &fixture("matrix.mat"),
    ]);
    assert_eq!(direct["fs"], 1000.0);
    assert_eq!(point["K"], direct["K"], "{point}");
}

#[test]
fn identify_gives_the_csv_result_bit_for_bit_from_each_v73_layout() {
    let csv = result(&identify(&[&fixture("a.csv")]));
    for file in ["plain_v73.mat", "compressed_v73.mat", "latest_v73.mat"] {
        assert_eq!(result(&identify(&[&fixture(file)])), csv, "{file}");
    }
    let columns = [
        "--force",
        "data:2,data:3",
        "--disp",
        "data:4,data:5",
        "--time",
        "data:1",
    ];
    let matrix = identify(&[&columns[..], &[&fixture("matrix_v73.mat")]].concat());
    assert_eq!(result(&matrix), csv);
    // The struct array reads as its level 5 twin, bit for bit.
    let fields = ["--force", "recs.fx,recs.fy", "--disp", "recs.x,recs.y"];
    let v5 = identify(&[&fields[..], &[&fixture("struct_array.mat")]].concat());
    let v73 = identify(&[&fields[..], &[&fixture("struct_array_v73.mat")]].concat());
    assert_eq!(v73["n_records"], 2);
    assert_eq!(result(&v73), result(&v5));
}

#[test]
fn inspect_lists_v73_variables_fields_class_and_size() {
    let out = run(&[
        "inspect",
        &fixture("struct_array_v73.mat"),
        &fixture("cell_v73.mat"),
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("struct_array_v73.mat: 2 MAT-file variables"),
        "{text}"
    );
    for line in [
        "recs                     struct     1×2",
        "recs.fx                  double     512×1",
        "hits                     cell       1×2",
        "hits.Fs                  double     1×1",
    ] {
        assert!(text.contains(line), "{line}\n{text}");
    }
    let out = run(&["inspect", "--json", &fixture("wrong_classes_v73.mat")]);
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let fx = &v["variables"][0];
    assert_eq!(fx["name"], "fx");
    assert_eq!(fx["class"], "char");
    assert_eq!(fx["size"], serde_json::json!([1, 12]));
}
