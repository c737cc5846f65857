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
//! Reading streams the file block by block through a buffer the reader keeps ([`CsvReader`],
//! reused across files): only the parsed channels are held, never the whole text. Plain numeric
//! lines are split and parsed straight from the bytes (a correctly rounded parser, the same
//! `f64` as `str::parse`); quoted fields and other unusual lines go through the csv crate.
//! Every problem names the file, the line and the column.
//!
//! # Limits
//! Memory of reading stays proportional to the values actually read: the input's length is a
//! hint, never the size of an allocation, and the channel buffers at most double as rows
//! arrive. A line is at most [`MAX_LINE_BYTES`] (1 MiB), a header at most [`MAX_COLUMNS`]
//! (4096) columns, a record at most [`MAX_VALUES`] (2²⁸) values; past any of them reading stops
//! with [`Error::CsvLimit`] naming the file and line. Messages quote at most
//! [`QUOTE_CHARS`](crate::error::QUOTE_CHARS) characters of the input.

mod reader;

#[cfg(test)]
use crate::error::CsvLimitKind;
pub use reader::CsvReader;
#[cfg(test)]
use reader::{Limits, MIN_CAPACITY, next_capacity};
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
/// [`Error::MissingColumn`]; [`Error::CsvNonFinite`]; [`Error::NonUniformTime`] (naming the
/// line whose time is off the grid); [`Error::CsvLimit`] past a [limit](self#limits); and the
/// [`Record::new`] errors (too few rows, mismatched channel counts in the layout).
pub fn read_record(path: impl AsRef<Path>, layout: &CsvLayout) -> Result<Record> {
    CsvReader::new(layout.clone()).read(path)
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
    CsvReader::new(layout.clone()).read_from(reader, label)
}

// The one size rule of every reader (`crate::limits`), under the names this module has always
// given it.
pub use crate::limits::{MAX_COLUMNS, MAX_LINE_BYTES, MAX_VALUES};

/// One input read with `limits` (tests use small ones).
#[cfg(test)]
fn read_csv_limited(
    reader: impl std::io::Read,
    label: &str,
    layout: &CsvLayout,
    bytes: u64,
    limits: Limits,
) -> Result<Record> {
    CsvReader::new(layout.clone()).read_limited(reader, label, bytes, limits)
}

/// The sampling rate of a uniform time column: `(N − 1)/(t_last − t_0)`, every sample within
/// [`TIME_GRID_TOLERANCE`](crate::records::TIME_GRID_TOLERANCE) (1 %) of a step of its place
/// on the grid. A time off the grid is blamed on its own line (see
/// [`offending_sample`]).
pub(crate) fn uniform_rate(
    time: &[f64],
    label: &str,
    line_of: &dyn Fn(usize) -> u64,
) -> Result<f64> {
    if time.len() < 2 {
        return Err(Error::RecordTooShort {
            record: label.to_owned(),
            samples: time.len(),
            minimum: crate::records::MIN_SAMPLES,
        });
    }
    // The grid that fits the times best (least squares of t on the sample index), not the one
    // through the end points: a first and a last time each off by 0.9 % of a step, inside the
    // tolerance, skew the end-point grid by 1.8 % and put good samples off it.
    // Either grid will do: the end points' (as always) or the fitted one.
    let (t0, last) = (time[0], time[time.len() - 1]);
    let ends = (t0, (last - t0) / (time.len() - 1) as f64);
    let first_off = |(t0, step): (f64, f64)| -> Option<usize> {
        let increasing = step > 0.0 && step.is_finite() && last > t0;
        (!increasing).then_some(0).or_else(|| {
            time.iter().enumerate().position(|(i, &t)| {
                (t - (t0 + i as f64 * step)).abs() > crate::records::TIME_GRID_TOLERANCE * step
            })
        })
    };
    let fitted = fitted_grid(time);
    let (off_grid, step) = match first_off(ends) {
        None => (None, ends.1),
        Some(at) => match first_off(fitted) {
            None => (None, fitted.1),
            Some(_) => (Some(at), ends.1),
        },
    };
    match off_grid {
        None => Ok(1.0 / step),
        Some(first_off) => {
            let (i, expected_s, step_s) = offending_sample(time, first_off, step);
            Err(Error::NonUniformTime {
                path: label.to_owned(),
                line: line_of(i),
                expected_s,
                actual_s: time[i],
                step_s,
            })
        }
    }
}

/// The uniform grid `t_i = t_0 + i·step` closest to `time` in least squares, as `(t_0, step)`:
/// with `ī = (N−1)/2`, `step = Σ (i − ī)(t_i − t̄) / Σ (i − ī)²`, `t_0 = t̄ − step·ī`. Times are
/// taken relative to the first, so that a clock far from zero loses no digits.
fn fitted_grid(time: &[f64]) -> (f64, f64) {
    let n = time.len() as f64;
    let first = time[0];
    let mean_i = (n - 1.0) / 2.0;
    let mean_t = time.iter().map(|t| t - first).sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &t) in time.iter().enumerate() {
        let di = i as f64 - mean_i;
        sxy += di * (t - first - mean_t);
        sxx += di * di;
    }
    let step = sxy / sxx;
    (first + mean_t - step * mean_i, step)
}

/// Most time differences sampled for the local step of [`offending_sample`].
const STEP_SAMPLES: usize = 4095;

/// The sample to blame for a time column off its grid, with the time it should have had and
/// the step: the grid through the end points is skewed by a bad first or last time, so the
/// step is taken as the median of (up to [`STEP_SAMPLES`], evenly spread) consecutive
/// differences, and the first difference off that step by more than the tolerance names the
/// sample — the later one of the pair, or the first sample when only the first difference is
/// off. `first_off` is the first sample off the end-point grid of step `grid_step`, the answer
/// when every difference agrees with the median (a slow drift).
fn offending_sample(time: &[f64], first_off: usize, grid_step: f64) -> (usize, f64, f64) {
    let n = time.len();
    let stride = (n - 1).div_ceil(STEP_SAMPLES).max(1);
    let mut diffs: Vec<f64> = (1..n)
        .step_by(stride)
        .map(|i| time[i] - time[i - 1])
        .filter(|d| d.is_finite())
        .collect();
    let step = if diffs.is_empty() {
        f64::NAN
    } else {
        let mid = diffs.len() / 2;
        *diffs.select_nth_unstable_by(mid, f64::total_cmp).1
    };
    if !(step > 0.0 && step.is_finite()) {
        // Time that stands still or runs backwards: the first sample not after its predecessor.
        let i = (1..n).find(|&i| time[i] <= time[i - 1]).unwrap_or(1);
        return (i, time[i - 1] + grid_step.abs(), grid_step);
    }
    let off = |i: usize| {
        (time[i] - time[i - 1] - step).abs() > crate::records::TIME_GRID_TOLERANCE * step
    };
    match (1..n).find(|&i| off(i)) {
        Some(1) if n > 2 && !off(2) => (0, time[1] - step, step),
        Some(i) => (i, time[i - 1] + step, step),
        None => (first_off, time[0] + first_off as f64 * grid_step, grid_step),
    }
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

    /// A column the layout reads given twice in the header (before: the first was read
    /// silently) is refused naming it; a repeated column nobody reads is harmless.
    #[test]
    fn a_repeated_column_name_is_refused() {
        let body = |extra: &str| -> String {
            rows(10)
                .lines()
                .skip(1)
                .map(|l| format!("{l}{extra}\n"))
                .collect()
        };
        let text = format!("t,fx,x,fx\n{}", body(",9"));
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(
            matches!(&e, Error::Csv { line: 1, message, .. }
                if message.starts_with("column `fx` appears twice in the header (fields 2 and 4)")),
            "{e:?}"
        );
        let text = format!("t,fx,x,q,q\n{}", body(",9,9"));
        assert_eq!(
            read_record_from(text.as_bytes(), "f.csv", &layout1())
                .unwrap()
                .len(),
            10
        );
    }

    #[test]
    fn non_finite_value_is_named() {
        let text = rows(10).replace("0.02,2,4\n", "0.02,2,NaN\n");
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(&e, Error::CsvNonFinite { line: 4, column, .. } if column == "x"));
    }

    #[test]
    fn jitter_inside_the_tolerance_is_accepted() {
        // Every time off its grid by up to ±0.9 % of a step, the first and last included in
        // opposite senses (before: refused, the end-point grid being skewed by 1.8 %).
        let jitter = |i: usize| 0.009 * [1.0, -0.5, 0.3, -1.0, 0.8, -0.2][i % 6];
        let n = 200;
        let column = |extra_at_10: f64| {
            let mut text = String::from("t,fx,x\n");
            for i in 0..n {
                let j = if i == n - 1 { -0.009 } else { jitter(i) };
                let j = if i == 10 { j + extra_at_10 } else { j };
                let _ = writeln!(text, "{},{},{}", (i as f64 + j) * 0.01, i % 7, i % 5);
            }
            text
        };
        let r = read_record_from(column(0.0).as_bytes(), "j.csv", &layout1()).unwrap();
        assert!(
            (r.sample_rate() / 100.0 - 1.0).abs() < 1e-4,
            "{}",
            r.sample_rate()
        );
        // Past the tolerance (1.7 % at one sample) it is still refused.
        let e = read_record_from(column(0.01).as_bytes(), "j.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::NonUniformTime { .. }), "{e:?}");
    }

    #[test]
    fn nonuniform_time_is_named() {
        let text = rows(10).replace("0.05,5,10\n", "0.055,5,10\n");
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::NonUniformTime { line: 7, .. }), "{e:?}");
    }

    /// A time error in the second data row, the middle and the last row is each blamed on
    /// its own line; so is one in the first row.
    #[test]
    fn nonuniform_time_names_the_offending_line() {
        let cases = [
            ("0,0,0\n", "0.005,0,0\n", 2),
            ("0.01,1,2\n", "0.013,1,2\n", 3),
            ("0.04,4,8\n", "0.047,4,8\n", 6),
            ("0.09,9,18\n", "0.1,9,18\n", 11),
            ("0.09,9,18\n", "0,9,18\n", 11),
            ("0.09,9,18\n", "1e9,9,18\n", 11),
            ("0.09,9,18\n", "0.08,9,18\n", 11),
        ];
        for (from, to, line) in cases {
            let text = rows(10).replace(from, to);
            let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
            assert!(
                matches!(e, Error::NonUniformTime { line: l, .. } if l == line),
                "{to}: {e:?}"
            );
        }
        // A time column that stands still names its second line.
        let text = "t,fx,x\n".to_owned() + &"0,0,0\n".repeat(10);
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::NonUniformTime { line: 3, .. }), "{e:?}");
        // The expected time and step come from the uniform part of the column.
        let text = rows(10).replace("0.09,9,18\n", "1e9,9,18\n");
        let Err(Error::NonUniformTime {
            expected_s, step_s, ..
        }) = read_record_from(text.as_bytes(), "f.csv", &layout1())
        else {
            panic!("not a time error")
        };
        assert!((expected_s - 0.09).abs() < 1e-12 && (step_s - 0.01).abs() < 1e-12);
    }

    fn small_limits() -> Limits {
        Limits {
            line_bytes: 100,
            columns: 8,
            values: 3 * 50,
        }
    }

    fn read_small(reader: impl std::io::Read) -> Result<Record> {
        read_csv_limited(reader, "f.csv", &layout1(), 0, small_limits())
    }

    #[test]
    fn a_line_past_the_limit_stops_the_reader() {
        // No newline at all: an endless header.
        let e = read_small(std::io::repeat(b'a')).unwrap_err();
        assert!(
            matches!(
                e,
                Error::CsvLimit {
                    line: 1,
                    limit: 100,
                    what: CsvLimitKind::LineBytes,
                    ..
                }
            ),
            "{e:?}"
        );
        // Zeros, as from /dev/zero.
        let e = read_small(std::io::repeat(0)).unwrap_err();
        assert!(matches!(e, Error::CsvLimit { line: 1, .. }), "{e:?}");
        // A long row after good ones is named by its line.
        let text = rows(10) + &"1".repeat(101) + "\n";
        let e = read_small(text.as_bytes()).unwrap_err();
        assert!(matches!(e, Error::CsvLimit { line: 12, .. }), "{e:?}");
        // A line of exactly the limit is fine.
        let text = rows(10) + "0.1,10," + &"0".repeat(93) + "\n";
        assert_eq!(read_small(text.as_bytes()).unwrap().len(), 11);
        // The real limit stops /dev/zero after a mebibyte.
        let e = read_record_from(std::io::repeat(0), "zero", &layout1()).unwrap_err();
        assert!(
            matches!(
                e,
                Error::CsvLimit {
                    limit: MAX_LINE_BYTES,
                    ..
                }
            ),
            "{e:?}"
        );
    }

    #[test]
    fn too_many_columns_or_values_stop_the_reader() {
        let header = (0..9)
            .map(|i| format!("c{i}"))
            .collect::<Vec<_>>()
            .join(",");
        let e = read_small(format!("{header}\n").as_bytes()).unwrap_err();
        assert!(
            matches!(
                e,
                Error::CsvLimit {
                    line: 1,
                    what: CsvLimitKind::Columns,
                    limit: 8,
                    ..
                }
            ),
            "{e:?}"
        );
        // 50 rows of 3 values fit; the 51st row (line 52) does not.
        assert_eq!(read_small(rows(50).as_bytes()).unwrap().len(), 50);
        let e = read_small(rows(51).as_bytes()).unwrap_err();
        assert!(
            matches!(
                e,
                Error::CsvLimit {
                    line: 52,
                    what: CsvLimitKind::Values,
                    ..
                }
            ),
            "{e:?}"
        );
        // An endless stream of valid rows stops at the limit.
        let endless = rows(1)
            .into_bytes()
            .into_iter()
            .chain((1u64..).flat_map(|m| format!("{},{m},{m}\n", m as f64 * 0.01).into_bytes()));
        let reader = IterRead(endless);
        let e = read_small(reader).unwrap_err();
        assert!(matches!(e, Error::CsvLimit { line: 52, .. }), "{e:?}");
    }

    /// Bytes from an iterator, as a reader.
    struct IterRead<I>(I);

    impl<I: Iterator<Item = u8>> std::io::Read for IterRead<I> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let mut n = 0;
            for (slot, b) in buf.iter_mut().zip(&mut self.0) {
                *slot = b;
                n += 1;
            }
            Ok(n)
        }
    }

    /// A 1 TiB sparse file after valid rows: the length is a hint, never an allocation; the
    /// NUL bytes then end at the line limit.
    #[test]
    fn a_sparse_terabyte_file_fails_fast() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sparse.csv");
        std::fs::write(&path, rows(100)).unwrap();
        let file = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
        file.set_len(1 << 40).unwrap();
        drop(file);
        let start = std::time::Instant::now();
        let e = read_record(&path, &layout1()).unwrap_err();
        assert!(matches!(e, Error::CsvLimit { line: 102, .. }), "{e:?}");
        assert!(start.elapsed().as_secs_f64() < 10.0);
    }

    #[test]
    fn capacity_follows_the_rows_read() {
        // Without a hint: doubling from the minimum.
        assert_eq!(next_capacity(0, 0), MIN_CAPACITY);
        assert_eq!(next_capacity(64, 0), 128);
        // A hint of 1000 rows: 125, 250, 500, 1000, then doubling past the hint.
        assert_eq!(next_capacity(64, 1000), 125);
        assert_eq!(next_capacity(125, 1000), 250);
        assert_eq!(next_capacity(500, 1000), 1000);
        assert_eq!(next_capacity(1000, 1000), 2000);
        // A hint of 2⁶⁰ rows never more than doubles the buffer.
        assert!(next_capacity(64, 1 << 60) <= 128);
    }

    #[test]
    fn messages_quote_at_most_80_characters_of_input() {
        // A header with no newline-separated rows and one huge field.
        let text = format!("t,{},x\n0,0,0\n", "h".repeat(50_000));
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::MissingColumn { .. }));
        assert!(e.to_string().len() < 300, "{}", e.to_string().len());
        let text = rows(10).replace("0.04,4,8\n", &format!("0.04,{},8\n", "9x".repeat(50_000)));
        let e = read_record_from(text.as_bytes(), "f.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::Csv { line: 6, .. }), "{e:?}");
        assert!(e.to_string().len() < 300, "{}", e.to_string().len());
    }

    #[test]
    fn missing_file_is_an_io_error() {
        let e = read_record("/nonexistent/r.csv", &layout1()).unwrap_err();
        assert!(matches!(e, Error::Io { .. }));
    }
}
