//! What a point is identified with: the `identify` options a plan can set, a point's
//! [`Options`] and [`Channels`] from the plan's shared settings and its own, and the files its
//! patterns match. Free functions of the plan's parts, so the plan's reader can check every
//! point with them and the run can build each point's job.

use std::path::{Path, PathBuf};

use super::point::{Condition, Point, Setting, Value};
use crate::error::{Error, Result, excerpt};
use crate::job::{Channels, Geometry, Options};
use crate::records::Response;

/// The options of `identify` that name channels rather than set the identification (`rate`:
/// the sample rate, Hz, of MAT-files that hold neither a time vector nor a rate).
pub(super) const CHANNEL_NAMES: [&str; 9] = [
    "force",
    "disp",
    "resp",
    "response",
    "time",
    "record-by",
    "force-unit",
    "disp-unit",
    "rate",
];

/// Whether `name` (with `-` between words) is an option a plan can set.
pub(super) fn is_setting(name: &str) -> bool {
    Options::NAMES.contains(&name) || CHANNEL_NAMES.contains(&name)
}

/// Every option a plan can set, for messages.
pub(super) fn setting_names() -> String {
    Options::NAMES
        .iter()
        .chain(&CHANNEL_NAMES)
        .copied()
        .collect::<Vec<_>>()
        .join(", ")
}

/// The conditions that are also options of `identify` ([`Options::conditions`]): a
/// point's value with the condition's unit sets them.
const OPERATING: [&str; 3] = ["clearance", "load", "speed"];

/// The options of `point`: the command's defaults, then the `shared` settings, then the
/// point's own, in order, then its values of the plan's `conditions` named `clearance`,
/// `load`, `speed` with their units (a speed or load of 0, a test without rotation or load,
/// sets none); and
/// its channel settings (name, text). `source` is the plan's file, as errors name it.
///
/// # Errors
/// [`Options::set`]'s, as [`Error::Plan`] naming the setting's line (the point's for a
/// condition); [`Error::Plan`] when no band is given.
pub(super) fn options(
    source: &str,
    shared: &[Setting],
    conditions: &[Condition],
    point: &Point,
) -> Result<(Options, Vec<Setting>)> {
    let mut o = Options::new(f64::NAN, f64::NAN);
    let mut channels = Vec::new();
    let mut band = false;
    for s in shared.iter().chain(&point.overrides) {
        if CHANNEL_NAMES.contains(&s.name.as_str()) {
            channels.push(s.clone());
            continue;
        }
        band |= s.name == "band";
        o.set(&s.name, &s.text).map_err(|e| Error::Plan {
            file: source.to_owned(),
            line: s.line,
            message: e.to_string(),
        })?;
    }
    for (condition, value) in conditions.iter().zip(&point.values) {
        let name = condition.name.as_str();
        let Some(Value::Number(x)) = value.as_ref().filter(|_| OPERATING.contains(&name)) else {
            continue;
        };
        if name != "clearance" && *x == 0.0 {
            continue;
        }
        let text = format!("{x}{}", condition.unit.name());
        o.set(name, &text).map_err(|e| Error::Plan {
            file: source.to_owned(),
            line: point.line,
            message: format!("point `{}`: {e}", excerpt(&point.name)),
        })?;
    }
    if !band {
        return Err(Error::Plan {
            file: source.to_owned(),
            line: point.line,
            message: format!(
                "point `{}` has no band: give `band = [LO, HI]` in [identify] or its own \
                 identify table",
                excerpt(&point.name)
            ),
        });
    }
    Ok((o, channels))
}

/// The channels of a point from its channel `settings` (the last of a name wins) and the
/// plan's `geometry`, for `files`.
///
/// # Errors
/// A response kind, a `record_by` (TDMS files: `file` or `group`) or a `rate` that does not
/// parse; [`Channels::named`]'s.
pub(super) fn channels(
    settings: &[Setting],
    geometry: Option<&Geometry>,
    files: &[PathBuf],
) -> Result<Channels> {
    let list = |names: &[&str]| -> Vec<String> {
        settings
            .iter()
            .rev()
            .find(|s| names.contains(&s.name.as_str()))
            .map(|s| s.text.split(',').map(|c| c.trim().to_owned()).collect())
            .unwrap_or_default()
    };
    let responses = list(&["response"])
        .iter()
        .map(|r| r.parse::<Response>())
        .collect::<Result<Vec<_>>>()?;
    let time = list(&["time"]).pop().unwrap_or_else(|| "t".to_owned());
    let mut channels = Channels::named(
        &list(&["force"]),
        &list(&["disp", "resp"]),
        &responses,
        &time,
        files,
    )?;
    channels.mat.rate = list(&["rate"])
        .pop()
        .map(|r| {
            r.parse::<f64>()
                .ok()
                .filter(|r| r.is_finite() && *r > 0.0)
                .ok_or_else(|| Error::InvalidOption {
                    option: "rate",
                    message: format!("rate `{}`: a sample rate in Hz, above 0", excerpt(&r)),
                })
        })
        .transpose()?;
    channels.geometry = geometry.cloned();
    if let Some(by) = list(&["record-by"]).pop() {
        channels.record_by = by.parse().map_err(|message| Error::InvalidOption {
            option: "record-by",
            message,
        })?;
    }
    channels.force_units = list(&["force-unit"]);
    channels.response_units = list(&["disp-unit"]);
    Ok(channels)
}

/// The files of `point`: each pattern matched (relative to `base`, the plan's folder), in
/// sorted order within a pattern, patterns in the order given.
///
/// # Errors
/// [`Error::InvalidOption`] (`files`) for a pattern that does not parse or matches no file.
pub(super) fn files(base: &Path, point: &Point) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for pattern in &point.files {
        let full = if Path::new(pattern).is_absolute() {
            PathBuf::from(pattern)
        } else {
            base.join(pattern)
        };
        let text = full.to_string_lossy();
        let bad = |message: String| Error::InvalidOption {
            option: "files",
            message,
        };
        let matches =
            glob::glob(&text).map_err(|e| bad(format!("files `{}`: {e}", excerpt(pattern))))?;
        let mut found: Vec<PathBuf> = matches.filter_map(std::result::Result::ok).collect();
        found.sort();
        if found.is_empty() {
            return Err(bad(format!(
                "point `{}`: no file matches `{}`",
                excerpt(&point.name),
                excerpt(&text)
            )));
        }
        out.extend(found);
    }
    Ok(out)
}
