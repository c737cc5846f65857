//! Velocity and acceleration records through Universal Files and the command line: data types
//! 11 and 12 become velocity and acceleration responses; `--force`/`--disp` name channels by
//! node and direction or by ID line; `--response` overrides the kinds. Every path gives the
//! result of the records written.
#![cfg(all(feature = "uff", feature = "csv"))]

use crate::common;
#[cfg(feature = "cli")]
use crate::common::bin;

use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::uff::{self, ByteOrder, Function, UffChannel, UffLayout};
use bearing_ident::{Error, Identifier, Record, Response};
use common::block_relative_error;

/// Sampling rate whose interval six significant digits hold (see `uff`'s precision notes).
const FS: f64 = 5000.0;

/// Impacts on the seed rig, 2 per direction, x recorded as velocity and y as acceleration.
fn mixed_records() -> Vec<Record> {
    ImpactTest {
        per_direction: 2,
        sample_rate: FS,
        ..ImpactTest::seed_rig()
    }
    .run_responding(&seed_rig(), &[Response::Velocity, Response::Acceleration])
    .unwrap()
}

/// The time histories of `record` with load case `lc`: forces at node 1 (data type 13), the
/// responses at node 2 with the data type of their kind (8, 11, 12) and ID lines `probe x`,
/// `probe y`.
fn functions(record: &Record, lc: i64) -> Vec<Function> {
    let code = |r: Response| match r {
        Response::Displacement => 8,
        Response::Velocity => 11,
        Response::Acceleration => 12,
    };
    let dt = 1.0 / record.sample_rate();
    let mut out = Vec::new();
    for c in 0..record.dofs() {
        let mut f = Function::time_response(1, c as i64 + 1, 13, 0.0, dt, record.force(c).to_vec());
        f.id[0] = format!("hammer {}", ["x", "y"][c]);
        f.load_case = lc;
        out.push(f);
        let mut x = Function::time_response(
            2,
            c as i64 + 1,
            code(record.response(c)),
            0.0,
            dt,
            record.displacement(c).to_vec(),
        );
        x.id[0] = format!("probe {}", ["x", "y"][c]);
        x.load_case = lc;
        out.push(x);
    }
    out
}

/// The time histories of `records`, record `i` as load case `i + 1`.
fn load_cases(records: &[Record]) -> Vec<Function> {
    records
        .iter()
        .enumerate()
        .flat_map(|(i, r)| functions(r, i as i64 + 1))
        .collect()
}

fn binary(functions: &[Function]) -> Vec<u8> {
    let mut bytes = Vec::new();
    uff::write_binary(&mut bytes, functions, ByteOrder::Little).unwrap();
    bytes
}

#[test]
fn data_types_11_and_12_are_velocity_and_acceleration() {
    let records = mixed_records();
    let all = load_cases(&records);
    let back = uff::records(
        &uff::parse(&binary(&all), "mixed.uff").unwrap(),
        "mixed.uff",
    )
    .unwrap();
    assert_eq!(back.len(), records.len());
    for (a, b) in back.iter().zip(&records) {
        assert_eq!(a.responses(), &[Response::Velocity, Response::Acceleration]);
        assert_eq!(a.displacement(1), b.displacement(1));
    }
    let want = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    let got = Identifier::new(8.0, 49.0).identify(&back).unwrap();
    // Binary doubles round-trip exactly: the same records, the same result.
    assert_eq!(got.coefficients(), want.coefficients());
    let to_truth = block_relative_error(got.coefficients(), &seed_rig());
    assert!(to_truth < common::EXACT, "{to_truth:e}");
}

#[test]
fn named_channels_and_kind_overrides() {
    let record = &mixed_records()[0];
    let fs = functions(record, 0);
    // Swapped order by name: DOF 0 is y, DOF 1 is x.
    let layout = UffLayout {
        forces: vec!["1+Y".parse().unwrap(), "id:hammer x".parse().unwrap()],
        responses: vec!["id:probe y".parse().unwrap(), "2+1".parse().unwrap()],
        ..UffLayout::default()
    };
    let r = &uff::records_with(&fs, "rig.uff", &layout).unwrap()[0];
    assert_eq!(r.force(0), record.force(1));
    assert_eq!(r.displacement(1), record.displacement(0));
    assert_eq!(r.responses(), &[Response::Acceleration, Response::Velocity]);
    // An override replaces the data types.
    let layout = UffLayout {
        kinds: vec![Response::Displacement],
        ..UffLayout::default()
    };
    let r = &uff::records_with(&fs, "rig.uff", &layout).unwrap()[0];
    assert_eq!(r.responses(), &[Response::Displacement; 2]);
    // A missing channel names the file, the load case and the channel.
    let layout = UffLayout {
        forces: vec!["7-Z".parse().unwrap()],
        responses: vec!["2+X".parse().unwrap()],
        ..UffLayout::default()
    };
    let e = uff::records_with(&fs, "rig.uff", &layout).unwrap_err();
    let Error::UffRecord { path, message, .. } = &e else {
        panic!("{e:?}");
    };
    assert_eq!(path, "rig.uff");
    assert!(message.contains("`7-Z`"), "{message}");
    assert!(message.contains("1+X `hammer x`"), "{message}");
    // A response of another data type needs its kind.
    let mut other = fs.clone();
    other[1].numerator.data_type = uff::DataType::General;
    let layout = UffLayout {
        responses: vec!["2+X".parse().unwrap(), "2+Y".parse().unwrap()],
        ..UffLayout::default()
    };
    let e = uff::records_with(&other, "rig.uff", &layout).unwrap_err();
    assert!(e.to_string().contains("data type 1"), "{e}");
    let layout = UffLayout {
        kinds: vec![Response::Velocity, Response::Acceleration],
        ..layout
    };
    // The stated kinds stand in for the data types: the same record as written.
    let r = &uff::records_with(&other, "rig.uff", &layout).unwrap()[0];
    assert_eq!(r.responses(), &[Response::Velocity, Response::Acceleration]);
    for c in 0..2 {
        assert_eq!(r.force(c), record.force(c));
        assert_eq!(r.displacement(c), record.displacement(c));
    }
    // Unequal numbers of forces and responses.
    let layout = UffLayout {
        forces: vec!["1+X".parse().unwrap()],
        ..UffLayout::default()
    };
    assert!(uff::records_with(&fs, "rig.uff", &layout).is_err());
    assert_eq!(
        "5*X".parse::<UffChannel>().unwrap_err().kind(),
        "invalid_argument"
    );
    assert_eq!(
        UffChannel::Dof {
            node: 12,
            direction: -6
        }
        .to_string(),
        "12-RZ"
    );
}

#[cfg(feature = "cli")]
fn identify_json(args: &[&str]) -> serde_json::Value {
    let out = bin()
        .arg("identify")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    serde_json::from_slice(&out.stdout).unwrap_or_else(|_| {
        panic!(
            "{}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

#[cfg(feature = "cli")]
fn k(v: &serde_json::Value) -> Vec<f64> {
    v["K"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|row| row.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect()
}

#[cfg(feature = "cli")]
#[test]
fn command_line_velocity_csv_and_uff_give_the_displacement_result() {
    let dir = tempfile::tempdir().unwrap();
    let path = |p: &str| dir.path().join(p).display().to_string();
    for (sub, response) in [
        ("d", "displacement"),
        ("v", "velocity"),
        ("a", "acceleration,velocity"),
    ] {
        let out = bin()
            .args([
                "simulate",
                "--impacts",
                "2",
                "--response",
                response,
                "--out",
            ])
            .arg(path(sub))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let files = |sub: &str| -> Vec<String> {
        let mut f: Vec<String> = std::fs::read_dir(path(sub))
            .unwrap()
            .map(|e| e.unwrap().path().display().to_string())
            .collect();
        f.sort();
        f
    };
    let mut base = vec!["--band", "8,49"];
    let d = files("d");
    base.extend(d.iter().map(String::as_str));
    let kd = k(&identify_json(&base));
    for (sub, response) in [("v", "velocity"), ("a", "acceleration,velocity")] {
        let f = files(sub);
        let mut args = vec!["--band", "8,49", "--response", response];
        args.extend(f.iter().map(String::as_str));
        let kv = k(&identify_json(&args));
        for (a, b) in kv.iter().zip(&kd) {
            // Both within the simulation's error budget (`common::EXACT`) of the truth.
            assert!(
                (a - b).abs() < 2.0 * common::EXACT * 169.1e3,
                "{sub}: {kv:?} vs {kd:?}"
            );
        }
    }
    // Velocity columns without --response: the x,y columns are missing.
    let out = bin()
        .args(["identify", "--band", "8,49", "--json"])
        .args(files("v"))
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains("missing_column"));

    // A Universal File of velocity (11) and acceleration (12) time histories, read by data
    // type, by named channels, and with a kind override.
    let records = mixed_records();
    let all = load_cases(&records);
    let uff_path = path("mixed.uff");
    std::fs::write(&uff_path, binary(&all)).unwrap();
    let want = Identifier::new(8.0, 49.0).identify(&records).unwrap();
    let want_k: Vec<f64> = (0..2)
        .flat_map(|i| (0..2).map(move |j| (i, j)))
        .map(|(i, j)| want.coefficients().stiffness()[(i, j)])
        .collect();
    let by_type = k(&identify_json(&["--band", "8,49", &uff_path]));
    let named = k(&identify_json(&[
        "--band",
        "8,49",
        "--force",
        "id:hammer x,1+Y",
        "--resp",
        "2+X,id:probe y",
        &uff_path,
    ]));
    for (got, name) in [(&by_type, "by type"), (&named, "named")] {
        for (a, b) in got.iter().zip(&want_k) {
            assert!((a / b - 1.0).abs() < 1e-9, "{name}: {got:?} vs {want_k:?}");
        }
    }
    // Saying both are displacement gives another (wrong) answer: the override applies.
    let wrong = identify_json(&["--band", "8,49", "--response", "displacement", &uff_path]);
    match wrong.get("K") {
        Some(_) => assert!((k(&wrong)[0] / want_k[0] - 1.0).abs() > 0.1, "{wrong}"),
        None => assert!(wrong.get("error").is_some(), "{wrong}"),
    }
    // A channel the file does not hold: an error naming the file and the channel.
    let out = bin()
        .args([
            "identify", "--band", "8,49", "--json", "--force", "9+X,1+Y", "--disp", "2+X,2+Y",
        ])
        .arg(&uff_path)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(!out.status.success());
    assert!(text.contains("mixed.uff") && text.contains("9+X"), "{text}");
    // A bad channel name.
    let out = bin()
        .args([
            "identify", "--json", "--force", "9X,1+Y", "--disp", "2+X,2+Y",
        ])
        .arg(&uff_path)
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains("invalid_argument"));
}
