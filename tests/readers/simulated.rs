//! `simulate --format csv|tdms|mat`: the same records as CSV, TDMS and MAT-files read back to
//! the same samples bit for bit and identify to the same result; npTDMS and SciPy (independent
//! readers) read the TDMS and MAT-files to the numbers of the CSV. The Python check needs numpy,
//! npTDMS and SciPy (`TDMS_FIXTURE_PYTHON`, default `python3`); without them it says in one line
//! that it skips, unless `TDMS_FIXTURES_REQUIRED` is set.

use std::path::{Path, PathBuf};

use bearing_ident::job::{Channels, read_file};

use crate::common::run;

/// The records of one simulated impact test written as `format` into `dir/format`.
fn simulate(dir: &Path, format: &str) -> Vec<PathBuf> {
    let out = dir.join(format);
    let o = out.display().to_string();
    let args = [
        "simulate",
        "--kind",
        "impact",
        "--impacts",
        "2",
        "--rate",
        "1024",
        "--seed",
        "7",
        "--noise",
        "0.01",
        "--format",
        format,
        "--out",
        &o,
    ];
    let done = run(&args);
    assert!(
        done.status.success(),
        "{format}: {}",
        String::from_utf8_lossy(&done.stderr)
    );
    // The columns each file holds: a TDMS file has no time channel.
    let columns = if format == "tdms" {
        "fx,fy,x,y"
    } else {
        "t,fx,fy,x,y"
    };
    let said = String::from_utf8_lossy(&done.stdout);
    assert!(said.ends_with(&format!("columns {columns}\n")), "{said}");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), 4, "{files:?}");
    files
}

fn coefficients(files: &[PathBuf]) -> serde_json::Value {
    let mut args: Vec<String> = ["identify", "--json", "--band", "8,49"]
        .map(String::from)
        .to_vec();
    args.extend(files.iter().map(|f| f.display().to_string()));
    let out = run(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    serde_json::json!({"M": v["M"], "C": v["C"], "K": v["K"], "warnings": v["warning_kinds"]})
}

#[test]
fn simulated_tdms_and_mat_files_read_and_identify_as_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = simulate(dir.path(), "csv");
    let tdms = simulate(dir.path(), "tdms");
    let mat = simulate(dir.path(), "mat");
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for ((c, t), m) in csv.iter().zip(&tdms).zip(&mat) {
        let want = read_file(c, &Channels::default()).unwrap().swap_remove(0);
        for path in [t, m] {
            let got = read_file(
                path,
                &Channels::named(&[], &[], &[], "t", std::slice::from_ref(path)).unwrap(),
            )
            .unwrap()
            .swap_remove(0);
            assert_eq!(
                got.sample_rate().to_bits(),
                want.sample_rate().to_bits(),
                "{}",
                path.display()
            );
            for i in 0..2 {
                assert_eq!(
                    bits(got.force(i)),
                    bits(want.force(i)),
                    "{}",
                    path.display()
                );
                assert_eq!(
                    bits(got.displacement(i)),
                    bits(want.displacement(i)),
                    "{}",
                    path.display()
                );
            }
            assert!(got.warnings().is_empty());
        }
    }
    let want = coefficients(&csv);
    assert_eq!(coefficients(&tdms), want, "TDMS");
    assert_eq!(coefficients(&mat), want, "MAT");
    independent_readers(dir.path(), &csv);
}

/// npTDMS and SciPy read the TDMS and MAT-files to the CSV's numbers, bit for bit.
fn independent_readers(dir: &Path, csv: &[PathBuf]) {
    const SCRIPT: &str = r#"
import sys
import numpy as np
from nptdms import TdmsFile
from scipy.io import loadmat
d = sys.argv[1]
for label in sys.argv[2:]:
    rows = np.loadtxt(f"{d}/csv/{label}.csv", delimiter=",", skiprows=1, ndmin=2)
    group = TdmsFile.read(f"{d}/tdms/{label}.tdms")[label]
    for i, name in enumerate(["fx", "fy", "x", "y"]):
        channel = group[name]
        assert np.array_equal(channel[:], rows[:, i + 1]), (label, name)
        assert channel.properties["unit_string"] == ("N" if i < 2 else "m"), channel.properties
        assert channel.properties["wf_increment"] == 1 / 1024
    m = loadmat(f"{d}/mat/{label}.mat")
    for i, name in enumerate(["t", "fx", "fy", "x", "y"]):
        assert m[name].shape == (rows.shape[0], 1), (name, m[name].shape)
        assert np.array_equal(m[name][:, 0], rows[:, i]), (label, name)
print("ok")
"#;
    let python = std::env::var("TDMS_FIXTURE_PYTHON").unwrap_or_else(|_| "python3".into());
    let labels = csv
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned());
    let out = std::process::Command::new(&python)
        .arg("-c")
        .arg(SCRIPT)
        .arg(dir)
        .args(labels)
        .output();
    let why = match &out {
        Ok(o) if o.status.success() => return,
        Ok(o) => String::from_utf8_lossy(&o.stderr).into_owned(),
        Err(e) => format!("{python}: {e}"),
    };
    let missing = why.contains("ModuleNotFoundError") || out.is_err();
    if missing && std::env::var_os("TDMS_FIXTURES_REQUIRED").is_none() {
        eprintln!(
            "simulated_tdms_and_mat_files_read_and_identify_as_the_csv: the npTDMS and SciPy \
             check skipped ({})",
            why.lines().last().unwrap_or_default()
        );
        return;
    }
    panic!("npTDMS / SciPy disagree with the CSV: {why}");
}
