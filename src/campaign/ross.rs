//! A campaign's bearing as one ROSS 3.x bearing element over rotor speed: a 1-D table of the
//! points' constant coefficients along the `speed` axis, or, with per-line coefficients, a
//! 2-D table over `speed × frequency` (shape `(len(speed), len(frequency))`, as ROSS's
//! `BearingElement(..., speed=[...], frequency=[...])` takes it).

use std::fmt::Write as _;

use serde_json::Value as Json;

use super::point::Value;
use super::run::Campaign;
use crate::error::{Error, Result, excerpt};
use crate::export::ross::{Matrix2, array, quoted, two};

/// A bearing element tabulated over rotor speed (rad/s), and over whirl frequency (rad/s)
/// when built from per-line coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedTable {
    /// The ROSS node.
    pub node: usize,
    /// The element's tag.
    pub tag: String,
    /// The rotor speed axis (rad/s), strictly increasing.
    pub speed_rad_s: Vec<f64>,
    /// The whirl frequency axis (rad/s) of a 2-D table.
    pub frequency_rad_s: Option<Vec<f64>>,
    /// The points' names, in speed order.
    pub points: Vec<String>,
    /// `K` per speed, then per frequency (one entry for a 1-D table).
    pub stiffness: Vec<Vec<Matrix2>>,
    /// `C`, as `stiffness`.
    pub damping: Vec<Vec<Matrix2>>,
    /// `M`, as `stiffness` (the fitted, constant over frequency).
    pub mass: Vec<Vec<Matrix2>>,
    /// Whether a 1-D table holds the synchronous `K`, `C` (each point's `K(ω)`, `C(ω)` at `ω`
    /// equal to its speed, [`crate::job::Outcome::synchronous`]) rather than the constant
    /// fit's.
    pub synchronous: bool,
}

fn bad(option: &'static str, message: String) -> Error {
    Error::InvalidOption { option, message }
}

/// Rows of a 2 × 2 block at `key` of a per-line JSON object.
fn two_json(line: &Json, key: &str) -> Option<Matrix2> {
    let rows = line.get(key)?.as_array()?;
    let r = |i: usize| -> Option<[f64; 2]> {
        let row = rows.get(i)?.as_array()?;
        Some([row.first()?.as_f64()?, row.get(1)?.as_f64()?])
    };
    Some([r(0)?, r(1)?])
}

fn minus(a: Matrix2, b: Matrix2) -> Matrix2 {
    [
        [a[0][0] - b[0][0], a[0][1] - b[0][1]],
        [a[1][0] - b[1][0], a[1][1] - b[1][1]],
    ]
}

impl Campaign {
    /// The bearing as a ROSS element over the `speed` condition ([`SpeedTable`]), at ROSS node `node` with tag `tag`, from the points whose
    /// conditions equal `slice` (`(name, value)` pairs, e.g. `load = 200`), less those that
    /// are another chosen point's baseline (the structure). Each point gives its bearing's
    /// own coefficients when it has a baseline, else the system's; a mix of both is refused.
    /// When every point has synchronous coefficients (its speed within its lines, or an
    /// element model fitted; JSON `synchronous`), the 1-D table's `K`, `C` at each speed are
    /// the point's at that speed and `M` the fitted one, so that ROSS's `K − Ω²M + iΩC` at the
    /// speed is the measured impedance there ([`SpeedTable::synchronous`]); otherwise every
    /// point's constant `K`, `C`, `M`. With
    /// per-line coefficients ([`super::RunOptions::per_frequency`]) the table is 2-D, each
    /// point's `K(ω)`, `C(ω)` less its baseline's at the same lines.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (`ross`) without a `speed` condition in rpm, rad/s or Hz,
    /// for a point without a speed, two points at one speed, a point that failed, a
    /// bearing other than 2 × 2, no point left, or per-line tables on different lines;
    /// (`ross-where`) for a slice naming no condition, or points that still differ in
    /// another condition.
    pub fn ross_speed_table(
        &self,
        node: usize,
        tag: &str,
        slice: &[(String, Value)],
    ) -> Result<SpeedTable> {
        let conditions = &self.plan.conditions;
        let speed = conditions
            .iter()
            .position(|c| c.name == "speed" && c.unit.to_rad_per_s(1.0).is_some())
            .ok_or_else(|| {
                bad(
                    "ross",
                    "a ROSS speed table needs a condition `speed` in rpm, rad/s or Hz".into(),
                )
            })?;
        for (name, _) in slice {
            if !conditions.iter().any(|c| &c.name == name) {
                return Err(bad(
                    "ross-where",
                    format!(
                        "--ross-where `{}`: no condition of that name",
                        excerpt(name)
                    ),
                ));
            }
        }
        let chosen: Vec<usize> = (0..self.points.len())
            .filter(|&i| {
                slice.iter().all(|(name, v)| {
                    let c = conditions
                        .iter()
                        .position(|c| &c.name == name)
                        .expect("checked");
                    self.points[i].values[c].as_ref() == Some(v)
                })
            })
            .collect();
        // A point that is another's baseline is the structure, not the bearing: left out.
        let baselines: Vec<usize> = chosen
            .iter()
            .filter_map(|&i| self.plan.points[i].baseline)
            .collect();
        let chosen: Vec<usize> = chosen
            .into_iter()
            .filter(|i| !baselines.contains(i))
            .collect();
        if chosen.is_empty() {
            return Err(bad("ross", "no point is left for the ROSS table".into()));
        }
        let with_baseline = |i: &usize| self.plan.points[*i].baseline.is_some();
        if chosen.iter().any(with_baseline) && !chosen.iter().all(with_baseline) {
            let (a, b) = (
                chosen.iter().find(|i| with_baseline(i)).expect("one"),
                chosen.iter().find(|i| !with_baseline(i)).expect("one"),
            );
            return Err(bad(
                "ross",
                format!(
                    "point `{}` gives a bearing's own coefficients (less its baseline) and `{}` a \
                     system's: one table cannot hold both; give every point a baseline or none",
                    excerpt(&self.points[*a].name),
                    excerpt(&self.points[*b].name)
                ),
            ));
        }
        for (c, condition) in conditions.iter().enumerate() {
            if c == speed {
                continue;
            }
            let first = &self.points[chosen[0]].values[c];
            if let Some(&i) = chosen.iter().find(|&&i| &self.points[i].values[c] != first) {
                return Err(bad(
                    "ross-where",
                    format!(
                        "points `{}` and `{}` differ in `{}`: pick one slice with --ross-where \
                         {}=VALUE",
                        excerpt(&self.points[chosen[0]].name),
                        excerpt(&self.points[i].name),
                        condition.name,
                        condition.name
                    ),
                ));
            }
        }
        let unit = &conditions[speed].unit;
        let mut rows = Vec::with_capacity(chosen.len());
        for &i in &chosen {
            let p = &self.points[i];
            let fit = p.result.as_ref().map_err(|e| {
                bad(
                    "ross",
                    format!(
                        "point `{}` failed ({}): no coefficients for the ROSS table",
                        excerpt(&p.name),
                        e.kind
                    ),
                )
            })?;
            let value = p.values[speed]
                .as_ref()
                .and_then(Value::number)
                .ok_or_else(|| bad("ross", format!("point `{}` has no speed", excerpt(&p.name))))?;
            let (c, _) = fit.reported();
            if c.dofs() != 2 {
                return Err(bad(
                    "ross",
                    format!(
                        "a ROSS bearing element is 2 × 2; point `{}` has {} degrees of freedom",
                        excerpt(&p.name),
                        c.dofs()
                    ),
                ));
            }
            let omega = unit.to_rad_per_s(value).expect("a speed unit");
            rows.push((omega, i));
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(w) = rows.windows(2).find(|w| w[0].0.total_cmp(&w[1].0).is_eq()) {
            return Err(bad(
                "ross",
                format!(
                    "points `{}` and `{}` are at one speed: the speed axis must increase",
                    excerpt(&self.points[w[0].1].name),
                    excerpt(&self.points[w[1].1].name)
                ),
            ));
        }
        let mut table = SpeedTable {
            node,
            tag: tag.to_owned(),
            speed_rad_s: rows.iter().map(|r| r.0).collect(),
            frequency_rad_s: None,
            points: rows.iter().map(|r| self.points[r.1].name.clone()).collect(),
            stiffness: Vec::new(),
            damping: Vec::new(),
            mass: Vec::new(),
            synchronous: false,
        };
        let synchronous_of = |i: usize| -> Option<(Matrix2, Matrix2)> {
            let fit = self.points[i].result.as_ref().ok()?;
            let sync = fit.json.get("synchronous")?;
            Some((two_json(sync, "K")?, two_json(sync, "C")?))
        };
        table.synchronous =
            !self.per_frequency && rows.iter().all(|&(_, i)| synchronous_of(i).is_some());
        for &(_, i) in &rows {
            let fit = self.points[i].result.as_ref().expect("checked");
            let (c, _) = fit.reported();
            if !self.per_frequency {
                let (k, d) = synchronous_of(i)
                    .filter(|_| table.synchronous)
                    .unwrap_or((two(c.stiffness()), two(c.damping())));
                table.stiffness.push(vec![k]);
                table.damping.push(vec![d]);
                table.mass.push(vec![two(c.mass())]);
                continue;
            }
            let lines = self.lines(i)?;
            let freqs: Vec<f64> = lines.iter().map(|l| l.0).collect();
            match &table.frequency_rad_s {
                None => table.frequency_rad_s = Some(freqs),
                Some(f)
                    if f.len() == freqs.len()
                        && f.iter()
                            .zip(&freqs)
                            .all(|(a, b)| (a - b).abs() <= 1e-9 * a.abs()) => {}
                Some(_) => {
                    return Err(bad(
                        "ross",
                        format!(
                            "point `{}` has other per-line frequencies than `{}`: a 2-D table needs \
                             one frequency axis (the same band and record length)",
                            excerpt(&self.points[i].name),
                            excerpt(&table.points[0])
                        ),
                    ));
                }
            }
            table.stiffness.push(lines.iter().map(|l| l.1).collect());
            table.damping.push(lines.iter().map(|l| l.2).collect());
            table.mass.push(vec![two(c.mass()); lines.len()]);
        }
        Ok(table)
    }

    /// Point `i`'s per-line `(ω, K(ω), C(ω))`, less its baseline point's at the same lines.
    fn lines(&self, i: usize) -> Result<Vec<(f64, Matrix2, Matrix2)>> {
        let read = |i: usize| -> Result<Vec<(f64, Matrix2, Matrix2)>> {
            let p = &self.points[i];
            let missing = || {
                bad(
                    "ross",
                    format!("point `{}` has no per-line coefficients", excerpt(&p.name)),
                )
            };
            let fit = p.result.as_ref().map_err(|_| missing())?;
            let lines = fit
                .json
                .get("per_frequency")
                .and_then(Json::as_array)
                .ok_or_else(missing)?;
            lines
                .iter()
                .map(|l| {
                    let f = l
                        .get("freq_hz")
                        .and_then(Json::as_f64)
                        .ok_or_else(missing)?;
                    Ok((
                        2.0 * std::f64::consts::PI * f,
                        two_json(l, "K").ok_or_else(missing)?,
                        two_json(l, "C").ok_or_else(missing)?,
                    ))
                })
                .collect()
        };
        let mut own = read(i)?;
        if let Some(j) = self.plan.points[i].baseline {
            let dry = read(j)?;
            if dry.len() != own.len() {
                return Err(bad(
                    "ross",
                    format!(
                        "point `{}` and its baseline have other lines",
                        excerpt(&self.points[i].name)
                    ),
                ));
            }
            for (o, d) in own.iter_mut().zip(&dry) {
                o.1 = minus(o.1, d.1);
                o.2 = minus(o.2, d.2);
            }
        }
        if own.len() < crate::export::ross::MIN_POINTS {
            return Err(bad(
                "ross",
                format!(
                    "point `{}` has {} lines; a ROSS table needs at least {}",
                    excerpt(&self.points[i].name),
                    own.len(),
                    crate::export::ross::MIN_POINTS
                ),
            ));
        }
        Ok(own)
    }
}

impl SpeedTable {
    /// The element as a ROSS TOML file: `[BearingElement_<tag>]` with `n`, `tag`, `speed`,
    /// `frequency` (2-D tables only) and the twelve terms, arrays over speed (of arrays over
    /// frequency for 2-D tables). SI units; numbers in their shortest round-trip form.
    pub fn to_toml(&self) -> String {
        let mut s = format!(
            "# bearing-ident {}: ROSS 3.x bearing element over rotor speed; speed and frequency in \
             rad/s, k in N/m, c in N*s/m, m in kg\n# points, in speed order: {}\n",
            env!("CARGO_PKG_VERSION"),
            self.points.join(", ").replace('\n', " ")
        );
        if self.synchronous {
            s.push_str(
                "# k, c: each point's synchronous K(w), C(w) at w equal to its speed; m: the fitted M\n",
            );
        }
        let _ = writeln!(s, "[{}]", quoted(&format!("BearingElement_{}", self.tag)));
        let _ = writeln!(s, "n = {}", self.node);
        let _ = writeln!(s, "tag = {}", quoted(&self.tag));
        let _ = writeln!(s, "speed = {}", array(&self.speed_rad_s, ", "));
        if let Some(f) = &self.frequency_rad_s {
            let _ = writeln!(s, "frequency = {}", array(f, ", "));
        }
        for (letter, table) in [
            ('k', &self.stiffness),
            ('c', &self.damping),
            ('m', &self.mass),
        ] {
            for (row, col, axes) in [(0, 0, "xx"), (0, 1, "xy"), (1, 0, "yx"), (1, 1, "yy")] {
                let per_speed: Vec<Vec<f64>> = table
                    .iter()
                    .map(|by_f| by_f.iter().map(|m| m[row][col]).collect())
                    .collect();
                let text = if self.frequency_rad_s.is_some() {
                    let inner: Vec<String> = per_speed.iter().map(|v| array(v, ", ")).collect();
                    format!("[{}]", inner.join(", "))
                } else {
                    let flat: Vec<f64> = per_speed.iter().map(|v| v[0]).collect();
                    array(&flat, ", ")
                };
                let _ = writeln!(s, "{letter}{axes} = {text}");
            }
        }
        s
    }
}
