//! `bearing-ident campaign`: a plan's points identified exactly as `identify` identifies
//! them, baselines, references, geometry, failures, the cache and the ROSS speed table, on
//! impact records simulated into a temporary folder.

use std::path::{Path, PathBuf};

use bearing_ident::Coefficients;
use bearing_ident::faer::mat;
use bearing_ident::io::{CsvLayout, write_record};
use bearing_ident::simulate::ImpactTest;
use serde_json::Value;

use crate::commands::{block_error, matrix};
use crate::common::run;

/// A 2-DOF system whose direct damping is `c` (N·s/m): the seed rig's mass and stiffness.
fn system(c: f64) -> Coefficients {
    Coefficients::new(
        mat![[4.7, 0.0], [0.0, 4.8]],
        mat![[c, 3.0], [-2.0, c]],
        mat![[146.3e3, 22.3e3], [11.5e3, 169.1e3]],
    )
    .unwrap()
}

/// Writes `per_direction` noisy impacts per direction on `system` into `dir`, each response
/// multiplied by `arm` (1 for probes at the bearing).
fn write_hits(dir: &Path, system: &Coefficients, seed: u64, arm: [f64; 2]) {
    std::fs::create_dir_all(dir).unwrap();
    // 4 s at 1 kHz: long enough for the lightest damping here to ring down.
    let test = ImpactTest {
        per_direction: 3,
        sample_rate: 1000.0,
        duration_s: 4.0,
        pulse_s: 0.005,
        noise: 0.01,
        seed,
        ..ImpactTest::seed_rig()
    };
    for (k, r) in test.run(system).unwrap().iter().enumerate() {
        let forces = (0..2).map(|i| r.force(i).to_vec()).collect();
        let responses = (0..2)
            .map(|i| r.displacement(i).iter().map(|x| x * arm[i]).collect())
            .collect();
        let r = bearing_ident::Record::new(r.label(), r.sample_rate(), forces, responses).unwrap();
        write_record(dir.join(format!("hit-{k}.csv")), &r, &CsvLayout::default()).unwrap();
    }
}

/// `value` without the keys that hold wall times.
fn timeless(mut value: Value) -> Value {
    if let Some(map) = value.as_object_mut() {
        map.remove("compute_ms");
        map.remove("timings_ms");
    }
    value
}

fn json_of(out: &std::process::Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "{e}: stdout {} stderr {}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The files of a folder, sorted, as arguments.
fn files(dir: &Path) -> Vec<String> {
    let mut f: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    f.sort();
    f.iter().map(|p| p.display().to_string()).collect()
}

const PLAN: &str = r#"
[identify]
band = [8.0, 49.0]
[conditions]
speed = "rpm"
[geometry]
mode = "conical"
pivot = 0.0
bearing = 0.151
probes = [0.213, 0.254]
[[point]]
name = "dry"
files = "dry/*.csv"
speed = 0
[point.expect]
C_xx = [40.0, 0.5]
K_xx = [146.3e3, 2e3]
[[point]]
name = "oil"
files = ["oil/*.csv"]
speed = 3000
baseline = "dry"
identify = { reject_bad_records = true }
"#;

/// Records of the plan above: dry (C = 40) and oil (C = 140), measured at the probes.
fn study(dir: &Path) {
    let arm = [0.213 / 0.151, 0.254 / 0.151];
    write_hits(&dir.join("dry"), &system(40.0), 1, arm);
    write_hits(&dir.join("oil"), &system(140.0), 2, arm);
    std::fs::write(dir.join("plan.toml"), PLAN).unwrap();
    std::fs::write(
        dir.join("geometry.toml"),
        "mode = \"conical\"\npivot = 0.0\nbearing = 0.151\nprobes = [0.213, 0.254]\n",
    )
    .unwrap();
}

/// Each point's JSON is, but for wall times, `identify --json` on its files with the same
/// options (the geometry by `--geometry`, the baseline point by `--baseline` its saved JSON);
/// the geometry brings back the coefficients at the bearing (the closed form of the lever
/// arms), the baseline's variances add, and the references' z-scores are as stated.
#[test]
fn points_are_identify_bit_for_bit() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    study(dir);
    let out_dir = dir.join("out");
    let plan = dir.join("plan.toml");
    let report = dir.join("report");
    let out = run(&[
        "campaign".as_ref(),
        plan.as_os_str(),
        "--json".as_ref(),
        "--out".as_ref(),
        out_dir.as_os_str(),
        "--plot".as_ref(),
        report.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let campaign = json_of(&out);
    // The report: three figures, and each point's own report linked from the index; every
    // figure stored once, as its file, the pages showing it from there; the coefficients
    // named as the table on stdout names them.
    let index = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(index.contains("<img src=\"damping.svg\"") && !index.contains("<svg"));
    assert!(index.contains("K_xx ") && !index.contains("K00"));
    for point in ["dry", "oil"] {
        assert!(index.contains(&format!("href=\"points/{point}/index.html\"")));
        let folder = report.join("points").join(point);
        assert!(folder.join("impedance.svg").exists());
        let page = std::fs::read_to_string(folder.join("index.html")).unwrap();
        assert!(page.contains("<img src=\"impedance.svg\"") && !page.contains("<svg"));
    }
    let svg = std::fs::read_to_string(report.join("damping.svg")).unwrap();
    assert!(
        svg.contains("data-series=\"C_xx less dry\""),
        "series named by what they draw"
    );
    assert!(svg.contains("data-series=\"C_xx reference\""));

    let geometry = dir.join("geometry.toml").display().to_string();
    let mut args = vec![
        "identify",
        "--json",
        "--band",
        "8,49",
        "--geometry",
        &geometry,
    ];
    let dry_files = files(&dir.join("dry"));
    args.extend(dry_files.iter().map(String::as_str));
    let dry = json_of(&run(&args));
    assert_eq!(
        timeless(read_json(&out_dir.join("dry.json"))),
        timeless(dry.clone())
    );

    let saved_dry = out_dir.join("dry.json").display().to_string();
    let mut args = vec![
        "identify",
        "--json",
        "--band",
        "8,49",
        "--geometry",
        &geometry,
        "--reject-bad-records",
        "--speed",
        "3000rpm",
        "--baseline",
        &saved_dry,
    ];
    let oil_files = files(&dir.join("oil"));
    args.extend(oil_files.iter().map(String::as_str));
    let mut oil = timeless(json_of(&run(&args)));
    let mut point = timeless(read_json(&out_dir.join("oil.json")));
    // The baseline is named by its source: a path there, a point here, with which of its
    // results: the dry files again with the oil point's settings (`reject_bad_records`, which
    // rejects none of them, so the saved dry result is the same).
    assert_eq!(point["bearing"]["baseline"], "point dry");
    oil["bearing"]["baseline"] = "point dry".into();
    let bearing = point["bearing"].as_object_mut().unwrap();
    assert_eq!(bearing.remove("baseline_point").unwrap(), "dry");
    assert_eq!(bearing.remove("baseline_settings").unwrap(), "point");
    assert_eq!(point, oil);

    // The geometry: the lever arms undone, the coefficients are the bearing plane's.
    let truth = system(40.0);
    let k = dry["K"][0][0].as_f64().unwrap();
    assert!(
        (k / truth.stiffness()[(0, 0)] - 1.0).abs() < 2e-3,
        "K_xx {k}"
    );
    let m = dry["M"][1][1].as_f64().unwrap();
    assert!((m / 4.8 - 1.0).abs() < 2e-3, "M_yy {m}");

    // Baseline: the bearing's own is the difference, its variance the sum.
    let p = &campaign["points"][1];
    let c = |v: &Value, i: usize, j: usize| v[i][j].as_f64().unwrap();
    let bearing = &p["bearing"];
    let (sys, dry_c) = (&p["C"], &campaign["points"][0]["C"]);
    assert_eq!(c(&bearing["C"], 0, 0), c(sys, 0, 0) - c(dry_c, 0, 0));
    let (s_sys, s_dry) = (
        c(&p["C_std"], 0, 0),
        c(&campaign["points"][0]["C_std"], 0, 0),
    );
    let s_b = c(&bearing["C_std"], 0, 0);
    assert!(
        (s_b - s_sys.hypot(s_dry)).abs() <= 1e-12 * s_b,
        "{s_b} vs {s_sys} ⊕ {s_dry}"
    );
    assert!((c(&bearing["C"], 0, 0) / 100.0 - 1.0).abs() < 5e-3);

    // References: z as stated; K_xx agrees, C_xx = 40 ± 0.5 agrees too.
    let expect = campaign["points"][0]["expect"].as_array().unwrap();
    assert_eq!(expect.len(), 2);
    for e in expect {
        let f = |k: &str| e[k].as_f64().unwrap();
        let z = (f("value") - f("reference")) / f("std").hypot(f("reference_std"));
        assert!((f("z") - z).abs() < 1e-12, "{e}");
        assert!(f("z").abs() < 3.0, "{e}");
    }
    assert_eq!(campaign["conditions"]["speed"], "rpm");
    assert_eq!(campaign["points"][1]["conditions"]["speed"], 3000.0);
    let csv = std::fs::read_to_string(out_dir.join("coefficients.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.starts_with("name,speed [rpm],baseline,kxx,kxx_std,kxy"),
        "{header}"
    );
    assert!(csv.lines().nth(2).unwrap().starts_with("oil,3000,dry,"));
}

/// A reference far from the value warns `reference_mismatch`; a point whose files match
/// nothing fails with its error, a point whose baseline failed fails naming it, the others
/// complete, and the exit status is 1 after the JSON is printed.
#[test]
fn failures_stay_in_their_point() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_hits(&dir.join("a"), &system(50.0), 3, [1.0, 1.0]);
    let plan = dir.join("plan.toml");
    std::fs::write(
        &plan,
        "[identify]\nband = [8.0, 49.0]\n\
         [[point]]\nname = \"a\"\nfiles = \"a/*.csv\"\n[point.expect]\nC_xx = [80.0, 1.0]\n\
         [[point]]\nname = \"missing\"\nfiles = \"nowhere/*.csv\"\n\
         [[point]]\nname = \"on-missing\"\nfiles = \"a/*.csv\"\nbaseline = \"missing\"\n",
    )
    .unwrap();
    let out = run(&["campaign".as_ref(), plan.as_os_str(), "--json".as_ref()]);
    assert_eq!(out.status.code(), Some(1));
    let v = json_of(&out);
    let p = &v["points"];
    assert!(p[0].get("error").is_none());
    assert_eq!(p[0]["warning_kinds"][0], "reference_mismatch");
    assert!(p[0]["expect"][0]["z"].as_f64().unwrap() < -3.0);
    assert_eq!(p[1]["error"]["kind"], "invalid_argument");
    assert!(
        p[1]["error"]["message"]
            .as_str()
            .unwrap()
            .contains("no file matches")
    );
    let m = p[2]["error"]["message"].as_str().unwrap();
    assert!(m.starts_with("baseline point `missing` failed"), "{m}");
    // The table says the same without --json.
    let out = run(&["campaign".as_ref(), plan.as_os_str()]);
    assert_eq!(out.status.code(), Some(1));
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table
            .lines()
            .any(|l| l.starts_with("missing ") && l.contains("error invalid_argument")),
        "{table}"
    );
    // Under the table, each warning kind with its sentence; every line at most 120 wide.
    let said = table
        .lines()
        .find(|l| l.starts_with("  a: reference_mismatch: "))
        .unwrap_or_else(|| panic!("{table}"));
    assert!(said.contains("C_xx = ") && said.contains("from the reference 8.0000e1"));
    assert!(
        table
            .lines()
            .filter(|l| !l.starts_with("  a: ") && !l.contains("error"))
            .all(|l| l.chars().count() <= bearing_ident::text::TABLE_WIDTH),
        "{table}"
    );
}

/// With `--cache`, a rerun reuses every point; after one file changes, the point holding it
/// and the point using it as baseline are recomputed, the other reused, and the results are
/// those of a run without cache.
#[test]
fn the_cache_recomputes_what_changed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (name, c, seed) in [("a", 40.0, 4), ("b", 70.0, 5), ("c", 100.0, 6)] {
        write_hits(&dir.join(name), &system(c), seed, [1.0, 1.0]);
    }
    let plan = dir.join("plan.toml");
    std::fs::write(
        &plan,
        "[identify]\nband = [8.0, 49.0]\n\
         [[point]]\nname = \"a\"\nfiles = \"a/*.csv\"\n\
         [[point]]\nname = \"b\"\nfiles = \"b/*.csv\"\nbaseline = \"a\"\n\
         [[point]]\nname = \"c\"\nfiles = \"c/*.csv\"\n",
    )
    .unwrap();
    let cache = dir.join("cache");
    let go = || {
        json_of(&run(&[
            "campaign".as_ref(),
            plan.as_os_str(),
            "--json".as_ref(),
            "--cache".as_ref(),
            cache.as_os_str(),
            "--jobs".as_ref(),
            "2".as_ref(),
        ]))
    };
    let first = go();
    assert_eq!(first["reused"], 0);
    let second = go();
    assert_eq!(second["reused"], 3);
    let strip = |v: &Value| {
        let mut v = v.clone();
        for p in v["points"].as_array_mut().unwrap() {
            p.as_object_mut().unwrap().remove("reused");
        }
        v.as_object_mut().unwrap().remove("reused");
        v
    };
    assert_eq!(strip(&first), strip(&second));
    // Another record in place of a's first: a and b (its baseline is a) are recomputed.
    write_hits(&dir.join("a"), &system(40.0), 40, [1.0, 1.0]);
    let third = go();
    assert_eq!(third["reused"], 1);
    let reused: Vec<bool> = third["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["reused"].as_bool().unwrap())
        .collect();
    assert_eq!(reused, [false, false, true]);
    let fresh = json_of(&run(&[
        "campaign".as_ref(),
        plan.as_os_str(),
        "--json".as_ref(),
    ]));
    assert_eq!(strip(&third), strip(&fresh));
    assert_ne!(first["points"][0]["K"], third["points"][0]["K"]);
}

/// The plan of issue 40: a dry point at the shared band and a point of its own band
/// (`identify = { band = [9.0, 48.0] }`) with `baseline = "dry"`. The dry files are identified
/// again at 9–48 Hz and that subtracted: the bearing equals, bit for bit, `identify --band 9,48`
/// on the oil files less `identify --band 9,48` on the dry files (variances added), while the
/// dry row keeps its own 8–49 Hz result and a point at the shared band subtracts that. Each
/// result names the baseline result used, the table marks it; on a rerun everything comes from
/// the cache, the baseline identified again included (a point recomputed takes it from there).
#[test]
fn a_baseline_is_identified_again_at_the_points_settings() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_hits(&dir.join("dry"), &system(40.0), 21, [1.0, 1.0]);
    write_hits(&dir.join("oil"), &system(140.0), 22, [1.0, 1.0]);
    let plan = dir.join("plan.toml");
    std::fs::write(
        &plan,
        "[identify]\nband = [8.0, 49.0]\n\
         [[point]]\nname = \"dry\"\nfiles = \"dry/*.csv\"\n\
         [[point]]\nname = \"oil\"\nfiles = \"oil/*.csv\"\nbaseline = \"dry\"\n\
         identify = { band = [9.0, 48.0] }\n\
         [[point]]\nname = \"oil-wide\"\nfiles = \"oil/*.csv\"\nbaseline = \"dry\"\n",
    )
    .unwrap();
    let cache = dir.join("cache");
    let campaign = |json: bool| {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "campaign".as_ref(),
            plan.as_os_str(),
            "--cache".as_ref(),
            cache.as_os_str(),
        ];
        if json {
            args.push("--json".as_ref());
        }
        run(&args)
    };
    let out = campaign(true);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let first = json_of(&out);
    assert_eq!(first["reused"], 0);
    let identify = |band: &str, folder: &str| {
        let mut args = vec!["identify", "--json", "--band", band];
        let files = files(&dir.join(folder));
        args.extend(files.iter().map(String::as_str));
        json_of(&run(&args))
    };
    let (dry_9_48, oil_9_48) = (identify("9,48", "dry"), identify("9,48", "oil"));
    let (dry, oil, wide) = (
        &first["points"][0],
        &first["points"][1],
        &first["points"][2],
    );
    let entries = |v: &Value, key: &str| -> Vec<f64> {
        v[key]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|row| row.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
            .collect()
    };
    // The dry row is the dry files at the shared band, not at the oil point's.
    assert_eq!(dry["K"], identify("8,49", "dry")["K"]);
    assert_ne!(entries(dry, "K"), entries(&dry_9_48, "K"));
    assert_eq!(oil["K"], oil_9_48["K"]);
    for key in ["M", "C", "K"] {
        let std = format!("{key}_std");
        let by_hand: Vec<f64> = entries(&oil_9_48, key)
            .iter()
            .zip(entries(&dry_9_48, key))
            .map(|(s, d)| s - d)
            .collect();
        assert_eq!(entries(&oil["bearing"], key), by_hand, "{key}");
        let std_by_hand: Vec<f64> = entries(&oil_9_48, &std)
            .iter()
            .zip(entries(&dry_9_48, &std))
            .map(|(s, d)| s.hypot(d))
            .collect();
        assert_eq!(entries(&oil["bearing"], &std), std_by_hand, "{std}");
        // The point at the shared band subtracts the dry row itself.
        let own: Vec<f64> = entries(wide, key)
            .iter()
            .zip(entries(dry, key))
            .map(|(s, d)| s - d)
            .collect();
        assert_eq!(entries(&wide["bearing"], key), own, "{key}");
    }
    let c_xx = entries(&oil["bearing"], "C")[0];
    assert!((c_xx / 100.0 - 1.0).abs() < 5e-3, "C_xx {c_xx}");
    assert_eq!(oil["bearing"]["baseline_point"], "dry");
    assert_eq!(oil["bearing"]["baseline_settings"], "point");
    assert_eq!(wide["bearing"]["baseline_settings"], "own");

    // A rerun: every point from the cache, the same results; the table marks the baseline
    // identified again.
    let out = campaign(true);
    let second = json_of(&out);
    assert_eq!(second["reused"], 3);
    let strip = |v: &Value| {
        let mut v = v.clone();
        for p in v["points"].as_array_mut().unwrap() {
            p.as_object_mut().unwrap().remove("reused");
        }
        v.as_object_mut().unwrap().remove("reused");
        v
    };
    assert_eq!(strip(&first), strip(&second));
    let out = campaign(false);
    let table = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = table.lines().collect();
    assert!(lines[0].starts_with("point     baseline"), "{table}");
    assert!(lines[2].starts_with("oil       dry* "), "{table}");
    assert!(lines[3].starts_with("oil-wide  dry "), "{table}");
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("* the baseline point's files identified again")),
        "{table}"
    );
    // Wider than 120 characters in one piece: the warnings column splits off.
    assert!(
        lines
            .iter()
            .all(|l| l.chars().count() <= bearing_ident::text::TABLE_WIDTH),
        "{table}"
    );

    // The cache holds the dry files at 9–48 Hz beside the three points. With the oil point's
    // entry gone and that baseline's K_xx altered, the oil point is identified again and
    // subtracts the altered baseline: it came from the cache.
    let entries_of = |band: f64, folder: &str| -> Vec<PathBuf> {
        files(&cache)
            .into_iter()
            .map(PathBuf::from)
            .filter(|path| {
                let v = read_json(path);
                let first = Path::new(v["files"][0].as_str().unwrap());
                v["band_hz"][0] == band
                    && first.parent().and_then(Path::file_name) == Some(folder.as_ref())
            })
            .collect()
    };
    assert_eq!(files(&cache).len(), 4);
    let [baseline] = &entries_of(9.0, "dry")[..] else {
        panic!("one cache entry of the dry files at 9-48 Hz");
    };
    let [oil_entry] = &entries_of(9.0, "oil")[..] else {
        panic!("one cache entry of the oil point");
    };
    std::fs::remove_file(oil_entry).unwrap();
    let mut altered = read_json(baseline);
    let k_xx = altered["K"][0][0].as_f64().unwrap() + 1000.0;
    altered["K"][0][0] = k_xx.into();
    std::fs::write(baseline, altered.to_string()).unwrap();
    let third = json_of(&campaign(true));
    assert_eq!(third["reused"], 2);
    let oil = &third["points"][1];
    assert_eq!(oil["reused"], false);
    assert_eq!(
        oil["bearing"]["K"][0][0].as_f64().unwrap(),
        oil["K"][0][0].as_f64().unwrap() - k_xx
    );
}

/// A plan's faults are `invalid_input` naming the plan's line.
#[test]
fn plan_faults_name_the_line() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = tmp.path().join("plan.toml");
    for (text, line, what) in [
        (
            "[identify]\nband = [8.0, 49.0]\nmetod = \"ls\"\n[[point]]\nname = \"a\"\nfiles = \"x\"\n",
            3,
            "unknown option `metod`",
        ),
        (
            "[identify]\nband = [8.0, 49.0]\nmethod = \"lsq\"\n[[point]]\nname = \"a\"\nfiles = \"x\"\n",
            3,
            "lsq",
        ),
        ("[[point]]\nname = \"a\"\nfiles = \"x\"\n", 1, "has no band"),
        (
            "[identify]\nband = [8.0, 49.0]\n[[point]]\nname = \"a\"\nfiles = \"x\"\nbaseline = \"b\"\n",
            6,
            "baseline `b` names no point",
        ),
    ] {
        std::fs::write(&plan, text).unwrap();
        let out = run(&["campaign".as_ref(), plan.as_os_str(), "--json".as_ref()]);
        assert_eq!(out.status.code(), Some(2));
        let v = json_of(&out);
        assert_eq!(v["error"], "invalid_input", "{v}");
        let m = v["message"].as_str().unwrap();
        assert!(
            m.contains(&format!("plan.toml:{line}: ")) && m.contains(what),
            "{m}"
        );
    }
}

/// `--ross`: one bearing element over the `speed` condition in rad/s, each speed's terms
/// those of its point (the bearing's own, less the baseline; the baseline point left out);
/// points differing in another condition are refused unless `--ross-where` picks a slice.
#[test]
fn ross_speed_table() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut plan = String::from(
        "[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = \"rpm\"\nload = \"N\"\n",
    );
    write_hits(&dir.join("dry"), &system(40.0), 7, [1.0, 1.0]);
    plan.push_str("[[point]]\nname = \"dry\"\nfiles = \"dry/*.csv\"\nspeed = 0\nload = 0\n");
    for (k, rpm) in [1000.0, 2000.0, 3000.0, 4000.0, 5000.0].iter().enumerate() {
        let name = format!("s{k}");
        write_hits(
            &dir.join(&name),
            &system(80.0 + 10.0 * k as f64),
            10 + k as u64,
            [1.0, 1.0],
        );
        plan.push_str(&format!(
            "[[point]]\nname = \"{name}\"\nfiles = \"{name}/*.csv\"\nspeed = {rpm}\nload = 200\nbaseline = \"dry\"\n"
        ));
    }
    // Another load at one speed (its records those of s0): a slice of its own.
    plan.push_str("[[point]]\nname = \"heavy\"\nfiles = \"s0/*.csv\"\nspeed = 1000\nload = 400\nbaseline = \"dry\"\n");
    let path = dir.join("plan.toml");
    std::fs::write(&path, &plan).unwrap();
    let ross = dir.join("brg.toml");
    let args = |extra: &[&str]| -> Vec<std::ffi::OsString> {
        let mut a: Vec<std::ffi::OsString> = vec![
            "campaign".into(),
            path.clone().into(),
            "--json".into(),
            "--ross".into(),
            ross.clone().into(),
        ];
        a.extend(extra.iter().map(Into::into));
        a
    };
    let out = run(&args(&[]));
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("differ in `load`"));
    let out = run(&args(&[
        "--ross-where",
        "load=200",
        "--ross-node",
        "3",
        "--ross-tag",
        "sfd",
    ]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json_of(&out);
    let table: toml::Table = std::fs::read_to_string(&ross).unwrap().parse().unwrap();
    let element = table["BearingElement_sfd"].as_table().unwrap();
    assert_eq!(element["n"].as_integer(), Some(3));
    let floats = |key: &str| -> Vec<f64> {
        element[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_float().unwrap())
            .collect()
    };
    let speed = floats("speed");
    assert_eq!(speed.len(), 5);
    for (k, w) in speed.iter().enumerate() {
        let rpm = 1000.0 * (k + 1) as f64;
        assert!((w - rpm * std::f64::consts::PI / 30.0).abs() < 1e-9);
        let b = &v["points"][k + 1]["bearing"];
        assert_eq!(floats("cxx")[k], b["C"][0][0].as_f64().unwrap());
        assert_eq!(floats("kyx")[k], b["K"][1][0].as_f64().unwrap());
        assert_eq!(floats("myy")[k], b["M"][1][1].as_f64().unwrap());
        assert!((floats("cxx")[k] / (40.0 + 10.0 * k as f64) - 1.0).abs() < 0.02);
    }
    // Per line: a 2-D table, speed × frequency.
    let out = run(&args(&["--ross-where", "load=200", "--per-frequency"]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table: toml::Table = std::fs::read_to_string(&ross).unwrap().parse().unwrap();
    let element = table["BearingElement_bearing"].as_table().unwrap();
    let f = element["frequency"].as_array().unwrap().len();
    let kxx = element["kxx"].as_array().unwrap();
    assert_eq!(kxx.len(), 5);
    assert!(kxx.iter().all(|row| row.as_array().unwrap().len() == f));
    assert!(f >= 5);
}

/// A two-plane campaign end to end: a rigid rotor's motion measured at 213 and 254 mm in x and
/// y (a tilt unrelated to the bearing's motion on top of it), files of `fx, fy, x1, y1, x2, y2`;
/// `mode = "two-plane"` brings back the bearing plane's M, C, K (at 151 mm, outside the
/// probes) to the noise-free simulation's floor, and `identify --geometry` gives the same
/// point; without the geometry the four response columns are refused naming `--disp`.
#[test]
fn two_plane_geometry_recovers_the_bearing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let truth = system(131.98);
    let (bearing, planes) = (0.151, [0.213, 0.254]);
    let test = ImpactTest {
        per_direction: 2,
        ..ImpactTest::seed_rig()
    };
    std::fs::create_dir_all(dir.join("hits")).unwrap();
    let layout = CsvLayout {
        time: "t".into(),
        // The record holds each force twice (the reader reads fx, fy twice); fx2, fy2 unread.
        forces: ["fx", "fy", "fx2", "fy2"].map(String::from).to_vec(),
        displacements: ["x1", "y1", "x2", "y2"].map(String::from).to_vec(),
    };
    for (k, r) in test.run(&truth).unwrap().iter().enumerate() {
        let tilt =
            |d: usize, m: usize| 40.0 * r.displacement(1 - d)[m] + 1e-4 * (m as f64 * 0.01).sin();
        let at = |z: f64, d: usize| -> Vec<f64> {
            (0..r.len())
                .map(|m| r.displacement(d)[m] + tilt(d, m) * (z - bearing))
                .collect()
        };
        let x = vec![
            at(planes[0], 0),
            at(planes[0], 1),
            at(planes[1], 0),
            at(planes[1], 1),
        ];
        let f = (0..4).map(|i| r.force(i % 2).to_vec()).collect();
        let r = bearing_ident::Record::new(r.label(), r.sample_rate(), f, x).unwrap();
        write_record(dir.join("hits").join(format!("hit-{k}.csv")), &r, &layout).unwrap();
    }
    let geometry = "[geometry]\nmode = \"two-plane\"\nbearing = 0.151\n\
                    probes = [0.213, 0.213, 0.254, 0.254]\n";
    std::fs::write(
        dir.join("plan.toml"),
        format!(
            "[identify]\nband = [8.0, 49.0]\ndisp = [\"x1\", \"y1\", \"x2\", \"y2\"]\n{geometry}\
             [[point]]\nname = \"rig\"\nfiles = \"hits/*.csv\"\n"
        ),
    )
    .unwrap();
    std::fs::write(
        dir.join("geometry.toml"),
        geometry.replace("[geometry]\n", ""),
    )
    .unwrap();
    let plan = dir.join("plan.toml");
    let out = run(&["campaign".as_ref(), plan.as_os_str(), "--json".as_ref()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let point = &json_of(&out)["points"][0];
    let worst = [
        ("M", truth.mass()),
        ("C", truth.damping()),
        ("K", truth.stiffness()),
    ]
    .iter()
    .map(|(key, t)| block_error(&matrix(point, key), &bearing_ident::model::rows(*t)))
    .fold(0.0, f64::max);
    assert!(worst < 1e-6, "worst block error {worst}");
    let files = files(&dir.join("hits"));
    let g = dir.join("geometry.toml").display().to_string();
    let identify = |geometry: &[&str]| {
        let mut args = vec![
            "identify",
            "--json",
            "--band",
            "8,49",
            "--disp",
            "x1,y1,x2,y2",
        ];
        args.extend(geometry);
        args.extend(files.iter().map(String::as_str));
        json_of(&run(&args))
    };
    assert_eq!(identify(&["--geometry", &g])["K"], point["K"]);
    let refused = identify(&[]);
    assert_eq!(refused["error"], "invalid_argument");
    assert!(refused["message"].as_str().unwrap().contains("--disp 4"));
}

/// A point that asks for an element model (`identify = { model = "auto" }`) gets the family
/// chosen in the text table and in `coefficients.csv`; a point that does not is blank there.
#[test]
fn the_chosen_element_model_is_a_column() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_hits(&dir.join("a"), &system(140.0), 31, [1.0, 1.0]);
    let plan = dir.join("plan.toml");
    std::fs::write(
        &plan,
        "[identify]\nband = [8.0, 49.0]\n\
         [[point]]\nname = \"plain\"\nfiles = \"a/*.csv\"\n\
         [[point]]\nname = \"auto\"\nfiles = \"a/*.csv\"\nidentify = { model = \"auto\" }\n",
    )
    .unwrap();
    let out_dir = dir.join("out");
    let out = run(&[
        "campaign".as_ref(),
        plan.as_os_str(),
        "--out".as_ref(),
        out_dir.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = String::from_utf8_lossy(&out.stdout);
    let header = table.lines().next().unwrap();
    assert!(header.contains("model"), "{table}");
    let row = |name: &str| {
        table
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("no row {name} in\n{table}"))
            .to_owned()
    };
    assert!(row("auto ").contains(" kcm "), "{table}");
    assert!(!row("plain ").contains(" kcm "), "{table}");
    let csv = std::fs::read_to_string(out_dir.join("coefficients.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let at = header
        .iter()
        .position(|h| *h == "model")
        .expect("a model column");
    assert_eq!(header[at + 1], "status");
    let cells = |line: usize| -> Vec<String> {
        csv.lines()
            .nth(line)
            .unwrap()
            .split(',')
            .map(str::to_owned)
            .collect()
    };
    assert_eq!(cells(1)[at], "");
    assert_eq!(cells(2)[at], "kcm");
    assert_eq!(cells(2).len(), header.len());
}

/// With a `speed` condition, each point's synchronous coefficients are its per-line `K(ω)`,
/// `C(ω)` and their σ at the line equal to the speed (1800 rpm = 30 Hz and 2415 rpm =
/// 40.25 Hz are lines of these 4 s records), bit for bit; between lines (2007 rpm =
/// 33.45 Hz, 0.8 of the way from 33.25 Hz to 33.5 Hz), the linear interpolation; in the JSON, `coefficients.csv` (`kxx_sync`, …) and the table.
#[test]
fn synchronous_coefficients_are_the_lines_at_the_speed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut plan = String::from(
        "[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = \"rpm\"\nload = \"N\"\n",
    );
    let speeds = [1800.0, 2415.0, 2007.0];
    for (k, rpm) in speeds.iter().enumerate() {
        let name = format!("s{k}");
        write_hits(&dir.join(&name), &system(80.0), 20 + k as u64, [1.0, 1.0]);
        plan.push_str(&format!(
            "[[point]]\nname = \"{name}\"\nfiles = \"{name}/*.csv\"\nspeed = {rpm}\nload = 200\n"
        ));
    }
    let path = dir.join("plan.toml");
    std::fs::write(&path, &plan).unwrap();
    let out_dir = dir.join("out");
    let out = run(&[
        "campaign".as_ref(),
        path.as_os_str(),
        "--json".as_ref(),
        "--per-frequency".as_ref(),
        "--out".as_ref(),
        out_dir.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json_of(&out);
    let csv = std::fs::read_to_string(out_dir.join("coefficients.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for (k, rpm) in speeds.iter().enumerate() {
        let point = &v["points"][k];
        let sync = &point["synchronous"];
        let f = rpm / 60.0;
        assert!((sync["frequency_hz"].as_f64().unwrap() - f).abs() < 1e-12);
        assert_eq!(sync["source"], "lines");
        let lines = point["per_frequency"].as_array().unwrap();
        let at = |hz: f64| {
            lines
                .iter()
                .position(|l| (l["freq_hz"].as_f64().unwrap() - hz).abs() < 1e-9)
                .unwrap()
        };
        let value = |l: usize, key: &str, i: usize, j: usize| -> f64 {
            lines[l][key][i][j].as_f64().unwrap()
        };
        for key in ["K", "C", "K_std", "C_std"] {
            for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let got = sync[key][i][j].as_f64().unwrap();
                let expected = if k < 2 {
                    value(at(f), key, i, j)
                } else if key.ends_with("_std") {
                    let (a, b) = (value(at(33.25), key, i, j), value(at(33.5), key, i, j));
                    (0.2f64.powi(2) * a * a + 0.8f64.powi(2) * b * b).sqrt()
                } else {
                    0.2 * value(at(33.25), key, i, j) + 0.8 * value(at(33.5), key, i, j)
                };
                if k < 2 {
                    assert_eq!(got, expected, "{key}");
                } else {
                    assert!(
                        (got - expected).abs() <= 1e-9 * expected.abs(),
                        "{key}: {got} vs {expected}"
                    );
                }
            }
        }
        let row: Vec<&str> = csv.lines().nth(k + 1).unwrap().split(',').collect();
        let kxx: f64 = row[column("kxx_sync")].parse().unwrap();
        let cyy_std: f64 = row[column("cyy_sync_std")].parse().unwrap();
        assert_eq!(kxx, sync["K"][0][0].as_f64().unwrap());
        assert_eq!(cyy_std, sync["C_std"][1][1].as_f64().unwrap());
        let gamma: f64 = row[column("whirl_frequency_ratio")]
            .parse()
            .unwrap_or(f64::NAN);
        let json_gamma = point["stability"]["whirl_frequency_ratio"].as_f64();
        assert_eq!(json_gamma.is_some(), gamma.is_finite());
    }
    let table = run(&["campaign".as_ref(), path.as_os_str()]);
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(
        text.contains("K_xx sync [N/m]") && text.contains("whirl ratio"),
        "{text}"
    );
}

/// `campaign --plot` with a `speed` condition adds `synchronous.svg`: per element of `K` and
/// `C`, each point's synchronous value (`±σ`) against its speed in rpm, one series per load,
/// and the plan's predictions (`expect`) as crosses on a dashed line; `index.html` shows it.
#[test]
fn synchronous_figure_against_speed_with_predictions() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut plan = String::from(
        "[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = \"rpm\"\nload = \"N\"\n",
    );
    // Damping rising with speed, as predicted (± 10 %); K as the seed rig's.
    let speeds = [900.0, 1500.0, 2100.0, 2700.0];
    for (k, rpm) in speeds.iter().enumerate() {
        let name = format!("s{k}");
        let c = 60.0 + 20.0 * k as f64;
        write_hits(&dir.join(&name), &system(c), 40 + k as u64, [1.0, 1.0]);
        plan.push_str(&format!(
            "[[point]]\nname = \"{name}\"\nfiles = \"{name}/*.csv\"\nspeed = {rpm}\nload = 200\n\
             [point.expect]\nK_xx = [146.3e3, 5e3]\nC_xx = [{c}, {}]\nC_yy = [{c}, {}]\n",
            0.1 * c,
            0.1 * c
        ));
    }
    let path = dir.join("plan.toml");
    std::fs::write(&path, &plan).unwrap();
    let report = dir.join("report");
    let out = run(&[
        "campaign".as_ref(),
        path.as_os_str(),
        "--per-frequency".as_ref(),
        "--plot".as_ref(),
        report.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(report.join("synchronous.svg")).unwrap();
    // Eight panels (K and C, 2 × 2), one series of points each; predictions where given.
    for element in [
        "K_xx", "K_xy", "K_yx", "K_yy", "C_xx", "C_xy", "C_yx", "C_yy",
    ] {
        assert!(
            svg.contains(&format!(
                "data-series=\"{element} sync load = 200, system\""
            )),
            "{element}"
        );
    }
    for element in ["K_xx", "C_xx", "C_yy"] {
        assert!(
            svg.contains(&format!(
                "data-series=\"{element} sync prediction load = 200, system\""
            )),
            "{element}"
        );
    }
    assert_eq!(svg.matches("sync prediction").count(), 3 * 2);
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(html.contains("synchronous.svg"));
}

/// `--ross` on a campaign whose points all have a speed within their lines: the 1-D table's
/// `k`, `c` at each speed are the point's synchronous `K`, `C` (bit for bit with its JSON), `m`
/// its fitted `M`, and the file says so.
#[test]
fn ross_speed_table_is_synchronous_when_every_point_has_a_speed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut plan = String::from("[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = \"rpm\"\n");
    let speeds = [900.0, 1500.0, 2100.0, 2700.0];
    for (k, rpm) in speeds.iter().enumerate() {
        let name = format!("s{k}");
        write_hits(
            &dir.join(&name),
            &system(60.0 + 20.0 * k as f64),
            60 + k as u64,
            [1.0, 1.0],
        );
        plan.push_str(&format!(
            "[[point]]\nname = \"{name}\"\nfiles = \"{name}/*.csv\"\nspeed = {rpm}\n"
        ));
    }
    let path = dir.join("plan.toml");
    std::fs::write(&path, &plan).unwrap();
    let ross = dir.join("brg.toml");
    let out = run(&[
        "campaign".as_ref(),
        path.as_os_str(),
        "--json".as_ref(),
        "--ross".as_ref(),
        ross.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json_of(&out);
    let text = std::fs::read_to_string(&ross).unwrap();
    assert!(text.contains("synchronous K(w), C(w)"), "{text}");
    let table: toml::Table = text.parse().unwrap();
    let element = table["BearingElement_bearing"].as_table().unwrap();
    let floats = |key: &str| -> Vec<f64> {
        element[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_float().unwrap())
            .collect()
    };
    for k in 0..speeds.len() {
        let point = &v["points"][k];
        let sync = &point["synchronous"];
        assert_eq!(floats("kxx")[k], sync["K"][0][0].as_f64().unwrap());
        assert_eq!(floats("kyx")[k], sync["K"][1][0].as_f64().unwrap());
        assert_eq!(floats("cyy")[k], sync["C"][1][1].as_f64().unwrap());
        assert_eq!(floats("mxx")[k], point["M"][0][0].as_f64().unwrap());
        assert_ne!(floats("kxx")[k], point["K"][0][0].as_f64().unwrap());
    }
    // `--ross-samples N FILE.csv`: N samples per speed about the same synchronous values
    // (each sample mean within 5 standard errors), the same file for the same seed; a count
    // of 0 or a seed that is not a whole number refused naming the option, before any work.
    let csv = dir.join("samples.csv");
    let n = 400;
    let with_samples = |count: &str, seed: &str| {
        run(&[
            "campaign".as_ref(),
            path.as_os_str(),
            "--json".as_ref(),
            "--ross-samples".as_ref(),
            count.as_ref(),
            csv.as_os_str(),
            "--ross-seed".as_ref(),
            seed.as_ref(),
        ])
    };
    let out = with_samples("400", "5");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "speed_rpm,point,sample,kxx,kxy,kyx,kyy,cxx,cxy,cyx,cyy,mxx,mxy,myx,myy"
    );
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    assert_eq!(rows.len(), n * speeds.len());
    for (k, rpm) in speeds.iter().enumerate() {
        let at: Vec<&Vec<String>> = rows[k * n..(k + 1) * n].iter().collect();
        assert!(
            at.iter()
                .all(|r| (r[0].parse::<f64>().unwrap() - rpm).abs() < 1e-9)
        );
        assert!(at.iter().enumerate().all(|(i, r)| r[2] == i.to_string()));
        let sync = &v["points"][k]["synchronous"];
        for (column, key, i, j) in [
            (3, "K", 0, 0),
            (6, "K", 1, 1),
            (7, "C", 0, 0),
            (10, "C", 1, 1),
        ] {
            let mean = at
                .iter()
                .map(|r| r[column].parse::<f64>().unwrap())
                .sum::<f64>()
                / n as f64;
            let (value, std) = (
                sync[key][i][j].as_f64().unwrap(),
                sync[format!("{key}_std")][i][j].as_f64().unwrap(),
            );
            assert!(
                (mean - value).abs() < 5.0 * std / (n as f64).sqrt(),
                "{key}{i}{j} at {rpm}"
            );
        }
    }
    assert!(with_samples("400", "5").status.success());
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), text);
    for (count, seed, option) in [("0", "5", "--ross-samples"), ("4", "abc", "--ross-seed")] {
        let out = with_samples(count, seed);
        assert_eq!(out.status.code(), Some(2));
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
        let e = json_of(&out);
        assert_eq!(e["error"], "invalid_argument", "{e}");
        assert!(e["message"].as_str().unwrap().contains(option), "{e}");
    }
}
