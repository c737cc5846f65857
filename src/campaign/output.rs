//! A campaign's outputs: its JSON, the table of coefficients by point as CSV, and the text
//! table for a terminal.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::{Map, Value as Json, json};

use super::baseline::Settings;
use super::point::Value;
use super::run::{Campaign, Fit, PointResult};
use crate::error::{Error, Result};
use crate::model::Coefficients;
use crate::text::{Align, significant as sig};

/// The blocks in the CSV's column order (`k…`, `c…`, `m…`), by letter.
/// One block of a coefficient set.
type Pick = fn(&Coefficients) -> faer::MatRef<'_, f64>;

const BLOCKS: [(char, Pick); 3] = [
    ('k', Coefficients::stiffness),
    ('c', Coefficients::damping),
    ('m', Coefficients::mass),
];

fn value_json(v: &Option<Value>) -> Json {
    match v {
        None => Json::Null,
        Some(Value::Number(x)) => (*x).into(),
        Some(Value::Text(s)) => s.clone().into(),
    }
}

impl Campaign {
    /// The campaign as JSON: `conditions` (name → unit), `reused` (points from the cache)
    /// and `points`, each with `name`, `conditions`, `files`, `M`, `C`, `K` and their
    /// `*_std` (the system's), `bearing` (when it has a baseline: its `M`, `C`, `K`, their
    /// `*_std`, `baseline_point` and `baseline_settings`, `own` or `point`), `expect` (the references
    /// compared: `coefficient`, `reference`, `reference_std`, `value`, `std`, `z`),
    /// `warning_kinds`, `warnings`; or `error: {kind, message}`.
    pub fn to_json(&self) -> Json {
        let conditions: Map<String, Json> = self
            .plan
            .conditions
            .iter()
            .map(|c| (c.name.clone(), c.unit.name().into()))
            .collect();
        let points: Vec<Json> = self.points.iter().map(|p| self.point_json(p)).collect();
        json!({ "conditions": conditions, "reused": self.reused, "points": points })
    }

    fn point_json(&self, p: &PointResult) -> Json {
        let conditions: Map<String, Json> = self
            .plan
            .conditions
            .iter()
            .zip(&p.values)
            .map(|(c, v)| (c.name.clone(), value_json(v)))
            .collect();
        let mut out = json!({ "name": p.name, "conditions": conditions, "files": p.files });
        let map = out.as_object_mut().expect("an object");
        match &p.result {
            Err(e) => {
                map.insert(
                    "error".into(),
                    json!({ "kind": e.kind, "message": e.message }),
                );
            }
            Ok(fit) => {
                for key in [
                    "M",
                    "C",
                    "K",
                    "M_std",
                    "C_std",
                    "K_std",
                    "bearing",
                    "per_frequency",
                    "dimensionless",
                    "stability",
                    "synchronous",
                ] {
                    if let Some(v) = fit.json.get(key) {
                        map.insert(key.into(), v.clone());
                    }
                }
                let expect: Vec<Json> = fit
                    .checks
                    .iter()
                    .map(|c| {
                        json!({
                            "coefficient": c.coefficient.name(),
                            "reference": c.reference,
                            "reference_std": c.reference_std,
                            "value": c.value,
                            "std": c.std,
                            "z": c.z,
                        })
                    })
                    .collect();
                if !expect.is_empty() {
                    map.insert("expect".into(), expect.into());
                }
                map.insert("warning_kinds".into(), fit.warning_kinds.clone().into());
                map.insert("warnings".into(), fit.warnings.clone().into());
                map.insert("reused".into(), fit.reused.into());
            }
        }
        out
    }

    /// Whether some point's identification fitted an element model (a `model` column).
    fn has_models(&self) -> bool {
        self.points
            .iter()
            .any(|p| p.result.as_ref().is_ok_and(|f| family(f).is_some()))
    }

    /// The coefficients by point as CSV: `name`, each condition (`name [unit]`), `baseline`
    /// (the point subtracted, if any), then `kxx, kxx_std, kxy, …, myy, myy_std` (the
    /// bearing's own when there is a baseline, else the system's; empty for a point that
    /// failed or a term without error bar), `model` (the element model's family chosen, when a
    /// point asked for one: `identify = { model = "auto" }`), the synchronous coefficients
    /// `kxx_sync, kxx_sync_std, …, cyy_sync_std` when a point has a speed (`K(ω)`, `C(ω)` at
    /// the speed's frequency: [`crate::job::Outcome::synchronous`]), the stability
    /// `whirl_frequency_ratio, …, c_eff_crossover_hz_std` when a point has a speed or load
    /// ([`crate::rotor::Stability`]), then `status` (`ok`, `warnings`, or `error:KIND`).
    pub fn to_csv(&self) -> String {
        let n = self
            .points
            .iter()
            .find_map(|p| p.result.as_ref().ok().map(|f| f.coefficients.dofs()))
            .unwrap_or(2);
        let axes = super::axis_names(n);
        let mut s = String::from("name");
        for c in &self.plan.conditions {
            let _ = write!(s, ",{} [{}]", csv_field(&c.name), csv_field(c.unit.name()));
        }
        s.push_str(",baseline");
        for (letter, _) in BLOCKS {
            for r in &axes {
                for c in &axes {
                    let _ = write!(s, ",{letter}{r}{c},{letter}{r}{c}_std");
                }
            }
        }
        let models = self.has_models();
        if models {
            s.push_str(",model");
        }
        let synchronous = self.has("synchronous");
        if synchronous {
            for letter in ['k', 'c'] {
                for r in &axes {
                    for c in &axes {
                        let _ = write!(s, ",{letter}{r}{c}_sync,{letter}{r}{c}_sync_std");
                    }
                }
            }
        }
        let stability = self.has("stability");
        if stability {
            s.push_str(&STABILITY_KEYS.map(|k| format!(",{k}")).concat());
        }
        s.push_str(",status\n");
        for (i, p) in self.points.iter().enumerate() {
            s.push_str(&csv_field(&p.name));
            for v in &p.values {
                let _ = write!(
                    s,
                    ",{}",
                    v.as_ref()
                        .map_or(String::new(), |v| csv_field(&v.to_string()))
                );
            }
            let baseline = self.plan.points[i]
                .baseline
                .map_or(String::new(), |j| csv_field(&self.plan.points[j].name));
            let _ = write!(s, ",{baseline}");
            match &p.result {
                Ok(fit) if fit.coefficients.dofs() == n => {
                    let (c, std) = fit.reported();
                    for (_, block) in BLOCKS {
                        for r in 0..n {
                            for col in 0..n {
                                let sd = std.map_or(String::new(), |sd| {
                                    format!("{:?}", block(sd)[(r, col)])
                                });
                                let _ = write!(s, ",{:?},{sd}", block(c)[(r, col)]);
                            }
                        }
                    }
                    if models {
                        let _ = write!(s, ",{}", family(fit).unwrap_or_default());
                    }
                    if synchronous {
                        for field in synchronous_fields(&fit.json, n) {
                            let _ = write!(s, ",{field}");
                        }
                    }
                    if stability {
                        for key in STABILITY_KEYS {
                            let v = fit.json.get("stability").and_then(|x| x.get(key));
                            let field = v.and_then(Json::as_f64).map(|x| format!("{x:?}"));
                            let _ = write!(s, ",{}", field.unwrap_or_default());
                        }
                    }
                    let status = if fit.warning_kinds.is_empty() {
                        "ok"
                    } else {
                        "warnings"
                    };
                    let _ = writeln!(s, ",{status}");
                }
                other => {
                    let extra = usize::from(models)
                        + usize::from(synchronous) * 4 * n * n
                        + usize::from(stability) * STABILITY_KEYS.len();
                    s.push_str(&",".repeat(6 * n * n + extra));
                    let status = match other {
                        Err(e) => format!("error:{}", e.kind),
                        Ok(_) => "error:inconsistent_records".to_owned(),
                    };
                    let _ = writeln!(s, ",{status}");
                }
            }
        }
        s
    }

    /// Writes `coefficients.csv`, `campaign.json` and each identified point's JSON
    /// (`NAME.json`, as `identify --json` prints it) into `dir`, made if missing.
    ///
    /// # Errors
    /// [`Error::Io`] naming the file that cannot be written.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let io = |path: &Path| {
            let path = path.display().to_string();
            move |e: std::io::Error| Error::Io {
                path: crate::error::excerpt(&path),
                message: e.to_string(),
            }
        };
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let csv = dir.join("coefficients.csv");
        std::fs::write(&csv, self.to_csv()).map_err(io(&csv))?;
        let all = dir.join("campaign.json");
        let text = serde_json::to_string_pretty(&self.to_json()).unwrap_or_default();
        std::fs::write(&all, text + "\n").map_err(io(&all))?;
        for p in &self.points {
            if let Ok(fit) = &p.result {
                let path = dir.join(json_file_name(&p.name));
                let text = serde_json::to_string_pretty(&fit.json).unwrap_or_default();
                std::fs::write(&path, text + "\n").map_err(io(&path))?;
            }
        }
        Ok(())
    }

    /// The text table: one row per point with its conditions, its baseline point when a plan
    /// has baselines (`dry*`: that point's files identified again at this point's settings),
    /// the element model's family when a point asked for one, the diagonal coefficients `± σ` (the bearing's own when it has a baseline),
    /// the diagonal synchronous coefficients and the whirl-frequency ratio and threshold speed
    /// of a rigid rotor when points have a speed, and its
    /// warning kinds or error, split into blocks of whole coefficient groups when wider than
    /// [`TABLE_WIDTH`](crate::text::TABLE_WIDTH); then, under `warnings`, each point's
    /// warnings with their sentences (`dry: reference_mismatch: M_xx = … is +6.8 σ from the
    /// reference …`).
    pub fn to_table(&self) -> String {
        let mut header: Vec<String> = vec!["point".into()];
        header.extend(
            self.plan
                .conditions
                .iter()
                .map(|c| format!("{} [{}]", c.name, c.unit.name())),
        );
        let baselines = self.plan.points.iter().any(|p| p.baseline.is_some());
        if baselines {
            header.push("baseline".into());
        }
        let models = self.has_models();
        if models {
            header.push("model".into());
        }
        let mut again = false;
        let n = self
            .points
            .iter()
            .find_map(|p| p.result.as_ref().ok().map(|f| f.coefficients.dofs()))
            .unwrap_or(0);
        let axes = super::axis_names(n);
        for (letter, unit) in [('K', "N/m"), ('C', "N·s/m"), ('M', "kg")] {
            for a in &axes {
                header.push(format!("{letter}_{a}{a} [{unit}]"));
            }
        }
        let synchronous = self.has("synchronous");
        if synchronous {
            for (letter, unit) in [('K', "N/m"), ('C', "N·s/m")] {
                for a in &axes {
                    header.push(format!("{letter}_{a}{a} sync [{unit}]"));
                }
            }
        }
        let stability = self.has("stability");
        if stability {
            header.push("whirl ratio".into());
            header.push("threshold [rpm]".into());
        }
        header.push("warnings".into());
        let mut rows_out = vec![header];
        for (p, planned) in self.points.iter().zip(&self.plan.points) {
            let mut row = vec![p.name.clone()];
            row.extend(
                p.values
                    .iter()
                    .map(|v| v.as_ref().map_or("-".into(), Value::to_string)),
            );
            if baselines {
                row.push(match planned.baseline {
                    None => "-".into(),
                    Some(j) => {
                        let name = &self.plan.points[j].name;
                        let settings = p.result.as_ref().ok().and_then(|f| Settings::of(&f.json));
                        if settings == Some(Settings::Point) {
                            again = true;
                            format!("{name}*")
                        } else {
                            name.clone()
                        }
                    }
                });
            }
            if models {
                let chosen = p.result.as_ref().ok().and_then(family);
                row.push(chosen.unwrap_or_else(|| "-".into()));
            }
            match &p.result {
                Ok(fit) => {
                    row.extend(diagonal(fit, n));
                    if synchronous {
                        row.extend(synchronous_diagonal(&fit.json, n));
                    }
                    if stability {
                        row.extend(stability_cells(&fit.json));
                    }
                    row.push(if fit.warning_kinds.is_empty() {
                        "-".into()
                    } else {
                        fit.warning_kinds.join(",")
                    });
                }
                Err(e) => {
                    let extra = usize::from(synchronous) * 2 * n + usize::from(stability) * 2;
                    row.extend(std::iter::repeat_n("-".to_owned(), 3 * n + extra));
                    row.push(format!("error {}: {}", e.kind, e.message));
                }
            }
            rows_out.push(row);
        }
        let mut groups = vec![n, n, n];
        if synchronous {
            groups.extend([n, n]);
        }
        if stability {
            groups.push(2);
        }
        groups.push(1);
        let keys = rows_out[0].len() - groups.iter().sum::<usize>();
        let mut s = crate::text::table(&rows_out, keys, &groups, Align::Left, 0);
        if again {
            let _ = writeln!(
                s,
                "* the baseline point's files identified again at this point's settings"
            );
        }
        if self.reused > 0 {
            let _ = writeln!(
                s,
                "{} of {} points reused from the cache",
                self.reused,
                self.points.len()
            );
        }
        // What each warning kind of the table says, point by point.
        let mut said = false;
        for p in &self.points {
            let Ok(fit) = &p.result else { continue };
            for (kind, sentence) in fit.warning_kinds.iter().zip(&fit.warnings) {
                if !said {
                    let _ = writeln!(s, "\nwarnings");
                    said = true;
                }
                let _ = writeln!(s, "  {}: {kind}: {sentence}", p.name);
            }
        }
        s
    }
}

/// The family of the element model a point's identification chose (`model.family` of its
/// JSON), if it asked for one.
fn family(fit: &Fit) -> Option<String> {
    let family = fit.json.get("model")?.get("family")?.as_str()?;
    Some(family.to_owned())
}

/// The stability values of the CSV, by their JSON names.
const STABILITY_KEYS: [&str; 6] = [
    "whirl_frequency_ratio",
    "whirl_frequency_ratio_std",
    "threshold_speed_rpm",
    "threshold_speed_rpm_std",
    "c_eff_crossover_hz",
    "c_eff_crossover_hz_std",
];

impl Campaign {
    /// Whether some point's JSON has a non-null `key`.
    fn has(&self, key: &str) -> bool {
        self.points.iter().any(|p| {
            p.result
                .as_ref()
                .is_ok_and(|f| f.json.get(key).is_some_and(|v| !v.is_null()))
        })
    }
}

/// The `n × n` matrix `key` of a JSON object, if it has one.
fn json_matrix(v: Option<&Json>, key: &str, n: usize) -> Option<Vec<Vec<f64>>> {
    let rows: Vec<Vec<f64>> = serde_json::from_value(v?.get(key)?.clone()).ok()?;
    (rows.len() == n && rows.iter().all(|r| r.len() == n)).then_some(rows)
}

/// `kxx_sync, kxx_sync_std, …, cyy_sync_std` of a point's `synchronous` (empty fields
/// without).
fn synchronous_fields(json: &Json, n: usize) -> Vec<String> {
    let sync = json.get("synchronous");
    let mut out = Vec::with_capacity(4 * n * n);
    for key in ["K", "C"] {
        let (v, sd) = (
            json_matrix(sync, key, n),
            json_matrix(sync, &format!("{key}_std"), n),
        );
        for r in 0..n {
            for c in 0..n {
                let field = |m: &Option<Vec<Vec<f64>>>| {
                    m.as_ref()
                        .map_or(String::new(), |m| format!("{:?}", m[r][c]))
                };
                out.push(field(&v));
                out.push(field(&sd));
            }
        }
    }
    out
}

/// `value ± σ` of the diagonal synchronous `K`, `C` (`-` without).
fn synchronous_diagonal(json: &Json, n: usize) -> Vec<String> {
    let sync = json.get("synchronous");
    let mut out = Vec::with_capacity(2 * n);
    for key in ["K", "C"] {
        let (v, sd) = (
            json_matrix(sync, key, n),
            json_matrix(sync, &format!("{key}_std"), n),
        );
        for i in 0..n {
            out.push(match (&v, &sd) {
                (Some(v), Some(sd)) => format!("{} ± {}", sig(v[i][i], 4), sig(sd[i][i], 2)),
                (Some(v), None) => sig(v[i][i], 4),
                _ => "-".into(),
            });
        }
    }
    out
}

/// The whirl-frequency ratio and threshold speed `± σ` of a point's `stability` (`-` where
/// they do not apply).
fn stability_cells(json: &Json) -> [String; 2] {
    let s = json.get("stability");
    let cell = |key: &str, digits: usize| {
        let get = |k: &str| s.and_then(|s| s.get(k)).and_then(Json::as_f64);
        match (get(key), get(&format!("{key}_std"))) {
            (Some(v), Some(sd)) => format!("{} ± {}", sig(v, digits), sig(sd, 2)),
            (Some(v), None) => sig(v, digits),
            _ => "-".into(),
        }
    };
    [
        cell("whirl_frequency_ratio", 3),
        cell("threshold_speed_rpm", 4),
    ]
}

/// `value ± σ` of the diagonal terms of K, C, M (the reported set).
fn diagonal(fit: &Fit, n: usize) -> Vec<String> {
    let (c, std) = fit.reported();
    if c.dofs() != n {
        return vec!["-".into(); 3 * n];
    }
    let mut out = Vec::with_capacity(3 * n);
    for block in [
        Coefficients::stiffness,
        Coefficients::damping,
        Coefficients::mass,
    ] {
        for i in 0..n {
            let v = block(c)[(i, i)];
            out.push(match std {
                Some(sd) => format!("{} ± {}", sig(v, 4), sig(block(sd)[(i, i)], 2)),
                None => sig(v, 4),
            });
        }
    }
    out
}

/// A CSV field, quoted when it holds a comma, quote or line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// The file of a point's JSON in `--out`: its name with characters other than letters,
/// digits, `-`, `_` and `.` as `_`, and `.json`.
///
/// # Examples
/// ```
/// use bearing_ident::campaign::json_file_name;
/// assert_eq!(json_file_name("oil 3000/a"), "oil_3000_a.json");
/// assert_eq!(json_file_name(".."), "_...json");
/// ```
pub fn json_file_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with('.') {
        format!("_{s}.json")
    } else {
        format!("{s}.json")
    }
}
