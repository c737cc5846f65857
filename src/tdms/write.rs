//! Records written as a TDMS file: one group and one segment per record, float64 channels
//! with `wf_increment`, `wf_start_offset` and `unit_string`, the way LabVIEW programs that
//! write one group per hit lay them out.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result, excerpt};
use crate::records::{Record, Response};

/// Table of contents of every segment written: metadata, a new object list, raw data
/// (contiguous, little-endian).
const TOC: u32 = (1 << 1) | (1 << 2) | (1 << 3);
/// The TDMS version written (2.0).
const VERSION: u32 = 4713;
/// `tdsTypeDoubleFloat`.
const F64: u32 = 10;
/// `tdsTypeString`.
const STRING: u32 = 0x20;

/// Writes `records` to a TDMS file at `path`: record `r` is group `r.label()` (in order), its
/// force channels named `forces` and its response channels `responses` (one name per degree
/// of freedom), each float64 with `wf_increment` = 1/rate, `wf_start_offset` = 0 and
/// `unit_string` in SI (`N`; `m`, `m/s` or `m/s^2` by what the response measures). Read back
/// with [`records`](super::records) by group ([`super::RecordBy::Group`]), every sample is the record's, bit
/// for bit.
///
/// # Errors
/// [`Error::DofMismatch`] if a record has other than one force and one response name per
/// degree of freedom; [`Error::TdmsRecord`] for two records of one label (one group each);
/// [`Error::Io`] if the file cannot be written.
///
/// # Examples
/// ```
/// use bearing_ident::Record;
/// use bearing_ident::tdms::{self, RecordBy, TdmsLayout};
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("hits.tdms");
/// let hit = Record::new("hit1", 1024.0, vec![vec![0.1, 2.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]], vec![vec![1e-7; 8]])?;
/// let names = |s: &str| vec![s.to_string()];
/// tdms::write(&path, std::slice::from_ref(&hit), &names("fx"), &names("x"))?;
/// let layout = TdmsLayout {
///     forces: names("fx"),
///     responses: names("x"),
///     record_by: RecordBy::Group,
///     ..TdmsLayout::default()
/// };
/// let back = tdms::records(&tdms::read(&path)?, "hits.tdms", &layout)?;
/// assert_eq!(back[0].force(0), hit.force(0));
/// assert_eq!(back[0].sample_rate(), 1024.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write(
    path: impl AsRef<Path>,
    records: &[Record],
    forces: &[String],
    responses: &[String],
) -> Result<()> {
    let path = path.as_ref();
    let mut bytes = Vec::new();
    for (i, r) in records.iter().enumerate() {
        if forces.len() != r.dofs() || responses.len() != r.dofs() {
            return Err(Error::DofMismatch {
                record: r.label().to_owned(),
                expected: if forces.len() == r.dofs() {
                    responses.len()
                } else {
                    forces.len()
                },
                actual: r.dofs(),
            });
        }
        if records[..i].iter().any(|o| o.label() == r.label()) {
            return Err(Error::TdmsRecord {
                path: excerpt(&path.display().to_string()),
                message: format!(
                    "two records are labelled `{}`: a group each needs a name of its own",
                    excerpt(r.label())
                ),
            });
        }
        segment(&mut bytes, r, forces, responses);
    }
    let io = |e: std::io::Error| Error::Io {
        path: excerpt(&path.display().to_string()),
        message: e.to_string(),
    };
    let mut file = std::fs::File::create(path).map_err(io)?;
    file.write_all(&bytes).map_err(io)
}

/// A string as TDMS writes it: its byte length, then its UTF-8 bytes.
fn string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// A name inside an object path: quoted, a quote doubled.
fn quoted(name: &str) -> String {
    format!("'{}'", name.replace('\'', "''"))
}

/// The SI unit of a response channel.
fn response_unit(kind: Response) -> &'static str {
    match kind {
        Response::Displacement => "m",
        Response::Velocity => "m/s",
        Response::Acceleration => "m/s^2",
    }
}

/// One segment: the record's group and channels, then their values one channel after another.
fn segment(out: &mut Vec<u8>, r: &Record, forces: &[String], responses: &[String]) {
    let group = format!("/{}", quoted(r.label()));
    let channels: Vec<(&String, &[f64], &str)> = forces
        .iter()
        .enumerate()
        .map(|(i, n)| (n, r.force(i), "N"))
        .chain(
            responses
                .iter()
                .enumerate()
                .map(|(i, n)| (n, r.displacement(i), response_unit(r.response(i)))),
        )
        .collect();
    let mut meta = Vec::new();
    meta.extend_from_slice(&(channels.len() as u32 + 1).to_le_bytes());
    string(&mut meta, &group);
    meta.extend_from_slice(&u32::MAX.to_le_bytes()); // no raw data
    meta.extend_from_slice(&0u32.to_le_bytes()); // no properties
    for (name, values, unit) in &channels {
        string(&mut meta, &format!("{group}/{}", quoted(name)));
        meta.extend_from_slice(&20u32.to_le_bytes()); // the raw data index's length
        meta.extend_from_slice(&F64.to_le_bytes());
        meta.extend_from_slice(&1u32.to_le_bytes()); // dimension
        meta.extend_from_slice(&(values.len() as u64).to_le_bytes());
        meta.extend_from_slice(&3u32.to_le_bytes()); // properties
        for (property, value) in [
            ("wf_increment", 1.0 / r.sample_rate()),
            ("wf_start_offset", 0.0),
        ] {
            string(&mut meta, property);
            meta.extend_from_slice(&F64.to_le_bytes());
            meta.extend_from_slice(&value.to_le_bytes());
        }
        string(&mut meta, "unit_string");
        meta.extend_from_slice(&STRING.to_le_bytes());
        string(&mut meta, unit);
    }
    let raw: usize = channels.iter().map(|(_, v, _)| v.len() * 8).sum();
    out.extend_from_slice(b"TDSm");
    out.extend_from_slice(&TOC.to_le_bytes());
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&((meta.len() + raw) as u64).to_le_bytes());
    out.extend_from_slice(&(meta.len() as u64).to_le_bytes());
    out.extend_from_slice(&meta);
    for (_, values, _) in &channels {
        out.reserve(values.len() * 8);
        for v in *values {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tdms::{RecordBy, TdmsLayout, records};

    /// Records written and read back by group are the records, bit for bit: samples, rate,
    /// response kinds (from `unit_string`, SI, so nothing is scaled); labels with quotes
    /// survive the path's quoting; a label twice and a name count that does not fit are
    /// refused.
    #[test]
    fn written_records_read_back_bit_for_bit() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("w.tdms");
        let wave = |a: f64| {
            (0..64)
                .map(|k| (a * k as f64).sin() * 1e-5)
                .collect::<Vec<_>>()
        };
        let a = Record::new(
            "hit 'x' 1",
            5000.0,
            vec![wave(0.1), wave(0.2)],
            vec![wave(0.3), wave(0.4)],
        )
        .unwrap()
        .with_responses(vec![Response::Velocity, Response::Acceleration])
        .unwrap();
        let b = Record::new(
            "hit-y-1",
            5000.0,
            vec![wave(0.5), wave(0.6)],
            vec![wave(0.7), wave(0.8)],
        )
        .unwrap();
        let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let (f, x) = (names(&["fx", "fy"]), names(&["x", "y"]));
        write(&path, &[a.clone(), b.clone()], &f, &x).unwrap();
        let layout = TdmsLayout {
            forces: f.clone(),
            responses: x.clone(),
            record_by: RecordBy::Group,
            ..TdmsLayout::default()
        };
        let file = crate::tdms::read(&path).unwrap();
        let units: Vec<Option<&str>> = file.groups[0].channels.iter().map(|c| c.unit()).collect();
        assert_eq!(units, [Some("N"), Some("N"), Some("m/s"), Some("m/s^2")]);
        let back = records(&file, "w.tdms", &layout).unwrap();
        assert_eq!(back.len(), 2);
        for (got, want) in back.iter().zip([&a, &b]) {
            assert_eq!(got.label(), format!("w.tdms:{}", want.label()));
            assert_eq!(got.sample_rate().to_bits(), want.sample_rate().to_bits());
            for c in 0..2 {
                assert_eq!(got.force(c), want.force(c));
                assert_eq!(got.displacement(c), want.displacement(c));
            }
            assert!(got.warnings().is_empty());
        }
        let e = write(&path, &[b.clone(), b.clone()], &f, &x).unwrap_err();
        assert!(
            e.to_string().contains("two records are labelled `hit-y-1`"),
            "{e}"
        );
        let e = write(&path, &[b], &f[..1], &x).unwrap_err();
        assert_eq!(e.kind(), "inconsistent_records", "{e}");
    }
}
