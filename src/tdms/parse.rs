//! The segments of a TDMS file: lead-ins, metadata, raw data indexes and raw data, in the
//! order the file holds them (NI, "TDMS file format internal structure").

use std::collections::HashMap;

use super::{Channel, Group, Property, TWO_64, TdmsFile, Value, scaling};
use crate::error::{Error, Result, excerpt};
use crate::limits::MAX_VALUES;

/// Table-of-contents flags of a lead-in.
const TOC_META_DATA: u32 = 1 << 1;
const TOC_NEW_OBJ_LIST: u32 = 1 << 2;
const TOC_RAW_DATA: u32 = 1 << 3;
const TOC_INTERLEAVED: u32 = 1 << 5;
const TOC_BIG_ENDIAN: u32 = 1 << 6;
const TOC_DAQMX_RAW_DATA: u32 = 1 << 7;

/// Bytes of a lead-in.
const LEAD_IN: usize = 28;
/// A raw data index saying "no raw data in this segment".
const NO_DATA: u32 = 0xFFFF_FFFF;
/// A raw data index saying "as in the previous segment".
const SAME_AS_BEFORE: u32 = 0;
/// Raw data indexes of DAQmx data (format changing and digital line scalers).
const DAQMX_FORMAT_CHANGING: u32 = 0x6912_0000;
const DAQMX_DIGITAL_LINE: u32 = 0x6913_0000;
/// Next-segment offset of a segment whose writer stopped before finishing it.
const INCOMPLETE: u64 = u64::MAX;

/// TDMS data types (`tdsType…`).
const STRING: u32 = 0x20;
const BOOLEAN: u32 = 0x21;
const TIMESTAMP: u32 = 0x44;
const DAQMX: u32 = 0xFFFF_FFFF;

/// A value's byte size, for types of fixed size; `None` for strings and unknown types.
fn fixed_size(data_type: u32) -> Option<usize> {
    Some(match data_type {
        0 => 0,
        1 | 5 | BOOLEAN => 1,
        2 | 6 => 2,
        3 | 7 | 9 | 0x19 => 4,
        4 | 8 | 10 | 0x1A | 0x08_000C => 8,
        11 | 0x1B | TIMESTAMP | 0x10_000D => 16,
        _ => return None,
    })
}

/// How the raw data of one channel in one segment are laid out.
#[derive(Debug, Clone, PartialEq)]
enum RawIndex {
    /// `count` values of `data_type` per chunk; `bytes` per chunk (strings: their total size).
    Plain {
        data_type: u32,
        count: u64,
        bytes: u64,
    },
    /// DAQmx raw data: `count` samples per chunk, read by the first scaler from the raw
    /// buffers of `widths` bytes per sample.
    Daqmx {
        count: u64,
        scaler: DaqmxScaler,
        widths: Vec<u32>,
    },
}

/// Where one DAQmx channel's values are in the raw buffers.
#[derive(Debug, Clone, PartialEq)]
struct DaqmxScaler {
    /// The DAQmx data type (0 u8, 1 i8, 2 u16, 3 i16, 4 u32, 5 i32, 6 u64, 7 i64, 8 f32, 9 f64).
    data_type: u32,
    /// Which raw buffer.
    buffer: u32,
    /// Byte offset within that buffer's stride.
    offset: u32,
}

impl RawIndex {
    /// Bytes of one chunk of this channel (DAQmx: of every raw buffer, which the channels of
    /// a segment share).
    fn chunk_bytes(&self) -> Option<u64> {
        match self {
            RawIndex::Plain { bytes, .. } => Some(*bytes),
            RawIndex::Daqmx { count, widths, .. } => {
                count.checked_mul(widths.iter().map(|&w| u64::from(w)).sum())
            }
        }
    }
}

/// An object of the file as the segments build it.
#[derive(Debug, Default)]
struct Object {
    path: String,
    properties: Vec<Property>,
    /// The raw data index of the last segment that gave one.
    index: Option<RawIndex>,
    data_type: u32,
    /// Raw values (before scaling).
    values: Vec<f64>,
    /// First timestamp of a timestamp channel, the origin of its values.
    time_origin: Option<(i64, u64)>,
    unreadable: Option<String>,
}

/// A reader of the bytes of one file, naming the file and the byte offset in its errors.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    big_endian: bool,
    label: &'a str,
}

impl<'a> Cursor<'a> {
    fn error(&self, at: usize, message: impl Into<String>) -> Error {
        Error::Tdms {
            path: excerpt(self.label),
            offset: at as u64,
            message: message.into(),
        }
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        match end {
            Some(end) => {
                let slice = &self.bytes[self.pos..end];
                self.pos = end;
                Ok(slice)
            }
            None => Err(self.error(
                self.pos,
                format!(
                    "{what} needs {n} bytes; the segment holds {} more",
                    self.bytes.len() - self.pos
                ),
            )),
        }
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let mut a = [0; N];
        a.copy_from_slice(self.take(N, what)?);
        if self.big_endian {
            a.reverse();
        }
        Ok(a)
    }

    fn u32(&mut self, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    fn u64(&mut self, what: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }

    fn string(&mut self, what: &str) -> Result<String> {
        let n = self.u32(what)? as usize;
        let at = self.pos;
        let bytes = self.take(n, what)?;
        String::from_utf8(bytes.to_vec())
            .map_err(|_| self.error(at, format!("{what} is not UTF-8")))
    }

    /// A property value of `data_type`.
    fn value(&mut self, data_type: u32) -> Result<Value> {
        let what = "a property value";
        Ok(match data_type {
            1 => Value::Int(i64::from(i8::from_le_bytes(self.array(what)?))),
            2 => Value::Int(i64::from(i16::from_le_bytes(self.array(what)?))),
            3 => Value::Int(i64::from(i32::from_le_bytes(self.array(what)?))),
            4 => Value::Int(i64::from_le_bytes(self.array(what)?)),
            5 => Value::Uint(u64::from(u8::from_le_bytes(self.array(what)?))),
            6 => Value::Uint(u64::from(u16::from_le_bytes(self.array(what)?))),
            7 => Value::Uint(u64::from(u32::from_le_bytes(self.array(what)?))),
            8 => Value::Uint(u64::from_le_bytes(self.array(what)?)),
            9 | 0x19 => Value::Float(f64::from(f32::from_le_bytes(self.array(what)?))),
            10 | 0x1A => Value::Float(f64::from_le_bytes(self.array(what)?)),
            STRING => Value::Text(self.string(what)?),
            BOOLEAN => Value::Bool(self.take(1, what)?[0] != 0),
            TIMESTAMP => {
                let (seconds, fraction) = self.timestamp(what)?;
                Value::Time { seconds, fraction }
            }
            other => match fixed_size(other) {
                Some(n) => {
                    self.take(n, what)?;
                    Value::Other(other)
                }
                None => {
                    return Err(self.error(
                        self.pos,
                        format!("a property of unknown data type {other:#x}"),
                    ));
                }
            },
        })
    }

    /// A timestamp: little-endian files hold the fraction first, big-endian the seconds.
    fn timestamp(&mut self, what: &str) -> Result<(i64, u64)> {
        if self.big_endian {
            let seconds = i64::from_le_bytes(self.array(what)?);
            Ok((seconds, u64::from_le_bytes(self.array(what)?)))
        } else {
            let fraction = u64::from_le_bytes(self.array(what)?);
            Ok((i64::from_le_bytes(self.array(what)?), fraction))
        }
    }
}

/// The objects of a file and the segment being read.
struct Reader<'a> {
    label: &'a str,
    objects: Vec<Object>,
    by_path: HashMap<String, usize>,
    /// The objects of the current segment's list, in order, and whether each has raw data in
    /// it.
    active: Vec<(usize, bool)>,
    /// Values read so far, against [`MAX_VALUES`].
    values: u64,
}

pub(super) fn file(bytes: &[u8], label: &str) -> Result<TdmsFile> {
    let mut reader = Reader {
        label,
        objects: Vec::new(),
        by_path: HashMap::new(),
        active: Vec::new(),
        values: 0,
    };
    let mut pos = 0;
    while pos < bytes.len() {
        pos = reader.segment(bytes, pos)?;
    }
    reader.finish()
}

impl Reader<'_> {
    fn error(&self, at: usize, message: impl Into<String>) -> Error {
        Error::Tdms {
            path: excerpt(self.label),
            offset: at as u64,
            message: message.into(),
        }
    }

    /// Reads the segment at `start`; returns where the next begins.
    fn segment(&mut self, bytes: &[u8], start: usize) -> Result<usize> {
        let rest = bytes.len() - start;
        if rest < LEAD_IN {
            return Err(self.error(
                start,
                format!("a lead-in of {LEAD_IN} bytes cut short after {rest}"),
            ));
        }
        let lead = &bytes[start..start + LEAD_IN];
        if &lead[..4] != b"TDSm" {
            return Err(self.error(
                start,
                format!(
                    "a segment must begin with `TDSm`, not {:?}",
                    String::from_utf8_lossy(&lead[..4])
                ),
            ));
        }
        let toc = u32::from_le_bytes([lead[4], lead[5], lead[6], lead[7]]);
        let mut cursor = Cursor {
            bytes: lead,
            pos: 8,
            big_endian: toc & TOC_BIG_ENDIAN != 0,
            label: self.label,
        };
        let _version = cursor.u32("the version")?;
        let next = cursor.u64("the segment length")?;
        let raw_offset = cursor.u64("the raw data offset")?;
        let body = start + LEAD_IN;
        let available = (bytes.len() - body) as u64;
        let length = if next == INCOMPLETE {
            available
        } else if next > available {
            return Err(self.error(
                start,
                format!(
                    "the segment declares {next} bytes after its lead-in; the file holds {available}"
                ),
            ));
        } else {
            next
        };
        if raw_offset > length {
            return Err(self.error(
                start,
                format!("raw data declared at byte {raw_offset} of a segment of {length} bytes"),
            ));
        }
        // Both fit in the file's bytes, so in `usize`.
        let (length, raw_offset) = (length as usize, raw_offset as usize);
        if toc & TOC_META_DATA != 0 {
            if toc & TOC_NEW_OBJ_LIST != 0 {
                self.active.clear();
            }
            let mut meta = Cursor {
                bytes: &bytes[..body + raw_offset],
                pos: body,
                big_endian: cursor.big_endian,
                label: self.label,
            };
            self.metadata(&mut meta, toc & TOC_DAQMX_RAW_DATA != 0)?;
        }
        if toc & TOC_RAW_DATA != 0 {
            let raw = &bytes[body + raw_offset..body + length];
            self.raw_data(
                raw,
                body + raw_offset,
                toc & TOC_INTERLEAVED != 0,
                cursor.big_endian,
                next == INCOMPLETE,
            )?;
        }
        Ok(body + length)
    }

    /// The object list of a segment with metadata.
    fn metadata(&mut self, c: &mut Cursor<'_>, daqmx: bool) -> Result<()> {
        let objects = c.u32("the number of objects")?;
        for _ in 0..objects {
            let at = c.pos;
            let path = c.string("an object path")?;
            let i = match self.by_path.get(&path) {
                Some(&i) => i,
                None => {
                    self.objects.push(Object {
                        path: path.clone(),
                        ..Object::default()
                    });
                    self.by_path.insert(path.clone(), self.objects.len() - 1);
                    self.objects.len() - 1
                }
            };
            let header = c.u32("a raw data index")?;
            let index = match header {
                NO_DATA => None,
                SAME_AS_BEFORE => match &self.objects[i].index {
                    Some(index) => Some(index.clone()),
                    None => {
                        return Err(c.error(
                            at,
                            format!(
                                "object {} reuses a raw data index it never had",
                                excerpt(&path)
                            ),
                        ));
                    }
                },
                DAQMX_FORMAT_CHANGING | DAQMX_DIGITAL_LINE => Some(daqmx_index(c, daqmx)?),
                _ => Some(plain_index(c)?),
            };
            let object = &mut self.objects[i];
            if let Some(index) = &index {
                let data_type = match index {
                    RawIndex::Plain { data_type, .. } => *data_type,
                    RawIndex::Daqmx { .. } => DAQMX,
                };
                if object.data_type != 0 && object.data_type != data_type {
                    return Err(c.error(
                        at,
                        format!(
                            "object {} changes its data type from {:#x} to {data_type:#x}",
                            excerpt(&path),
                            object.data_type
                        ),
                    ));
                }
                object.data_type = data_type;
                object.index = Some(index.clone());
            }
            let properties = c.u32("the number of properties")?;
            for _ in 0..properties {
                let name = c.string("a property name")?;
                let data_type = c.u32("a property's data type")?;
                let value = c.value(data_type)?;
                let object = &mut self.objects[i];
                match object.properties.iter_mut().find(|p| p.name == name) {
                    Some(p) => p.value = value,
                    None => object.properties.push(Property { name, value }),
                }
            }
            // In this segment's list, with data here or not.
            let has_data = index.is_some();
            match self.active.iter_mut().find(|(a, _)| *a == i) {
                Some(entry) => entry.1 = has_data,
                None => self.active.push((i, has_data)),
            }
        }
        Ok(())
    }

    /// The raw data of a segment: whole chunks of every listed channel with data.
    fn raw_data(
        &mut self,
        raw: &[u8],
        at: usize,
        interleaved: bool,
        big_endian: bool,
        incomplete: bool,
    ) -> Result<()> {
        let listed: Vec<usize> = self
            .active
            .iter()
            .filter(|&&(i, has_data)| has_data && self.objects[i].index.is_some())
            .map(|&(i, _)| i)
            .collect();
        let daqmx = listed
            .iter()
            .any(|&i| matches!(self.objects[i].index, Some(RawIndex::Daqmx { .. })));
        let mut chunk: u64 = 0;
        for &i in &listed {
            let Some(index) = &self.objects[i].index else {
                continue;
            };
            let bytes = index
                .chunk_bytes()
                .ok_or_else(|| self.error(at, "a chunk size past 2^64 bytes"))?;
            // DAQmx channels share their raw buffers: a chunk holds them once.
            chunk = if daqmx {
                chunk.max(bytes)
            } else {
                chunk
                    .checked_add(bytes)
                    .ok_or_else(|| self.error(at, "a chunk size past 2^64 bytes"))?
            };
        }
        if chunk == 0 {
            return Ok(());
        }
        let raw_len = raw.len() as u64;
        let chunks = raw_len / chunk;
        if raw_len % chunk != 0 && !incomplete {
            return Err(self.error(
                at,
                format!(
                    "{raw_len} bytes of raw data are not whole chunks of {chunk} bytes (the \
                     channels' declared sizes)"
                ),
            ));
        }
        // Whole chunks only: at most `raw_len` bytes, so in `usize`.
        let chunk = chunk as usize;
        let raw = &raw[..chunks as usize * chunk];
        for c in 0..chunks as usize {
            let bytes = &raw[c * chunk..(c + 1) * chunk];
            let start = at + c * chunk;
            if daqmx {
                for &i in &listed {
                    self.daqmx_chunk(i, bytes, start, big_endian)?;
                }
            } else if interleaved {
                self.interleaved_chunk(&listed, bytes, start, big_endian)?;
            } else {
                let mut offset = 0;
                for &i in &listed {
                    let Some(RawIndex::Plain {
                        data_type,
                        count,
                        bytes: n,
                    }) = self.objects[i].index.clone()
                    else {
                        continue;
                    };
                    let n = n as usize;
                    self.decode(
                        i,
                        data_type,
                        count,
                        &bytes[offset..offset + n],
                        start + offset,
                        1,
                        big_endian,
                    )?;
                    offset += n;
                }
            }
        }
        Ok(())
    }

    /// One chunk of interleaved data: sample by sample, one value of each channel.
    fn interleaved_chunk(
        &mut self,
        listed: &[usize],
        bytes: &[u8],
        at: usize,
        big_endian: bool,
    ) -> Result<()> {
        let mut layout = Vec::with_capacity(listed.len());
        let mut stride = 0;
        let mut samples = None;
        for &i in listed {
            let Some(RawIndex::Plain {
                data_type, count, ..
            }) = self.objects[i].index
            else {
                continue;
            };
            let size = fixed_size(data_type).ok_or_else(|| {
                self.error(
                    at,
                    format!("interleaved data of type {data_type:#x}, which has no fixed size"),
                )
            })?;
            if *samples.get_or_insert(count) != count {
                return Err(self.error(
                    at,
                    "interleaved channels of different numbers of values per chunk",
                ));
            }
            layout.push((i, data_type, count, stride));
            stride += size;
        }
        for (i, data_type, count, offset) in layout {
            self.decode(
                i,
                data_type,
                count,
                bytes.get(offset..).unwrap_or_default(),
                at + offset,
                stride,
                big_endian,
            )?;
        }
        Ok(())
    }

    /// One chunk of DAQmx raw data for channel `i`: its scaler's values from its raw buffer.
    fn daqmx_chunk(&mut self, i: usize, bytes: &[u8], at: usize, big_endian: bool) -> Result<()> {
        let Some(RawIndex::Daqmx {
            count,
            scaler,
            widths,
        }) = self.objects[i].index.clone()
        else {
            return Ok(());
        };
        let buffer = scaler.buffer as usize;
        let Some(&width) = widths.get(buffer) else {
            return Err(self.error(
                at,
                format!(
                    "a DAQmx scaler reads raw buffer {buffer} of {}",
                    widths.len()
                ),
            ));
        };
        let start: u64 = widths[..buffer].iter().map(|&w| u64::from(w) * count).sum();
        let data_type = match scaler.data_type {
            0 => 5,
            1 => 1,
            2 => 6,
            3 => 2,
            4 => 7,
            5 => 3,
            6 => 8,
            7 => 4,
            8 => 9,
            9 => 10,
            other => {
                return Err(self.error(at, format!("a DAQmx scaler of unknown data type {other}")));
            }
        };
        let size = fixed_size(data_type).unwrap_or(1);
        let offset = scaler.offset as usize;
        if offset + size > width as usize {
            return Err(self.error(
                at,
                format!("a DAQmx scaler at byte {offset} of a raw buffer {width} bytes wide"),
            ));
        }
        let from = start as usize + offset;
        self.decode(
            i,
            data_type,
            count,
            bytes.get(from..).unwrap_or_default(),
            at + from,
            width as usize,
            big_endian,
        )
    }

    /// Appends `count` values of `data_type` from `bytes`, one every `stride` bytes (`1`:
    /// packed) to object `i`.
    #[allow(clippy::too_many_arguments)]
    fn decode(
        &mut self,
        i: usize,
        data_type: u32,
        count: u64,
        bytes: &[u8],
        at: usize,
        stride: usize,
        big_endian: bool,
    ) -> Result<()> {
        let Some(size) = fixed_size(data_type) else {
            let object = &mut self.objects[i];
            if object.unreadable.is_none() {
                object.unreadable = Some(match data_type {
                    STRING => "strings, not numbers".to_owned(),
                    other => format!("values of data type {other:#x}"),
                });
            }
            return Ok(());
        };
        let stride = stride.max(size);
        // The chunk's bytes were checked against the declared sizes: `count` values fit.
        let count = count as usize;
        self.values += count as u64;
        if self.values > MAX_VALUES {
            return Err(Error::FileLimit {
                path: excerpt(self.label),
                what: "values of a TDMS file".into(),
                limit: MAX_VALUES,
            });
        }
        let needed = count
            .checked_sub(1)
            .map_or(Some(0), |k| k.checked_mul(stride)?.checked_add(size));
        if needed.is_none_or(|n| n > bytes.len()) {
            return Err(self.error(at, "a channel's values run past its chunk"));
        }
        let object = &mut self.objects[i];
        let take = |k: usize| &bytes[k * stride..k * stride + size];
        macro_rules! numbers {
            ($t:ty) => {{
                object.values.extend((0..count).map(|k| {
                    let mut a = [0u8; std::mem::size_of::<$t>()];
                    a.copy_from_slice(take(k));
                    if big_endian {
                        <$t>::from_be_bytes(a) as f64
                    } else {
                        <$t>::from_le_bytes(a) as f64
                    }
                }))
            }};
        }
        match data_type {
            1 => numbers!(i8),
            2 => numbers!(i16),
            3 => numbers!(i32),
            4 => numbers!(i64),
            5 => numbers!(u8),
            6 => numbers!(u16),
            7 => numbers!(u32),
            8 => numbers!(u64),
            9 | 0x19 => numbers!(f32),
            10 | 0x1A => numbers!(f64),
            BOOLEAN => object
                .values
                .extend((0..count).map(|k| f64::from(u8::from(bytes[k * stride] != 0)))),
            TIMESTAMP => {
                for k in 0..count {
                    let mut c = Cursor {
                        bytes: take(k),
                        pos: 0,
                        big_endian,
                        label: "",
                    };
                    let (seconds, fraction) = c.timestamp("a timestamp")?;
                    let (s0, f0) = *object.time_origin.get_or_insert((seconds, fraction));
                    let whole = seconds.wrapping_sub(s0) as f64;
                    object
                        .values
                        .push(whole + (fraction as f64 - f0 as f64) / TWO_64);
                }
            }
            0 => {}
            other => {
                if object.unreadable.is_none() {
                    object.unreadable = Some(format!(
                        "values of data type {other:#x} (extended or complex numbers)"
                    ));
                }
            }
        }
        Ok(())
    }

    /// The file's groups and channels, scaled.
    fn finish(self) -> Result<TdmsFile> {
        let mut file = TdmsFile::default();
        for object in self.objects {
            let names = split_path(&object.path).ok_or_else(|| Error::Tdms {
                path: excerpt(self.label),
                offset: 0,
                message: format!(
                    "object path {} is not /'group'/'channel'",
                    excerpt(&object.path)
                ),
            })?;
            match names.as_slice() {
                [] => file.properties = object.properties,
                [group] => {
                    let g = group_of(&mut file, group);
                    g.properties = object.properties;
                }
                [group, channel] => {
                    let mut values = object.values;
                    let mut unreadable = object.unreadable;
                    if unreadable.is_none() {
                        match scaling::scale(&object.properties, &mut values) {
                            Ok(()) => {}
                            Err(why) => {
                                values.clear();
                                unreadable = Some(why);
                            }
                        }
                    }
                    group_of(&mut file, group).channels.push(Channel {
                        name: channel.clone(),
                        properties: object.properties,
                        data_type: object.data_type,
                        values,
                        unreadable,
                    });
                }
                _ => {
                    return Err(Error::Tdms {
                        path: excerpt(self.label),
                        offset: 0,
                        message: format!(
                            "object path {} has more than a group and a channel",
                            excerpt(&object.path)
                        ),
                    });
                }
            }
        }
        Ok(file)
    }
}

/// The group named `name`, added at the end if new.
fn group_of<'a>(file: &'a mut TdmsFile, name: &str) -> &'a mut Group {
    let i = match file.groups.iter().position(|g| g.name == name) {
        Some(i) => i,
        None => {
            file.groups.push(Group {
                name: name.to_owned(),
                ..Group::default()
            });
            file.groups.len() - 1
        }
    };
    &mut file.groups[i]
}

/// The names in an object path: `/` none, `/'g'` one, `/'g'/'c'` two (a quote in a name is
/// doubled); `None` if it is not of that form.
fn split_path(path: &str) -> Option<Vec<String>> {
    let mut names = Vec::new();
    let mut chars = path.chars().peekable();
    if path == "/" {
        return Some(names);
    }
    while let Some(c) = chars.next() {
        if c != '/' || chars.next() != Some('\'') {
            return None;
        }
        let mut name = String::new();
        loop {
            match chars.next()? {
                '\'' if chars.peek() == Some(&'\'') => {
                    chars.next();
                    name.push('\'');
                }
                '\'' => break,
                c => name.push(c),
            }
        }
        names.push(name);
    }
    Some(names)
}

/// A raw data index of a plain channel (after its length field).
fn plain_index(c: &mut Cursor<'_>) -> Result<RawIndex> {
    let at = c.pos;
    let data_type = c.u32("a raw data index's data type")?;
    let dimension = c.u32("a raw data index's dimension")?;
    if dimension != 1 {
        return Err(c.error(
            at,
            format!("a raw data index of dimension {dimension}, not 1"),
        ));
    }
    let count = c.u64("a raw data index's number of values")?;
    let bytes = if data_type == STRING {
        c.u64("a raw data index's size of strings")?
    } else {
        let size = fixed_size(data_type)
            .ok_or_else(|| c.error(at, format!("raw data of unknown data type {data_type:#x}")))?;
        count
            .checked_mul(size as u64)
            .ok_or_else(|| c.error(at, format!("{count} values: a size past 2^64 bytes")))?
    };
    Ok(RawIndex::Plain {
        data_type,
        count,
        bytes,
    })
}

/// A DAQmx raw data index (after its format code): the first scaler and the raw buffers'
/// widths.
fn daqmx_index(c: &mut Cursor<'_>, daqmx: bool) -> Result<RawIndex> {
    let at = c.pos;
    if !daqmx {
        return Err(c.error(at, "a DAQmx raw data index in a segment without DAQmx data"));
    }
    let _data_type = c.u32("a DAQmx index's data type")?;
    let _dimension = c.u32("a DAQmx index's dimension")?;
    let count = c.u64("a DAQmx index's number of values")?;
    let scalers = c.u32("a DAQmx index's number of scalers")?;
    let mut first = None;
    for _ in 0..scalers {
        let data_type = c.u32("a DAQmx scaler")?;
        let buffer = c.u32("a DAQmx scaler")?;
        let offset = c.u32("a DAQmx scaler")?;
        let _sample_format = c.u32("a DAQmx scaler")?;
        let _scale_id = c.u32("a DAQmx scaler")?;
        first.get_or_insert(DaqmxScaler {
            data_type,
            buffer,
            offset,
        });
    }
    let scaler = first.ok_or_else(|| c.error(at, "a DAQmx index without a scaler"))?;
    let n = c.u32("a DAQmx index's number of raw buffers")?;
    let mut widths = Vec::new();
    for _ in 0..n {
        widths.push(c.u32("a DAQmx raw buffer's width")?);
    }
    Ok(RawIndex::Daqmx {
        count,
        scaler,
        widths,
    })
}

#[cfg(test)]
pub(super) fn split_path_for_test(path: &str) -> Option<Vec<String>> {
    split_path(path)
}
