//! Export of an identification on known truth: simulate → identify → UFF dataset 58 and ROSS
//! bearing element → read back. The measured functions equal the FRF stage's, the model's
//! equal the closed form `K − ω²M + iωC` (and its inverse) at the lines, and the ROSS terms
//! equal the fitted coefficients, every bit.
#![cfg(all(feature = "uff", feature = "ross", feature = "json"))]

use crate::common::bin;

use bearing_ident::export::ross::{BearingElement, Table};
use bearing_ident::faer::{c64, mat};
use bearing_ident::simulate::{ImpactTest, seed_rig};
use bearing_ident::uff::{self, Abscissa, ByteOrder, DataType, FunctionType, Ordinate};
use bearing_ident::{Band, Coefficients, Identification, Identifier, Window};

fn identified(window: Window) -> Identification {
    let test = ImpactTest {
        per_direction: 2,
        noise: 0.02,
        ..ImpactTest::seed_rig()
    };
    let records = test.run(&seed_rig()).expect("simulated");
    Identifier::new(8.0, 49.0)
        .window(window)
        .identify(&records)
        .expect("identified")
}

fn complex(o: &Ordinate) -> &[c64] {
    match o {
        Ordinate::Complex(v) => v,
        Ordinate::Real(_) => panic!("real ordinate"),
    }
}

fn same_bits(a: c64, b: c64) -> bool {
    a.re.to_bits() == b.re.to_bits() && a.im.to_bits() == b.im.to_bits()
}

#[test]
fn uff_export_round_trips_the_measured_and_model_frfs_exactly() {
    let id = identified(Window::Rectangular);
    let mut bytes = Vec::new();
    uff::write_binary(
        &mut bytes,
        &bearing_ident::export::uff::functions(&id, 7).unwrap(),
        ByteOrder::Little,
    )
    .unwrap();
    let back = uff::parse(&bytes, "export.uff").unwrap();
    let frf = id.frf();
    let freqs = frf.freqs_hz();
    // 4 FRF kinds × 4 pairs, 4 ordinary and 2 multiple coherences (2 paired sets).
    assert_eq!(back.len(), 16 + 4 + 2);
    let c = id.coefficients();
    for (index, f) in back.iter().take(16).enumerate() {
        let (kind, i, j) = (index / 4, (index % 4) / 2, index % 2);
        assert_eq!(f.function_type, FunctionType::Frf);
        assert_eq!(f.function_id, index as i64 + 1);
        assert_eq!((f.response.node, f.response.direction), (7, i as i64 + 1));
        assert_eq!((f.reference.node, f.reference.direction), (7, j as i64 + 1));
        let force_first = kind < 2;
        assert_eq!(
            (f.numerator.data_type, f.denominator.data_type),
            if force_first {
                (DataType::ExcitationForce, DataType::Displacement)
            } else {
                (DataType::Displacement, DataType::ExcitationForce)
            }
        );
        let y = complex(&f.ordinate);
        assert_eq!(y.len(), freqs.len());
        for (k, &hz) in freqs.iter().enumerate() {
            let expected = match kind {
                0 => frf.impedance(k)[(i, j)],
                1 => c.impedance_at(hz)[(i, j)],
                2 => frf.flexibility(k)[(i, j)],
                _ => c.flexibility_at(hz).unwrap()[(i, j)],
            };
            assert!(same_bits(y[k], expected), "{} line {k}", f.id[0]);
        }
    }
    // The model's H is the closed form: K − ω²M + iωC, element (1, 2) at the 10th line.
    let w = 2.0 * std::f64::consts::PI * freqs[9];
    let h12 = complex(&back[5].ordinate)[9];
    let closed = c64::new(
        c.stiffness()[(0, 1)] - w * w * c.mass()[(0, 1)],
        w * c.damping()[(0, 1)],
    );
    assert!(same_bits(h12, closed));
    // Close to the truth too (2 % noise): K_xy = 22.3 kN/m − ω²·0 at 10 Hz-ish.
    assert!((h12.re / 22.3e3 - 1.0).abs() < 0.05, "{h12}");
    // 49 lines 1/1.2 s apart: one even abscissa, record 7's six digits.
    let Abscissa::Even { x0, dx, n } = back[0].abscissa else {
        panic!("uneven abscissa")
    };
    assert_eq!(n, 49);
    assert!((x0 / freqs[0] - 1.0).abs() < 1e-5 && (dx * 1.2 - 1.0).abs() < 1e-5);
    // Coherences: real, function type 6; the ordinary ones equal the FRF stage's.
    let coherence = &back[16 + 2];
    assert_eq!(coherence.function_type, FunctionType::Coherence);
    assert_eq!(coherence.id[0], "Ordinary coherence (2,1)");
    let Ordinate::Real(g) = &coherence.ordinate else {
        panic!("complex coherence")
    };
    for (k, v) in g.iter().enumerate() {
        assert_eq!(
            v.to_bits(),
            frf.ordinary_coherence(k).unwrap()[(1, 0)].to_bits()
        );
    }
    assert_eq!(back[21].id[0], "Multiple coherence (2)");
    assert_eq!(back[21].reference.node, 0);
}

#[test]
fn ascii_export_keeps_thirteen_digits() {
    let id = identified(Window::Rectangular);
    let functions = bearing_ident::export::uff::functions(&id, 1).unwrap();
    let mut text = Vec::new();
    uff::write(&mut text, &functions).unwrap();
    let back = uff::parse(&text, "export.uff").unwrap();
    for (f, g) in functions.iter().take(16).zip(&back) {
        for (a, b) in complex(&f.ordinate).iter().zip(complex(&g.ordinate)) {
            // E20.12: 13 significant digits, a relative error of at most 5e-13 per part.
            assert!((a - b).norm() <= 1e-12 * a.norm(), "{a} {b}");
        }
    }
}

#[test]
fn exponential_window_model_is_evaluated_where_the_data_were() {
    // Under an exponential window the measured H is the system's at s = a + iω; the
    // model's functions are evaluated there, so measured and model agree on noise-free data.
    let records = ImpactTest {
        per_direction: 1,
        ..ImpactTest::seed_rig()
    }
    .run(&seed_rig())
    .unwrap();
    let window = Window::exponential_to(0.05, 1.2);
    let id = Identifier::new(8.0, 49.0)
        .window(window)
        .identify(&records)
        .unwrap();
    let f = bearing_ident::export::uff::functions(&id, 1).unwrap();
    assert!(
        f[0].id[4].starts_with("exp window, decay"),
        "{}",
        f[0].id[4]
    );
    let a = window.decay_per_s().unwrap();
    let c = id.coefficients();
    let hz = id.freqs_hz()[20];
    let s = c64::new(a, 2.0 * std::f64::consts::PI * hz);
    let closed = s * s * c.mass()[(0, 0)] + s * c.damping()[(0, 0)] + c.stiffness()[(0, 0)];
    let (measured, model) = (complex(&f[0].ordinate)[20], complex(&f[4].ordinate)[20]);
    assert!((model - closed).norm() <= 1e-12 * closed.norm());
    assert!(
        (measured - model).norm() < 1e-6 * model.norm(),
        "{measured} {model}"
    );
}

/// The numbers of `key` in a parsed TOML or JSON table, as `f64` bits.
fn bits_toml(table: &toml::Table, key: &str) -> Vec<u64> {
    table[key]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_float().expect("a float").to_bits())
        .collect()
}

/// The numbers of the (nested) array after `"key":` in JSON text, parsed exactly by
/// `f64::from_str` (serde_json's default float parsing may be one unit in the last place off:
/// its `float_roundtrip` feature is not enabled here).
fn json_numbers(text: &str, key: &str) -> Vec<f64> {
    let at = text.find(&format!("\"{key}\":")).expect("key") + key.len() + 3;
    let rest = &text[at..];
    let start = rest.find('[').expect("array");
    let mut depth = 0;
    let end = rest[start..]
        .char_indices()
        .find_map(|(i, c)| {
            depth += i32::from(c == '[') - i32::from(c == ']');
            (depth == 0).then_some(start + i)
        })
        .expect("closed array");
    rest[start..=end]
        .split(|c: char| c == '[' || c == ']' || c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().expect("a number"))
        .collect()
}

fn bits_json(text: &str, key: &str) -> Vec<u64> {
    json_numbers(text, key)
        .iter()
        .map(|v| v.to_bits())
        .collect()
}

const TERMS: [(&str, usize, usize, usize); 12] = [
    ("kxx", 0, 0, 0),
    ("kxy", 0, 0, 1),
    ("kyx", 0, 1, 0),
    ("kyy", 0, 1, 1),
    ("cxx", 1, 0, 0),
    ("cxy", 1, 0, 1),
    ("cyx", 1, 1, 0),
    ("cyy", 1, 1, 1),
    ("mxx", 2, 0, 0),
    ("mxy", 2, 0, 1),
    ("myx", 2, 1, 0),
    ("myy", 2, 1, 1),
];

/// `[K, C, M]` of the coefficients, `(row, col)`.
fn term(c: &Coefficients, block: usize, row: usize, col: usize) -> f64 {
    [c.stiffness(), c.damping(), c.mass()][block][(row, col)]
}

#[test]
fn ross_constant_table_parses_back_to_the_fitted_coefficients() {
    let id = identified(Window::Rectangular);
    let brg = BearingElement::new(&id, 3, "brg1", Table::Constant).unwrap();
    let parsed: toml::Table = brg.to_toml().parse().expect("valid TOML");
    assert_eq!(parsed.len(), 1);
    let t = parsed["BearingElement_brg1"].as_table().unwrap();
    assert_eq!(t["n"].as_integer(), Some(3));
    assert_eq!(t["tag"].as_str(), Some("brg1"));
    let j = brg.to_json();
    let json: serde_json::Value = serde_json::from_str(&j).expect("valid JSON");
    assert_eq!(json["BearingElement_brg1"]["n"].as_u64(), Some(3));
    let two_pi = 2.0 * std::f64::consts::PI;
    let expected_w: Vec<u64> = [8.0, 18.25, 28.5, 38.75, 49.0]
        .iter()
        .map(|f| (two_pi * f).to_bits())
        .collect();
    assert_eq!(bits_toml(t, "frequency"), expected_w);
    assert_eq!(bits_json(&j, "frequency"), expected_w);
    let c = id.coefficients();
    for (key, block, row, col) in TERMS {
        let expected = vec![term(c, block, row, col).to_bits(); 5];
        assert_eq!(bits_toml(t, key), expected, "{key}");
        assert_eq!(bits_json(&j, key), expected, "{key}");
    }
    // Known truth within the noise: the seed rig's K_xx = 146.3 kN/m, C_yy = 131.98 N·s/m.
    let kxx = t["kxx"].as_array().unwrap()[0].as_float().unwrap();
    assert!((kxx / 146.3e3 - 1.0).abs() < 0.01, "{kxx}");
}

#[test]
fn ross_per_frequency_table_holds_every_line() {
    let id = identified(Window::Rectangular);
    let brg = BearingElement::new(&id, 0, "line table", Table::PerFrequency).unwrap();
    let parsed: toml::Table = brg.to_toml().parse().expect("valid TOML");
    let t = parsed["BearingElement_line table"].as_table().unwrap();
    let pf = id.per_frequency().unwrap();
    let w: Vec<u64> = pf
        .freqs_hz()
        .iter()
        .map(|f| (2.0 * std::f64::consts::PI * f).to_bits())
        .collect();
    assert_eq!(bits_toml(t, "frequency"), w);
    let k: Vec<u64> = (0..w.len())
        .map(|p| pf.stiffness(p)[(1, 0)].to_bits())
        .collect();
    assert_eq!(bits_toml(t, "kyx"), k);
    let c: Vec<u64> = (0..w.len())
        .map(|p| pf.damping(p)[(0, 0)].to_bits())
        .collect();
    assert_eq!(bits_toml(t, "cxx"), c);
    let m = id.coefficients().mass()[(1, 1)].to_bits();
    assert_eq!(bits_toml(t, "myy"), vec![m; w.len()]);
}

#[test]
fn ross_refuses_other_than_two_dofs() {
    let c = Coefficients::new(mat![[1.0]], mat![[10.0]], mat![[1e4]]).unwrap();
    let e = BearingElement::constant(&c, Band::new(5.0, 50.0).unwrap(), 0, "b").unwrap_err();
    assert_eq!(e.kind(), "invalid_argument");
    assert!(e.to_string().contains("has 1"), "{e}");
}

// ------------------------------------------------------------------------------------------
// The command line: `identify --uff OUT --ross OUT`.
// ------------------------------------------------------------------------------------------

fn simulate(dir: &std::path::Path, extra: &[&str]) -> Vec<std::path::PathBuf> {
    let out = dir.join("records");
    let status = bin()
        .args(["simulate", "--out"])
        .arg(&out)
        .args(["--impacts", "2"])
        .args(extra)
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    let mut files: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

#[test]
fn cli_writes_uff_and_ross_that_read_back_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &[]);
    let (uff_path, toml_path) = (dir.path().join("out.uff"), dir.path().join("brg.toml"));
    let out = bin()
        .args([
            "identify",
            "--band",
            "8,49",
            "--json",
            "--uff-encoding",
            "binary",
        ])
        .arg("--uff")
        .arg(&uff_path)
        .arg("--ross")
        .arg(&toml_path)
        .args(["--ross-node", "4", "--ross-tag", "b4"])
        .args(&files)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let matrix = |key: &str| {
        let v = json_numbers(&stdout, key);
        mat![[v[0], v[1]], [v[2], v[3]]]
    };
    let coefficients = Coefficients::new(matrix("M"), matrix("C"), matrix("K")).unwrap();
    // ROSS: the printed coefficients, every bit.
    let parsed: toml::Table = std::fs::read_to_string(&toml_path)
        .unwrap()
        .parse()
        .unwrap();
    let t = parsed["BearingElement_b4"].as_table().unwrap();
    assert_eq!(t["n"].as_integer(), Some(4));
    for (key, block, row, col) in TERMS {
        let expected = vec![term(&coefficients, block, row, col).to_bits(); 5];
        assert_eq!(bits_toml(t, key), expected, "{key}");
    }
    // UFF: the model's H at the printed lines is the closed form of the printed M, C, K.
    let functions = uff::read(&uff_path).unwrap();
    assert_eq!(functions.len(), 22);
    let freqs = json_numbers(&stdout, "freqs_hz");
    for (index, f) in functions[4..8].iter().enumerate() {
        let (i, j) = (index / 2, index % 2);
        assert_eq!(f.id[0], format!("Model impedance H({},{})", i + 1, j + 1));
        for (k, &hz) in freqs.iter().enumerate() {
            let expected = coefficients.impedance_at(hz)[(i, j)];
            assert!(same_bits(complex(&f.ordinate)[k], expected), "line {k}");
        }
    }
}

#[test]
fn cli_ross_json_by_extension_and_per_frequency() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &[]);
    let path = dir.path().join("brg.JSON");
    let out = bin()
        .args(["identify", "--band", "8,49", "--per-frequency", "--ross"])
        .arg(&path)
        .args(&files)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let j = &json["BearingElement_brg1"];
    assert_eq!(j["n"].as_u64(), Some(0));
    assert_eq!(j["frequency"].as_array().unwrap().len(), 49);
    // K(ω) of the test system is its K on every line (noise-free simulation).
    for v in j["kyy"].as_array().unwrap() {
        assert!((v.as_f64().unwrap() / 169.1e3 - 1.0).abs() < 1e-5, "{v}");
    }
}

/// A frequency-dependent element model goes to ROSS as its curve: 21 points over the band,
/// each the model's `K(ω)`, `C(ω)` (printed in the JSON's `model.curve` at the lines).
#[test]
fn cli_ross_of_a_frequency_dependent_model_is_its_curve() {
    let dir = tempfile::tempdir().unwrap();
    let files = simulate(dir.path(), &[]);
    let path = dir.path().join("seal.json");
    let out = bin()
        .args([
            "identify", "--band", "8,49", "--json", "--model", "poly:2", "--ross",
        ])
        .arg(&path)
        .args(&files)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let result: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(result["model"]["family"], "poly:2");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let j = &json["BearingElement_brg1"];
    let hz: Vec<f64> = j["frequency"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_f64().unwrap() / (2.0 * std::f64::consts::PI))
        .collect();
    assert_eq!(hz.len(), 21);
    assert!((hz[0] - 8.0).abs() < 1e-9 && (hz[20] - 49.0).abs() < 1e-9);
    // Each point is the model's curve there: between the lines of `model.curve` (1 Hz apart
    // or closer), interpolated linearly, to the curvature of a parabola over a line spacing.
    let curve = &result["model"]["curve"];
    let lines: Vec<f64> = curve["frequency_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_f64().unwrap())
        .collect();
    let at = |key: &str, i: usize, j: usize, f: f64| {
        let k = lines.partition_point(|&l| l < f).clamp(1, lines.len() - 1);
        let (f0, f1) = (lines[k - 1], lines[k]);
        let (v0, v1) = (
            curve[key][k - 1][i][j].as_f64().unwrap(),
            curve[key][k][i][j].as_f64().unwrap(),
        );
        v0 + (v1 - v0) * (f - f0) / (f1 - f0)
    };
    for (p, &f) in hz.iter().enumerate().filter(|(_, f)| **f >= lines[0]) {
        let (k, c) = (at("K", 0, 0, f), at("C", 1, 1, f));
        assert!(
            (j["kxx"][p].as_f64().unwrap() / k - 1.0).abs() < 1e-5,
            "kxx at {f} Hz"
        );
        assert!(
            (j["cyy"][p].as_f64().unwrap() / c - 1.0).abs() < 1e-4,
            "cyy at {f} Hz"
        );
    }
    // The records are of a constant K: the curve stays on it.
    for v in j["kxx"].as_array().unwrap() {
        assert!((v.as_f64().unwrap() / 146.3e3 - 1.0).abs() < 1e-3, "{v}");
    }
}

#[test]
fn cli_ross_names_the_dof_count_of_a_three_dof_result() {
    let dir = tempfile::tempdir().unwrap();
    let three = [
        "--mass",
        "4.7,0,0;0,4.8,0;0,0,4.9",
        "--damping",
        "130,0,0;0,132,0;0,0,128",
        "--stiffness",
        "146300,0,0;0,169100,0;0,0,158000",
    ];
    let files = simulate(dir.path(), &three);
    let out = bin()
        .args([
            "identify", "--band", "8,49", "--json", "--force", "fx,fy,fz", "--disp", "x,y,z",
            "--ross",
        ])
        .arg(dir.path().join("brg.toml"))
        .args(&files)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let failure: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(failure["error"], "invalid_argument");
    let message = failure["message"].as_str().unwrap();
    assert!(message.contains("has 3"), "{message}");
    assert!(!dir.path().join("brg.toml").exists());
}

#[test]
fn cli_refuses_a_per_frequency_ross_table_of_a_baseline_before_work() {
    let out = bin()
        .args([
            "identify",
            "--band",
            "8,49",
            "--per-frequency",
            "--baseline",
            "dry.json",
            "--ross",
            "brg.toml",
            "no-such-file.csv",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--per-frequency and --baseline"),
        "{stderr}"
    );
}
