//! Records from MAT-file variables: channels named as variables (`fx`), struct fields
//! (`rec.fx`) or matrix columns (`data:2`, one-based); the time from a vector or a scalar rate.

use std::str::FromStr;

use crate::error::{Error, Result};
use crate::records::Record;

use super::{Array, Variable};

/// A channel of a MAT-file: a path of names (a variable, then struct fields) and, for a
/// matrix, a one-based column.
///
/// A struct array or cell array met on the path gives one channel per element, in order
/// (MATLAB's linear index): `rec.fx` of a 1×3 struct array `rec` is three channels, one per
/// record.
///
/// # Examples
/// ```
/// use bearing_ident::mat::MatChannel;
/// let c: MatChannel = "rec.data:2".parse()?;
/// assert_eq!(c.path, ["rec", "data"]);
/// assert_eq!(c.column, Some(2));
/// assert_eq!(c.to_string(), "rec.data:2");
/// assert!("data:0".parse::<MatChannel>().is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MatChannel {
    /// The variable, then the fields of the structs inside it.
    pub path: Vec<String>,
    /// One-based column of a matrix, if any.
    pub column: Option<usize>,
}

impl FromStr for MatChannel {
    type Err = Error;

    /// `NAME`, `NAME.FIELD…`, each optionally followed by `:COLUMN` (one-based).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for an empty name or a column that is not a positive integer.
    fn from_str(s: &str) -> Result<Self> {
        let bad = |message: String| Error::InvalidOption {
            option: "force",
            message,
        };
        let (names, column) = match s.rsplit_once(':') {
            Some((names, c)) => {
                let column = c
                    .trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|&c| c > 0)
                    .ok_or_else(|| {
                        bad(format!(
                            "MAT channel `{}`: the column after `:` is counted from 1",
                            crate::error::excerpt(s)
                        ))
                    })?;
                (names, Some(column))
            }
            None => (s, None),
        };
        let path: Vec<String> = names.split('.').map(|n| n.trim().to_owned()).collect();
        if path.iter().any(String::is_empty) {
            return Err(bad(format!(
                "MAT channel `{}`: a variable, then struct fields, separated by `.`",
                crate::error::excerpt(s)
            )));
        }
        Ok(MatChannel { path, column })
    }
}

impl std::fmt::Display for MatChannel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.path.join("."))?;
        match self.column {
            Some(c) => write!(f, ":{c}"),
            None => Ok(()),
        }
    }
}

/// Where a record is in a MAT-file: its force and response channels (one per degree of
/// freedom), its time, and a sample rate to use when the file holds neither.
///
/// The sample rate is, in order: from the time vector `time` (uniform, as a CSV time column),
/// else from a scalar found by name beside the first force channel (in its struct) or at the
/// top of the file: `fs`, `Fs`, `rate` (Hz) or `dt` (s), else `rate`.
///
/// # Examples
/// ```
/// use bearing_ident::mat::MatLayout;
/// let layout = MatLayout::default();
/// assert_eq!(layout.forces[0].to_string(), "fx");
/// assert_eq!(layout.time, "t");
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MatLayout {
    /// Force channels.
    pub forces: Vec<MatChannel>,
    /// Response channels.
    pub responses: Vec<MatChannel>,
    /// The time vector's name (`t`); a path `rec.t` is looked up as a channel.
    pub time: String,
    /// Sample rate (Hz) when the file states none.
    pub rate: Option<f64>,
}

impl Default for MatLayout {
    fn default() -> Self {
        let channel = |n: &str| MatChannel {
            path: vec![n.to_owned()],
            column: None,
        };
        MatLayout {
            forces: vec![channel("fx"), channel("fy")],
            responses: vec![channel("x"), channel("y")],
            time: "t".to_owned(),
            rate: None,
        }
    }
}

/// Names of a scalar sample rate (Hz) or interval (s) looked up when there is no time vector.
const RATE_NAMES: [(&str, bool); 4] = [("fs", true), ("Fs", true), ("rate", true), ("dt", false)];

/// The records of a MAT-file's variables: one, or one per element of the struct arrays or cell
/// arrays the channels pass through, labelled `FILE` or `FILE(i)` (one-based).
///
/// # Errors
/// [`Error::MatRecord`] naming the file and the channel: a variable or field that is not
/// there (the names there are listed), an array that is not real numbers (`char`, complex,
/// sparse, an object such as `timetable`: its class and size said), a matrix named without a
/// column or a column past its last, channels giving different numbers of records, no
/// sample rate. [`Record::new`]'s errors (lengths, NaN) for the records built.
///
/// # Examples
/// ```
/// use bearing_ident::mat::{self, Array, MatLayout, Variable};
/// let v = |name: &str, real: Vec<f64>| Variable {
///     name: name.into(),
///     array: Array::Numeric { class: "double", dims: vec![real.len(), 1], real, complex: false },
/// };
/// let vars = [
///     v("fx", vec![1.0; 8]), v("fy", vec![2.0; 8]), v("x", vec![0.5; 8]), v("y", vec![0.25; 8]),
///     v("fs", vec![512.0]),
/// ];
/// let r = &mat::records(&vars, "hit.mat", &MatLayout::default())?[0];
/// assert_eq!(r.sample_rate(), 512.0);
/// assert_eq!(r.displacement(1)[7], 0.25);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn records(variables: &[Variable], label: &str, layout: &MatLayout) -> Result<Vec<Record>> {
    let top = Scope::Top(variables);
    let resolve = |c: &MatChannel| channel(&top, c, label);
    let forces = layout
        .forces
        .iter()
        .map(resolve)
        .collect::<Result<Vec<_>>>()?;
    let responses = layout
        .responses
        .iter()
        .map(resolve)
        .collect::<Result<Vec<_>>>()?;
    let all = forces.iter().chain(&responses);
    let n = all.clone().map(Vec::len).max().unwrap_or(1);
    for (c, found) in layout.forces.iter().chain(&layout.responses).zip(all) {
        if found.len() != n && found.len() != 1 {
            return Err(record_error(
                label,
                &c.to_string(),
                format!("{} records here, {n} in another channel", found.len()),
            ));
        }
    }
    let rates = rates(&top, layout, label)?;
    if rates.len() != n && rates.len() != 1 {
        return Err(record_error(
            label,
            &layout.time,
            format!("{} sample rates for {n} records", rates.len()),
        ));
    }
    let pick = |v: &Vec<Vec<f64>>, i: usize| v[if v.len() == 1 { 0 } else { i }].clone();
    (0..n)
        .map(|i| {
            let name = if n == 1 {
                label.to_owned()
            } else {
                format!("{label}({})", i + 1)
            };
            let rate = rates[if rates.len() == 1 { 0 } else { i }];
            Record::new(
                name,
                rate,
                forces.iter().map(|f| pick(f, i)).collect(),
                responses.iter().map(|x| pick(x, i)).collect(),
            )
        })
        .collect()
}

fn record_error(label: &str, channel: &str, message: String) -> Error {
    Error::MatRecord {
        path: label.to_owned(),
        variable: crate::error::excerpt(channel),
        message,
    }
}

/// Where names are looked up: the file's variables or a struct element's fields.
enum Scope<'a> {
    Top(&'a [Variable]),
    Fields(&'a [String], &'a [Array]),
}

impl<'a> Scope<'a> {
    fn get(&self, name: &str) -> Option<&'a Array> {
        match self {
            Scope::Top(vars) => vars.iter().find(|v| v.name == name).map(|v| &v.array),
            Scope::Fields(names, values) => {
                names.iter().position(|n| n == name).map(|i| &values[i])
            }
        }
    }

    fn names(&self) -> String {
        let names: Vec<&str> = match self {
            Scope::Top(vars) => vars.iter().map(|v| v.name.as_str()).collect(),
            Scope::Fields(names, _) => names.iter().map(String::as_str).collect(),
        };
        crate::error::excerpt(&names.join(", "))
    }
}

/// The arrays at `path` below `scope`, one per element of every struct or cell array passed.
fn arrays<'a>(
    scope: &Scope<'a>,
    path: &[String],
    channel: &str,
    label: &str,
) -> Result<Vec<&'a Array>> {
    let Some((name, rest)) = path.split_first() else {
        return Ok(Vec::new());
    };
    let array = scope.get(name).ok_or_else(|| {
        record_error(
            label,
            channel,
            format!(
                "no `{}` here; there are: {}",
                crate::error::excerpt(name),
                scope.names()
            ),
        )
    })?;
    below(array, rest, channel, label)
}

/// The arrays at `rest` below `array` (itself when `rest` is empty and it is no cell array).
fn below<'a>(
    array: &'a Array,
    rest: &[String],
    channel: &str,
    label: &str,
) -> Result<Vec<&'a Array>> {
    match array {
        Array::Cell { cells, .. } => {
            let mut out = Vec::new();
            for cell in cells {
                out.extend(below(cell, rest, channel, label)?);
            }
            Ok(out)
        }
        _ if rest.is_empty() => Ok(vec![array]),
        Array::Struct {
            fields, elements, ..
        } => {
            let mut out = Vec::new();
            for element in elements {
                out.extend(arrays(
                    &Scope::Fields(fields, element),
                    rest,
                    channel,
                    label,
                )?);
            }
            Ok(out)
        }
        other => Err(record_error(
            label,
            channel,
            format!(
                "`{}` is a {} {}, not a struct with fields",
                rest[0],
                other.size_text(),
                other.class()
            ),
        )),
    }
}

/// The samples of a channel, one vector per record.
fn channel(scope: &Scope<'_>, c: &MatChannel, label: &str) -> Result<Vec<Vec<f64>>> {
    let name = c.to_string();
    arrays(scope, &c.path, &name, label)?
        .into_iter()
        .map(|a| samples(a, c.column, &name, label))
        .collect()
}

/// A vector's samples, or a matrix column's.
fn samples(array: &Array, column: Option<usize>, channel: &str, label: &str) -> Result<Vec<f64>> {
    let bad = |m: String| record_error(label, channel, m);
    let real = match array {
        Array::Numeric {
            complex: false,
            real,
            ..
        } => real,
        Array::Numeric { .. } => {
            return Err(bad(format!(
                "a complex {} {}: a channel is real",
                array.size_text(),
                array.class()
            )));
        }
        other => {
            return Err(bad(format!(
                "a {} {}, not numbers",
                other.size_text(),
                other.class()
            )));
        }
    };
    let dims = array.dims();
    let rows = dims.first().copied().unwrap_or(0);
    let columns = real.len().checked_div(rows).unwrap_or(0);
    match column {
        None if dims.iter().filter(|&&d| d != 1).count() <= 1 => Ok(real.clone()),
        None => Err(bad(format!(
            "a {} matrix: name one column, `{channel}:2` (counted from 1)",
            array.size_text()
        ))),
        Some(c) if dims.len() == 2 && c <= columns => Ok(real[(c - 1) * rows..c * rows].to_vec()),
        Some(c) => Err(bad(format!(
            "column {c} of a {} {}, which has {columns} columns",
            array.size_text(),
            array.class()
        ))),
    }
}

/// The sample rate of each record (or one for all).
fn rates(top: &Scope<'_>, layout: &MatLayout, label: &str) -> Result<Vec<f64>> {
    let time: MatChannel = layout.time.parse()?;
    if let Ok(times) = channel(top, &time, label) {
        return times
            .iter()
            .map(|t| {
                crate::io::uniform_rate(t, label, &|i| i as u64 + 1).map_err(|e| match e {
                    Error::NonUniformTime {
                        line,
                        expected_s,
                        actual_s,
                        ..
                    } => record_error(
                        label,
                        &layout.time,
                        format!(
                            "not uniform: sample {line} at {actual_s} s, {expected_s} s on the grid"
                        ),
                    ),
                    e => e,
                })
            })
            .collect();
    }
    // A scalar beside the first force channel (in its struct), then at the top.
    let prefix = layout
        .forces
        .first()
        .map_or(&[][..], |c| &c.path[..c.path.len().saturating_sub(1)]);
    for prefix in [prefix, &[][..]] {
        for (name, is_rate) in RATE_NAMES {
            let mut path = prefix.to_vec();
            path.push(name.to_owned());
            let Ok(found) = arrays(top, &path, name, label) else {
                continue;
            };
            return found
                .into_iter()
                .map(|a| match a.samples() {
                    Some(&[v]) if v.is_finite() && v > 0.0 => Ok(if is_rate { v } else { 1.0 / v }),
                    _ => Err(record_error(
                        label,
                        &path.join("."),
                        format!(
                            "a {} {}: a sample rate is a positive scalar",
                            a.size_text(),
                            a.class()
                        ),
                    )),
                })
                .collect();
        }
    }
    layout.rate.map(|r| vec![r]).ok_or_else(|| {
        record_error(
            label,
            &layout.time,
            "no time vector of that name and no sample rate `fs`, `Fs`, `rate` or interval `dt`: \
             name the time with --time or give --rate"
                .into(),
        )
    })
}
