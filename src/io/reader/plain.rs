//! The fast path of the reader: a *plain* line (not empty, no `"`, no `\r` but one just
//! before the `\n`) splits at every `,` exactly as the csv crate would split it, so its fields
//! are trimmed of ASCII whitespace and parsed straight from the bytes by `fast_float2`
//! (correctly rounded, the same `f64` as `str::parse`; no UTF-8 check: a non-ASCII byte is not
//! part of a number). A plain line the fast parse does not take whole (a field that is not a
//! finite plain number, a ragged line, the value limit reached) is judged again field by field
//! with `str::parse` ([`Rows::row`]) in the order and with the errors of the csv path.

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

impl Rows<'_> {
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
