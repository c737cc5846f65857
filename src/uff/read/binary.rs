//! The binary part of a dataset 58b block: its header line (byte order, float format, ASCII
//! lines, bytes) and record 12 read from the bytes that follow, by count.

use super::*;

/// The 58b dataset line's byte order (1 little-, 2 big-endian), float format, number of ASCII
/// lines and number of bytes.
#[derive(Debug, Clone, Copy)]
pub(super) struct BinaryHeader {
    pub(super) order: i64,
    pub(super) format: i64,
    pub(super) ascii_lines: i64,
    pub(super) bytes: i64,
}

/// Reads `    58b     1     2          11        6408 …` at its widths (`I6,A1,I6,I6,I12,I12`),
/// or split at whitespace.
pub(super) fn binary_header(line: &[u8]) -> Option<BinaryHeader> {
    let c = fortran::columns(line, &[6, 1, 6, 6, 12, 12]);
    let fixed = || -> Option<BinaryHeader> {
        if c[0].trim_ascii() != b"58"
            || c[1] != b"b"
            || c[2..].iter().any(|f| f.trim_ascii().is_empty())
        {
            return None;
        }
        Some(BinaryHeader {
            order: fortran::integer(c[2]).ok()?,
            format: fortran::integer(c[3]).ok()?,
            ascii_lines: fortran::integer(c[4]).ok()?,
            bytes: fortran::integer(c[5]).ok()?,
        })
    };
    fixed().or_else(|| {
        let mut t = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
            .skip(1);
        let mut next = || t.next().and_then(|f| fortran::integer(f).ok());
        Some(BinaryHeader {
            order: next()?,
            format: next()?,
            ascii_lines: next()?,
            bytes: next()?,
        })
    })
}

/// Record 12 in binary (its byte count checked against the points), and the closing `-1`.
pub(super) fn binary_values(
    lines: &mut Lines<'_, impl BufRead>,
    at: &Where,
    shape: &Shape,
    h: BinaryHeader,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let line = lines.line;
    let little = match h.order {
        1 => true,
        2 => false,
        o => {
            return Err(at.error(
                line,
                format!("58b byte order {o} is not 1 (little-endian) or 2 (big-endian)"),
            ));
        }
    };
    if h.format != 2 {
        return Err(at.error(
            line,
            format!(
                "58b float format {} is not 2 (IEEE 754); others are not supported",
                h.format
            ),
        ));
    }
    if h.ascii_lines != 11 {
        return Err(at.error(
            line,
            format!(
                "58b header gives {} ASCII lines; dataset 58 has 11",
                h.ascii_lines
            ),
        ));
    }
    let y_bytes = match shape.precision {
        Precision::Single => 4,
        Precision::Double => 8,
    };
    let point = shape.parts() * y_bytes + if shape.even { 0 } else { 4 };
    let expected = shape.n.checked_mul(point);
    if expected.is_none_or(|e| i64::try_from(e).ok() != Some(h.bytes)) {
        return Err(at.error(
            line,
            format!(
                "58b header gives {} bytes, but {} points of this ordinate type take {}",
                h.bytes,
                shape.n,
                expected.map_or_else(|| "more than memory holds".into(), |e| e.to_string())
            ),
        ));
    }
    let expected = expected.unwrap_or(0);
    let bytes = lines.take(expected)?;
    if bytes.len() < expected {
        return Err(at.error(
            line,
            format!(
                "the binary block holds {} of its {expected} bytes",
                bytes.len()
            ),
        ));
    }
    let f32_at = |b: &[u8]| -> f64 {
        let a = [b[0], b[1], b[2], b[3]];
        f64::from(if little {
            f32::from_le_bytes(a)
        } else {
            f32::from_be_bytes(a)
        })
    };
    let f64_at = |b: &[u8]| -> f64 {
        let a = [b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]];
        if little {
            f64::from_le_bytes(a)
        } else {
            f64::from_be_bytes(a)
        }
    };
    let mut xs = Vec::with_capacity(if shape.even { 0 } else { shape.n });
    let mut ys = Vec::with_capacity(shape.n * shape.parts());
    for p in bytes.chunks_exact(point) {
        let mut rest = p;
        if !shape.even {
            xs.push(f32_at(&rest[..4]));
            rest = &rest[4..];
        }
        for v in rest.chunks_exact(y_bytes) {
            ys.push(if y_bytes == 4 { f32_at(v) } else { f64_at(v) });
        }
    }
    lines.skip_blank()?;
    match lines.next()? {
        Some(l) if l.trim_ascii() == b"-1" => Ok((xs, ys)),
        Some(l) => Err(at.error(
            lines.line,
            format!(
                "expected `-1` after the {expected} bytes of values, found `{}`",
                excerpt_bytes(l.trim_ascii())
            ),
        )),
        None => Err(at.error(
            lines.line,
            format!("the file ends after the {expected} bytes of values, before the closing `-1`"),
        )),
    }
}
