//! The one size rule of every file reader: CSV records, Universal Files, baseline, rotor and
//! tests JSON.
//!
//! A reader holds at most the values it has parsed and one line it has not: a line is at most
//! [`MAX_LINE_BYTES`] (1 MiB), a file at most [`MAX_VALUES`] (2²⁸) values, a JSON text (which
//! is parsed whole) at most [`MAX_JSON_BYTES`] (16 MiB). Past any of them reading stops with a
//! typed error naming the file, so that `/dev/zero`, `/dev/urandom` or a sparse huge file costs
//! at most a mebibyte of memory before it is refused.

use std::io::{BufRead, Read};
use std::path::Path;

use crate::error::{Error, Result, excerpt};

/// Longest line a reader accepts, in bytes (1 MiB). A longer line, or an input with no
/// newline at all (`/dev/zero`), stops reading as soon as the limit is passed.
pub const MAX_LINE_BYTES: u64 = 1 << 20;

/// Most columns a CSV record file may have (header fields).
pub const MAX_COLUMNS: usize = 4096;

/// Most values one file may hold: for a CSV record samples × columns read (time, forces and
/// displacements), for a Universal File the reals of all its functions; `2²⁸` (2 GiB of
/// `f64`), e.g. 53 million samples of a 2-DOF record. An endless stream of valid rows stops
/// there.
pub const MAX_VALUES: u64 = 1 << 28;

/// Longest JSON text read (16 MiB): a saved result, a rotor model or a set of field tests is a
/// few kilobytes to a few megabytes, and JSON is parsed whole.
pub const MAX_JSON_BYTES: u64 = 1 << 24;

/// Opens a file for one of the readers. A folder is refused in words, where the system would
/// say only "Is a directory" at the first read, naming the files to give instead when the
/// reader takes many (`pattern`, e.g. `*.csv`: the folder's `records/*.csv`).
///
/// # Errors
/// [`Error::Io`] naming the path: a folder, or a file that cannot be opened.
///
/// # Examples
/// ```
/// let dir = std::env::temp_dir();
/// let e = bearing_ident::limits::open(&dir, Some("*.csv")).unwrap_err();
/// assert_eq!(e.kind(), "io_error");
/// let hint = format!("a folder, not a file: give its files: {}", dir.join("*.csv").display());
/// assert!(e.to_string().ends_with(&hint));
/// ```
pub fn open(path: &Path, pattern: Option<&str>) -> Result<std::fs::File> {
    let io = |message: String| Error::Io {
        path: excerpt(&path.display().to_string()),
        message,
    };
    if path.is_dir() {
        return Err(io(match pattern {
            Some(pattern) => format!(
                "a folder, not a file: give its files: {}",
                excerpt(&path.join(pattern).display().to_string())
            ),
            None => "a folder, not a file".to_owned(),
        }));
    }
    std::fs::File::open(path).map_err(|e| io(e.to_string()))
}

/// The bytes of the file at `path` (opened as [`open`] opens it), at most `limit` of them:
/// read into a buffer sized from the file's length, so that a large file is copied once.
///
/// # Errors
/// As [`open`]; [`Error::Io`] if it cannot be read; [`Error::FileLimit`] (naming `what`)
/// past `limit` bytes.
#[cfg(any(feature = "tdms", feature = "mat"))]
pub(crate) fn read_bytes(
    path: &Path,
    pattern: Option<&str>,
    limit: u64,
    what: &str,
) -> Result<Vec<u8>> {
    let label = || excerpt(&path.display().to_string());
    let file = open(path, pattern)?;
    let stated = file.metadata().map_or(0, |m| m.len()).min(limit + 1);
    let mut bytes = Vec::with_capacity(usize::try_from(stated).unwrap_or(0));
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::Io {
            path: label(),
            message: e.to_string(),
        })?;
    if bytes.len() as u64 > limit {
        return Err(Error::FileLimit {
            path: label(),
            what: what.into(),
            limit,
        });
    }
    Ok(bytes)
}

/// Reads the whole text of a JSON file, at most [`MAX_JSON_BYTES`] of it; invalid UTF-8 is
/// replaced (the JSON parser then names it).
///
/// # Errors
/// [`Error::Io`] if the file cannot be read; [`Error::FileLimit`] if it is longer than
/// [`MAX_JSON_BYTES`] (`/dev/zero` is refused after 16 MiB, never read to the end).
///
/// # Examples
/// ```
/// let e = bearing_ident::limits::read_json_text("/nonexistent/rotor.json").unwrap_err();
/// assert_eq!(e.kind(), "io_error");
/// # Ok::<(), bearing_ident::Error>(())
/// ```
pub fn read_json_text(path: impl AsRef<Path>) -> Result<String> {
    let path = path.as_ref();
    let io = |e: std::io::Error| Error::Io {
        path: excerpt(&path.display().to_string()),
        message: e.to_string(),
    };
    let file = open(path, None)?;
    let mut bytes = Vec::new();
    file.take(MAX_JSON_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_JSON_BYTES {
        return Err(Error::FileLimit {
            path: excerpt(&path.display().to_string()),
            what: "bytes of a JSON text".into(),
            limit: MAX_JSON_BYTES,
        });
    }
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// Reads one line (up to and without its `\n`) into `line`, taking at most `limit + 1` bytes of
/// the input: `Some(true)` for a line, `Some(false)` at the end of the input, `None` when the
/// line is longer than `limit` (the caller names the file and line).
#[cfg_attr(not(feature = "uff"), allow(dead_code))]
pub(crate) fn read_line(
    reader: &mut impl std::io::BufRead,
    line: &mut Vec<u8>,
    limit: u64,
) -> std::io::Result<Option<bool>> {
    line.clear();
    let n = reader.take(limit + 1).read_until(b'\n', line)?;
    if n == 0 {
        return Ok(Some(false));
    }
    if line.last() == Some(&b'\n') {
        line.pop();
    } else if line.len() as u64 > limit {
        return Ok(None);
    }
    Ok(Some(true))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_stop_at_their_limit() {
        let mut line = Vec::new();
        let mut input: &[u8] = b"ab\ncdef\ngh";
        assert_eq!(read_line(&mut input, &mut line, 4).unwrap(), Some(true));
        assert_eq!(line, b"ab");
        assert_eq!(read_line(&mut input, &mut line, 4).unwrap(), Some(true));
        assert_eq!(line, b"cdef");
        assert_eq!(read_line(&mut input, &mut line, 4).unwrap(), Some(true));
        assert_eq!(line, b"gh");
        assert_eq!(read_line(&mut input, &mut line, 4).unwrap(), Some(false));
        // Five bytes with no newline: past the limit, and only limit + 1 bytes were taken.
        let mut zeros = std::io::BufReader::new(std::io::repeat(0));
        assert_eq!(read_line(&mut zeros, &mut line, 4).unwrap(), None);
        assert_eq!(line.len(), 5);
    }

    #[test]
    fn json_text_past_its_limit_is_refused_unread() {
        let dir = std::env::temp_dir().join(format!("limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("big.json");
        let file = std::fs::File::create(&path).unwrap();
        // Sparse: no disk used, and the reader stops one byte past the limit.
        file.set_len(MAX_JSON_BYTES + 10).unwrap();
        let e = read_json_text(&path).unwrap_err();
        assert_eq!(e.kind(), "too_large");
        assert!(e.to_string().contains("big.json"), "{e}");
        file.set_len(3).unwrap();
        assert_eq!(read_json_text(&path).unwrap().len(), 3);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_is_refused_in_words_by_every_reader() {
        let dir = std::env::temp_dir().join(format!("limits-folder-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = open(&dir, Some("*.csv")).unwrap_err();
        assert_eq!(e.kind(), "io_error");
        let text = e.to_string();
        assert!(text.ends_with(&format!("give its files: {}", dir.join("*.csv").display())));
        assert!(!text.contains("os error"), "{text}");
        let e = read_json_text(&dir).unwrap_err();
        assert!(e.to_string().ends_with(": a folder, not a file"), "{e}");
        let e = open(&dir.join("none.csv"), Some("*.csv")).unwrap_err();
        assert!(e.to_string().contains("none.csv"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
