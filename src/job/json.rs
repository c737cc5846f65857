//! The JSON of an identification run: the library's serialization of the [`Identification`]
//! with the run's own fields ([`Facts`]), as `identify --json` prints it.

use crate::Choice;
use faer::MatRef;
use serde_json::{Map, Value, json as object};

use super::{Outcome, Timings};
use crate::identify::Identification;
use crate::model::{Coefficients, rows};
use crate::per_frequency::PerFrequency;

/// What the JSON of a run says besides the identification: the excitation and how it was
/// decided, the Welch choice, the records, times, a baseline's subtraction, per-line
/// coefficients.
#[derive(Debug, Clone, Copy)]
pub struct Facts<'a> {
    /// `"impact"`, `"random"`, `"periodic"`, `"stepped-sine"` or `"sweep"`.
    pub excitation: &'static str,
    /// Whether the excitation was detected rather than given.
    pub excitation_auto: bool,
    /// Crest factor the excitation was decided by.
    pub crest_factor: f64,
    /// Welch segment length or period, if any.
    pub segment_len: Option<usize>,
    /// How the Welch segment length was chosen from the data, if it was.
    pub welch_choice: Option<crate::excitation::WelchChoice>,
    /// Sampling rate (Hz).
    pub sample_rate: f64,
    /// The record files (or labels), in order.
    pub files: &'a [String],
    /// Wall time per stage of the run; `compute` is the time after the data were in
    /// memory, `read` the time spent reading the record files.
    pub timings: Timings,
    /// System minus baseline: coefficients, standard deviations and where the baseline came
    /// from.
    pub bearing: Option<(&'a Coefficients, Option<&'a Coefficients>, &'a str)>,
    /// Per-line coefficients, when asked for.
    pub per_frequency: Option<&'a PerFrequency>,
    /// The coefficients in dimensionless form, when a clearance was given.
    pub dimensionless: Option<&'a crate::rotor::Dimensionless>,
    /// The stability of a rigid rotor on the element, when a speed or load was given.
    pub stability: Option<&'a crate::rotor::Stability>,
    /// `K(ω)`, `C(ω)` at the excitation frequency equal to the speed, when a speed was given.
    pub synchronous: Option<&'a crate::rotor::Synchronous>,
}

impl Outcome {
    /// The facts of this run for [`json`], with `per_frequency` if given.
    pub fn facts<'a>(&'a self, per_frequency: Option<&'a PerFrequency>) -> Facts<'a> {
        Facts {
            excitation: self.excitation.name(),
            excitation_auto: self.detected,
            crest_factor: self.crest_factor,
            segment_len: self.segment_len,
            welch_choice: self.welch_choice,
            sample_rate: self.sample_rate,
            files: &self.files,
            timings: self.timings,
            bearing: self
                .bearing
                .as_ref()
                .map(|b| (&b.coefficients, b.std_dev.as_ref(), b.source.as_str())),
            per_frequency,
            dimensionless: self.dimensionless(),
            stability: self.stability(),
            synchronous: self.synchronous(),
        }
    }

    /// The JSON of this run, as `identify --json` prints it (with `per_frequency` when
    /// `per_frequency` is true).
    ///
    /// # Errors
    /// [`crate::Error::NonFiniteCoefficient`]-like errors of the per-line coefficients;
    /// serialization errors as [`crate::Error::Io`].
    pub fn to_json(&self, per_frequency: bool) -> crate::Result<Value> {
        let pf = per_frequency
            .then(|| self.identification.per_frequency())
            .transpose()?;
        let io = |e: serde_json::Error| crate::Error::Io {
            path: "JSON".into(),
            message: e.to_string(),
        };
        json(&self.identification, &self.facts(pf.as_ref())).map_err(io)
    }
}

/// The library's serialization of `id` plus the run's own fields: `excitation`,
/// `excitation_auto`, `crest_factor`, `nperseg`, `welch_choice`, `fs`, `n_records`, `files`,
/// `compute_ms`, `timings_ms` (every stage of the run, [`Timings::stages`], and `total`),
/// `bearing` and `per_frequency` when there are; `dimensionless`
/// ([`crate::rotor::Dimensionless`]), `stability` ([`crate::rotor::Stability`]) and
/// `synchronous` ([`crate::rotor::Synchronous`]), null without the conditions they need.
///
/// # Errors
/// Serialization errors.
pub fn json(id: &Identification, f: &Facts<'_>) -> serde_json::Result<Value> {
    let mut v = serde_json::to_value(id)?;
    if let Some(map) = v.as_object_mut() {
        map.insert("excitation".into(), f.excitation.into());
        map.insert("excitation_auto".into(), f.excitation_auto.into());
        map.insert("crest_factor".into(), f.crest_factor.into());
        map.insert("nperseg".into(), f.segment_len.into());
        map.insert("welch_choice".into(), serde_json::to_value(f.welch_choice)?);
        map.insert("fs".into(), f.sample_rate.into());
        map.insert("n_records".into(), f.files.len().into());
        map.insert("files".into(), f.files.to_vec().into());
        map.insert("compute_ms".into(), ms(f.timings.compute).into());
        map.insert("timings_ms".into(), timings_ms(&f.timings));
        if let Some((b, std, source)) = &f.bearing {
            let block = |m: MatRef<'_, f64>| Value::from(rows(m));
            let std_block = |get: Block| std.map(|s| block(get(s)));
            let bearing = object!({
                "baseline": source,
                "M": block(b.mass()),
                "C": block(b.damping()),
                "K": block(b.stiffness()),
                "M_std": std_block(Coefficients::mass),
                "C_std": std_block(Coefficients::damping),
                "K_std": std_block(Coefficients::stiffness),
            });
            map.insert("bearing".into(), bearing);
        }
        if let Some(pf) = &f.per_frequency {
            map.insert("per_frequency".into(), per_frequency_json(pf));
        }
        map.insert(
            "dimensionless".into(),
            serde_json::to_value(f.dimensionless)?,
        );
        map.insert("stability".into(), serde_json::to_value(f.stability)?);
        map.insert("synchronous".into(), serde_json::to_value(f.synchronous)?);
    }
    Ok(v)
}

/// Every stage of the run ([`Timings::stages`]: `read`, `detect`, `welch_choice`, the
/// identification's, `baseline`) and `total` (reading plus compute), in milliseconds.
fn timings_ms(t: &Timings) -> Value {
    let mut map = Map::new();
    for (name, d) in t.stages() {
        map.insert(name.into(), ms(d).into());
    }
    map.insert("total".into(), ms(t.total()).into());
    Value::Object(map)
}

/// `d` in milliseconds.
fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// One object per line: `freq_hz`, `K`, `C` (rows), `K_std`, `C_std` (null without an FRF
/// variance), and for n = 2 `K_eff`, `C_eff`, `K_eff_std`, `C_eff_std`.
fn per_frequency_json(pf: &PerFrequency) -> Value {
    let effective = pf.effective();
    let lines: Vec<Value> = pf
        .freqs_hz()
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            let mut line = object!({
                "freq_hz": f,
                "K": rows(pf.stiffness(k)),
                "C": rows(pf.damping(k)),
                "K_std": pf.stiffness_std(k).map(rows),
                "C_std": pf.damping_std(k).map(rows),
            });
            if let (Some(e), Some(map)) = (effective.as_ref().map(|e| e[k]), line.as_object_mut()) {
                map.insert("K_eff".into(), e.stiffness.into());
                map.insert("C_eff".into(), e.damping.into());
                map.insert("K_eff_std".into(), e.stiffness_std.into());
                map.insert("C_eff_std".into(), e.damping_std.into());
            }
            line
        })
        .collect();
    lines.into()
}

/// Picks one block (M, C or K) out of a coefficient set.
type Block = fn(&Coefficients) -> MatRef<'_, f64>;
