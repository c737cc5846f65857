//! Reading dataset 58 / 58b blocks; every other dataset is skipped by its block boundaries.

use std::io::{BufRead, BufReader};
use std::path::Path;

use faer::c64;

use super::fortran;
use super::types::{Abscissa, Axis, DataType, Dof, Function, FunctionType, Ordinate, Precision};
use crate::error::{Error, Result, excerpt, excerpt_bytes};
use crate::limits::{MAX_LINE_BYTES, MAX_VALUES, read_line};

mod binary;

use binary::{BinaryHeader, binary_header, binary_values};

/// Reads every dataset 58 and 58b block of a Universal File, in file order; other datasets are
/// skipped. The file is streamed, line by line and binary block by block: memory holds the
/// values read and one line, under the readers' size rule ([`crate::limits`]).
///
/// # Errors
/// [`Error::Io`] if the file cannot be read; [`Error::FileLimit`] for a line longer than
/// [`MAX_LINE_BYTES`] or more than [`MAX_VALUES`] values (`/dev/zero` is refused after a
/// mebibyte); [`Error::Uff`] (naming the file, block and line) as [`parse`].
///
/// # Examples
/// ```no_run
/// let functions = bearing_ident::uff::read("rig.uff")?;
/// println!("{} functions", functions.len());
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn read(path: impl AsRef<Path>) -> Result<Vec<Function>> {
    let path = path.as_ref();
    let label = excerpt(&path.display().to_string());
    let file = crate::limits::open(path, Some("*.uff"))?;
    parse_from(BufReader::new(file), &label)
}

/// Reads every dataset 58 and 58b block of the bytes of a Universal File; `path` names it in
/// errors.
///
/// # Errors
/// [`Error::Uff`], naming the block (one-based) and the line, for text outside a block, a block
/// that is not closed by `-1`, a header field that is not a number, an unknown ordinate type,
/// byte order or float format, a 58b byte count that differs from what the points take or
/// exceeds the bytes present, too few or too many values, or a value that is not a number or
/// overflows `f64`; [`Error::FileLimit`] as [`read`].
///
/// # Examples
/// ```
/// use bearing_ident::uff::{self, Abscissa, Ordinate};
/// let text = "    -1\n    58\nID 1\nID 2\nID 3\nID 4\nID 5\n\
/// \x20   1         0    0         0 NONE               3   2 NONE               0   0\n\
/// \x20        2         3         1  0.00000E+00  1.00000E-03  0.00000E+00\n\
/// \x20       17    0    0    0 Time                 s\n\
/// \x20       13    0    0    0 Force                N\n\
/// \x20        0    0    0    0 NONE                 NONE\n\
/// \x20        0    0    0    0 NONE                 NONE\n\
/// \x20 1.50000E+00-2.00000E+00  2.50000E-01\n    -1\n";
/// let f = &uff::parse(text.as_bytes(), "mem.uff")?[0];
/// assert_eq!(f.response.node, 3);
/// assert_eq!(f.response.direction, 2);
/// assert_eq!(f.abscissa, Abscissa::Even { x0: 0.0, dx: 1e-3, n: 3 });
/// assert_eq!(f.ordinate, Ordinate::Real(vec![1.5, -2.0, 0.25]));
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn parse(data: &[u8], path: &str) -> Result<Vec<Function>> {
    parse_from(data, path)
}

/// [`parse`] of a stream.
fn parse_from(reader: impl BufRead, path: &str) -> Result<Vec<Function>> {
    let mut lines = Lines {
        reader,
        path,
        line: 0,
        values: 0,
    };
    let mut functions = Vec::new();
    let mut block = 0;
    while let Some(l) = lines.next()? {
        let t = l.trim_ascii();
        if t.is_empty() {
            continue;
        }
        let at = Where {
            path,
            block: block + 1,
        };
        if t != b"-1" {
            return Err(at.error(
                lines.line,
                format!(
                    "text outside a block (expected `    -1`): `{}`",
                    excerpt_bytes(t)
                ),
            ));
        }
        block += 1;
        let start = lines.line;
        let Some(head) = lines.next()? else {
            return Err(at.error(start, "the file ends after the block's opening `-1`".into()));
        };
        let dataset = head
            .split(|b| b.is_ascii_whitespace())
            .find(|t| !t.is_empty())
            .unwrap_or(b"");
        match dataset {
            b"58" => functions.push(read_block(&mut lines, &at, None)?),
            b"58b" => {
                let header = binary_header(&head).ok_or_else(|| {
                    at.error(
                        lines.line,
                        format!("unreadable 58b header `{}`", excerpt_bytes(&head)),
                    )
                })?;
                functions.push(read_block(&mut lines, &at, Some(header))?);
            }
            _ => loop {
                match lines.next()? {
                    Some(l) if l.trim_ascii() == b"-1" => break,
                    Some(_) => {}
                    None => {
                        return Err(at.error(
                            start,
                            format!(
                                "block of dataset `{}` is not closed by `-1`",
                                excerpt_bytes(dataset)
                            ),
                        ));
                    }
                }
            },
        }
    }
    Ok(functions)
}

/// The file and block an error is in.
struct Where<'a> {
    path: &'a str,
    block: usize,
}

impl Where<'_> {
    fn error(&self, line: u64, message: String) -> Error {
        Error::Uff {
            path: self.path.to_owned(),
            block: self.block,
            line,
            message,
        }
    }
}

/// The lines of the file, with their one-based numbers, read as they are needed.
struct Lines<'a, R> {
    reader: R,
    /// The file, for errors.
    path: &'a str,
    /// Number of the line last returned.
    line: u64,
    /// Values read so far, against [`MAX_VALUES`].
    values: u64,
}

impl<R: BufRead> Lines<'_, R> {
    fn io(&self, e: &std::io::Error) -> Error {
        Error::Io {
            path: self.path.to_owned(),
            message: e.to_string(),
        }
    }

    /// The next line, without its `\n` or `\r\n`, into `line`; `false` at the end.
    ///
    /// # Errors
    /// [`Error::Io`]; [`Error::FileLimit`] for a line longer than [`MAX_LINE_BYTES`].
    fn next_into(&mut self, line: &mut Vec<u8>) -> Result<bool> {
        match read_line(&mut self.reader, line, MAX_LINE_BYTES).map_err(|e| self.io(&e))? {
            None => Err(Error::FileLimit {
                path: self.path.to_owned(),
                what: format!("line {}: bytes of a line", self.line + 1),
                limit: MAX_LINE_BYTES,
            }),
            Some(false) => Ok(false),
            Some(true) => {
                self.line += 1;
                if line.last() == Some(&b'\r') {
                    line.pop();
                }
                Ok(true)
            }
        }
    }

    /// The next line, without its `\n` or `\r\n`, or `None` at the end.
    fn next(&mut self) -> Result<Option<Vec<u8>>> {
        let mut line = Vec::new();
        Ok(self.next_into(&mut line)?.then_some(line))
    }

    /// The next `n` bytes as they are; fewer if the file ends first (memory grows only with
    /// what arrives, never to a count a header claims).
    fn take(&mut self, n: usize) -> Result<Vec<u8>> {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(
            &mut std::io::Read::take(&mut self.reader, n as u64),
            &mut bytes,
        )
        .map_err(|e| self.io(&e))?;
        self.line += bytes.iter().filter(|&&b| b == b'\n').count() as u64;
        Ok(bytes)
    }

    /// Skips blanks and line ends up to the next text, counting the lines.
    fn skip_blank(&mut self) -> Result<()> {
        loop {
            let path = self.path;
            let buf = self.reader.fill_buf().map_err(|e| Error::Io {
                path: path.to_owned(),
                message: e.to_string(),
            })?;
            if buf.is_empty() {
                return Ok(());
            }
            let blanks = buf.iter().take_while(|b| b.is_ascii_whitespace()).count();
            let ends = buf[..blanks].iter().filter(|&&b| b == b'\n').count();
            let more = blanks == buf.len();
            self.reader.consume(blanks);
            self.line += ends as u64;
            if !more {
                return Ok(());
            }
        }
    }

    /// Counts `n` more values of the file against [`MAX_VALUES`].
    ///
    /// # Errors
    /// [`Error::FileLimit`] past it.
    fn count_values(&mut self, n: usize) -> Result<()> {
        self.values = self.values.saturating_add(n as u64);
        if self.values > MAX_VALUES {
            return Err(Error::FileLimit {
                path: self.path.to_owned(),
                what: format!("line {}: values", self.line),
                limit: MAX_VALUES,
            });
        }
        Ok(())
    }
}

/// Widths of record 6's fields: `2(I5,I10),2(1X,10A1,I10,I4)`.
const RECORD6: [usize; 12] = [5, 10, 5, 10, 1, 10, 10, 4, 1, 10, 10, 4];
/// Widths of record 7's fields: `3I10,3E13.5`.
const RECORD7: [usize; 6] = [10, 10, 10, 13, 13, 13];
/// Widths of records 8–11's fields: `I10,3I5,2(1X,20A1)`.
const AXIS: [usize; 8] = [10, 5, 5, 5, 1, 20, 1, 20];

/// Text of a field, blanks at both ends removed, non-UTF-8 bytes replaced.
fn text(field: &[u8]) -> String {
    String::from_utf8_lossy(field.trim_ascii()).into_owned()
}

/// Reads the eleven header lines and the values of a block whose dataset line was read, and its
/// closing `-1`.
fn read_block(
    lines: &mut Lines<'_, impl BufRead>,
    at: &Where,
    binary: Option<BinaryHeader>,
) -> Result<Function> {
    let mut header: [Vec<u8>; 11] = Default::default();
    for (k, slot) in header.iter_mut().enumerate() {
        *slot = lines.next()?.ok_or_else(|| {
            at.error(
                lines.line,
                format!("the file ends in the header, before record {}", k + 1),
            )
        })?;
    }
    let first = lines.line - 10;
    let id =
        std::array::from_fn(|k| String::from_utf8_lossy(header[k].trim_ascii_end()).into_owned());
    let int = |field: &[u8], line: u64, what: &str| -> Result<i64> {
        fortran::integer(field).map_err(|()| {
            at.error(
                line,
                format!("{what} `{}` is not an integer", excerpt_bytes(field)),
            )
        })
    };
    let small = |v: i64, line: u64, what: &str| -> Result<i32> {
        i32::try_from(v).map_err(|_| at.error(line, format!("{what} {v} is out of range")))
    };

    // Record 6.
    let line6 = first + 5;
    let c = fortran::columns(&header[5], &RECORD6);
    let function_type = FunctionType::from_code(small(
        int(c[0], line6, "function type")?,
        line6,
        "function type",
    )?);
    let function_id = int(c[1], line6, "function ID")?;
    let version = int(c[2], line6, "version number")?;
    let load_case = int(c[3], line6, "load case")?;
    let response = Dof {
        entity: text(c[5]),
        node: int(c[6], line6, "response node")?,
        direction: int(c[7], line6, "response direction")?,
    };
    let reference = Dof {
        entity: text(c[9]),
        node: int(c[10], line6, "reference node")?,
        direction: int(c[11], line6, "reference direction")?,
    };

    // Record 7.
    let line7 = first + 6;
    let (ordinate_type, n, even, x0, dx, z_value) = record7(&header[6]).ok_or_else(|| {
        at.error(
            line7,
            format!(
                "record 7 `{}` is not `3I10,3E13.5`",
                excerpt_bytes(header[6].trim_ascii_end())
            ),
        )
    })?;
    let (complex, precision) = match ordinate_type {
        2 => (false, Precision::Single),
        4 => (false, Precision::Double),
        5 => (true, Precision::Single),
        6 => (true, Precision::Double),
        t => {
            return Err(at.error(
                line7,
                format!(
                    "ordinate type {t} is not 2 (real single), 4 (real double), 5 (complex single) or 6 (complex double)"
                ),
            ));
        }
    };
    let n = usize::try_from(n)
        .map_err(|_| at.error(line7, format!("number of points {n} is negative")))?;
    let even = match even {
        1 => true,
        0 => false,
        s => {
            return Err(at.error(
                line7,
                format!("abscissa spacing {s} is not 1 (even) or 0 (uneven)"),
            ));
        }
    };
    // Checked before any value is read: a header may claim any count.
    lines.count_values(n.saturating_mul(usize::from(complex) + 1 + usize::from(!even)))?;
    if !(x0.is_finite() && dx.is_finite() && z_value.is_finite()) {
        return Err(at.error(line7, "an abscissa value overflows f64".into()));
    }

    // Records 8–11.
    let mut axes = Vec::with_capacity(4);
    for (k, text_line) in header.iter().enumerate().skip(7) {
        let line = first + k as u64;
        let c = fortran::columns(text_line, &AXIS);
        let code = small(int(c[0], line, "data type")?, line, "data type")?;
        axes.push(Axis {
            data_type: DataType::from_code(code),
            length_exponent: small(int(c[1], line, "length exponent")?, line, "length exponent")?,
            force_exponent: small(int(c[2], line, "force exponent")?, line, "force exponent")?,
            temperature_exponent: small(
                int(c[3], line, "temperature exponent")?,
                line,
                "temperature exponent",
            )?,
            label: text(c[5]),
            units: text(c[7]),
        });
    }
    let mut axes = axes.into_iter();
    let mut axis = || axes.next().unwrap_or_else(Axis::none);
    let (abscissa_axis, numerator, denominator, z_axis) = (axis(), axis(), axis(), axis());

    let shape = Shape {
        n,
        even,
        complex,
        precision,
    };
    let (xs, ys) = match binary {
        None => ascii_values(lines, at, &shape)?,
        Some(h) => binary_values(lines, at, &shape, h)?,
    };
    let abscissa = if even {
        Abscissa::Even { x0, dx, n }
    } else {
        Abscissa::Uneven(xs)
    };
    let ordinate = if complex {
        Ordinate::Complex(ys.chunks_exact(2).map(|p| c64::new(p[0], p[1])).collect())
    } else {
        Ordinate::Real(ys)
    };
    Ok(Function {
        id,
        function_type,
        function_id,
        version,
        load_case,
        response,
        reference,
        precision,
        z_value,
        abscissa_axis,
        numerator,
        denominator,
        z_axis,
        abscissa,
        ordinate,
    })
}

/// Record 7's ordinate type, number of points, spacing, `x0`, `dx` and z value, at the widths
/// or split at whitespace.
fn record7(line: &[u8]) -> Option<(i64, i64, i64, f64, f64, f64)> {
    let parse = |f: &[&[u8]]| -> Option<(i64, i64, i64, f64, f64, f64)> {
        let r = |k: usize| -> Option<f64> {
            Some(
                fortran::real(f.get(k).copied().unwrap_or(b""))
                    .ok()?
                    .unwrap_or(0.0),
            )
        };
        Some((
            fortran::integer(f.first()?).ok()?,
            fortran::integer(f.get(1)?).ok()?,
            fortran::integer(f.get(2)?).ok()?,
            r(3)?,
            r(4)?,
            r(5)?,
        ))
    };
    parse(&fortran::columns(line, &RECORD7)).or_else(|| {
        let tokens: Vec<&[u8]> = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
            .take(7)
            .collect();
        parse(&tokens)
    })
}

/// What record 12 holds.
struct Shape {
    n: usize,
    even: bool,
    complex: bool,
    precision: Precision,
}

impl Shape {
    /// Ordinate reals per point (1 or 2).
    fn parts(&self) -> usize {
        if self.complex { 2 } else { 1 }
    }

    /// Field widths of one line of record 12, repeating.
    fn widths(&self) -> &'static [usize] {
        match (self.precision, self.even, self.complex) {
            (Precision::Single, _, _) => &[13],
            (Precision::Double, true, _) => &[20],
            (Precision::Double, false, false) => &[13, 20],
            (Precision::Double, false, true) => &[13, 20, 20],
        }
    }
}

/// Splits interleaved values into the abscissa (uneven) and the ordinate reals.
fn split(values: Vec<f64>, shape: &Shape) -> (Vec<f64>, Vec<f64>) {
    if shape.even {
        return (Vec::new(), values);
    }
    let per = 1 + shape.parts();
    let mut xs = Vec::with_capacity(shape.n);
    let mut ys = Vec::with_capacity(shape.n * shape.parts());
    for point in values.chunks_exact(per) {
        xs.push(point[0]);
        ys.extend_from_slice(&point[1..]);
    }
    (xs, ys)
}

/// Record 12 in ASCII, and the closing `-1`.
fn ascii_values(
    lines: &mut Lines<'_, impl BufRead>,
    at: &Where,
    shape: &Shape,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let per = shape.parts() + usize::from(!shape.even);
    let needed = shape.n.checked_mul(per).ok_or_else(|| {
        at.error(
            lines.line,
            format!("{} points overflow the address space", shape.n),
        )
    })?;
    // A header may claim any count: the values grow as they arrive, from a small start.
    let mut values = Vec::with_capacity(needed.min(1 << 16));
    let mut line = Vec::new();
    loop {
        if !lines.next_into(&mut line)? {
            return Err(at.error(
                lines.line,
                format!(
                    "the file ends after {} of {needed} values, before the closing `-1`",
                    values.len()
                ),
            ));
        }
        if line.trim_ascii() == b"-1" {
            if values.len() < needed {
                return Err(at.error(
                    lines.line,
                    format!(
                        "the block ends after {} of the {needed} values of {} points",
                        values.len(),
                        shape.n
                    ),
                ));
            }
            break;
        }
        if line.trim_ascii().is_empty() {
            continue;
        }
        if values.len() >= needed {
            return Err(at.error(
                lines.line,
                format!(
                    "more than the {needed} values of {} points before the closing `-1`",
                    shape.n
                ),
            ));
        }
        fortran::values(&line, shape.widths(), &mut values)
            .map_err(|t| at.error(lines.line, format!("value `{t}` is not a number")))?;
        if values.len() > needed {
            // Some writers fill the last line with zeros; anything else is a wrong count.
            if values[needed..].iter().any(|&v| v != 0.0) {
                return Err(at.error(
                    lines.line,
                    format!("more than the {needed} values of {} points", shape.n),
                ));
            }
            values.truncate(needed);
        }
        if let Some(v) = values.iter().rev().take(8).find(|v| !v.is_finite()) {
            return Err(at.error(lines.line, format!("value {v} overflows f64")));
        }
    }
    Ok(split(values, shape))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_strip_crlf_and_count() {
        let mut l = Lines {
            reader: &b"a\r\nb\n\nc"[..],
            path: "m.uff",
            line: 0,
            values: 0,
        };
        assert_eq!(l.next().unwrap(), Some(b"a".to_vec()));
        assert_eq!(l.next().unwrap(), Some(b"b".to_vec()));
        assert_eq!(l.take(2).unwrap(), b"\nc");
        assert_eq!(l.line, 3);
        assert_eq!(l.take(1).unwrap(), b"");
        assert_eq!(l.next().unwrap(), None);
    }

    /// The readers' size rule: `/dev/zero` (no newline) stops after a mebibyte, a header that
    /// claims more values than a file may hold is refused before any is read, and neither
    /// holds more than the line it refuses.
    #[test]
    fn endless_or_huge_input_is_refused_by_the_size_rule() {
        let zeros = BufReader::new(std::io::repeat(0));
        let e = parse_from(zeros, "zero.uff").unwrap_err();
        assert_eq!(e.kind(), "too_large");
        assert!(
            e.to_string()
                .starts_with("zero.uff: line 1: bytes of a line"),
            "{e}"
        );
        let head = "    -1\n    58\n1\n2\n3\n4\n5\n\
            \x20   1         0    0         0 NONE               1   1 NONE               0   0\n\
            \x20        4 300000000         1  0.00000E+00  1.00000E+00  0.00000E+00\n\
            0\n0\n0\n0\n";
        let e = parse(head.as_bytes(), "big.uff").unwrap_err();
        assert_eq!(e.kind(), "too_large");
        assert!(e.to_string().contains(&MAX_VALUES.to_string()), "{e}");
        // An endless stream of good value lines stops at the value limit too (checked here
        // with the header's count just under it: the block's own count ends it first).
        let ok = head.replace("300000000", "        3") + "1 2 3\n    -1\n";
        assert_eq!(parse(ok.as_bytes(), "ok.uff").unwrap().len(), 1);
    }

    #[test]
    fn binary_header_at_widths_or_whitespace() {
        let h = binary_header(b"    58b     2     2          11        6408     0").unwrap();
        assert_eq!(
            (h.order, h.format, h.ascii_lines, h.bytes),
            (2, 2, 11, 6408)
        );
        let h = binary_header(b"58b 1 2 11 32").unwrap();
        assert_eq!((h.order, h.bytes), (1, 32));
        assert!(binary_header(b"    58b     1").is_none());
    }

    #[test]
    fn uff_error_names_file_block_and_line() {
        let e = Where {
            path: "f.uff",
            block: 3,
        }
        .error(17, "value `x` is not a number".into());
        assert_eq!(e.kind(), "malformed_uff");
        assert_eq!(
            e.to_string(),
            "f.uff, block 3, line 17: value `x` is not a number"
        );
    }

    #[test]
    fn unsupported_binary_formats_are_errors() {
        let head = "    -1\n    58b     3     2          11           0\n1\n2\n3\n4\n5\n\
            \x20   1         0    0         0 NONE               1   1 NONE               0   0\n\
            \x20        2         0         1  0.00000E+00  1.00000E+00  0.00000E+00\n\
            0\n0\n0\n0\n    -1\n";
        for (from, to, says) in [
            ("    3     2", "    3     2", "byte order 3"),
            ("    3     2", "    1     1", "float format 1"),
        ] {
            let text = head.replacen(from, to, 1);
            let e = parse(text.as_bytes(), "b.uff").unwrap_err();
            assert!(e.to_string().contains(says), "{e}");
        }
        let e = Error::UffRecord {
            path: "b.uff".into(),
            load_case: 2,
            message: "no force".into(),
        };
        assert_eq!(e.kind(), "inconsistent_records");
        assert_eq!(e.to_string(), "b.uff: load case 2: no force");
    }
}
