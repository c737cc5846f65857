//! A record written as a MATLAB MAT-file, level 5, uncompressed: one double column vector per
//! channel and the time vector, as `save -v6` writes them.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result, excerpt};
use crate::records::Record;

/// Data types of MAT-file elements.
const MI_INT8: u32 = 1;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_DOUBLE: u32 = 9;
const MI_MATRIX: u32 = 14;
/// The class of a double array.
const MX_DOUBLE_CLASS: u8 = 6;

/// Writes `record` to a MAT-file at `path`: variables `time` (the sample times `k/rate`, s),
/// the force channels named `forces` and the response channels named `responses` (one name per
/// degree of freedom), each a double column vector. Read back with
/// [`records`](super::records) naming those variables, every sample is the record's, bit for
/// bit.
///
/// # Errors
/// [`Error::DofMismatch`] unless there is one force and one response name per degree of
/// freedom; [`Error::InvalidOption`] (`mat`) for a name that is not a MATLAB variable name
/// (a letter, then letters, digits or `_`, at most 63) or one given twice; [`Error::Io`] if the
/// file cannot be written.
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::mat::{self, MatLayout};
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("hit1.mat");
/// let hit = Record::new("hit1", 1024.0, vec![vec![0.1, 2.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]], vec![vec![1e-7; 8]])?;
/// let names = |s: &str| vec![s.to_string()];
/// mat::write(&path, &hit, "t", &names("fx"), &names("x"))?;
/// let layout = MatLayout {
///     forces: vec!["fx".parse()?],
///     responses: vec!["x".parse()?],
///     time: "t".into(),
///     rate: None,
/// };
/// let back = mat::records(&mat::read(&path)?, "hit1.mat", &layout)?;
/// assert_eq!(back[0].force(0), hit.force(0));
/// assert!((back[0].sample_rate() - 1024.0).abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write(
    path: impl AsRef<Path>,
    record: &Record,
    time: &str,
    forces: &[String],
    responses: &[String],
) -> Result<()> {
    let path = path.as_ref();
    let n = record.dofs();
    if forces.len() != n || responses.len() != n {
        return Err(Error::DofMismatch {
            record: record.label().to_owned(),
            expected: if forces.len() == n {
                responses.len()
            } else {
                forces.len()
            },
            actual: n,
        });
    }
    let names: Vec<&str> = std::iter::once(time)
        .chain(forces.iter().map(String::as_str))
        .chain(responses.iter().map(String::as_str))
        .collect();
    for (i, name) in names.iter().enumerate() {
        let valid = name.len() <= 63
            && name.starts_with(|c: char| c.is_ascii_alphabetic())
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !valid || names[..i].contains(name) {
            return Err(Error::InvalidOption {
                option: "mat",
                message: format!(
                    "`{}` {}: a MAT-file variable is named once, by a letter then letters, \
                     digits or `_` (at most 63)",
                    excerpt(name),
                    if valid {
                        "is named twice"
                    } else {
                        "is not a MATLAB name"
                    }
                ),
            });
        }
    }
    let t: Vec<f64> = (0..record.len())
        .map(|k| k as f64 / record.sample_rate())
        .collect();
    let mut bytes = header();
    matrix(&mut bytes, time, &t);
    for (i, name) in forces.iter().enumerate() {
        matrix(&mut bytes, name, record.force(i));
    }
    for (i, name) in responses.iter().enumerate() {
        matrix(&mut bytes, name, record.displacement(i));
    }
    let io = |e: std::io::Error| Error::Io {
        path: excerpt(&path.display().to_string()),
        message: e.to_string(),
    };
    let mut file = std::fs::File::create(path).map_err(io)?;
    file.write_all(&bytes).map_err(io)
}

/// The 128-byte header: text, no subsystem data, version 0x0100, little-endian (`IM`).
fn header() -> Vec<u8> {
    let text = b"MATLAB 5.0 MAT-file, written by bearing-ident";
    let mut h = vec![b' '; 116];
    h[..text.len()].copy_from_slice(text);
    h.extend_from_slice(&[0; 8]);
    h.extend_from_slice(&0x0100u16.to_le_bytes());
    h.extend_from_slice(b"IM");
    h
}

/// A data element: its tag (type, byte count) and its data, padded to 8 bytes.
fn element(out: &mut Vec<u8>, kind: u32, data: &[u8]) {
    out.extend_from_slice(&kind.to_le_bytes());
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(data);
    out.resize(out.len().next_multiple_of(8), 0);
}

/// Variable `name`, a double column vector of `values`.
fn matrix(out: &mut Vec<u8>, name: &str, values: &[f64]) {
    let mut body = Vec::with_capacity(64 + values.len() * 8);
    element(
        &mut body,
        MI_UINT32,
        &[MX_DOUBLE_CLASS, 0, 0, 0, 0, 0, 0, 0],
    );
    let rows = i32::try_from(values.len()).unwrap_or(i32::MAX);
    let dims: Vec<u8> = [rows, 1].iter().flat_map(|d| d.to_le_bytes()).collect();
    element(&mut body, MI_INT32, &dims);
    element(&mut body, MI_INT8, name.as_bytes());
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    element(&mut body, MI_DOUBLE, &data);
    element(out, MI_MATRIX, &body);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mat::{MatLayout, read, records};
    use crate::records::Response;

    /// A record written and read back is the record, bit for bit; the time vector is `k/rate`;
    /// bad names and counts are refused.
    #[test]
    fn written_record_reads_back_bit_for_bit() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("w.mat");
        let wave = |a: f64| {
            (0..37)
                .map(|k| (a * k as f64).sin() * 1e-5)
                .collect::<Vec<_>>()
        };
        let r = Record::new(
            "hit",
            4096.0,
            vec![wave(0.1), wave(0.2)],
            vec![wave(0.3), wave(0.4)],
        )
        .unwrap()
        .with_responses(vec![Response::Displacement; 2])
        .unwrap();
        let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let (f, x) = (names(&["fx", "fy"]), names(&["x", "y"]));
        write(&path, &r, "t", &f, &x).unwrap();
        let variables = read(&path).unwrap();
        let listed: Vec<&str> = variables.iter().map(|v| v.name.as_str()).collect();
        assert_eq!(listed, ["t", "fx", "fy", "x", "y"]);
        let layout = MatLayout {
            forces: f.iter().map(|n| n.parse().unwrap()).collect(),
            responses: x.iter().map(|n| n.parse().unwrap()).collect(),
            time: "t".into(),
            rate: None,
        };
        let back = &records(&variables, "w.mat", &layout).unwrap()[0];
        assert_eq!(back.len(), 37);
        assert!((back.sample_rate() / 4096.0 - 1.0).abs() < 1e-12);
        for c in 0..2 {
            assert_eq!(back.force(c), r.force(c));
            assert_eq!(back.displacement(c), r.displacement(c));
        }
        for (bad, named) in [
            (names(&["fx", "2y"]), "`2y` is not a MATLAB name"),
            (names(&["fx", "t"]), "`t` is named twice"),
        ] {
            let e = write(&path, &r, "t", &bad, &x).unwrap_err();
            assert_eq!(e.kind(), "invalid_argument");
            assert!(e.to_string().contains(named), "{e}");
        }
        let e = write(&path, &r, "t", &f[..1], &x).unwrap_err();
        assert_eq!(e.kind(), "inconsistent_records");
    }
}
