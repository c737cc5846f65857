//! Records from the channels of a TDMS file: forces and responses by name, the sampling rate
//! from the channels' waveform properties or a time channel, one record per file or per group.

use super::{Channel, Group, TdmsFile, Value, property};
use crate::error::{Error, Result, Warning, excerpt};
use crate::records::{Record, TIME_GRID_TOLERANCE};

/// Which records a TDMS file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RecordBy {
    /// One record of the whole file.
    #[default]
    File,
    /// One record per group that holds the named channels (LabVIEW programs often write one
    /// group per hit or per test point), in the file's order.
    Group,
}

impl std::str::FromStr for RecordBy {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "file" => Ok(RecordBy::File),
            "group" => Ok(RecordBy::Group),
            other => Err(format!(
                "`{}` is not a way to cut records: file or group",
                excerpt(other)
            )),
        }
    }
}

impl std::fmt::Display for RecordBy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RecordBy::File => "file",
            RecordBy::Group => "group",
        })
    }
}

/// The channels of a TDMS record: each `GROUP/CHANNEL`, or `CHANNEL` when it is unique in
/// the file (with [`RecordBy::Group`], in the group).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TdmsLayout {
    /// The time channel, read when the force channels have no `wf_increment` property.
    pub time: String,
    /// Force channels, one per degree of freedom.
    pub forces: Vec<String>,
    /// Response channels, one per degree of freedom.
    pub responses: Vec<String>,
    /// One record per file or per group.
    pub record_by: RecordBy,
    /// Units of the force channels, one for all or one per channel ([`crate::units::Unit`]),
    /// in place of the channels' `unit_string`; none: as the file states them.
    pub force_units: Vec<String>,
    /// Units of the response channels, as `force_units`.
    pub response_units: Vec<String>,
}

/// The records of a TDMS file read as `layout` says; `label` (the file) names them: the file
/// itself, or `FILE:GROUP` per group. The sampling rate is `1/wf_increment` of the named
/// channels (which must agree), or that of the time channel (uniform within
/// [`TIME_GRID_TOLERANCE`] of a step) when they have none. Each channel is converted to SI
/// from its unit: the layout's, else its `unit_string` (none: SI). A `unit_string` this crate
/// does not know leaves the samples as read (SI) and the record carries a
/// [`Warning::UnknownUnit`] naming it ([`Record::warnings`]).
///
/// # Errors
/// [`Error::TdmsChannel`] for a channel that is not in the file, named ambiguously, or whose
/// samples cannot be read (strings, a scaling other than linear or polynomial, a unit of
/// another quantity, a given unit that is not a recognised one: kind `unsupported`);
/// [`Error::TdmsRecord`] for channels of different lengths or rates, no rate, a number of
/// given units other than one or one per channel,
/// a time channel off its grid, or no group holding the channels; the errors of
/// [`Record::new`].
///
/// # Examples
/// ```
/// use bearing_ident::tdms::{Channel, Group, Property, TdmsFile, TdmsLayout, Value, records};
/// let channel = |name: &str, v: f64| Channel {
///     name: name.into(),
///     values: vec![v; 16],
///     properties: vec![Property { name: "wf_increment".into(), value: Value::Float(0.001) }],
///     ..Channel::default()
/// };
/// let file = TdmsFile {
///     groups: vec![Group { name: "hit".into(), channels: vec![channel("fx", 1.0), channel("x", 2.0)], ..Group::default() }],
///     ..TdmsFile::default()
/// };
/// let layout = TdmsLayout { forces: vec!["fx".into()], responses: vec!["hit/x".into()], ..TdmsLayout::default() };
/// let r = records(&file, "run3.tdms", &layout)?;
/// assert_eq!(r[0].sample_rate(), 1000.0);
/// assert_eq!(r[0].displacement(0)[0], 2.0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn records(file: &TdmsFile, label: &str, layout: &TdmsLayout) -> Result<Vec<Record>> {
    match layout.record_by {
        RecordBy::File => Ok(vec![record(file, None, label, layout)?]),
        RecordBy::Group => {
            let named = |g: &Group| {
                layout
                    .forces
                    .iter()
                    .chain(&layout.responses)
                    .any(|n| find_in(g, n).is_some())
            };
            let groups: Vec<&Group> = file.groups.iter().filter(|g| named(g)).collect();
            if groups.is_empty() {
                return Err(Error::TdmsRecord {
                    path: excerpt(label),
                    message: format!(
                        "no group holds the channels {}",
                        excerpt(
                            &layout
                                .forces
                                .iter()
                                .chain(&layout.responses)
                                .cloned()
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    ),
                });
            }
            groups
                .into_iter()
                .map(|g| record(file, Some(g), &format!("{label}:{}", g.name), layout))
                .collect()
        }
    }
}

/// The channel `name` of group `g`: `CHANNEL`, or `GROUP/CHANNEL` of this group.
fn find_in<'a>(g: &'a Group, name: &str) -> Option<&'a Channel> {
    let name = match name.split_once('/') {
        Some((group, channel)) if group == g.name => channel,
        Some(_) if g.channels.iter().all(|c| c.name != name) => return None,
        _ => name,
    };
    g.channels.iter().find(|c| c.name == name)
}

/// The channel `name`: in `group` when records are cut by group, else in the whole file.
fn find<'a>(
    file: &'a TdmsFile,
    group: Option<&'a Group>,
    name: &str,
    label: &str,
) -> Result<&'a Channel> {
    let missing = |message: String| Error::TdmsChannel {
        path: excerpt(label),
        channel: excerpt(name),
        message,
        unsupported: false,
    };
    if let Some(g) = group {
        return find_in(g, name).ok_or_else(|| {
            missing(format!(
                "not in group `{}`, which holds {}",
                excerpt(&g.name),
                names(g.channels.iter().map(|c| c.name.clone()))
            ))
        });
    }
    if let Some((g, c)) = name.split_once('/')
        && let Some(found) = file
            .groups
            .iter()
            .find(|x| x.name == g)
            .and_then(|x| x.channels.iter().find(|y| y.name == c))
    {
        return Ok(found);
    }
    let hits: Vec<(&Group, &Channel)> = file
        .groups
        .iter()
        .flat_map(|g| {
            g.channels
                .iter()
                .filter(|c| c.name == name)
                .map(move |c| (g, c))
        })
        .collect();
    match hits.as_slice() {
        [(_, c)] => Ok(c),
        [] => Err(missing(format!(
            "not in the file, which holds {}",
            names(file.groups.iter().flat_map(|g| {
                g.channels
                    .iter()
                    .map(move |c| format!("{}/{}", g.name, c.name))
            }))
        ))),
        many => Err(missing(format!(
            "in groups {}: name it GROUP/CHANNEL, or give --record-by group",
            names(many.iter().map(|(g, _)| g.name.clone()))
        ))),
    }
}

/// Names for a message: comma-separated, at most 80 characters, then `…`.
fn names(names: impl Iterator<Item = String>) -> String {
    let all: Vec<String> = names.collect();
    if all.is_empty() {
        return "no channel".into();
    }
    let text = all.join(", ");
    if text.chars().count() > 80 {
        format!("{}…", text.chars().take(80).collect::<String>())
    } else {
        text
    }
}

/// The samples of a channel, or why they cannot be read.
fn samples<'a>(c: &'a Channel, name: &str, label: &str) -> Result<&'a [f64]> {
    match &c.unreadable {
        None => Ok(&c.values),
        Some(why) => Err(Error::TdmsChannel {
            path: excerpt(label),
            channel: excerpt(name),
            message: why.clone(),
            unsupported: true,
        }),
    }
}

/// One record of the named channels (in `group`, or anywhere in the file).
#[allow(clippy::float_cmp)] // a factor of exactly 1 (SI) leaves the samples as read
fn record(
    file: &TdmsFile,
    group: Option<&Group>,
    label: &str,
    layout: &TdmsLayout,
) -> Result<Record> {
    let bad = |message: String| Error::TdmsRecord {
        path: excerpt(label),
        message,
    };
    let forces: Vec<(&String, &Channel)> = layout
        .forces
        .iter()
        .map(|n| Ok((n, find(file, group, n, label)?)))
        .collect::<Result<_>>()?;
    let responses: Vec<(&String, &Channel)> = layout
        .responses
        .iter()
        .map(|n| Ok((n, find(file, group, n, label)?)))
        .collect::<Result<_>>()?;
    let mut increment: Option<(f64, &String)> = None;
    for (name, c) in forces.iter().chain(&responses) {
        let Some(dt) = property(&c.properties, "wf_increment").and_then(Value::as_f64) else {
            continue;
        };
        match increment {
            None => increment = Some((dt, name)),
            Some((first, other)) if (dt - first).abs() > TIME_GRID_TOLERANCE * first.abs() => {
                return Err(bad(format!(
                    "channel `{}` has wf_increment {dt} s and `{}` {first} s",
                    excerpt(name),
                    excerpt(other)
                )));
            }
            Some(_) => {}
        }
    }
    let rate = match increment {
        Some((dt, _)) => 1.0 / dt,
        None => {
            let time = find(file, group, &layout.time, label).map_err(|_| {
                bad(format!(
                    "no wf_increment property on the channels and no time channel `{}`: \
                     give --time",
                    excerpt(&layout.time)
                ))
            })?;
            uniform_rate(samples(time, &layout.time, label)?).map_err(bad)?
        }
    };
    let mut warnings = Vec::new();
    let mut own =
        |set: &[(&String, &Channel)], given: &[String], force: bool| -> Result<Vec<Vec<f64>>> {
            set.iter()
                .enumerate()
                .map(|(i, (n, c))| {
                    let mut v = samples(c, n, label)?.to_vec();
                    let count = given.len();
                    let given = crate::units::given(given, i, set.len());
                    if given.is_none() && count > 0 {
                        return Err(bad(format!(
                            "--{} names {count} units for {} channels: give one for all or one per \
                         channel",
                            if force { "force-unit" } else { "disp-unit" },
                            set.len()
                        )));
                    }
                    let Some(stated) = given.or_else(|| c.unit()) else {
                        return Ok(v);
                    };
                    let to_si = match si_factor(stated, force) {
                        Ok(to_si) => to_si,
                        // A unit the file states and this crate does not know: used as read (SI),
                        // with a warning naming it; one the user gives is never guessed.
                        Err(Unknown::Name) if given.is_none() => {
                            warnings.push(Warning::UnknownUnit {
                                record: excerpt(label),
                                channel: excerpt(n),
                                unit: excerpt(stated),
                                force,
                            });
                            return Ok(v);
                        }
                        Err(why) => {
                            return Err(Error::TdmsChannel {
                                path: excerpt(label),
                                channel: excerpt(n),
                                message: why.message(stated, force),
                                unsupported: true,
                            });
                        }
                    };
                    // SI stays bit for bit as read.
                    if to_si != 1.0 {
                        v.iter_mut().for_each(|x| *x *= to_si);
                    }
                    Ok(v)
                })
                .collect()
        };
    let forces = own(&forces, &layout.force_units, true)?;
    let responses = own(&responses, &layout.response_units, false)?;
    Ok(Record::new(label, rate, forces, responses)?.with_warnings(warnings))
}

/// Why a unit has no factor to SI for a channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Unknown {
    /// Not a unit this crate knows.
    Name,
    /// A known unit of another quantity (a length on a force channel).
    Quantity,
}

impl Unknown {
    /// The message of [`Error::TdmsChannel`] for unit `name` of a force (`force`) or response
    /// channel.
    fn message(self, name: &str, force: bool) -> String {
        let what = if force { "force" } else { "response" };
        let option = if force { "--force-unit" } else { "--disp-unit" };
        match self {
            Unknown::Quantity => format!(
                "its unit `{}` is not a {what} unit: give {option}",
                excerpt(name)
            ),
            Unknown::Name => format!(
                "its unit `{}` is not one this reader converts to SI (N, kN, lbf; m, mm, um, \
                 in, mil; m/s, in/s; m/s^2, g): give {option}",
                excerpt(name)
            ),
        }
    }
}

/// The factor to SI of unit `name` of a force (`force`) or response channel.
fn si_factor(name: &str, force: bool) -> std::result::Result<f64, Unknown> {
    match crate::units::Unit::named(name) {
        Some(u) if u.fits(force) => Ok(u.to_si),
        Some(_) => Err(Unknown::Quantity),
        None => Err(Unknown::Name),
    }
}

/// The rate of a uniform time channel: `(N − 1)/(t_last − t_0)`, every time within
/// [`TIME_GRID_TOLERANCE`] of a step of its place on that grid.
fn uniform_rate(t: &[f64]) -> std::result::Result<f64, String> {
    let n = t.len();
    if n < 2 {
        return Err(format!("a time channel of {n} samples"));
    }
    let step = (t[n - 1] - t[0]) / (n - 1) as f64;
    if !(step > 0.0 && step.is_finite()) {
        return Err(format!("a time channel from {} s to {} s", t[0], t[n - 1]));
    }
    if let Some(i) = t
        .iter()
        .enumerate()
        .position(|(i, &ti)| (ti - (t[0] + i as f64 * step)).abs() > TIME_GRID_TOLERANCE * step)
    {
        return Err(format!(
            "the time channel's sample {i} is at {} s, off its uniform grid of {step} s by more \
             than {} %",
            t[i],
            TIME_GRID_TOLERANCE * 100.0
        ));
    }
    Ok(1.0 / step)
}
