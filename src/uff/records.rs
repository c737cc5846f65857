//! [`Record`]s from dataset 58 time histories, by data type or by an explicit [`UffLayout`].

use super::types::{Abscissa, DataType, Function, FunctionType, Ordinate};
use crate::error::{Error, Result, Warning};
use crate::records::{Record, Response};

/// One time history of a Universal File named on the command line or in a [`UffLayout`]: a
/// response node and signed direction (`5+X`, `12-Y`, `3+2`), or the text of the first ID line
/// (`id:TEXT`).
///
/// # Matching
/// - `NODE+DIR` / `NODE-DIR` match the time history whose response node is `NODE` and whose
///   signed direction (record 6) is `+DIR` / `−DIR` exactly. Directions are `X`, `Y`, `Z`,
///   `RX`, `RY`, `RZ` (any case) or their codes `1`…`6`.
/// - `id:TEXT` matches the time history whose first ID line (record 1), with leading and
///   trailing spaces removed, equals `TEXT` exactly (case and inner spaces count): a substring
///   would match `force x` inside `force xy`.
///
/// Either way a time history with a negative direction is negated, as by the rule.
///
/// A name that matches no time history of a load case, or more than one, is an error.
///
/// # Examples
/// ```
/// use bearing_ident::uff::UffChannel;
/// assert_eq!("5+X".parse::<UffChannel>()?, UffChannel::Dof { node: 5, direction: 1 });
/// assert_eq!("12-ry".parse::<UffChannel>()?, UffChannel::Dof { node: 12, direction: -5 });
/// assert_eq!("3+2".parse::<UffChannel>()?, UffChannel::Dof { node: 3, direction: 2 });
/// assert_eq!("id:Hammer X".parse::<UffChannel>()?, UffChannel::Id("Hammer X".into()));
/// assert!("5X".parse::<UffChannel>().is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum UffChannel {
    /// Response node and signed direction code (±1…±6 for ±X, ±Y, ±Z, ±RX, ±RY, ±RZ).
    Dof {
        /// Response node (record 6).
        node: i64,
        /// Signed direction code.
        direction: i64,
    },
    /// The first ID line, trimmed, equal to this text.
    Id(String),
}

impl UffChannel {
    /// Whether time history `f` is this channel.
    fn matches(&self, f: &Function) -> bool {
        match self {
            UffChannel::Dof { node, direction } => {
                f.response.node == *node && f.response.direction == *direction
            }
            UffChannel::Id(text) => f.id[0].trim() == text,
        }
    }
}

impl std::fmt::Display for UffChannel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UffChannel::Dof { node, direction } => {
                let name = (direction.unsigned_abs() as usize)
                    .checked_sub(1)
                    .and_then(|d| ["X", "Y", "Z", "RX", "RY", "RZ"].get(d))
                    .copied()
                    .unwrap_or("?");
                let sign = if *direction < 0 { '-' } else { '+' };
                write!(f, "{node}{sign}{name}")
            }
            UffChannel::Id(text) => write!(f, "id:{text}"),
        }
    }
}

impl std::str::FromStr for UffChannel {
    type Err = Error;

    /// Parses `NODE+DIR`, `NODE-DIR` or `id:TEXT` (see [`UffChannel`]).
    ///
    /// # Errors
    /// [`Error::UnknownName`] quoting the text given.
    fn from_str(s: &str) -> Result<Self> {
        let bad = || Error::UnknownName {
            what: "Universal File channel",
            given: s.to_owned(),
            expected: "NODE+DIR or NODE-DIR (DIR one of X, Y, Z, RX, RY, RZ or 1-6), or id:TEXT"
                .into(),
        };
        if let Some(text) = s.strip_prefix("id:") {
            return Ok(UffChannel::Id(text.trim().to_owned()));
        }
        let at = s.find(['+', '-']).filter(|&i| i > 0).ok_or_else(bad)?;
        let node: i64 = s[..at].trim().parse().map_err(|_| bad())?;
        let dir = s[at + 1..].trim().to_ascii_uppercase();
        let code = match dir.as_str() {
            "X" | "1" => 1,
            "Y" | "2" => 2,
            "Z" | "3" => 3,
            "RX" | "4" => 4,
            "RY" | "5" => 5,
            "RZ" | "6" => 6,
            _ => return Err(bad()),
        };
        let sign = if s.as_bytes()[at] == b'-' { -1 } else { 1 };
        Ok(UffChannel::Dof {
            node,
            direction: sign * code,
        })
    }
}

/// Which time histories of a Universal File make a record, beyond the default rule of
/// [`records`]: explicit force and response channels, and the kind of the responses.
///
/// Empty lists keep the rule: forces are the time histories of data type 13, responses those
/// of data types 8, 11 and 12, each sorted by direction, then node; a response's kind is its
/// data type (8 displacement, 11 velocity, 12 acceleration). Channels named here are taken in
/// the order given, whatever their data type; a named response of another data type needs
/// its kind in `kinds`.
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, Function, UffLayout};
/// use bearing_ident::Response;
/// let t: Vec<f64> = (0..16).map(|k| k as f64).collect();
/// let mut hammer = Function::time_response(9, 1, 13, 0.0, 1e-3, t.clone());
/// hammer.id[0] = "hammer".into();
/// let functions = [
///     hammer,
///     Function::time_response(5, 1, 12, 0.0, 1e-3, t.clone()), // an accelerometer, +X
///     Function::time_response(6, 1, 8, 0.0, 1e-3, t.clone()), // a probe elsewhere
/// ];
/// let layout = UffLayout {
///     forces: vec!["id:hammer".parse()?],
///     responses: vec!["5+X".parse()?],
///     ..UffLayout::default()
/// };
/// let r = &uff::records_with(&functions, "rig.uff", &layout)?[0];
/// assert_eq!((r.dofs(), r.response(0)), (1, Response::Acceleration));
/// assert_eq!(r.force(0)[2], 2.0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct UffLayout {
    /// Force channels, one per degree of freedom, in order; empty: data type 13.
    pub forces: Vec<UffChannel>,
    /// Response channels, one per degree of freedom, in order; empty: data types 8, 11, 12.
    pub responses: Vec<UffChannel>,
    /// What the responses measure: empty (by data type), one for all, or one per degree of
    /// freedom ([`Response::per_channel`]); given, it overrides the data types.
    pub kinds: Vec<Response>,
    /// Units of the force channels ([`crate::units::Unit::named`]), one for all or one per
    /// channel, in place of the units label of each time history's ordinate (record 9);
    /// none: as the file states them.
    pub force_units: Vec<String>,
    /// Units of the response channels, as `force_units`.
    pub response_units: Vec<String>,
}

/// The response kind of a data type: 8, 11, 12.
fn response_kind(data_type: DataType) -> Option<Response> {
    match data_type {
        DataType::Displacement => Some(Response::Displacement),
        DataType::Velocity => Some(Response::Velocity),
        DataType::Acceleration => Some(Response::Acceleration),
        _ => None,
    }
}

/// Builds one [`Record`] per load case from the time histories among `functions`; `label`
/// names the source (a file) in labels and errors.
///
/// # The rule
/// - Only time responses (function type 1) are used; FRFs, spectra and the rest are ignored.
/// - Time histories with the same load case (record 6) form one record, in the order of the
///   load cases' first appearance. A file whose time histories all carry one load case (0, as
///   most writers leave it) is one record.
/// - The ordinate numerator's data type assigns a channel: 13 (excitation force, N) a force;
///   8 (displacement, m), 11 (velocity, m/s) and 12 (acceleration, m/s²) a response of that
///   [`Response`] kind (a record may mix them). Other quantities are ignored.
///   [`records_with`] and a [`UffLayout`] name the channels instead.
/// - Forces and responses are each sorted by the absolute response direction
///   (1 X, 2 Y, 3 Z, …), then by response node: with `n` of each, degree of freedom `i` is the
///   `i`-th of each list. A negative direction (−X is −1) is a sensor pointing the other way;
///   its values are negated.
/// - Every channel of a record must be real, evenly spaced with one increment `dx` and one
///   length; the sampling rate is `1/dx`.
///
/// The record's label is `label` when there is one record, `label#lc` (the load case)
/// otherwise.
///
/// # Errors
/// [`Error::UffRecord`] naming the load case when no time history is a force or response,
/// when a channel's abscissa is uneven or its values complex, or when channels' increments
/// differ; and [`Record::new`]'s errors (unequal force and displacement counts, lengths, too
/// few samples, non-finite values).
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, Function};
/// let t: Vec<f64> = (0..16).map(|k| k as f64).collect();
/// let functions = [
///     Function::time_response(5, 2, 8, 0.0, 1e-3, t.iter().map(|v| 2.0 * v).collect()),
///     Function::time_response(5, 1, 13, 0.0, 1e-3, t.clone()),
///     Function::time_response(5, -1, 8, 0.0, 1e-3, t.clone()),
///     Function::time_response(5, 2, 13, 0.0, 1e-3, t.iter().map(|v| 3.0 * v).collect()),
/// ];
/// let records = uff::records(&functions, "rig.uff")?;
/// assert_eq!(records.len(), 1);
/// let r = &records[0];
/// assert_eq!(r.dofs(), 2);
/// assert!((r.sample_rate() - 1000.0).abs() < 1e-9);
/// assert_eq!(r.force(1)[1], 3.0); // +Y force
/// assert_eq!(r.displacement(0)[1], -1.0); // −X sensor, negated
/// assert_eq!(r.displacement(1)[1], 2.0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn records(functions: &[Function], label: &str) -> Result<Vec<Record>> {
    records_with(functions, label, &UffLayout::default())
}

/// [`records`] with the channels chosen by `layout` ([`UffLayout`]; its default is the rule of
/// [`records`]).
///
/// # Errors
/// As [`records`]; [`Error::UffRecord`] naming the file, the load case and the channel when a
/// named channel matches no time history of a load case, or more than one; when a named
/// response has a data type other than 8, 11 or 12 and `layout.kinds` is empty; when the
/// numbers of forces and responses named differ; [`Error::LengthMismatch`] for a count of
/// kinds other than 0, 1 or the degrees of freedom.
pub fn records_with(
    functions: &[Function],
    label: &str,
    layout: &UffLayout,
) -> Result<Vec<Record>> {
    let mut cases: Vec<i64> = Vec::new();
    for f in functions {
        if f.function_type == FunctionType::TimeResponse && !cases.contains(&f.load_case) {
            cases.push(f.load_case);
        }
    }
    if cases.is_empty() {
        return Err(Error::UffRecord {
            path: label.to_owned(),
            load_case: 0,
            message: "no time history (function type 1) in the file".into(),
        });
    }
    let single = cases.len() == 1;
    cases
        .iter()
        .map(|&lc| {
            let name = if single {
                label.to_owned()
            } else {
                format!("{label}#{lc}")
            };
            record_of_case(functions, lc, label, &name, layout)
        })
        .collect()
}

/// The record of one load case's time histories, by the rule of [`records`], the records of
/// every other load case left out: one file per record.
///
/// # Errors
/// As [`records`]; [`Error::UffRecord`] also when the load case has no time history.
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, Function};
/// let mut f = Function::time_response(1, 1, 13, 0.0, 0.5, vec![1.0; 8]);
/// let mut x = Function::time_response(1, 1, 8, 0.0, 0.5, vec![2.0; 8]);
/// f.load_case = 3;
/// x.load_case = 3;
/// let r = uff::record(&[f, x], 3, "rig.uff")?;
/// assert_eq!(r.len(), 8);
/// assert!((r.sample_rate() - 2.0).abs() < 1e-12);
/// assert!(uff::record(&[], 3, "rig.uff").is_err());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn record(functions: &[Function], load_case: i64, label: &str) -> Result<Record> {
    record_of_case(functions, load_case, label, label, &UffLayout::default())
}

fn record_of_case(
    functions: &[Function],
    lc: i64,
    path: &str,
    name: &str,
    layout: &UffLayout,
) -> Result<Record> {
    let fail = |message: String| Error::UffRecord {
        path: path.to_owned(),
        load_case: lc,
        message,
    };
    let histories = || {
        functions
            .iter()
            .filter(|f| f.function_type == FunctionType::TimeResponse && f.load_case == lc)
    };
    let mut forces: Vec<&Function> = Vec::new();
    let mut displacements: Vec<&Function> = Vec::new();
    let mut others = 0;
    let mut keyed: [Vec<(i64, i64, &Function)>; 2] = [Vec::new(), Vec::new()];
    for f in histories() {
        let key = (f.response.direction.saturating_abs(), f.response.node, f);
        match f.numerator.data_type {
            DataType::ExcitationForce => keyed[0].push(key),
            t if response_kind(t).is_some() => keyed[1].push(key),
            _ => others += 1,
        }
    }
    for list in &mut keyed {
        list.sort_by_key(|&(d, n, _)| (d, n));
    }
    let [by_type_forces, by_type_responses] = keyed;
    let named = |channels: &[UffChannel], what: &str| -> Result<Vec<&Function>> {
        channels
            .iter()
            .map(|c| {
                let mut found = histories().filter(|f| c.matches(f));
                match (found.next(), found.next()) {
                    (Some(f), None) => Ok(f),
                    (None, _) => Err(fail(format!(
                        "no time history is the {what} channel `{c}` (time histories: {})",
                        inventory(histories())
                    ))),
                    (Some(_), Some(_)) => Err(fail(format!(
                        "more than one time history is the {what} channel `{c}`"
                    ))),
                }
            })
            .collect()
    };
    if layout.forces.is_empty() {
        forces.extend(by_type_forces.iter().map(|&(_, _, f)| f));
    } else {
        forces = named(&layout.forces, "force")?;
    }
    if layout.responses.is_empty() {
        displacements.extend(by_type_responses.iter().map(|&(_, _, f)| f));
    } else {
        displacements = named(&layout.responses, "response")?;
    }
    if forces.is_empty() || displacements.is_empty() {
        return Err(fail(format!(
            "{} force (data type 13) and {} response (data types 8, 11, 12) time histories, \
             {others} of other quantities: a record needs both",
            forces.len(),
            displacements.len()
        )));
    }
    if forces.len() != displacements.len() {
        return Err(fail(format!(
            "{} force and {} response channels: one of each per degree of freedom",
            forces.len(),
            displacements.len()
        )));
    }
    let kinds = if layout.kinds.is_empty() {
        displacements
            .iter()
            .map(|f| {
                response_kind(f.numerator.data_type).ok_or_else(|| {
                    fail(format!(
                        "the response at node {} direction {} has data type {}, not \
                         displacement (8), velocity (11) or acceleration (12): say which it is",
                        f.response.node,
                        f.response.direction,
                        f.numerator.data_type.code()
                    ))
                })
            })
            .collect::<Result<Vec<_>>>()?
    } else {
        Response::per_channel(&layout.kinds, displacements.len())?
    };
    let mut dx_common: Option<f64> = None;
    let mut warnings = Vec::new();
    let mut channel = |f: &Function, given: Option<&str>, force: bool| -> Result<(f64, Vec<f64>)> {
        let Abscissa::Even { dx, x0, .. } = f.abscissa else {
            return Err(fail(format!(
                "the time history at node {} direction {} has an uneven abscissa",
                f.response.node, f.response.direction
            )));
        };
        match dx_common {
            None => dx_common = Some(dx),
            Some(d) if d.to_bits() == dx.to_bits() => {}
            Some(d) => {
                return Err(fail(format!(
                    "time increments differ: {d} s and {dx} s (node {} direction {})",
                    f.response.node, f.response.direction
                )));
            }
        }
        let Ordinate::Real(values) = &f.ordinate else {
            return Err(fail(format!(
                "the time history at node {} direction {} is complex",
                f.response.node, f.response.direction
            )));
        };
        let sign = if f.response.direction < 0 { -1.0 } else { 1.0 };
        let dof = UffChannel::Dof {
            node: f.response.node,
            direction: f.response.direction,
        };
        let stated = given.or_else(|| stated_unit(&f.numerator.units));
        let to_si = match stated.map(|u| (u, crate::units::Unit::named(u))) {
            None => 1.0,
            Some((_, Some(u))) if u.fits(force) => u.to_si,
            // A units label this crate does not know: the values as read (SI), with a warning
            // naming it; a unit the user gives is never guessed.
            Some((unit, None)) if given.is_none() => {
                warnings.push(Warning::UnknownUnit {
                    record: crate::error::excerpt(name),
                    channel: dof.to_string(),
                    unit: crate::error::excerpt(unit),
                    force,
                });
                1.0
            }
            Some((unit, _)) => {
                return Err(fail(format!(
                    "the time history at node {} direction {} has unit `{}`, not a {} unit \
                     this crate converts (N, kN, lbf; m, mm, um, in, mil; m/s, in/s; m/s^2, \
                     g): give --{}",
                    f.response.node,
                    f.response.direction,
                    crate::error::excerpt(unit),
                    if force { "force" } else { "response" },
                    if force { "force-unit" } else { "disp-unit" }
                )));
            }
        };
        // Exactly 1 and a positive direction: the values stay bit for bit as read.
        #[allow(clippy::float_cmp)]
        let values = if sign * to_si == 1.0 {
            values.clone()
        } else {
            values.iter().map(|v| sign * (v * to_si)).collect()
        };
        Ok((x0, values))
    };
    let units = |given: &[String], i: usize, n: usize, force: bool| -> Result<Option<String>> {
        if given.is_empty() {
            return Ok(None);
        }
        crate::units::given(given, i, n)
            .map(|u| Some(u.to_owned()))
            .ok_or_else(|| {
                fail(format!(
                    "--{} names {} units for {n} channels: give one for all or one per channel",
                    if force { "force-unit" } else { "disp-unit" },
                    given.len()
                ))
            })
    };
    let force_channels = forces
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            let given = units(&layout.force_units, i, forces.len(), true)?;
            channel(f, given.as_deref(), true)
        })
        .collect::<Result<Vec<_>>>()?;
    let displacement_channels = displacements
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            let given = units(&layout.response_units, i, displacements.len(), false)?;
            channel(f, given.as_deref(), false)
        })
        .collect::<Result<Vec<_>>>()?;
    let dx = dx_common.unwrap_or(f64::NAN);
    let [force_channels, displacement_channels] =
        aligned(force_channels, displacement_channels, dx, |k| {
            let f = if k < forces.len() {
                forces[k]
            } else {
                displacements[k - forces.len()]
            };
            (f.response.node, f.response.direction)
        })
        .map_err(fail)?;
    Ok(
        Record::new(name, 1.0 / dx, force_channels, displacement_channels)?
            .with_responses(kinds)?
            .with_warnings(warnings),
    )
}

/// The unit a units label (records 8–11) states: none for a blank label or `NONE` (any case),
/// as most writers leave it.
fn stated_unit(label: &str) -> Option<&str> {
    let label = label.trim();
    (!label.is_empty() && !label.eq_ignore_ascii_case("none")).then_some(label)
}

/// The channels of a load case on one time grid: each channel's start time `x0` (record 7)
/// must lie a whole number of steps `dx` from the others' (within
/// [`TIME_GRID_TOLERANCE`](crate::tolerance::TIME_GRID_TOLERANCE) of a step); the channels are
/// then trimmed to the span they all cover, so that sample `k` of every channel is one instant.
/// Channels stamped at one start are returned as they are.
///
/// # Errors
/// A message naming the channel (`node`, `direction` from `dof(k)`, forces first) whose start
/// is not on the others' grid.
fn aligned(
    forces: Vec<(f64, Vec<f64>)>,
    responses: Vec<(f64, Vec<f64>)>,
    dx: f64,
    dof: impl Fn(usize) -> (i64, i64),
) -> std::result::Result<[Vec<Vec<f64>>; 2], String> {
    let first = forces.first().map_or(0.0, |c| c.0);
    let all = || forces.iter().chain(&responses);
    if all().all(|c| c.0.to_bits() == first.to_bits()) {
        let strip = |v: Vec<(f64, Vec<f64>)>| v.into_iter().map(|c| c.1).collect();
        return Ok([strip(forces), strip(responses)]);
    }
    // Offsets in whole steps from the first force channel's start.
    let mut steps = Vec::new();
    for (k, (x0, _)) in all().enumerate() {
        let s = (x0 - first) / dx;
        let whole = s.round();
        if !((s - whole).abs() <= crate::tolerance::TIME_GRID_TOLERANCE && whole.abs() < 1e15) {
            let (node, direction) = dof(k);
            return Err(format!(
                "the channel at node {node} direction {direction} starts at {x0} s, {s:.3} \
                 steps of {dx} s from the first force channel's {first} s: not a whole number of \
                 samples, so its samples are not simultaneous with the others'"
            ));
        }
        steps.push(whole as i64);
    }
    let start = steps.iter().copied().max().unwrap_or(0);
    let end = all()
        .zip(&steps)
        .map(|((_, v), &s)| s.saturating_add(v.len() as i64))
        .min()
        .unwrap_or(0)
        .max(start);
    let trim = |v: Vec<(f64, Vec<f64>)>, steps: &[i64]| -> Vec<Vec<f64>> {
        v.into_iter()
            .zip(steps)
            .map(|((_, values), &s)| {
                let from = usize::try_from(start - s).unwrap_or(0);
                let to = usize::try_from(end - s).unwrap_or(0);
                values
                    .get(from..to)
                    .map(<[f64]>::to_vec)
                    .unwrap_or_default()
            })
            .collect()
    };
    let n_forces = forces.len();
    Ok([
        trim(forces, &steps[..n_forces]),
        trim(responses, &steps[n_forces..]),
    ])
}

/// The time histories of a load case as `NODE±DIR` (`id`), for a message.
fn inventory<'a>(histories: impl Iterator<Item = &'a Function>) -> String {
    let names: Vec<String> = histories
        .map(|f| {
            let dof = UffChannel::Dof {
                node: f.response.node,
                direction: f.response.direction,
            };
            format!("{dof} `{}`", crate::error::excerpt(f.id[0].trim()))
        })
        .collect();
    names.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Channels whose start times `x0` differ by whole samples are aligned on one time grid
    /// (before, a response stamped 5 samples late was used as simultaneous: C_xx +8.7 %); a
    /// start between samples is refused naming the channel.
    #[test]
    fn start_times_align_channels_or_refuse() {
        let dt = 1e-3;
        let wave = |a: f64| -> Vec<f64> { (0..64).map(|k| (a * k as f64).sin()).collect() };
        let (fx, fy, x, y) = (wave(0.3), wave(0.7), wave(0.2), wave(0.9));
        let functions = [
            Function::time_response(1, 1, 13, 0.0, dt, fx.clone()),
            Function::time_response(1, 2, 13, 0.0, dt, fy[..60].to_vec()),
            Function::time_response(1, 1, 8, 5.0 * dt, dt, x[5..].to_vec()),
            Function::time_response(1, 2, 8, 2.0 * dt, dt, y[2..].to_vec()),
        ];
        let r = &records(&functions, "late.uff").unwrap()[0];
        // The common span is samples 5..60 of the first force channel's grid.
        assert_eq!(r.len(), 55);
        assert_eq!(r.force(0), &fx[5..60]);
        assert_eq!(r.force(1), &fy[5..60]);
        assert_eq!(r.displacement(0), &x[5..60]);
        assert_eq!(r.displacement(1), &y[5..60]);
        // Half a sample late: no whole-sample shift makes it simultaneous.
        let mut off = functions.clone();
        off[3] = Function::time_response(1, 2, 8, 2.5 * dt, dt, y[2..].to_vec());
        let e = records(&off, "off.uff").unwrap_err();
        assert_eq!(e.kind(), "inconsistent_records");
        assert!(
            e.to_string()
                .contains("node 1 direction 2 starts at 0.0025 s, 2.500 steps"),
            "{e}"
        );
        // One start for all (the usual case): nothing is trimmed.
        let same: Vec<Function> = [&fx, &fy, &x, &y]
            .iter()
            .zip([(2, 13), (1, 13), (1, 8), (2, 8)])
            .map(|(v, (dir, t))| Function::time_response(3, dir, t, 0.25, dt, v.to_vec()))
            .collect();
        let r = &records(&same, "same.uff").unwrap()[0];
        assert_eq!((r.len(), r.force(1)), (64, &fx[..]));
    }
}
