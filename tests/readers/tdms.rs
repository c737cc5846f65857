//! TDMS files written by npTDMS (`tests/tdms/make_fixtures.py`, run here into
//! `target/tdms-fixtures/`): each layout reads to the samples of the CSV of the same data, bit
//! for bit, and identifies to the same result; `inspect` lists them; bad files are typed
//! errors naming the file.
//!
//! The script needs Python with numpy and npTDMS (`TDMS_FIXTURE_PYTHON`, default `python3`).
//! Without them each test says in one line that it skips, unless `TDMS_FIXTURES_REQUIRED` is
//! set (as `.ci/run` sets it), when that is a failure.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use bearing_ident::Record;
use bearing_ident::job::{Channels, read_file};
use bearing_ident::tdms::RecordBy;

use crate::common::run;

/// The fixtures' folder, written once per test binary; `None` (after a line saying so) when
/// the writer is not installed.
fn fixtures(test: &str) -> Option<PathBuf> {
    static DIR: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    let made = DIR.get_or_init(|| {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let dir = root.join("target/tdms-fixtures");
        let python = std::env::var("TDMS_FIXTURE_PYTHON").unwrap_or_else(|_| "python3".into());
        let out = std::process::Command::new(&python)
            .arg(root.join("tests/tdms/make_fixtures.py"))
            .arg(&dir)
            .output()
            .map_err(|e| format!("{python}: {e}"))?;
        if out.status.success() {
            Ok(dir)
        } else {
            Err(String::from_utf8_lossy(&out.stderr).into_owned())
        }
    });
    match made {
        Ok(dir) => Some(dir.clone()),
        Err(why) if std::env::var_os("TDMS_FIXTURES_REQUIRED").is_some() => {
            panic!("the TDMS fixtures could not be written: {why}")
        }
        Err(why) => {
            use std::io::Write;
            let last = why.lines().last().unwrap_or_default();
            let _ = writeln!(
                std::io::stderr(),
                "{test}: skipped, the TDMS fixtures need Python with numpy and npTDMS ({last})"
            );
            None
        }
    }
}

fn read(path: &Path, by: RecordBy) -> Vec<Record> {
    let channels = Channels {
        record_by: by,
        ..Channels::default()
    };
    read_file(path, &channels).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every channel and the rate, bit for bit.
fn assert_same(got: &Record, want: &Record, what: &str) {
    assert_eq!(
        got.sample_rate().to_bits(),
        want.sample_rate().to_bits(),
        "{what}: rate"
    );
    for k in 0..want.dofs() {
        let bits = |s: &[f64]| s.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(got.force(k)), bits(want.force(k)), "{what}: force {k}");
        assert_eq!(
            bits(got.displacement(k)),
            bits(want.displacement(k)),
            "{what}: response {k}"
        );
    }
}

#[test]
fn every_layout_reads_to_the_samples_of_the_csv_bit_for_bit() {
    let Some(dir) = fixtures("every_layout_reads_to_the_samples_of_the_csv_bit_for_bit") else {
        return;
    };
    let csv: Vec<Record> = (1..=2)
        .map(|h| read(&dir.join(format!("hit{h}.csv")), RecordBy::File).remove(0))
        .collect();
    for h in 1..=2 {
        for layout in ["f64", "i16", "be_interleaved"] {
            let name = format!("{layout}_hit{h}.tdms");
            let got = read(&dir.join(&name), RecordBy::File);
            assert_eq!(got.len(), 1, "{name}");
            assert_same(&got[0], &csv[h - 1], &name);
        }
    }
    let groups = read(&dir.join("f32_groups.tdms"), RecordBy::Group);
    assert_eq!(groups.len(), 2);
    for (got, want) in groups.iter().zip(&csv) {
        assert_same(got, want, got.label());
    }
    assert!(
        groups[1].label().ends_with("f32_groups.tdms:hit2"),
        "{}",
        groups[1].label()
    );
}

/// `identify --json` of the records: the coefficients and their standard deviations.
fn coefficients(files: &[String], extra: &[&str]) -> serde_json::Value {
    let mut args: Vec<String> = ["identify", "--json", "--band", "8,49"]
        .iter()
        .chain(extra)
        .map(|s| s.to_string())
        .collect();
    args.extend(files.iter().cloned());
    let out = run(&args);
    assert!(
        out.status.success(),
        "{files:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    serde_json::json!({
        "M": v["M"], "C": v["C"], "K": v["K"],
        "M_std": v["M_std"], "C_std": v["C_std"], "K_std": v["K_std"],
    })
}

#[test]
fn every_layout_identifies_to_the_result_of_the_csv() {
    let Some(dir) = fixtures("every_layout_identifies_to_the_result_of_the_csv") else {
        return;
    };
    let files = |pattern: &str| -> Vec<String> {
        (1..=2)
            .map(|h| {
                dir.join(pattern.replace('#', &h.to_string()))
                    .display()
                    .to_string()
            })
            .collect()
    };
    let csv = coefficients(&files("hit#.csv"), &[]);
    let k = csv["K"][0][0].as_f64().unwrap();
    assert!((k / 146.3e3 - 1.0).abs() < 0.05, "K_xx {k}");
    for layout in ["f64_hit#.tdms", "i16_hit#.tdms", "be_interleaved_hit#.tdms"] {
        assert_eq!(coefficients(&files(layout), &[]), csv, "{layout}");
    }
    let groups = [dir.join("f32_groups.tdms").display().to_string()];
    assert_eq!(
        coefficients(&groups, &["--record-by", "group"]),
        csv,
        "f32_groups.tdms"
    );
}

#[test]
fn inspect_lists_groups_channels_and_properties() {
    let Some(dir) = fixtures("inspect_lists_groups_channels_and_properties") else {
        return;
    };
    let path = dir.join("f32_groups.tdms");
    let out = run(&["inspect".as_ref(), "--json".as_ref(), path.as_os_str()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let groups = &v["tdms"][0]["groups"];
    assert_eq!(groups[1]["name"], "hit2");
    assert_eq!(groups[1]["channels"][3]["name"], "y");
    assert_eq!(groups[1]["channels"][3]["n"], 1024);
    assert_eq!(groups[1]["channels"][3]["data_type"], 9);
    assert_eq!(
        groups[0]["channels"][0]["properties"]["wf_increment"],
        1.0 / 1024.0
    );
    let path = dir.join("i16_hit1.tdms");
    let out = run(&["inspect".as_ref(), path.as_os_str()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("5 channels"), "{text}");
    assert!(
        text.contains("channel `fx`: 1024 samples, unit N"),
        "{text}"
    );
    assert!(
        text.contains("NI_Scale[0]_Scale_Type = Polynomial"),
        "{text}"
    );
}

#[test]
fn bad_files_are_typed_errors_naming_the_file() {
    let Some(dir) = fixtures("bad_files_are_typed_errors_naming_the_file") else {
        return;
    };
    let good = std::fs::read(dir.join("f64_hit1.tdms")).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "truncated.tdms",
            good[..good.len() - 100].to_vec(),
            "malformed_tdms",
        ),
        ("lead-in.tdms", good[..20].to_vec(), "malformed_tdms"),
        (
            "lying.tdms",
            {
                let mut b = good.clone();
                b[20..28].copy_from_slice(&(u64::MAX - 1).to_le_bytes());
                b
            },
            "malformed_tdms",
        ),
        (
            "zip.tdms",
            b"PK\x03\x04not a tdms file at all, really not".to_vec(),
            "malformed_tdms",
        ),
    ];
    for (name, bytes, kind) in cases {
        let path = tmp.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let out = run(&[
            "identify".as_ref(),
            "--json".as_ref(),
            "--band".as_ref(),
            "8,49".as_ref(),
            path.as_os_str(),
        ]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["error"], kind, "{name}: {v}");
        assert!(v["message"].as_str().unwrap().contains(name), "{name}: {v}");
    }
    // A channel not in the file, one in two groups, and a rate from nowhere.
    let groups = dir.join("f32_groups.tdms");
    let out = run(&[
        "identify".as_ref(),
        "--json".as_ref(),
        "--band".as_ref(),
        "8,49".as_ref(),
        groups.as_os_str(),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["error"], "missing_column", "{v}");
    assert!(
        v["message"]
            .as_str()
            .unwrap()
            .contains("in groups hit1, hit2"),
        "{v}"
    );
    let out = run(&[
        "identify".as_ref(),
        "--json".as_ref(),
        "--band".as_ref(),
        "8,49".as_ref(),
        "--force".as_ref(),
        "hit1/fx,hit1/nope".as_ref(),
        "--disp".as_ref(),
        "hit1/x,hit1/y".as_ref(),
        groups.as_os_str(),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["error"], "missing_column", "{v}");
    assert!(v["message"].as_str().unwrap().contains("hit1/nope"), "{v}");
}

/// A campaign plan reads TDMS files through the same reader: `files = [...]`, `record_by`,
/// the same coefficients as `identify`.
#[test]
fn a_campaign_plan_reads_tdms_files() {
    let Some(dir) = fixtures("a_campaign_plan_reads_tdms_files") else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let plan = tmp.path().join("plan.toml");
    std::fs::write(
        &plan,
        format!(
            "[identify]\nband = [8.0, 49.0]\nrecord_by = \"group\"\n\n[[point]]\nname = \"groups\"\n\
             files = [\"{}\"]\n\n[[point]]\nname = \"files\"\nfiles = [\"{}\", \"{}\"]\n\
             [point.identify]\nrecord_by = \"file\"\n",
            dir.join("f32_groups.tdms").display(),
            dir.join("f64_hit1.tdms").display(),
            dir.join("f64_hit2.tdms").display(),
        ),
    )
    .unwrap();
    let out = run(&["campaign".as_ref(), plan.as_os_str(), "--json".as_ref()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let points = v["points"].as_array().expect("points");
    let csv = coefficients(
        &[1, 2].map(|h| dir.join(format!("hit{h}.csv")).display().to_string()),
        &[],
    );
    assert_eq!(points.len(), 2);
    for p in points {
        assert_eq!(p["K"], csv["K"], "{p}");
    }
}

/// A record in lbf and mil, read with its units (stated in the TDMS file, or given for the
/// CSV), identifies to the coefficients of its SI version within rounding.
#[test]
fn records_in_lbf_and_mil_identify_as_their_si_version() {
    let Some(dir) = fixtures("records_in_lbf_and_mil_identify_as_their_si_version") else {
        return;
    };
    let files = |pattern: &str| -> Vec<String> {
        (1..=2)
            .map(|h| {
                dir.join(pattern.replace('#', &h.to_string()))
                    .display()
                    .to_string()
            })
            .collect()
    };
    let si = coefficients(&files("hit#.csv"), &[]);
    let close = |got: &serde_json::Value, what: &str| {
        for key in ["M", "C", "K"] {
            for (a, b) in got[key]
                .as_array()
                .unwrap()
                .iter()
                .zip(si[key].as_array().unwrap())
            {
                for (x, y) in a.as_array().unwrap().iter().zip(b.as_array().unwrap()) {
                    let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
                    let scale = si[key][0][0].as_f64().unwrap().abs();
                    assert!((x - y).abs() <= 1e-9 * scale, "{what} {key}: {x} vs {y}");
                }
            }
        }
    };
    close(
        &coefficients(&files("us_hit#.tdms"), &[]),
        "TDMS unit_string",
    );
    close(
        &coefficients(
            &files("us_hit#.csv"),
            &["--force-unit", "lbf", "--disp-unit", "mil"],
        ),
        "CSV --force-unit lbf --disp-unit mil",
    );
    // Given units outrank the file's: stating N and m reads the numbers as SI.
    let raw = coefficients(
        &files("us_hit#.tdms"),
        &["--force-unit", "N", "--disp-unit", "m"],
    );
    assert_eq!(raw, coefficients(&files("us_hit#.csv"), &[]));
    // `--units us`: the table in lbf/in, lbf·s/in, lbm; the JSON keeps SI and adds them.
    let mut args: Vec<String> = ["identify", "--json", "--band", "8,49", "--units", "us"]
        .map(String::from)
        .to_vec();
    args.extend(files("us_hit#.tdms"));
    let v: serde_json::Value = serde_json::from_slice(&run(&args).stdout).unwrap();
    assert_eq!(v["units"]["output"], "us");
    assert_eq!(v["units"]["K"], "lbf/in");
    let (k, k_us) = (
        v["K"][0][0].as_f64().unwrap(),
        v["K_us"][0][0].as_f64().unwrap(),
    );
    assert!(
        (k_us / (k * 0.0254 / 4.448_221_615_260_5) - 1.0).abs() < 1e-12,
        "{k} {k_us}"
    );
    let (m, m_us) = (
        v["M"][1][1].as_f64().unwrap(),
        v["M_us"][1][1].as_f64().unwrap(),
    );
    assert!((m_us * 0.453_592_37 / m - 1.0).abs() < 1e-12, "{m} {m_us}");
    args.remove(1);
    let text = String::from_utf8(run(&args).stdout).unwrap();
    for label in ["M_xx (lbm)", "C_xy (lbf·s/in)", "K_yy (lbf/in)"] {
        assert!(text.contains(label), "{label}: {text}");
    }
    // A unit nobody knows is refused, naming it.
    let out = run(&[
        "identify",
        "--json",
        "--band",
        "8,49",
        "--force-unit",
        "kip·ft",
        &files("hit#.csv")[0],
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["error"], "invalid_argument", "{v}");
    assert!(v["message"].as_str().unwrap().contains("kip·ft"), "{v}");
}

/// A unit the file states and the crate does not know (`V` on the forces) is a warning naming
/// file, channel and unit; the samples are used as read, so the result is the CSV's bit for
/// bit. Given a known unit in its place, the warning goes.
#[test]
fn an_unknown_unit_in_the_file_warns_and_reads_as_si() {
    let Some(dir) = fixtures("an_unknown_unit_in_the_file_warns_and_reads_as_si") else {
        return;
    };
    let files = |pattern: &str| -> Vec<String> {
        (1..=2)
            .map(|h| {
                dir.join(pattern.replace('#', &h.to_string()))
                    .display()
                    .to_string()
            })
            .collect()
    };
    assert_eq!(
        coefficients(&files("volts_hit#.tdms"), &[]),
        coefficients(&files("hit#.csv"), &[])
    );
    let json = |extra: &[&str]| -> serde_json::Value {
        let mut args: Vec<String> = ["identify", "--json", "--band", "8,49"]
            .iter()
            .chain(extra)
            .map(|s| s.to_string())
            .collect();
        args.extend(files("volts_hit#.tdms"));
        serde_json::from_slice(&run(&args).stdout).unwrap()
    };
    let v = json(&[]);
    let kinds: Vec<&str> = v["warning_kinds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| k.as_str().unwrap())
        .collect();
    // Two force channels in each of two files.
    assert_eq!(
        kinds.iter().filter(|k| **k == "unknown_unit").count(),
        4,
        "{v}"
    );
    let first = v["warnings"][0].as_str().unwrap();
    assert!(
        first.contains("volts_hit1.tdms`: channel `fx` has unit `V`")
            && first.contains("read, in N; give --force-unit"),
        "{first}"
    );
    let v = json(&["--force-unit", "N"]);
    assert!(
        v["warning_kinds"]
            .as_array()
            .unwrap()
            .iter()
            .all(|k| k != "unknown_unit"),
        "{v}"
    );
}
