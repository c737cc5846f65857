//! The record reader ([`CsvReader`]): plain numeric lines on a fast path, anything else
//! through the csv crate, the same values and the same errors either way.
//!
//! The text is read in blocks into a buffer the reader owns (kept across files) and cut into
//! lines at `\n`. A *plain* line — not empty, no `"`, no `\r` but one just before the `\n` —
//! goes through the fast path ([`plain`]); the first line that is not plain (a quoted field, a
//! lone `\r`, an empty line), or a header that is not, hands the rest of the input to the csv
//! crate ([`fallback`]), lines counted on from where it starts.
//!
//! Here: the reader and its buffer ([`Text`]), the header and the loop over lines
//! ([`read_rows`]), and the rows read so far ([`Rows`]): the checks and bookkeeping of every
//! row, the field-by-field parse through `str::parse` that both paths share for anything
//! unusual, and the record they finish into.

mod fallback;
mod plain;

use std::io::Read;

use crate::error::{CsvLimitKind, Error, Result};
use crate::records::Record;

use super::{CsvLayout, MAX_COLUMNS, MAX_LINE_BYTES, MAX_VALUES, uniform_rate};
use fallback::whole;
use plain::{plain, strip_cr};

/// The reader's limits; tests use small ones.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limits {
    pub(super) line_bytes: u64,
    pub(super) columns: usize,
    pub(super) values: u64,
}

pub(super) const LIMITS: Limits = Limits {
    line_bytes: MAX_LINE_BYTES,
    columns: MAX_COLUMNS,
    values: MAX_VALUES,
};

/// Rows read before the input's length is used as a hint of the row count (a power of two
/// times [`MIN_CAPACITY`], so the buffers are full there).
const SIZING_ROWS: usize = 64;

/// Smallest capacity of a channel buffer.
pub(super) const MIN_CAPACITY: usize = 64;

/// Bytes asked of the input at a time.
const BLOCK: usize = 1 << 18;

/// A file column no layout column reads.
const UNREAD: usize = usize::MAX;

/// Next capacity of the channel buffers, full at `cap`: at most twice `cap`, so memory stays
/// proportional to the samples actually read, whatever the hint says. `hint` (0 if unknown) is
/// the row count the input's length suggests; the capacities are then `hint / 2ᵏ`, so a file as
/// long as it says lands exactly on the hint, without a last oversized doubling.
pub(super) fn next_capacity(cap: usize, hint: usize) -> usize {
    if hint > cap {
        let mut c = hint;
        while c / 2 > cap && c / 2 >= MIN_CAPACITY {
            c /= 2;
        }
        c
    } else {
        cap.saturating_mul(2).max(MIN_CAPACITY)
    }
}

/// Reads record files, one after another, into [`Record`]s, keeping its text buffer between
/// them (plan once, read many): what [`read_record`](super::read_record) does for one file.
///
/// # Examples
/// ```
/// use bearing_ident::io::{CsvLayout, CsvReader};
/// let layout = CsvLayout { time: "t".into(), forces: vec!["fx".into()], displacements: vec!["x".into()] };
/// let mut reader = CsvReader::new(layout);
/// let text = "t,fx,x\n0,0,0\n0.5,1,0.1\n1,0,0.2\n1.5,0,0.1\n2,0,0\n2.5,0,0\n3,0,0\n3.5,0,0\n";
/// let rec = reader.read_from(text.as_bytes(), "mem.csv")?;
/// assert_eq!(rec.force(0)[1], 1.0);
/// assert!((rec.sample_rate() - 2.0).abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct CsvReader {
    layout: CsvLayout,
    /// The text buffer, `BLOCK` bytes and more as a long line needs (at most the line limit
    /// plus a block).
    buf: Vec<u8>,
    /// The time column of the record being read (the channels move into the record).
    time: Vec<f64>,
}

impl CsvReader {
    /// A reader of files in `layout`.
    pub fn new(layout: CsvLayout) -> Self {
        Self {
            layout,
            buf: Vec::new(),
            time: Vec::new(),
        }
    }

    /// The layout read.
    pub fn layout(&self) -> &CsvLayout {
        &self.layout
    }

    /// Reads one record file; the record's label is the path as given.
    ///
    /// # Errors
    /// As [`read_record`](super::read_record).
    pub fn read(&mut self, path: impl AsRef<std::path::Path>) -> Result<Record> {
        let path = path.as_ref();
        let label = path.display().to_string();
        let file = crate::limits::open(path, Some("*.csv"))?;
        let bytes = file.metadata().map_or(0, |m| m.len());
        self.read_limited(file, &label, bytes, LIMITS)
    }

    /// Reads one record from any reader; `label` names it in errors.
    ///
    /// # Errors
    /// As [`read_record`](super::read_record).
    pub fn read_from(&mut self, reader: impl Read, label: &str) -> Result<Record> {
        self.read_limited(reader, label, 0, LIMITS)
    }

    /// The reader behind both; `bytes` is the input's length when known (0 otherwise), a hint
    /// of the row count only (a sparse or lying length never sizes an allocation).
    pub(super) fn read_limited(
        &mut self,
        mut reader: impl Read,
        label: &str,
        bytes: u64,
        limits: Limits,
    ) -> Result<Record> {
        let Self { layout, buf, time } = self;
        let mut text = Text {
            buf: std::mem::take(buf),
            start: 0,
            end: 0,
            base: 0,
            eof: false,
            label,
            limits,
        };
        time.clear();
        let start = Start {
            layout,
            label,
            bytes,
            limits,
            time: std::mem::take(time),
        };
        let rows = read_rows(start, &mut text, &mut reader);
        *buf = text.buf;
        let (record, spare) = rows?.finish();
        *time = spare;
        record
    }
}

/// What the rows of one input start from.
struct Start<'a> {
    layout: &'a CsvLayout,
    label: &'a str,
    bytes: u64,
    limits: Limits,
    /// The time column's buffer.
    time: Vec<f64>,
}

/// The header and the rows of the input: the fast path while lines are plain, the csv crate
/// from the first that is not.
fn read_rows<'a, R: Read>(
    start: Start<'a>,
    text: &mut Text<'_>,
    reader: &mut R,
) -> Result<Rows<'a>> {
    let Some(header_end) = text.line(reader, 1)? else {
        return whole(start, text.rest(reader));
    };
    let header_line = strip_cr(&text.buf[text.start..header_end]);
    if !plain(header_line) {
        return whole(start, text.rest(reader));
    }
    let header = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(header_line)
        .byte_headers()
        .map_err(|e| Error::Csv {
            path: start.label.to_owned(),
            line: 1,
            message: e.to_string(),
        })?
        .clone();
    let mut rows = Rows::new(start, &header)?;
    text.start = (header_end + 1).min(text.end);
    let mut line = 2;
    loop {
        let (used, lines) = rows.plain_lines(&text.buf[text.start..text.end], line);
        text.start += used;
        line += lines;
        let Some(end) = text.line(reader, line)? else {
            break;
        };
        let offset = text.base + text.start as u64;
        let l = strip_cr(&text.buf[text.start..end]);
        if !plain(l) {
            return rows.slow(text.rest(reader), line - 1, offset);
        }
        rows.plain_row(l, line, offset)?;
        text.start = (end + 1).min(text.end);
        line += 1;
    }
    Ok(rows)
}

/// The input's text: `buf[start..end]` read and not yet parsed, `base` the input's offset of
/// `buf[0]`.
struct Text<'a> {
    buf: Vec<u8>,
    start: usize,
    end: usize,
    base: u64,
    eof: bool,
    label: &'a str,
    limits: Limits,
}

impl Text<'_> {
    /// The end of the line at `start` (the index of its `\n`, or `end` for a last line without
    /// one), reading more of the input as needed; `None` at the end of the input. `line` is
    /// the line's number, for [`Error::CsvLimit`] past the line limit.
    fn line(&mut self, reader: &mut impl Read, line: u64) -> Result<Option<usize>> {
        let mut searched = self.start;
        loop {
            if let Some(p) = memchr::memchr(b'\n', &self.buf[searched..self.end]) {
                let end = searched + p;
                self.check_length(end - self.start, line)?;
                return Ok(Some(end));
            }
            self.check_length(self.end - self.start, line)?;
            if self.eof {
                return Ok((self.start < self.end).then_some(self.end));
            }
            searched = self.end - self.start;
            self.fill(reader)?;
        }
    }

    fn check_length(&self, len: usize, line: u64) -> Result<()> {
        if len as u64 > self.limits.line_bytes {
            return Err(Error::CsvLimit {
                path: self.label.to_owned(),
                line,
                what: CsvLimitKind::LineBytes,
                limit: self.limits.line_bytes,
            });
        }
        Ok(())
    }

    /// Moves the unparsed text to the front and reads a block after it.
    fn fill(&mut self, reader: &mut impl Read) -> Result<()> {
        self.buf.copy_within(self.start..self.end, 0);
        self.base += self.start as u64;
        self.end -= self.start;
        self.start = 0;
        if self.buf.len() < self.end + BLOCK {
            self.buf.resize(self.end + BLOCK, 0);
        }
        loop {
            match reader.read(&mut self.buf[self.end..]) {
                Ok(0) => {
                    self.eof = true;
                    return Ok(());
                }
                Ok(n) => {
                    self.end += n;
                    return Ok(());
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    return Err(Error::Io {
                        path: self.label.to_owned(),
                        message: e.to_string(),
                    });
                }
            }
        }
    }

    /// The unparsed text followed by the rest of the input.
    fn rest<'r, R: Read>(
        &self,
        reader: &'r mut R,
    ) -> std::io::Chain<std::io::Cursor<Vec<u8>>, &'r mut R> {
        std::io::Cursor::new(self.buf[self.start..self.end].to_vec()).chain(reader)
    }
}

/// The rows read so far and what is needed to read more.
struct Rows<'a> {
    layout: &'a CsvLayout,
    label: &'a str,
    limits: Limits,
    /// The input's length, 0 if unknown.
    bytes: u64,
    header_len: usize,
    /// The file column of each layout column.
    index: Vec<usize>,
    /// The layout column of each file column ([`UNREAD`] for none); empty when a file column
    /// serves two layout columns (no fast path then).
    slot: Vec<usize>,
    /// The channels in layout order; the time column is the spare buffer's.
    columns: Vec<Vec<f64>>,
    /// A row's values in layout order.
    scratch: Vec<f64>,
    /// Line of every row, kept only once the rows stop being consecutive lines.
    lines: Option<Vec<u64>>,
    first_line: u64,
    columns_start: Option<u64>,
}

impl<'a> Rows<'a> {
    fn new(start: Start<'a>, header: &csv::ByteRecord) -> Result<Self> {
        let Start {
            layout,
            label,
            bytes,
            limits,
            time,
        } = start;
        if header.len() > limits.columns {
            return Err(Error::CsvLimit {
                path: label.to_owned(),
                line: 1,
                what: CsvLimitKind::Columns,
                limit: limits.columns as u64,
            });
        }
        let index: Vec<usize> = layout
            .columns()
            .map(|c| {
                header
                    .iter()
                    .position(|h| h == c.as_bytes())
                    .ok_or_else(|| {
                        let names: Vec<String> =
                            header.iter().map(crate::error::excerpt_bytes).collect();
                        Error::MissingColumn {
                            path: label.to_owned(),
                            column: crate::error::excerpt(c),
                            header: crate::error::excerpt(&names.join(",")),
                        }
                    })
            })
            .collect::<Result<_>>()?;
        // A name the layout reads that the header gives twice: which column is meant is unknown.
        for &i in &index {
            if let Some(again) = header.iter().skip(i + 1).position(|h| h == &header[i]) {
                return Err(Error::Csv {
                    path: label.to_owned(),
                    line: 1,
                    message: format!(
                        "column `{}` appears twice in the header (fields {} and {}): which \
                         one to read is not known",
                        crate::error::excerpt_bytes(&header[i]),
                        i + 1,
                        i + 2 + again
                    ),
                });
            }
        }
        let mut slot = vec![UNREAD; header.len()];
        for (k, &i) in index.iter().enumerate() {
            if slot[i] != UNREAD {
                slot.clear();
                break;
            }
            slot[i] = k;
        }
        let mut columns = vec![Vec::new(); index.len()];
        columns[0] = time;
        Ok(Self {
            layout,
            label,
            limits,
            bytes,
            header_len: header.len(),
            scratch: vec![0.0; index.len()],
            index,
            slot,
            columns,
            lines: None,
            first_line: 0,
            columns_start: None,
        })
    }

    /// [`Error::Csv`] for a line of `len` fields that the header does not have.
    fn ragged(&self, len: usize, line: u64) -> Result<()> {
        if len == self.header_len {
            return Ok(());
        }
        Err(Error::Csv {
            path: self.label.to_owned(),
            line,
            message: format!("{len} fields, the header has {}", self.header_len),
        })
    }

    /// The checks and bookkeeping before row `r` is pushed: the value limit, the channels'
    /// capacity, the lines of the rows.
    fn begin_row(&mut self, line: u64, offset: u64) -> Result<()> {
        let r = self.columns[0].len();
        if (r as u64 + 1).saturating_mul(self.index.len() as u64) > self.limits.values {
            return Err(Error::CsvLimit {
                path: self.label.to_owned(),
                line,
                what: CsvLimitKind::Values,
                limit: self.limits.values,
            });
        }
        if r == self.columns[0].capacity() {
            // Rows the input's length suggests, from the bytes per row so far (estimated again
            // at every growth, so it sharpens as rows arrive). A hint only: capacities never
            // more than double, whatever it says.
            let hint = if self.bytes > 0 && r >= SIZING_ROWS {
                let first = self.columns_start.unwrap_or(0);
                let per_row = (offset.saturating_sub(first) as f64 / r as f64).max(1.0);
                let rows = self.bytes.saturating_sub(first) as f64 / per_row * 1.02 + 16.0;
                rows.min((self.limits.values / self.index.len() as u64) as f64) as usize
            } else {
                0
            };
            let cap = next_capacity(r, hint);
            for c in &mut self.columns {
                c.reserve_exact(cap - c.len());
            }
        }
        if r == 0 {
            self.columns_start = Some(offset);
            self.first_line = line;
        }
        match &mut self.lines {
            Some(l) => l.push(line),
            None if line != self.first_line + r as u64 => {
                let mut l: Vec<u64> = (0..r as u64).map(|i| self.first_line + i).collect();
                l.push(line);
                self.lines = Some(l);
            }
            None => {}
        }
        Ok(())
    }

    /// Reads a row field by field (`field(i)` the trimmed field of file column `i`), each
    /// layout column in turn through `str::parse`, naming the first that fails.
    fn row<'f>(&mut self, line: u64, offset: u64, field: impl Fn(usize) -> &'f [u8]) -> Result<()> {
        self.begin_row(line, offset)?;
        for ((col, &i), name) in self
            .columns
            .iter_mut()
            .zip(&self.index)
            .zip(self.layout.columns())
        {
            let field = field(i);
            let value = std::str::from_utf8(field)
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| Error::Csv {
                    path: self.label.to_owned(),
                    line,
                    message: format!(
                        "column `{}`: `{}` is not a number",
                        crate::error::excerpt(name),
                        crate::error::excerpt_bytes(field)
                    ),
                })?;
            if !value.is_finite() {
                return Err(Error::CsvNonFinite {
                    path: self.label.to_owned(),
                    line,
                    column: crate::error::excerpt(name),
                });
            }
            col.push(value);
        }
        Ok(())
    }

    /// The record read: the sampling rate from the time column, the channels moved out; and
    /// the time column's buffer, for the next input.
    fn finish(self) -> (Result<Record>, Vec<f64>) {
        let mut columns = self.columns.into_iter();
        let time = columns.next().unwrap_or_default();
        let (first_line, lines) = (self.first_line, self.lines);
        let line_of = |r: usize| lines.as_ref().map_or(first_line + r as u64, |l| l[r]);
        let forces = self.layout.forces.len();
        let record = uniform_rate(&time, self.label, &line_of).and_then(|sample_rate| {
            let forces: Vec<Vec<f64>> = columns.by_ref().take(forces).collect();
            Record::new(self.label, sample_rate, forces, columns.collect())
        });
        (record, time)
    }
}
