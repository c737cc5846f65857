//! TDMS files (NI LabVIEW and DAQmx): groups of channels with their properties, read into
//! scaled samples, and records built from them; records written as one (feature `tdms`, no
//! dependencies).
//!
//! A TDMS file is a run of segments. Each begins with a 28-byte lead-in: the tag `TDSm`, a
//! table of contents (which parts the segment holds: metadata, a new object list, raw data,
//! interleaved data, big-endian numbers, DAQmx raw data), a version, the length of the rest of
//! the segment and the offset of its raw data. Metadata lists objects by path (`/`, `/'group'`,
//! `/'group'/'channel'`) with their properties and, for a channel, a raw data index (data type
//! and number of values per chunk). A segment may repeat the previous object list, change only
//! what it names (incremental metadata), or keep the previous metadata whole. Its raw data are
//! whole chunks, each holding every listed channel's values one channel after another
//! (contiguous) or sample by sample (interleaved). A channel's samples are its values over all
//! segments, scaled by NI's linear or polynomial scaling properties
//! (`NI_Scale[n]_Scale_Type`) when it has any ([`read`], [`parse`]).
//!
//! Every size the file declares is checked against the bytes that hold it before anything is
//! allocated: a truncated file, a segment longer than the file, raw data that are not whole
//! chunks or a declared count past the file are [`Error::Tdms`] naming the byte offset, and a
//! file holds at most [`MAX_VALUES`](crate::limits::MAX_VALUES) values; memory is at most the
//! file's bytes and eight bytes per value read.

mod parse;
mod records;
mod scaling;
mod write;

use std::path::Path;

#[cfg(doc)]
use crate::error::Error;
use crate::error::Result;

pub use records::{RecordBy, TdmsLayout, records};
pub use write::write;

/// A TDMS file read whole: its own properties and its groups in order of first appearance.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TdmsFile {
    /// Properties of the file object (`/`).
    pub properties: Vec<Property>,
    /// Groups, in order of first appearance.
    pub groups: Vec<Group>,
}

/// A group of channels (`/'group'`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Group {
    /// The group's name.
    pub name: String,
    /// Its properties.
    pub properties: Vec<Property>,
    /// Its channels, in order of first appearance.
    pub channels: Vec<Channel>,
}

/// A channel (`/'group'/'channel'`): its properties and its samples.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Channel {
    /// The channel's name.
    pub name: String,
    /// Its properties (`wf_increment`, `unit_string`, `NI_Scale[0]_Linear_Slope`, …).
    pub properties: Vec<Property>,
    /// The TDMS data type of its raw values (`10` double, `3` int32, `0xFFFFFFFF` DAQmx raw
    /// data, …; `0` for a channel without data).
    pub data_type: u32,
    /// Its samples, scaled: every segment's values in order, through the channel's linear or
    /// polynomial scaling; timestamps as seconds after the channel's first. Empty for a
    /// channel without numeric data (strings), with [`Channel::unreadable`] saying why.
    pub values: Vec<f64>,
    /// Why the samples could not be read, if they could not: strings, complex or extended
    /// numbers, a scaling other than linear or polynomial.
    pub unreadable: Option<String>,
}

/// A named property of a file, group or channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Property {
    /// Its name (`wf_increment`).
    pub name: String,
    /// Its value.
    pub value: Value,
}

/// The value of a [`Property`].
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A signed integer (`i8` … `i64`).
    Int(i64),
    /// An unsigned integer (`u8` … `u64`).
    Uint(u64),
    /// A floating-point number (single or double).
    Float(f64),
    /// A string.
    Text(String),
    /// A boolean.
    Bool(bool),
    /// A timestamp: seconds since 1904-01-01 00:00 UTC and the fraction of a second in
    /// units of 2⁻⁶⁴ s.
    Time {
        /// Whole seconds since 1904-01-01 00:00 UTC.
        seconds: i64,
        /// Fraction of a second, in units of 2⁻⁶⁴ s.
        fraction: u64,
    },
    /// A value of a type this reader does not interpret (extended or complex numbers), with
    /// its TDMS data type.
    Other(u32),
}

impl Value {
    /// The value as a number, if it is one (integers, floats, a boolean as 0 or 1).
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::tdms::Value;
    /// assert_eq!(Value::Int(-3).as_f64(), Some(-3.0));
    /// assert_eq!(Value::Text("V".into()).as_f64(), None);
    /// ```
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Value::Int(v) => Some(v as f64),
            Value::Uint(v) => Some(v as f64),
            Value::Float(v) => Some(v),
            Value::Bool(v) => Some(f64::from(u8::from(v))),
            _ => None,
        }
    }
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Int(v) => write!(f, "{v}"),
            Value::Uint(v) => write!(f, "{v}"),
            Value::Float(v) => write!(f, "{v}"),
            Value::Text(v) => write!(f, "{v}"),
            Value::Bool(v) => write!(f, "{v}"),
            Value::Time { seconds, fraction } => {
                write!(
                    f,
                    "{} s after 1904-01-01",
                    *seconds as f64 + *fraction as f64 / TWO_64
                )
            }
            Value::Other(code) => write!(f, "(data type {code:#x})"),
        }
    }
}

/// 2⁶⁴, the units of a timestamp's fraction per second.
const TWO_64: f64 = 18_446_744_073_709_551_616.0;

/// The value of the property `name` in `properties`, if there is one.
///
/// # Examples
/// ```
/// use bearing_ident::tdms::{Property, Value, property};
/// let p = vec![Property { name: "unit_string".into(), value: Value::Text("N".into()) }];
/// assert_eq!(property(&p, "unit_string"), Some(&Value::Text("N".into())));
/// assert_eq!(property(&p, "wf_increment"), None);
/// ```
pub fn property<'a>(properties: &'a [Property], name: &str) -> Option<&'a Value> {
    properties.iter().find(|p| p.name == name).map(|p| &p.value)
}

impl Channel {
    /// The channel's unit as its `unit_string` property states it, if it states one.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::tdms::{Channel, Property, Value};
    /// let mut c = Channel::default();
    /// assert_eq!(c.unit(), None);
    /// c.properties.push(Property { name: "unit_string".into(), value: Value::Text("lbf".into()) });
    /// assert_eq!(c.unit(), Some("lbf"));
    /// ```
    pub fn unit(&self) -> Option<&str> {
        match property(&self.properties, "unit_string") {
            Some(Value::Text(t)) if !t.trim().is_empty() => Some(t.trim()),
            _ => None,
        }
    }
}

/// Longest TDMS file read, in bytes: the bytes of [`MAX_VALUES`](crate::limits::MAX_VALUES)
/// doubles (2 GiB).
pub const MAX_FILE_BYTES: u64 = crate::limits::MAX_VALUES * 8;

/// Reads a TDMS file. Its index file (`.tdms_index`) is not needed: the file's own lead-ins
/// and metadata hold everything the index repeats.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read; [`Error::FileLimit`] past [`MAX_FILE_BYTES`];
/// [`Error::Tdms`] for a malformed file, as [`parse`].
///
/// # Examples
/// ```
/// let e = bearing_ident::tdms::read("/nonexistent/run3.tdms").unwrap_err();
/// assert_eq!(e.kind(), "io_error");
/// ```
pub fn read(path: impl AsRef<Path>) -> Result<TdmsFile> {
    let path = path.as_ref();
    let label = path.display().to_string();
    let bytes =
        crate::limits::read_bytes(path, Some("*.tdms"), MAX_FILE_BYTES, "bytes of a TDMS file")?;
    parse(&bytes, &label)
}

/// Parses the bytes of a TDMS file; `label` names it in errors.
///
/// # Errors
/// [`Error::Tdms`] naming the byte offset: a lead-in without its `TDSm` tag or cut short, a
/// segment longer than the file, metadata cut short or naming an unknown data type, a raw data
/// index `0` for a channel that had none before, raw data that are not whole chunks, an
/// interleaved segment of channels of different lengths; [`Error::FileLimit`] past
/// [`MAX_VALUES`](crate::limits::MAX_VALUES) values.
///
/// # Examples
/// ```
/// let e = bearing_ident::tdms::parse(b"TDSm\x0e\0\0\0", "cut.tdms").unwrap_err();
/// assert_eq!(e.kind(), "malformed_tdms");
/// assert_eq!(bearing_ident::tdms::parse(b"", "empty.tdms")?.groups.len(), 0);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn parse(bytes: &[u8], label: &str) -> Result<TdmsFile> {
    parse::file(bytes, label)
}

#[cfg(test)]
mod tests;
