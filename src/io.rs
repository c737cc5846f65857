//! Edge: records as CSV files (feature `csv`).
//!
//! One file per record: a header line, then one comma-separated row per sample, with a time
//! column (s, uniformly sampled) and named force (N) and displacement (m) columns:
//!
//! ```text
//! t,fx,fy,x,y
//! 0,0,0,0,0
//! 0.000149253731343,12.5,0.6,1.2e-9,-3.0e-11
//! …
//! ```
//!
//! Reading streams the file row by row (the csv crate, one reused row buffer): only the parsed
//! channels are held, never the text. Every problem names the file, the line and the column.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Error, Result};
use crate::records::Record;

/// Column names of a record file: the time column and one force and one displacement column per
/// degree of freedom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CsvLayout {
    /// Time column (s). Default `t`.
    pub time: String,
    /// Force columns (N), one per degree of freedom. Default `fx, fy`.
    pub forces: Vec<String>,
    /// Displacement columns (m), one per degree of freedom. Default `x, y`.
    pub displacements: Vec<String>,
}

impl Default for CsvLayout {
    fn default() -> Self {
        Self::for_dofs(2)
    }
}

impl CsvLayout {
    /// The conventional names for `n` degrees of freedom: `fx, fy, fz` and `x, y, z` up to
    /// three, `f1 … fn` and `x1 … xn` beyond; time `t`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::io::CsvLayout;
    /// assert_eq!(CsvLayout::for_dofs(3).forces, ["fx", "fy", "fz"]);
    /// assert_eq!(CsvLayout::for_dofs(4).displacements[3], "x4");
    /// ```
    pub fn for_dofs(n: usize) -> Self {
        let (forces, displacements) = if n <= 3 {
            let axes = ["x", "y", "z"];
            (
                axes[..n].iter().map(|a| format!("f{a}")).collect(),
                axes[..n].iter().map(|a| (*a).to_string()).collect(),
            )
        } else {
            (
                (1..=n).map(|i| format!("f{i}")).collect(),
                (1..=n).map(|i| format!("x{i}")).collect(),
            )
        };
        Self {
            time: "t".into(),
            forces,
            displacements,
        }
    }

    fn columns(&self) -> impl Iterator<Item = &String> {
        std::iter::once(&self.time)
            .chain(&self.forces)
            .chain(&self.displacements)
    }
}

/// Reads one record file. The record's label is the path as given.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read; [`Error::Csv`] for a ragged or unparsable line;
/// [`Error::MissingColumn`]; [`Error::CsvNonFinite`]; [`Error::NonUniformTime`]; and the
/// [`Record::new`] errors (too few rows, mismatched channel counts in the layout).
pub fn read_record(path: impl AsRef<Path>, layout: &CsvLayout) -> Result<Record> {
    let path = path.as_ref();
    let label = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| Error::Io {
        path: label.clone(),
        message: e.to_string(),
    })?;
    let bytes = file.metadata().map_or(0, |m| m.len());
    read_csv(
        std::io::BufReader::with_capacity(1 << 16, file),
        &label,
        layout,
        bytes,
    )
}

/// Reads one record from any reader; `label` names it in errors.
///
/// # Errors
/// As [`read_record`].
///
/// # Examples
/// ```
/// use bearing_ident::io::{CsvLayout, read_record_from};
/// let text = "t,fx,x\n0,0,0\n0.5,1,0.1\n1,0,0.2\n1.5,0,0.1\n2,0,0\n2.5,0,0\n3,0,0\n3.5,0,0\n";
/// let layout = CsvLayout { time: "t".into(), forces: vec!["fx".into()], displacements: vec!["x".into()] };
/// let rec = read_record_from(text.as_bytes(), "mem.csv", &layout)?;
/// assert_eq!(rec.len(), 8);
/// assert!((rec.sample_rate() - 2.0).abs() < 1e-12);
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn read_record_from(
    reader: impl std::io::Read,
    label: &str,
    layout: &CsvLayout,
) -> Result<Record> {
    read_csv(reader, label, layout, 0)
}

/// The most characters of a file's text (a field, the header) that an error message quotes;
/// longer text is cut and ends in `…`.
pub const QUOTE_CHARS: usize = 80;

/// `text` cut to [`QUOTE_CHARS`] characters, with `…` when cut.
fn quote(text: &str) -> String {
    match text.char_indices().nth(QUOTE_CHARS) {
        Some((end, _)) => format!("{}…", &text[..end]),
        None => text.to_owned(),
    }
}

/// Rows read before the channel buffers are sized from the file length.
const SIZING_ROWS: usize = 64;

/// The reader behind [`read_record`] and [`read_record_from`]; `bytes` is the input's length
/// when known (0 otherwise), used to size the channel buffers once so they never reallocate.
fn read_csv(
    reader: impl std::io::Read,
    label: &str,
    layout: &CsvLayout,
    bytes: u64,
) -> Result<Record> {
    let csv_error = |e: csv::Error| {
        let line = e.position().map_or(0, csv::Position::line);
        let message = match e.kind() {
            csv::ErrorKind::UnequalLengths {
                expected_len, len, ..
            } => format!("{len} fields, the header has {expected_len}"),
            _ => e.to_string(),
        };
        match e.kind() {
            csv::ErrorKind::Io(_) => Error::Io {
                path: label.to_owned(),
                message,
            },
            _ => Error::Csv {
                path: label.to_owned(),
                line,
                message,
            },
        }
    };
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(reader);
    let header = rdr.byte_headers().map_err(csv_error)?.clone();
    let names: Vec<String> = header
        .iter()
        .map(|h| String::from_utf8_lossy(h).into_owned())
        .collect();
    let index: Vec<usize> = layout
        .columns()
        .map(|c| {
            names
                .iter()
                .position(|h| h == c)
                .ok_or_else(|| Error::MissingColumn {
                    path: label.to_owned(),
                    column: c.clone(),
                    header: quote(&names.join(",")),
                })
        })
        .collect::<Result<_>>()?;

    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); index.len()];
    // Line of every row, kept only once the rows stop being consecutive lines.
    let mut lines: Option<Vec<u64>> = None;
    let mut first_line = 0;
    let mut columns_start: Option<u64> = None;
    let mut row = csv::ByteRecord::new();
    while rdr.read_byte_record(&mut row).map_err(csv_error)? {
        let line = row.position().map_or(0, csv::Position::line);
        let r = columns[0].len();
        if r == SIZING_ROWS && bytes > 0 {
            let offset = row.position().map_or(0, csv::Position::byte);
            let first = columns_start.unwrap_or(0);
            let per_row = (offset.saturating_sub(first) as f64 / r as f64).max(1.0);
            let rows = ((bytes.saturating_sub(first)) as f64 / per_row * 1.02) as usize + 16;
            for c in &mut columns {
                c.reserve_exact(rows.saturating_sub(c.len()));
            }
        }
        if r == 0 {
            columns_start = row.position().map(csv::Position::byte);
        }
        if r == 0 {
            first_line = line;
        }
        match &mut lines {
            Some(l) => l.push(line),
            None if line != first_line + r as u64 => {
                let mut l: Vec<u64> = (0..r as u64).map(|i| first_line + i).collect();
                l.push(line);
                lines = Some(l);
            }
            None => {}
        }
        for ((col, &i), name) in columns.iter_mut().zip(&index).zip(layout.columns()) {
            let field = row.get(i).unwrap_or_default();
            let value = std::str::from_utf8(field)
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| Error::Csv {
                    path: label.to_owned(),
                    line,
                    message: format!(
                        "column `{name}`: `{}` is not a number",
                        quote(&String::from_utf8_lossy(field))
                    ),
                })?;
            if !value.is_finite() {
                return Err(Error::CsvNonFinite {
                    path: label.to_owned(),
                    line,
                    column: name.clone(),
                });
            }
            col.push(value);
        }
    }
    let line_of = |r: usize| lines.as_ref().map_or(first_line + r as u64, |l| l[r]);

    let mut columns = columns.into_iter();
    let time = columns.next().unwrap_or_default();
    let sample_rate = uniform_rate(&time, label, &line_of)?;
    drop(time);
    let forces: Vec<Vec<f64>> = columns.by_ref().take(layout.forces.len()).collect();
    let displacements: Vec<Vec<f64>> = columns.collect();
    Record::new(label, sample_rate, forces, displacements)
}

/// The sampling rate of a uniform time column: `(N − 1)/(t_last − t_0)`, every sample within
/// 1 % of a step of its place on the grid.
fn uniform_rate(time: &[f64], label: &str, line_of: &dyn Fn(usize) -> u64) -> Result<f64> {
    if time.len() < 2 {
        return Err(Error::RecordTooShort {
            record: label.to_owned(),
            samples: time.len(),
            minimum: crate::records::MIN_SAMPLES,
        });
    }
    let (t0, last) = (time[0], time[time.len() - 1]);
    let step = (last - t0) / (time.len() - 1) as f64;
    let increasing = step > 0.0 && step.is_finite();
    for (i, &t) in time.iter().enumerate() {
        let expected = t0 + i as f64 * step;
        if !increasing || (t - expected).abs() > 0.01 * step {
            let i = if increasing { i } else { 1 };
            return Err(Error::NonUniformTime {
                path: label.to_owned(),
                line: line_of(i),
                expected_s: t0 + i as f64 * step,
                actual_s: time[i],
                step_s: step,
            });
        }
    }
    Ok(1.0 / step)
}

/// Writes a record in the layout [`read_record`] reads, times `t_m = m / f_s`, every number in
/// its shortest exact decimal form.
///
/// # Errors
/// [`Error::Io`] if the file cannot be written; [`Error::DofMismatch`] if the layout names a
/// different number of channels than the record has.
pub fn write_record(path: impl AsRef<Path>, record: &Record, layout: &CsvLayout) -> Result<()> {
    let path = path.as_ref();
    let label = path.display().to_string();
    let io_error = |e: std::io::Error| Error::Io {
        path: label.clone(),
        message: e.to_string(),
    };
    let file = std::fs::File::create(path).map_err(io_error)?;
    write_record_to(std::io::BufWriter::new(file), record, layout).map_err(|e| match e {
        Error::Io { message, .. } => Error::Io {
            path: label.clone(),
            message,
        },
        other => other,
    })
}

/// Writes a record to any writer; see [`write_record`].
///
/// # Errors
/// As [`write_record`].
pub fn write_record_to(
    writer: impl std::io::Write,
    record: &Record,
    layout: &CsvLayout,
) -> Result<()> {
    let n = record.dofs();
    if layout.forces.len() != n || layout.displacements.len() != n {
        return Err(Error::DofMismatch {
            record: record.label().to_owned(),
            expected: layout.forces.len(),
            actual: n,
        });
    }
    let io = |e: csv::Error| Error::Io {
        path: record.label().to_owned(),
        message: e.to_string(),
    };
    let mut w = csv::Writer::from_writer(writer);
    w.write_record(layout.columns()).map_err(io)?;
    let mut field = String::new();
    for m in 0..record.len() {
        let t = m as f64 / record.sample_rate();
        let values = std::iter::once(t)
            .chain((0..n).map(|c| record.force(c)[m]))
            .chain((0..n).map(|c| record.displacement(c)[m]));
        for v in values {
            field.clear();
            // Shortest exact decimal; scientific notation for very small or large values.
            if v == 0.0 || (1e-3..1e7).contains(&v.abs()) {
                write!(field, "{v}")
            } else {
                write!(field, "{v:e}")
            }
            .expect("writing to a String cannot fail");
            w.write_field(&field).map_err(io)?;
        }
        w.write_record(None::<&[u8]>).map_err(io)?;
    }
    w.flush().map_err(|e| Error::Io {
        path: record.label().to_owned(),
        message: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout1() -> CsvLayout {
        CsvLayout {
            time: "t".into(),
            forces: vec!["fx".into()],
            displacements: vec!["x".into()],
        }
    }

    fn rows(n: usize) -> String {
        let mut s = String::from("t,fx,x\n");
        for m in 0..n {
            s += &format!("{},{},{}\n", m as f64 * 0.01, m, 2 * m);
        }
        s
    }

    #[test]
    fn round_trip_is_exact() {
        let rec = Record::new(
            "r",
            1234.5,
            vec![(0..20).map(|m| (m as f64).sin() * 1e3).collect()],
            vec![(0..20).map(|m| (m as f64).cos() * 1e-7).collect()],
        )
        .unwrap();
        let mut buf = Vec::new();
        write_record_to(&mut buf, &rec, &layout1()).unwrap();
        let back = read_record_from(buf.as_slice(), "r", &layout1()).unwrap();
        assert_eq!(back.force(0), rec.force(0));
        assert_eq!(back.displacement(0), rec.displacement(0));
        assert!((back.sample_rate() / 1234.5 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn ragged_line_is_named() {
        let text = rows(10).replace("0.03,3,6\n", "0.03,3\n");
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::Csv { line: 5, .. }), "{e:?}");
    }

    #[test]
    fn unparsable_value_is_named() {
        let text = rows(10).replace("0.04,4,8\n", "0.04,four,8\n");
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(
            matches!(&e, Error::Csv { line: 6, message, .. } if message.contains("`fx`")),
            "{e:?}"
        );
    }

    #[test]
    fn missing_column_is_named() {
        let layout = CsvLayout {
            forces: vec!["fy".into()],
            ..layout1()
        };
        let e = read_record_from(rows(10).as_bytes(), "f.csv", &layout).unwrap_err();
        assert!(matches!(&e, Error::MissingColumn { column, .. } if column == "fy"));
    }

    #[test]
    fn non_finite_value_is_named() {
        let text = rows(10).replace("0.02,2,4\n", "0.02,2,NaN\n");
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(&e, Error::CsvNonFinite { line: 4, column, .. } if column == "x"));
    }

    #[test]
    fn nonuniform_time_is_named() {
        let text = rows(10).replace("0.05,5,10\n", "0.055,5,10\n");
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::NonUniformTime { line: 7, .. }), "{e:?}");
    }

    #[test]
    fn missing_file_is_an_io_error() {
        let e = read_record("/nonexistent/r.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::Io { .. }));
    }
}
