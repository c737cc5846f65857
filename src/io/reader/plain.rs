//! The fast path of the reader: a *plain* line (not empty, no `"`, no `\r` but one just
//! before the `\n`) splits at every `,` exactly as the csv crate would split it, so its fields
//! are trimmed of ASCII whitespace and parsed straight from the bytes by `fast_float2`
//! (correctly rounded, the same `f64` as `str::parse`; no UTF-8 check: a non-ASCII byte is not
//! part of a number). A plain line the fast parse does not take whole (a field that is not a
//! finite plain number, a ragged line, the value limit reached) is judged again field by field
//! with `str::parse` ([`Rows::row`]) in the order and with the errors of the csv path.
//!
//! Runs of ordinary lines are read without cutting them into lines first
//! ([`Rows::plain_lines`]): a window of the buffer is searched once for `"`, then the fields are
//! parsed one after another, each line's end found by the parse itself, until a line that is
//! not ordinary, which is left to the line-by-line path above.

use crate::error::Result;

use super::{Rows, UNREAD};

/// `line` without a final `\r`.
pub(super) fn strip_cr(line: &[u8]) -> &[u8] {
    line.strip_suffix(b"\r").unwrap_or(line)
}

/// Whether the csv crate splits `line` (a line without its terminator) at every comma into
/// one record: not empty, no quote, no carriage return.
pub(super) fn plain(line: &[u8]) -> bool {
    !line.is_empty() && memchr::memchr2(b'"', b'\r', line).is_none()
}

/// Bytes of the buffer searched for `"` at a time by [`Rows::plain_lines`] (bounds the work
/// spent on a window when its lines end up on the line-by-line path).
const WINDOW: usize = 1 << 16;

impl Rows<'_> {
    /// Reads the ordinary lines at the front of `text` (complete lines only, `line` the number
    /// of the first, `offset` its place in the input): the rows the line-by-line path would
    /// read from them, without its per-line checks. Ordinary: within the line limit, no `"`,
    /// no `\r` but one just before the `\n`, every field a finite number `fast_float2` takes
    /// whole (or a column not read, without `\r`), exactly as many fields as the header; and
    /// room for the row in the channels' capacity and the value limit. Stops at the first
    /// line that is not, and returns the bytes and lines read.
    pub(super) fn plain_lines(&mut self, text: &[u8], line: u64) -> (usize, u64) {
        let r = self.columns[0].len();
        // The row bookkeeping of `begin_row` is then only the push: rows so far are
        // consecutive lines from the first, and the next row is too.
        if r == 0
            || self.slot.is_empty()
            || self.lines.is_some()
            || line != self.first_line + r as u64
        {
            return (0, 0);
        }
        let text = &text[..text.len().min(WINDOW)];
        let text = &text[..memchr::memchr(b'"', text).unwrap_or(text.len())];
        let max_rows = (self.limits.values / self.index.len() as u64).min(usize::MAX as u64);
        let room = (self.columns[0].capacity() - r).min(max_rows.saturating_sub(r as u64) as usize);
        let mut pos = 0;
        let mut rows = 0;
        while rows < room {
            let Some(end) = fast_line(text, pos, &self.slot, &mut self.scratch) else {
                break;
            };
            if (end - pos) as u64 > self.limits.line_bytes {
                break;
            }
            for (c, &v) in self.columns.iter_mut().zip(&self.scratch) {
                c.push(v);
            }
            pos = end + 1;
            rows += 1;
        }
        (pos, rows as u64)
    }

    /// Reads a plain line (`\r` stripped): the fast parse, or the field-by-field one when it
    /// does not take the line whole.
    pub(super) fn plain_row(&mut self, line: &[u8], number: u64, offset: u64) -> Result<()> {
        let r = self.columns[0].len();
        let within = (r as u64 + 1).saturating_mul(self.index.len() as u64) <= self.limits.values;
        if within && !self.slot.is_empty() && fast_fields(line, &self.slot, &mut self.scratch) {
            self.begin_row(number, offset)?;
            for (c, &v) in self.columns.iter_mut().zip(&self.scratch) {
                c.push(v);
            }
            return Ok(());
        }
        let fields: Vec<&[u8]> = line.split(|&b| b == b',').map(<[u8]>::trim_ascii).collect();
        self.ragged(fields.len(), number)?;
        self.row(number, offset, |i| {
            fields.get(i).copied().unwrap_or_default()
        })
    }
}

/// Parses a plain line into `out` (layout order; `slot` gives each file column's place): true
/// if every field read is a finite number that `fast_float2` takes whole (trimmed of ASCII
/// whitespace) and the line has exactly `slot.len()` fields.
fn fast_fields(line: &[u8], slot: &[usize], out: &mut [f64]) -> bool {
    let n = line.len();
    let last = slot.len() - 1;
    let mut pos = 0;
    for (k, &s) in slot.iter().enumerate() {
        if s == UNREAD {
            match memchr::memchr(b',', &line[pos..]) {
                Some(p) if k < last => pos += p + 1,
                None if k == last => pos = n,
                _ => return false,
            }
            continue;
        }
        while pos < n && line[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let Ok((v, used)) = fast_float2::parse_partial::<f64, _>(&line[pos..]) else {
            return false;
        };
        if !v.is_finite() || used == 0 {
            return false;
        }
        pos += used;
        while pos < n && line[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if k == last {
            if pos != n {
                return false;
            }
        } else {
            if pos == n || line[pos] != b',' {
                return false;
            }
            pos += 1;
        }
        out[s] = v;
    }
    true
}

/// Whether `b` is ASCII whitespace inside a line (the csv crate trims `\t`, `\n`, `\x0C`,
/// `\r` and space; lines here hold no `\n` and no `\r`).
fn blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\x0C')
}

/// Parses the line at `text[start..]` like [`fast_fields`]: the index of its `\n` (a `\r`
/// just before it is the line's terminator too) if the line is whole in `text` and every field
/// read is a finite number that `fast_float2` takes whole (trimmed of blanks), the columns not
/// read hold no `\r`, and the line has exactly `slot.len()` fields; `None` otherwise.
fn fast_line(text: &[u8], start: usize, slot: &[usize], out: &mut [f64]) -> Option<usize> {
    let n = text.len();
    let last = slot.len() - 1;
    let mut pos = start;
    for (k, &s) in slot.iter().enumerate() {
        if s == UNREAD {
            pos += memchr::memchr3(b',', b'\n', b'\r', &text[pos..])?;
        } else {
            while pos < n && blank(text[pos]) {
                pos += 1;
            }
            let (v, used) = fast_float2::parse_partial::<f64, _>(&text[pos..]).ok()?;
            if !v.is_finite() || used == 0 {
                return None;
            }
            pos += used;
            while pos < n && blank(text[pos]) {
                pos += 1;
            }
            out[s] = v;
        }
        match (text.get(pos)?, k == last) {
            (b',', false) => pos += 1,
            (b'\n', true) => return Some(pos),
            (b'\r', true) if text.get(pos + 1) == Some(&b'\n') => return Some(pos + 1),
            _ => return None,
        }
    }
    None
}
