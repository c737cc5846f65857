//! The csv-crate path of the reader: the rest of an input from its first line that is not
//! plain (a quoted field, a lone `\r`, an empty line), or the whole input when its header is
//! not plain. The csv crate splits the records (quoting, its own line counting); each row goes
//! through the same field-by-field parse and checks as the fast path's unusual lines
//! ([`Rows::row`]), and the crate's errors become ours with the line counted on from where it
//! started ([`csv_error`]). Lines are limited as on the fast path by a reader in between
//! ([`LineLimit`]).

use std::io::Read;

use crate::error::{CsvLimitKind, Error, Result};

use super::{Limits, Rows, Start};

impl<'a> Rows<'a> {
    /// The rest of the input through the csv crate: `reader` starts at line `lines + 1`,
    /// `offset` bytes into the input.
    pub(super) fn slow(mut self, reader: impl Read, lines: u64, offset: u64) -> Result<Rows<'a>> {
        let mut rdr = csv_reader(reader, lines, self.limits, false);
        let mut row = csv::ByteRecord::new();
        let label = self.label;
        let limits = self.limits;
        while rdr
            .read_byte_record(&mut row)
            .map_err(|e| csv_error(e, label, lines, limits))?
        {
            let line = lines + row.position().map_or(0, csv::Position::line);
            let at = offset + row.position().map_or(0, csv::Position::byte);
            self.ragged(row.len(), line)?;
            self.row(line, at, |i| row.get(i).unwrap_or_default())?;
        }
        Ok(self)
    }
}

/// The whole input through the csv crate, header and all (a header that is not plain).
pub(super) fn whole(start: Start<'_>, input: impl Read) -> Result<Rows<'_>> {
    let (label, limits) = (start.label, start.limits);
    let mut rdr = csv_reader(input, 0, limits, true);
    let header = rdr
        .byte_headers()
        .map_err(|e| csv_error(e, label, 0, limits))?
        .clone();
    let mut rows = Rows::new(start, &header)?;
    let mut row = csv::ByteRecord::new();
    while rdr
        .read_byte_record(&mut row)
        .map_err(|e| csv_error(e, label, 0, limits))?
    {
        let line = row.position().map_or(0, csv::Position::line);
        let at = row.position().map_or(0, csv::Position::byte);
        rows.row(line, at, |i| row.get(i).unwrap_or_default())?;
    }
    Ok(rows)
}

/// A csv reader of `input` (which starts at line `lines + 1`), its lines limited; with the
/// header (and the csv crate's check of every row's length against it) or without.
fn csv_reader<R: Read>(
    input: R,
    lines: u64,
    limits: Limits,
    header: bool,
) -> csv::Reader<LineLimit<R>> {
    let limited = LineLimit {
        inner: input,
        limit: limits.line_bytes,
        run: 0,
        line: lines + 1,
    };
    csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .has_headers(header)
        .flexible(!header)
        .from_reader(limited)
}

/// The error of the csv crate as ours, its line counted from `lines`.
fn csv_error(e: csv::Error, label: &str, lines: u64, limits: Limits) -> Error {
    let line = lines + e.position().map_or(0, csv::Position::line);
    let message = match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} fields, the header has {expected_len}"),
        _ => e.to_string(),
    };
    match e.kind() {
        csv::ErrorKind::Io(io) => match io.get_ref().and_then(|i| i.downcast_ref()) {
            Some(LineTooLong { line }) => Error::CsvLimit {
                path: label.to_owned(),
                line: *line,
                what: CsvLimitKind::LineBytes,
                limit: limits.line_bytes,
            },
            None => Error::Io {
                path: label.to_owned(),
                message,
            },
        },
        _ => Error::Csv {
            path: label.to_owned(),
            line,
            message,
        },
    }
}

/// The payload of the I/O error [`LineLimit`] raises.
#[derive(Debug)]
struct LineTooLong {
    line: u64,
}

impl std::fmt::Display for LineTooLong {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {} is too long", self.line)
    }
}

impl std::error::Error for LineTooLong {}

/// A reader that fails once a line (bytes since the last `\n`) passes `limit` bytes.
struct LineLimit<R> {
    inner: R,
    limit: u64,
    /// Bytes since the last newline.
    run: u64,
    /// One-based number of the current line.
    line: u64,
}

impl<R: Read> Read for LineLimit<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        let too_long = |line| Err(std::io::Error::other(LineTooLong { line }));
        let mut rest = &buf[..n];
        while let Some(p) = memchr::memchr(b'\n', rest) {
            if self.run + p as u64 > self.limit {
                return too_long(self.line);
            }
            self.run = 0;
            self.line += 1;
            rest = &rest[p + 1..];
        }
        self.run += rest.len() as u64;
        if self.run > self.limit {
            return too_long(self.line);
        }
        Ok(n)
    }
}
