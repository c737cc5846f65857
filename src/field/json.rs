//! Edge (feature `json`): the rotor model and the tests as JSON ([`RotorModel::from_json`],
//! [`FieldTests::from_json`]).

use crate::error::FieldError;
use faer::{Mat, c64};
use serde_json::{Value, json};

use super::inputs::{FieldTests, Imbalance, Probe, Response, Run};
use super::model::{BearingSite, Direction, RotorModel};
use super::result::FieldIdentification;
use crate::error::{Error, Result, excerpt};

fn bad(message: impl AsRef<str>) -> Error {
    Error::Field(FieldError::Input {
        message: excerpt(message.as_ref()),
    })
}

/// Parses `text`, telling NaN and infinite literals (`NaN`, `Infinity`, numbers past f64), which
/// JSON does not have but some writers produce, from other syntax errors.
fn parse(text: &str, what: &str) -> Result<Value> {
    // A UTF-8 byte order mark, as some editors write, is skipped as the CSV reader skips it.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    serde_json::from_str(text).map_err(|e| {
        let line = text.lines().nth(e.line().saturating_sub(1)).unwrap_or("");
        let at = e.column().saturating_sub(1);
        let near: String = line.chars().skip(at.saturating_sub(1)).take(10).collect();
        let literal = ["NaN", "Infinity", "-Infinity", "nan", "inf"]
            .iter()
            .any(|t| near.contains(t));
        if literal || e.to_string().contains("out of range") {
            Error::Field(FieldError::NonFinite {
                what: format!(
                    "{what}: a value at line {}, column {}",
                    e.line(),
                    e.column()
                ),
            })
        } else {
            bad(format!("{what}: {e}"))
        }
    })
}

/// A finite number at `v`, naming `what` in the error: null is a non-finite value (the way many
/// writers spell NaN).
fn number(v: Option<&Value>, what: &dyn Fn() -> String) -> Result<f64> {
    match v {
        Some(Value::Number(n)) => n
            .as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| Error::Field(FieldError::NonFinite { what: what() })),
        Some(Value::Null) => Err(Error::Field(FieldError::NonFinite { what: what() })),
        Some(other) => Err(bad(format!("{}: expected a number, got {other}", what()))),
        None => Err(bad(format!("{} is missing", what()))),
    }
}

fn index(v: Option<&Value>, what: &dyn Fn() -> String) -> Result<usize> {
    match v {
        Some(Value::Number(n)) => n
            .as_u64()
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| bad(format!("{}: expected a non-negative integer", what()))),
        Some(other) => Err(bad(format!(
            "{}: expected a non-negative integer, got {other}",
            what()
        ))),
        None => Err(bad(format!("{} is missing", what()))),
    }
}

fn text<'a>(v: Option<&'a Value>, what: &dyn Fn() -> String) -> Result<&'a str> {
    match v {
        Some(Value::String(s)) => Ok(s),
        Some(other) => Err(bad(format!("{}: expected a string, got {other}", what()))),
        None => Err(bad(format!("{} is missing", what()))),
    }
}

fn matrix(v: &Value, key: &str) -> Result<Mat<f64>> {
    let rows = v
        .as_array()
        .ok_or_else(|| bad(format!("`{key}` must be a list of rows")))?;
    let n = rows.len();
    let mut m = Mat::zeros(n, n);
    for (i, row) in rows.iter().enumerate() {
        let row = row
            .as_array()
            .ok_or_else(|| bad(format!("`{key}` row {i} is not a list")))?;
        if row.len() != n {
            return Err(bad(format!(
                "`{key}` row {i} has {} entries; a square matrix of {n} rows needs {n}",
                row.len()
            )));
        }
        for (j, x) in row.iter().enumerate() {
            m[(i, j)] = number(Some(x), &|| format!("{key}[{i}][{j}]"))?;
        }
    }
    Ok(m)
}

impl RotorModel {
    /// A rotor model from JSON: `{"dof_per_node": 6, "dof_names": ["x","y","z","alpha","beta",
    /// "theta"], "M": [[…]], "K": [[…]], "G": [[…]], "C": [[…]] or null or absent,
    /// "bearings": [{"tag": "brg0", "node": 0}, …]}` (SI units; matrices as lists of rows).
    ///
    /// # Errors
    /// [`FieldError::Input`] for text that is not JSON, a missing or mistyped key, or a model
    /// [`RotorModel::new`] refuses; [`FieldError::NonFinite`] for NaN, infinite or null
    /// entries.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::field::RotorModel;
    /// let rotor = RotorModel::from_json(r#"{"dof_per_node": 2, "dof_names": ["x", "y"],
    ///     "M": [[2, 0], [0, 2]], "K": [[0, 0], [0, 0]], "G": [[0, 0], [0, 0]],
    ///     "bearings": [{"tag": "brg0", "node": 0}]}"#)?;
    /// assert_eq!(rotor.dynamic_stiffness(10.0)[(1, 1)].re, -200.0);
    /// let e = RotorModel::from_json(r#"{"dof_per_node": 2}"#).unwrap_err();
    /// assert_eq!(e.kind(), "invalid_input");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_json(text_in: &str) -> Result<RotorModel> {
        let v = parse(text_in, "rotor model")?;
        if !v.is_object() {
            return Err(bad("the rotor model must be a JSON object"));
        }
        let dof_per_node = index(v.get("dof_per_node"), &|| "`dof_per_node`".into())?;
        let names = v
            .get("dof_names")
            .and_then(Value::as_array)
            .ok_or_else(|| bad("`dof_names` must be a list of strings"))?
            .iter()
            .enumerate()
            .map(|(i, s)| text(Some(s), &|| format!("dof_names[{i}]")).map(str::to_owned))
            .collect::<Result<Vec<String>>>()?;
        let get = |key: &str| v.get(key).ok_or_else(|| bad(format!("`{key}` is missing")));
        let m = matrix(get("M")?, "M")?;
        let k = matrix(get("K")?, "K")?;
        let g = matrix(get("G")?, "G")?;
        let c = match v.get("C") {
            None | Some(Value::Null) => None,
            Some(c) => Some(matrix(c, "C")?),
        };
        let bearings = get("bearings")?
            .as_array()
            .ok_or_else(|| bad("`bearings` must be a list"))?
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let tag = text(b.get("tag"), &|| format!("bearings[{i}].tag"))?;
                let node = index(b.get("node"), &|| format!("bearings[{i}].node"))?;
                Ok(BearingSite::new(tag, node))
            })
            .collect::<Result<Vec<_>>>()?;
        RotorModel::new(dof_per_node, names, m, k, g, c, bearings)
    }
}

impl FieldTests {
    /// Tests from JSON: `{"imbalances": {"1": [{"node": 3, "magnitude_kg_m": 1e-4,
    /// "phase_rad": 0.0}, …], "2": […]}, "responses": [{"speed_rad_s": 100.0, "test":
    /// "baseline" | "1" | "2", "node": 1, "dir": "x" | "y", "re": …, "im": …, "std": …}, …]}`.
    /// `imbalances` lists only the added masses; responses of tests `1` and `2` are totals;
    /// `std` (optional) is the standard deviation of each of `re` and `im` (m); several
    /// responses with the same speed, test, node and direction are repeats.
    ///
    /// # Errors
    /// [`FieldError::Input`] for text that is not JSON, a missing or mistyped key, tests other
    /// than exactly `1` and `2`, an unknown run or direction; [`FieldError::NonFinite`] for NaN,
    /// infinite or null numbers.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::field::FieldTests;
    /// let t = FieldTests::from_json(r#"{"imbalances": {"1": [{"node": 0, "magnitude_kg_m": 1e-4,
    ///     "phase_rad": 0}], "2": [{"node": 1, "magnitude_kg_m": 1e-4, "phase_rad": 0}]},
    ///     "responses": [{"speed_rad_s": 100, "test": "1", "node": 0, "dir": "y",
    ///     "re": 1e-6, "im": 0}]}"#)?;
    /// assert_eq!(t.responses[0].value.re, 1e-6);
    /// let e = FieldTests::from_json(r#"{"imbalances": {}, "responses": []}"#).unwrap_err();
    /// assert_eq!(e.kind(), "invalid_input");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_json(text_in: &str) -> Result<FieldTests> {
        let v = parse(text_in, "tests")?;
        let sets = v
            .get("imbalances")
            .and_then(Value::as_object)
            .ok_or_else(|| bad("`imbalances` must be an object with keys \"1\" and \"2\""))?;
        if sets.len() != 2 || !sets.contains_key("1") || !sets.contains_key("2") {
            return Err(bad(
                "`imbalances` must list exactly two tests, keys \"1\" and \"2\"",
            ));
        }
        let set = |key: &str| -> Result<Vec<Imbalance>> {
            sets[key]
                .as_array()
                .ok_or_else(|| bad(format!("imbalances[\"{key}\"] must be a list")))?
                .iter()
                .enumerate()
                .map(|(i, u)| {
                    let at = |f: &'static str| move || format!("imbalances[\"{key}\"][{i}].{f}");
                    Ok(Imbalance {
                        node: index(u.get("node"), &at("node"))?,
                        magnitude_kg_m: number(u.get("magnitude_kg_m"), &at("magnitude_kg_m"))?,
                        phase_rad: number(u.get("phase_rad"), &at("phase_rad"))?,
                    })
                })
                .collect()
        };
        let imbalances = [set("1")?, set("2")?];
        let responses = v
            .get("responses")
            .and_then(Value::as_array)
            .ok_or_else(|| bad("`responses` must be a list"))?
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let at = |f: &'static str| move || format!("responses[{i}].{f}");
                let run = match text(r.get("test"), &at("test"))? {
                    "baseline" => Run::Baseline,
                    "1" => Run::First,
                    "2" => Run::Second,
                    other => {
                        return Err(bad(format!(
                            "responses[{i}].test `{}` is not \"baseline\", \"1\" or \"2\"",
                            excerpt(other)
                        )));
                    }
                };
                let dir: Direction = text(r.get("dir"), &at("dir"))?
                    .parse()
                    .map_err(|e: Error| bad(format!("responses[{i}]: {e}")))?;
                let std = match r.get("std") {
                    None => None,
                    Some(s) => Some(number(Some(s), &at("std"))?),
                };
                Ok(Response {
                    speed_rad_s: number(r.get("speed_rad_s"), &at("speed_rad_s"))?,
                    run,
                    probe: Probe {
                        node: index(r.get("node"), &at("node"))?,
                        dir,
                    },
                    value: c64::new(
                        number(r.get("re"), &at("re"))?,
                        number(r.get("im"), &at("im"))?,
                    ),
                    std,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(FieldTests {
            imbalances,
            responses,
        })
    }
}

/// A 2×2 matrix as rows, or null.
fn matrix_out(m: Option<[[f64; 2]; 2]>) -> Value {
    m.map_or(Value::Null, |m| json!(m))
}

/// A finite number, or null (JSON has no ∞).
fn finite(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

impl FieldIdentification {
    /// The result as `bearing-ident field --json` prints it: `speeds_rad_s`, per bearing
    /// (`bearings`) its `tag`, `node`, `K`, `C`, `K_std`, `C_std` per speed (rows, null where the
    /// pair is singular), `condition_number`, `noise_gain` and the constant fit `fit`
    /// (`K`, `C`, `M`, their `*_std`, `speeds`); `measured` probes, `model_residual`,
    /// `residual_ratio`, `pinned_critical_speeds_rad_s`, `mass_sum` (`M_sum_kg`, `M_sum_std_kg`,
    /// `rotor_mass_kg`, each `[x, y]`, or null; see [`MassSum`](super::MassSum)), `compute_ms` (given), `warnings` and
    /// `warning_kinds`. Numbers that are not finite are null.
    pub fn to_json(&self, compute_ms: f64) -> Value {
        let id = self;
        let fits = super::fit_constant(id);
        let bearings: Vec<Value> = id
        .bearings()
        .iter()
        .zip(&fits)
        .map(|(b, fit)| {
            let per = |f: &dyn Fn(&super::SpeedCoefficients) -> Option<[[f64; 2]; 2]>| {
                b.coefficients
                    .iter()
                    .map(|c| matrix_out(c.as_ref().and_then(f)))
                    .collect::<Vec<Value>>()
            };
            json!({
                "tag": b.tag,
                "node": b.node,
                "K": per(&|c| Some(c.stiffness)),
                "C": per(&|c| Some(c.damping)),
                "K_std": per(&|c| c.stiffness_std),
                "C_std": per(&|c| c.damping_std),
                "condition_number": b.condition_number.iter().map(|&c| finite(c)).collect::<Vec<_>>(),
                "noise_gain": b.coefficients.iter().map(|c| c.map_or(Value::Null, |c| finite(c.noise_gain))).collect::<Vec<_>>(),
                "fit": fit.map(|f| json!({
                    "K": f.stiffness, "C": f.damping, "M": f.mass, "speeds": f.speeds,
                    "K_std": f.stiffness_std, "C_std": f.damping_std, "M_std": f.mass_std
                })),
            })
        })
        .collect();
        let measured: Vec<Value> = id
            .probes()
            .iter()
            .map(|p| json!({"node": p.node, "dir": p.dir.name()}))
            .collect();
        json!({
            "speeds_rad_s": id.speeds_rad_s(),
            "bearings": bearings,
            "measured": measured,
            "model_residual": id.model_residual().iter().map(|r| r.map_or(Value::Null, finite)).collect::<Vec<_>>(),
            "residual_ratio": id.residual_ratio().iter().map(|r| r.map_or(Value::Null, finite)).collect::<Vec<_>>(),
            "pinned_critical_speeds_rad_s": id.pinned_critical_speeds(),
            "mass_sum": id.mass_sum().map(|s| json!({
                "M_sum_kg": s.sum.map(finite), "M_sum_std_kg": s.sum_std.map(finite),
                "rotor_mass_kg": s.rotor_mass.map(finite),
            })),
            "compute_ms": compute_ms,
            "warnings": id.warnings().iter().map(ToString::to_string).collect::<Vec<_>>(),
            "warning_kinds": id.warnings().iter().map(|w| w.kind()).collect::<Vec<_>>(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nan_literals_are_non_finite_and_other_syntax_is_invalid() {
        let e = FieldTests::from_json(
            r#"{"imbalances": {"1": [], "2": []}, "responses": [{"re": NaN}]}"#,
        )
        .unwrap_err();
        assert_eq!(e.kind(), "non_finite", "{e}");
        let e = FieldTests::from_json(r#"{"imbalances": 1e999}"#).unwrap_err();
        assert_eq!(e.kind(), "non_finite", "{e}");
        let e = FieldTests::from_json(r#"{"imbalances": [}"#).unwrap_err();
        assert_eq!(e.kind(), "invalid_input", "{e}");
        let e = RotorModel::from_json(
            r#"{"dof_per_node": 2, "dof_names": ["x", "y"],
            "M": [[1, 0], [0, null]], "K": [[0, 0], [0, 0]], "G": [[0, 0], [0, 0]],
            "bearings": [{"tag": "b", "node": 0}]}"#,
        )
        .unwrap_err();
        assert_eq!(e.kind(), "non_finite", "{e}");
        assert!(e.to_string().contains("M[1][1]"), "{e}");
    }
}
