//! Record files in: which columns or channels hold the forces and responses ([`Channels`]),
//! one file's records ([`read_file`]), and the files after the first parsed ahead on worker
//! threads ([`ReadAhead`]).

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, sync_channel};

use crate::error::{Error, Result};
use crate::io::{self, CsvLayout};
use crate::mat::{MatChannel, MatLayout, is_mat};
use crate::records::{Record, Response};
use crate::tdms::{RecordBy, TdmsLayout};
use crate::uff::{UffChannel, UffLayout};

use super::Geometry;

/// Where the forces and responses are in the record files, and what the responses measure.
///
/// # Examples
/// ```
/// use bearing_ident::job::Channels;
/// let channels = Channels::default();
/// assert_eq!(channels.csv.forces, ["fx", "fy"]);
/// assert!(channels.responses.is_empty()); // displacement unless a file says otherwise
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Channels {
    /// The columns of CSV files.
    pub csv: CsvLayout,
    /// The channels of Universal Files (`.uff`, `.unv`).
    pub uff: UffLayout,
    /// The channels of MATLAB MAT-files (`.mat`), and the sample rate when they hold none.
    pub mat: MatLayout,
    /// What the response channels measure: empty for the files' own word (displacement for
    /// CSV, the data type for Universal Files), one kind for all, or one per degree of
    /// freedom.
    pub responses: Vec<Response>,
    /// Sensor planes moved to the bearing plane after reading ([`Geometry::apply`]), if the
    /// probes are not at the bearing.
    pub geometry: Option<Geometry>,
    /// TDMS files (`.tdms`): one record per file or per group. Their channels are named as
    /// CSV columns are ([`Channels::csv`]: `GROUP/CHANNEL`, or `CHANNEL` when unique).
    pub record_by: RecordBy,
    /// Units of the force channels ([`crate::units::Unit::named`]), one for all or one per
    /// channel: each channel is converted to SI on reading. None: SI, or as a TDMS file
    /// (`unit_string`) or a Universal File (units label of the ordinate) states them.
    pub force_units: Vec<String>,
    /// Units of the response channels, as `force_units`.
    pub response_units: Vec<String>,
}

impl Channels {
    /// The channels as `identify` names them: `force` and `disp` (CSV column names, or
    /// Universal File channels `NODE+DIR` / `id:TEXT`; empty for the defaults), `responses`
    /// (what the response channels measure: none, one for all, or one per degree of freedom;
    /// the default CSV response columns follow it, `vx`, `ax`), the CSV `time` column, for
    /// `files` (when one is a Universal File, `force` and `disp` are parsed as its channels
    /// too; when all are, the kinds are checked by its reader against its channels).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for other than one (or, for two planes, two) response columns
    /// per force column, a Universal File channel that does not parse, a number of response kinds that is
    /// neither one nor one per response column, or a channel named twice
    /// ([`Channels::check`]).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::Response;
    /// use bearing_ident::job::Channels;
    /// let files = [std::path::PathBuf::from("hit-1.csv")];
    /// let c = Channels::named(&[], &[], &[Response::Velocity], "t", &files)?;
    /// assert_eq!(c.csv.displacements, ["vx", "vy"]);
    /// let three = ["fx".into(), "fy".into(), "fz".into()];
    /// let e = Channels::named(&three, &[], &[], "t", &files).unwrap_err();
    /// assert_eq!(e.kind(), "invalid_argument");
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn named(
        force: &[String],
        disp: &[String],
        responses: &[Response],
        time: &str,
        files: &[PathBuf],
    ) -> Result<Self> {
        let defaults = CsvLayout::default();
        let pick = |given: &[String], default: Vec<String>| {
            if given.is_empty() {
                default
            } else {
                given.to_vec()
            }
        };
        let csv = CsvLayout {
            time: time.to_owned(),
            forces: pick(force, defaults.forces),
            displacements: pick(disp, response_columns(&defaults.displacements, responses)),
        };
        let invalid = |option, message| Error::InvalidOption { option, message };
        // Two response columns per force are two measurement planes, for a two-plane
        // geometry ([`Geometry::reading_layout`] checks that one is given).
        let (f, x) = (csv.forces.len(), csv.displacements.len());
        if x != f && x != 2 * f {
            return Err(invalid(
                "disp",
                format!(
                    "--force names {f} columns and --disp {x}: one of each per degree of \
                     freedom (or two per force, at two planes, with a two-plane geometry)"
                ),
            ));
        }
        let uff_layout = if files.iter().any(|f| is_uff(f)) {
            let parse = |given: &[String], option: &'static str| {
                given
                    .iter()
                    .map(|c| {
                        c.parse::<UffChannel>()
                            .map_err(|e| invalid(option, format!("--{option}: {e}")))
                    })
                    .collect::<Result<Vec<_>>>()
            };
            UffLayout {
                forces: parse(force, "force")?,
                responses: parse(disp, "disp")?,
                kinds: responses.to_vec(),
                ..UffLayout::default()
            }
        } else {
            UffLayout::default()
        };
        if !responses.is_empty()
            && responses.len() != 1
            && responses.len() != csv.displacements.len()
            && !files.iter().all(|f| is_uff(f))
        {
            return Err(invalid(
                "response",
                format!(
                    "--response names {} kinds for {} response columns: give one for all or \
                     one per degree of freedom",
                    responses.len(),
                    csv.displacements.len()
                ),
            ));
        }
        let mat = if files.iter().any(|f| is_mat(f)) {
            let parse = |names: &[String], option: &'static str| {
                names
                    .iter()
                    .map(|c| {
                        c.parse::<MatChannel>().map_err(|e| match e {
                            Error::InvalidOption { message, .. } => invalid(option, message),
                            e => e,
                        })
                    })
                    .collect::<Result<Vec<_>>>()
            };
            MatLayout {
                forces: parse(&csv.forces, "force")?,
                responses: parse(&csv.displacements, "disp")?,
                time: csv.time.clone(),
                rate: None,
            }
        } else {
            MatLayout::default()
        };
        let channels = Channels {
            csv,
            uff: uff_layout,
            mat,
            responses: responses.to_vec(),
            geometry: None,
            record_by: RecordBy::File,
            force_units: Vec::new(),
            response_units: Vec::new(),
        };
        // A column given as both force and response, before any file is read.
        channels.check()?;
        Ok(channels)
    }
}

/// Default CSV names of response columns: the displacement names (`x, y`) prefixed `v` for
/// velocity and `a` for acceleration (`vx, vy`, `ax, ay`), by `kinds` (none: displacement; one
/// for all; or one per column). What `simulate --response` writes and `identify --response`
/// reads unless `--disp` names the columns.
///
/// # Examples
/// ```
/// use bearing_ident::Response;
/// use bearing_ident::job::response_columns;
/// let x = ["x".to_string(), "y".to_string()];
/// assert_eq!(response_columns(&x, &[Response::Acceleration]), ["ax", "ay"]);
/// assert_eq!(response_columns(&x, &[]), ["x", "y"]);
/// ```
pub fn response_columns(displacements: &[String], kinds: &[Response]) -> Vec<String> {
    displacements
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let kind = match kinds {
                [one] => *one,
                _ => kinds.get(i).copied().unwrap_or_default(),
            };
            match kind {
                Response::Displacement => x.clone(),
                Response::Velocity => format!("v{x}"),
                Response::Acceleration => format!("a{x}"),
            }
        })
        .collect()
}

impl Channels {
    /// The CSV columns read: [`Channels::csv`], or as the geometry reads them
    /// ([`Geometry::reading_layout`]: two-plane records hold each force twice).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for response columns that are not one per force column, or
    /// two with a two-plane geometry.
    pub fn layout(&self) -> Result<Cow<'_, CsvLayout>> {
        match &self.geometry {
            Some(g) if g.is_two_plane() => g.reading_layout(&self.csv),
            _ if self.csv.displacements.len() != self.csv.forces.len() => {
                Err(Error::InvalidOption {
                    option: "disp",
                    message: format!(
                        "--force names {} columns and --disp {}: one of each per degree of \
                         freedom, or two per force with a two-plane [geometry]",
                        self.csv.forces.len(),
                        self.csv.displacements.len()
                    ),
                })
            }
            _ => Ok(Cow::Borrowed(&self.csv)),
        }
    }

    /// Checks that no channel is named twice: a CSV column (time, force or response) or a
    /// Universal File channel (node and axis, either sign, or ID text) given as both a force
    /// and a response, or twice among either, would be read as two channels of one signal.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the channel and the options that name it.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::job::Channels;
    /// let mut channels = Channels::default();
    /// assert!(channels.check().is_ok());
    /// channels.csv.displacements = vec!["x".into(), "fy".into()];
    /// let e = channels.check().unwrap_err();
    /// assert_eq!(e.kind(), "invalid_argument");
    /// assert!(e.to_string().contains("`fy`"), "{e}");
    /// ```
    pub fn check(&self) -> Result<()> {
        let csv = std::iter::once(("time", &self.csv.time))
            .chain(self.csv.forces.iter().map(|c| ("force", c)))
            .chain(self.csv.displacements.iter().map(|c| ("disp", c)));
        let names: Vec<(&'static str, String)> = csv.map(|(o, c)| (o, c.clone())).collect();
        let same_sensor = |a: &UffChannel, b: &UffChannel| match (a, b) {
            (
                UffChannel::Dof { node, direction },
                UffChannel::Dof {
                    node: n2,
                    direction: d2,
                },
            ) => node == n2 && direction.abs() == d2.abs(),
            (a, b) => a == b,
        };
        let uff: Vec<(&'static str, &UffChannel)> = (self.uff.forces.iter().map(|c| ("force", c)))
            .chain(self.uff.responses.iter().map(|c| ("disp", c)))
            .collect();
        let twice = |(a, b): (&'static str, &'static str), name: String| {
            let options = if a == b {
                format!("twice in --{a}")
            } else {
                format!("in --{a} and in --{b}")
            };
            Err(Error::InvalidOption {
                option: if a == "time" { b } else { a },
                message: format!(
                    "channel `{}` is named {options}: a channel is read once, as one force, \
                     one response or the time (for swapped force and response columns, \
                     exchange --force and --disp)",
                    crate::error::excerpt(&name)
                ),
            })
        };
        for (i, (a, x)) in names.iter().enumerate() {
            if let Some((b, _)) = names[i + 1..].iter().find(|(_, y)| y == x) {
                return twice((*a, *b), x.clone());
            }
        }
        for (i, (a, x)) in uff.iter().enumerate() {
            if let Some((b, _)) = uff[i + 1..].iter().find(|(_, y)| same_sensor(x, y)) {
                return twice((*a, *b), x.to_string());
            }
        }
        for name in &self.force_units {
            unit_factor(name, true)?;
        }
        for name in &self.response_units {
            unit_factor(name, false)?;
        }
        Ok(())
    }
}

/// Whether `path` is a Universal File (`.uff`, `.unv`, any case) rather than a CSV record.
///
/// # Examples
/// ```
/// use bearing_ident::job::is_uff;
/// assert!(is_uff("rig/hit-3.UNV".as_ref()));
/// assert!(!is_uff("rig/hit-3.csv".as_ref()));
/// ```
pub fn is_uff(path: &Path) -> bool {
    path.extension()
        .and_then(|x| x.to_str())
        .is_some_and(|x| x.eq_ignore_ascii_case("uff") || x.eq_ignore_ascii_case("unv"))
}

/// Whether `path` is a TDMS file (`.tdms`, any case).
///
/// # Examples
/// ```
/// use bearing_ident::job::is_tdms;
/// assert!(is_tdms("rig/run3.TDMS".as_ref()));
/// assert!(!is_tdms("rig/run3.tdms_index".as_ref()));
/// ```
pub fn is_tdms(path: &Path) -> bool {
    path.extension()
        .and_then(|x| x.to_str())
        .is_some_and(|x| x.eq_ignore_ascii_case("tdms"))
}

/// Every record of a file, at least one: one from a CSV file, one per load case of the time
/// histories of a Universal File ([`crate::uff::records_with`]), one per TDMS file or group
/// ([`crate::tdms::records`]), one per element of the struct or cell arrays of a MAT-file
/// ([`crate::mat::records`]), with the response kinds of `channels`.
///
/// # Errors
/// The reader's errors, naming the file (and line, load case or channel);
/// [`Error::UffRecord`] for a Universal File without a record.
///
/// # Examples
/// ```
/// use bearing_ident::job::{Channels, read_file};
/// use bearing_ident::{io, Record};
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("hit.csv");
/// let r = Record::new("hit", 100.0, vec![vec![1.0; 16]; 2], vec![vec![0.5; 16]; 2])?;
/// io::write_record(&path, &r, &Channels::default().csv)?;
/// let back = read_file(&path, &Channels::default())?;
/// assert_eq!(back.len(), 1);
/// assert_eq!(back[0].displacement(1)[3], 0.5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_file(path: &Path, channels: &Channels) -> Result<Vec<Record>> {
    let records = read_any(path, channels, |path| {
        io::read_record(path, &*channels.layout()?)
    })?;
    if records.is_empty() {
        return Err(Error::UffRecord {
            path: path.display().to_string(),
            load_case: 0,
            message: "no record".into(),
        });
    }
    Ok(records)
}

/// The first record of a file ([`read_file`]).
///
/// # Errors
/// As [`read_file`].
pub fn read_first(path: &Path, channels: &Channels) -> Result<Record> {
    Ok(read_file(path, channels)?.swap_remove(0))
}

/// The records of a file read by `reader` (its buffers kept across files).
fn read_records(
    path: &Path,
    channels: &Channels,
    reader: &mut io::CsvReader,
) -> Result<Vec<Record>> {
    read_any(path, channels, |path| reader.read(path))
}

/// The records of a file of any format, a CSV file read by `csv`, in SI with the response
/// kinds of `channels`, moved to the bearing plane by its geometry.
fn read_any(
    path: &Path,
    channels: &Channels,
    csv: impl FnOnce(&Path) -> Result<Record>,
) -> Result<Vec<Record>> {
    let records = if is_uff(path) {
        read_uff(path, channels)?
    } else if is_tdms(path) {
        read_tdms(path, channels)?
    } else if is_mat(path) {
        in_si_all(read_mat(path, channels)?, channels)?
    } else {
        vec![with_kinds(in_si(csv(path)?, channels)?, channels)?]
    };
    moved(records, channels)
}

/// `records` moved to the bearing plane by the geometry of `channels`, if it has one.
fn moved(records: Vec<Record>, channels: &Channels) -> Result<Vec<Record>> {
    match &channels.geometry {
        None => Ok(records),
        Some(g) => records.into_iter().map(|r| g.apply(r)).collect(),
    }
}

/// The records of a Universal File, one per load case, converted to SI from the units given
/// or, failing those, the units labels of the file.
fn read_uff(path: &Path, channels: &Channels) -> Result<Vec<Record>> {
    let functions = crate::uff::read(path)?;
    let layout = UffLayout {
        force_units: channels.force_units.clone(),
        response_units: channels.response_units.clone(),
        ..channels.uff.clone()
    };
    crate::uff::records_with(&functions, &path.display().to_string(), &layout)
}

/// The records of a TDMS file, its channels named as CSV columns are.
fn read_tdms(path: &Path, channels: &Channels) -> Result<Vec<Record>> {
    let columns = channels.layout()?;
    let layout = TdmsLayout {
        time: columns.time.clone(),
        forces: columns.forces.clone(),
        responses: columns.displacements.clone(),
        record_by: channels.record_by,
        force_units: channels.force_units.clone(),
        response_units: channels.response_units.clone(),
    };
    let file = crate::tdms::read(path)?;
    crate::tdms::records(&file, &path.display().to_string(), &layout)?
        .into_iter()
        .map(|r| with_kinds(r, channels))
        .collect()
}

/// The records of a MAT-file, one per element of the struct or cell arrays its channels are
/// in.
fn read_mat(path: &Path, channels: &Channels) -> Result<Vec<Record>> {
    let variables = crate::mat::read(path)?;
    crate::mat::records(&variables, &path.display().to_string(), &channels.mat)?
        .into_iter()
        .map(|r| with_kinds(r, channels))
        .collect()
}

/// `record` with the response kinds of `channels`, if any were given.
fn with_kinds(record: Record, channels: &Channels) -> Result<Record> {
    if channels.responses.is_empty() {
        return Ok(record);
    }
    let kinds = Response::per_channel(&channels.responses, record.dofs())?;
    record.with_responses(kinds)
}

/// `record` with each channel multiplied by the SI factor of its unit as given
/// ([`Channels::force_units`], [`Channels::response_units`]; none: as read). TDMS records and
/// Universal Files are converted by their readers, which know the units the file states.
fn in_si(record: Record, channels: &Channels) -> Result<Record> {
    if channels.force_units.is_empty() && channels.response_units.is_empty() {
        return Ok(record);
    }
    let n = record.dofs();
    let factors = |given: &[String], force: bool| -> Result<Vec<f64>> {
        let option = if force { "force-unit" } else { "disp-unit" };
        (0..n)
            .map(|i| match crate::units::given(given, i, n) {
                None if given.is_empty() => Ok(1.0),
                None => Err(Error::InvalidOption {
                    option,
                    message: format!(
                        "--{option} names {} units for {n} channels: give one for all or one \
                         per channel",
                        given.len()
                    ),
                }),
                Some(name) => unit_factor(name, force),
            })
            .collect()
    };
    let (f, x) = (
        factors(&channels.force_units, true)?,
        factors(&channels.response_units, false)?,
    );
    // Exactly 1 (SI given): the record stays bit for bit as read.
    #[allow(clippy::float_cmp)]
    if f.iter().chain(&x).all(|&k| k == 1.0) {
        return Ok(record);
    }
    let scaled = |v: &[f64], k: f64| v.iter().map(|s| s * k).collect::<Vec<f64>>();
    let kinds = record.responses().to_vec();
    let warnings = record.warnings().to_vec();
    Record::new(
        record.label(),
        record.sample_rate(),
        (0..n).map(|i| scaled(record.force(i), f[i])).collect(),
        (0..n)
            .map(|i| scaled(record.displacement(i), x[i]))
            .collect(),
    )?
    .with_responses(kinds)
    .map(|r| r.with_warnings(warnings))
}

/// The factor to SI of a unit the user gives for a force (`force`) or response channel.
///
/// # Errors
/// [`Error::InvalidOption`] (`force-unit`, `disp-unit`) for a unit this crate does not know or
/// one of another quantity: a given unit is never guessed.
fn unit_factor(name: &str, force: bool) -> Result<f64> {
    let option = if force { "force-unit" } else { "disp-unit" };
    match crate::units::Unit::named(name) {
        Some(u) if u.fits(force) => Ok(u.to_si),
        _ => Err(Error::InvalidOption {
            option,
            message: format!(
                "--{option}: `{}` is not a {} unit this crate knows (N, kN, lbf; m, mm, um, \
                 in, mil; m/s, in/s; m/s^2, g)",
                crate::error::excerpt(name),
                if force { "force" } else { "response" }
            ),
        }),
    }
}

/// [`in_si`] of every record.
fn in_si_all(records: Vec<Record>, channels: &Channels) -> Result<Vec<Record>> {
    records.into_iter().map(|r| in_si(r, channels)).collect()
}

/// The files after the first, parsed ahead on worker threads: worker `w` of `k` reads files
/// `1 + w, 1 + w + k, …` in turn, each with its own [`io::CsvReader`], and hands each file's
/// records over a channel of one slot, so at most two files' records per worker wait. The
/// iterator hands them out in file order, each exactly once; the first file, which the caller
/// reads, is not read here. Dropping it stops the workers at their next file.
pub(crate) struct ReadAhead {
    slots: Vec<Receiver<Result<Vec<Record>>>>,
    /// Index (in the file list) of the next file handed out, from 1.
    next: usize,
    /// Files in all, the first included.
    files: usize,
}

/// Most worker threads parsing files.
const READERS: usize = 4;

impl ReadAhead {
    pub(crate) fn spawn<'s>(
        scope: &'s std::thread::Scope<'s, '_>,
        files: &'s [PathBuf],
        channels: &'s Channels,
    ) -> Self {
        let rest = files.get(1..).unwrap_or_default();
        let k = std::thread::available_parallelism()
            .map_or(1, std::num::NonZero::get)
            .clamp(1, READERS)
            .min(rest.len().max(1));
        let slots = (0..k)
            .map(|w| {
                let (tx, rx) = sync_channel(1);
                // A layout the geometry refuses fails the first file, read before these.
                let layout = channels
                    .layout()
                    .map_or_else(|_| channels.csv.clone(), Cow::into_owned);
                let mut reader = io::CsvReader::new(layout);
                scope.spawn(move || {
                    for path in rest.iter().skip(w).step_by(k) {
                        if tx.send(read_records(path, channels, &mut reader)).is_err() {
                            return;
                        }
                    }
                });
                rx
            })
            .collect();
        Self {
            slots,
            next: 1,
            files: files.len(),
        }
    }

    /// Index (in the file list) of the file the next call of [`Iterator::next`] hands out.
    pub(crate) fn position(&self) -> usize {
        self.next
    }
}

impl Iterator for ReadAhead {
    type Item = Result<Vec<Record>>;

    /// The records of the next file after the first, in file order; `None` after the last.
    fn next(&mut self) -> Option<Self::Item> {
        if self.next >= self.files {
            return None;
        }
        let i = self.next - 1;
        self.next += 1;
        let k = self.slots.len();
        Some(self.slots[i % k].recv().unwrap_or_else(|_| {
            Err(Error::Io {
                path: String::new(),
                message: "a reading thread stopped".into(),
            })
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The read-ahead hands out every file after the first once, in order, for any count of
    /// files and workers.
    #[test]
    fn read_ahead_hands_out_every_file_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let channels = Channels::default();
        let paths: Vec<PathBuf> = (0..9)
            .map(|i| {
                let path = dir.path().join(format!("r{i}.csv"));
                let r = Record::new(
                    format!("r{i}"),
                    10.0,
                    vec![vec![i as f64; 8]; 2],
                    vec![vec![1.0; 8]; 2],
                )
                .unwrap();
                io::write_record(&path, &r, &channels.csv).unwrap();
                path
            })
            .collect();
        for n in 0..=paths.len() {
            let files = &paths[..n];
            let labels: Vec<String> = std::thread::scope(|scope| {
                ReadAhead::spawn(scope, files, &channels)
                    .flat_map(|f| f.unwrap())
                    .map(|r| r.label().to_owned())
                    .collect()
            });
            let expected: Vec<String> = files
                .iter()
                .skip(1)
                .map(|p| p.display().to_string())
                .collect();
            assert_eq!(labels, expected, "{n} files");
        }
    }
}
