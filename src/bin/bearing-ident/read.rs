//! The record files in: how they are read (CSV columns, Universal File channels, response
//! kinds), one file's records, and the files parsed ahead on worker threads.

use std::path::PathBuf;

use bearing_ident::io::{self, CsvLayout};
use bearing_ident::uff::UffLayout;
use bearing_ident::{Error, Record, Response};

/// How the record files are read: CSV columns, Universal File channels, response kinds.
pub(crate) struct Layout {
    /// The CSV columns.
    pub(crate) csv: CsvLayout,
    /// The Universal File channels.
    pub(crate) uff: UffLayout,
    /// `--response`: empty for none given.
    pub(crate) responses: Vec<Response>,
}

/// The files after the first, parsed ahead of the identification on worker threads: worker
/// `w` of `k` reads files `1 + w, 1 + w + k, …` in turn, each with its own
/// [`io::CsvReader`] (buffers kept across its files), and hands each file's records over a
/// channel of one slot, so at most two files' records per worker wait. They are taken in file
/// order, each exactly once, by iterating ([`ReadAhead::next`]); the first file, which the
/// caller reads ([`read_file`]), is not read here. Dropping it stops the workers at their next
/// file.
pub(crate) struct ReadAhead {
    slots: Vec<std::sync::mpsc::Receiver<bearing_ident::Result<Vec<Record>>>>,
    /// Index of the next file handed out (from 1).
    next: usize,
    /// Files in all, the first included.
    files: usize,
}

/// Most worker threads parsing files.
const READERS: usize = 4;

impl ReadAhead {
    pub(crate) fn spawn<'s>(
        scope: &'s std::thread::Scope<'s, '_>,
        files: &'s [PathBuf],
        layout: &'s Layout,
    ) -> Self {
        let rest = files.get(1..).unwrap_or_default();
        let k = std::thread::available_parallelism()
            .map_or(1, std::num::NonZero::get)
            .clamp(1, READERS)
            .min(rest.len().max(1));
        let slots = (0..k)
            .map(|w| {
                let (tx, rx) = std::sync::mpsc::sync_channel(1);
                let mut reader = io::CsvReader::new(layout.csv.clone());
                scope.spawn(move || {
                    for path in rest.iter().skip(w).step_by(k) {
                        if tx.send(read_records(path, layout, &mut reader)).is_err() {
                            return;
                        }
                    }
                });
                rx
            })
            .collect();
        Self {
            slots,
            next: 1,
            files: files.len(),
        }
    }

    /// Index (in the file list) of the file the next call of [`ReadAhead::next`] hands out.
    pub(crate) fn position(&self) -> usize {
        self.next
    }
}

impl Iterator for ReadAhead {
    type Item = bearing_ident::Result<Vec<Record>>;

    /// The records of the next file after the first, in file order; `None` after the last.
    fn next(&mut self) -> Option<Self::Item> {
        if self.next >= self.files {
            return None;
        }
        let i = self.next - 1;
        self.next += 1;
        let k = self.slots.len();
        Some(self.slots[i % k].recv().unwrap_or_else(|_| {
            Err(Error::Io {
                path: String::new(),
                message: "a reading thread stopped".into(),
            })
        }))
    }
}

/// Whether `path` is a Universal File (`.uff`, `.unv`, any case) rather than a CSV record.
pub(crate) fn is_uff(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|x| x.to_str())
        .is_some_and(|x| x.eq_ignore_ascii_case("uff") || x.eq_ignore_ascii_case("unv"))
}

/// The records of a file: one from a CSV file, read by `reader` (its responses of the
/// `--response` kinds); one per load case of the time histories of a Universal File (by
/// [`uff::records_with`](bearing_ident::uff::records_with)'s rule and the channels named).
fn read_records(
    path: &std::path::Path,
    layout: &Layout,
    reader: &mut io::CsvReader,
) -> bearing_ident::Result<Vec<Record>> {
    if is_uff(path) {
        read_uff(path, layout)
    } else {
        with_kinds(reader.read(path)?, layout).map(|r| vec![r])
    }
}

/// The records of a Universal File, one per load case.
fn read_uff(path: &std::path::Path, layout: &Layout) -> bearing_ident::Result<Vec<Record>> {
    let functions = bearing_ident::uff::read(path)?;
    bearing_ident::uff::records_with(&functions, &path.display().to_string(), &layout.uff)
}

/// `record` with the `--response` kinds, if any were given.
fn with_kinds(record: Record, layout: &Layout) -> bearing_ident::Result<Record> {
    if layout.responses.is_empty() {
        return Ok(record);
    }
    let kinds = Response::per_channel(&layout.responses, record.dofs())?;
    record.with_responses(kinds)
}

/// Every record of a file, at least one: one from a CSV file, one per load case of a
/// Universal File ([`read_records`], reading the file on the calling thread).
pub(crate) fn read_file(
    path: &std::path::Path,
    layout: &Layout,
) -> bearing_ident::Result<Vec<Record>> {
    if is_uff(path) {
        let records = read_uff(path, layout)?;
        if records.is_empty() {
            return Err(Error::UffRecord {
                path: path.display().to_string(),
                load_case: 0,
                message: "no record".into(),
            });
        }
        Ok(records)
    } else {
        Ok(vec![with_kinds(
            io::read_record(path, &layout.csv)?,
            layout,
        )?])
    }
}

/// The first record of a file ([`read_file`]).
pub(crate) fn read_record(
    path: &std::path::Path,
    layout: &Layout,
) -> bearing_ident::Result<Record> {
    Ok(read_file(path, layout)?.swap_remove(0))
}
