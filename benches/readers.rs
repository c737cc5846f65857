//! Reading the lab's files: a TDMS file of 105 MB of float64 channels read by `tdms::read`
//! (a memory copy: the goal is ≥ 1 GB/s) and a compressed MAT-file v5 (67 MB of doubles of a
//! 16-bit converter, 26 MB compressed) read by `mat::read`, beside their floors: a copy of the TDMS file's bytes, and miniz_oxide's inflate
//! of the MAT-file's compressed elements (what `mat::read` cannot do faster). The files are
//! written once into a temporary directory, by hand-built TDMS segments and MAT elements (no
//! writer but this file's). MB/s (10⁶ bytes of file per second) and the ratios to the floors
//! are printed after the groups.
//!
//! `nice -n 10 cargo bench -p bearing-ident-benches --bench readers` (or `-- --quick`).

mod common;
use common::median;

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Duration;

use bearing_ident::{mat, tdms};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

/// Channels of the TDMS file.
const TDMS_CHANNELS: usize = 4;
/// Segments of the TDMS file (LabVIEW writes one per loop iteration or buffer).
const TDMS_SEGMENTS: usize = 50;
/// Values per channel and segment: 4 × 50 × 65 536 doubles, 104.9 MB of raw data.
const TDMS_VALUES: usize = 65_536;

/// Variables of the MAT-file.
const MAT_VARIABLES: usize = 4;
/// Values per variable.
const MAT_VALUES: usize = 1 << 21;

/// A lab signal: a sine and a deterministic noise, quantised as a 16-bit converter of ±10
/// full scale would quantise it.
fn signal(channel: usize, k: usize) -> f64 {
    let t = k as f64 / 10_240.0;
    let tone = 6.0 * (2.0 * std::f64::consts::PI * (37.0 + 11.0 * channel as f64) * t).sin();
    // A 64-bit LCG's top bits as noise in [−1, 1).
    let mut s = (k as u64 ^ ((channel as u64) << 40)).wrapping_mul(6_364_136_223_846_793_005);
    s = s.wrapping_add(1_442_695_040_888_963_407);
    let noise = (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0;
    let step = 20.0 / 65_536.0;
    ((tone + noise) / step).round() * step
}

/// A TDMS string: its length (u32) and its UTF-8 bytes.
fn tdms_string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// One TDMS segment of `TDMS_CHANNELS` float64 channels of group `data`, contiguous, little
/// endian, with a new object list and `wf_increment` on each channel.
fn tdms_segment(out: &mut Vec<u8>, first: usize) {
    let mut meta = Vec::new();
    meta.extend_from_slice(&(TDMS_CHANNELS as u32 + 2).to_le_bytes());
    for path in ["/", "/'data'"] {
        tdms_string(&mut meta, path);
        meta.extend_from_slice(&u32::MAX.to_le_bytes()); // no raw data
        meta.extend_from_slice(&0u32.to_le_bytes()); // no properties
    }
    for c in 0..TDMS_CHANNELS {
        tdms_string(&mut meta, &format!("/'data'/'ch{c}'"));
        meta.extend_from_slice(&20u32.to_le_bytes()); // raw data index length
        meta.extend_from_slice(&10u32.to_le_bytes()); // tdsTypeDoubleFloat
        meta.extend_from_slice(&1u32.to_le_bytes()); // dimension
        meta.extend_from_slice(&(TDMS_VALUES as u64).to_le_bytes());
        meta.extend_from_slice(&1u32.to_le_bytes()); // one property
        tdms_string(&mut meta, "wf_increment");
        meta.extend_from_slice(&10u32.to_le_bytes());
        meta.extend_from_slice(&(1.0f64 / 10_240.0).to_le_bytes());
    }
    let raw = TDMS_CHANNELS * TDMS_VALUES * 8;
    // kTocMetaData | kTocNewObjList | kTocRawData
    let toc: u32 = (1 << 1) | (1 << 2) | (1 << 3);
    out.extend_from_slice(b"TDSm");
    out.extend_from_slice(&toc.to_le_bytes());
    out.extend_from_slice(&4713u32.to_le_bytes());
    out.extend_from_slice(&((meta.len() + raw) as u64).to_le_bytes());
    out.extend_from_slice(&(meta.len() as u64).to_le_bytes());
    out.extend_from_slice(&meta);
    for c in 0..TDMS_CHANNELS {
        for k in first..first + TDMS_VALUES {
            out.extend_from_slice(&signal(c, k).to_le_bytes());
        }
    }
}

/// The TDMS file, written into `dir`.
fn write_tdms(dir: &Path) -> PathBuf {
    let mut bytes = Vec::new();
    for s in 0..TDMS_SEGMENTS {
        tdms_segment(&mut bytes, s * TDMS_VALUES);
    }
    let path = dir.join("run.tdms");
    std::fs::write(&path, bytes).expect("written");
    path
}

/// A MAT-file data element: its tag (type, byte count) and its data padded to 8 bytes.
fn mat_element(out: &mut Vec<u8>, kind: u32, data: &[u8]) {
    out.extend_from_slice(&kind.to_le_bytes());
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(data);
    out.resize(out.len().next_multiple_of(8), 0);
}

/// The miMATRIX element of a double column vector `name`.
fn mat_matrix(name: &str, values: &[f64]) -> Vec<u8> {
    let mut body = Vec::new();
    // Array flags: class mxDOUBLE_CLASS (6), no flags; nzmax 0.
    mat_element(&mut body, 6, &[6, 0, 0, 0, 0, 0, 0, 0]);
    let dims: Vec<u8> = [values.len() as i32, 1]
        .iter()
        .flat_map(|d| d.to_le_bytes())
        .collect();
    mat_element(&mut body, 5, &dims);
    mat_element(&mut body, 1, name.as_bytes());
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    mat_element(&mut body, 9, &data);
    let mut element = Vec::new();
    mat_element(&mut element, 14, &body);
    element
}

/// The MAT-file, written into `dir` (each variable a compressed element, as `save` writes
/// them), and the compressed elements' zlib streams.
fn write_mat(dir: &Path) -> (PathBuf, Vec<Vec<u8>>) {
    let mut bytes = vec![b' '; 116];
    bytes[..25].copy_from_slice(b"MATLAB 5.0 MAT-file, hand");
    bytes.extend_from_slice(&[0; 8]);
    bytes.extend_from_slice(&0x0100u16.to_le_bytes());
    bytes.extend_from_slice(b"IM");
    let mut streams = Vec::new();
    for v in 0..MAT_VARIABLES {
        let values: Vec<f64> = (0..MAT_VALUES).map(|k| signal(v, k)).collect();
        let zlib =
            miniz_oxide::deflate::compress_to_vec_zlib(&mat_matrix(&format!("ch{v}"), &values), 6);
        bytes.extend_from_slice(&15u32.to_le_bytes());
        bytes.extend_from_slice(&(zlib.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&zlib);
        streams.push(zlib);
    }
    let path = dir.join("run.mat");
    std::fs::write(&path, bytes).expect("written");
    (path, streams)
}

fn readers(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let tdms_path = write_tdms(dir.path());
    let (mat_path, streams) = write_mat(dir.path());
    let size = |p: &Path| std::fs::metadata(p).expect("metadata").len();
    let (tdms_bytes, mat_bytes) = (size(&tdms_path), size(&mat_path));
    let tdms_file = std::fs::read(&tdms_path).expect("read");
    // The readers read what was written: every value in place.
    let file = tdms::read(&tdms_path).expect("reads");
    let ch3 = &file.groups[0].channels[3].values;
    assert_eq!(ch3.len(), TDMS_SEGMENTS * TDMS_VALUES);
    assert_eq!(
        ch3[TDMS_VALUES + 5].to_bits(),
        signal(3, TDMS_VALUES + 5).to_bits()
    );
    let variables = mat::read(&mat_path).expect("reads");
    assert_eq!(variables.len(), MAT_VARIABLES);
    drop((file, variables));
    let inflated: usize = streams
        .iter()
        .map(|s| {
            miniz_oxide::inflate::decompress_to_vec_zlib(s)
                .expect("inflates")
                .len()
        })
        .sum();

    let mut group = c.benchmark_group("readers");
    group.sample_size(10);
    group.throughput(Throughput::BytesDecimal(tdms_bytes));
    group.bench_function("tdms_read_100MB", |b| {
        b.iter(|| black_box(tdms::read(&tdms_path).expect("reads")))
    });
    group.bench_function("tdms_parse_100MB_in_memory", |b| {
        b.iter(|| black_box(tdms::parse(&tdms_file, "run.tdms").expect("parses")))
    });
    group.bench_function("copy_100MB", |b| b.iter(|| black_box(tdms_file.to_vec())));
    group.throughput(Throughput::BytesDecimal(mat_bytes));
    group.bench_function("mat_read_compressed", |b| {
        b.iter(|| black_box(mat::read(&mat_path).expect("reads")))
    });
    group.bench_function("inflate_floor", |b| {
        b.iter(|| {
            for s in &streams {
                black_box(miniz_oxide::inflate::decompress_to_vec_zlib(s).expect("inflates"));
            }
        })
    });
    group.finish();

    const RUNS: usize = 7;
    let mb_s = |bytes: u64, d: Duration| bytes as f64 / 1e6 / d.as_secs_f64();
    let tdms_read = median(RUNS, || {
        black_box(tdms::read(&tdms_path).expect("reads"));
    });
    let tdms_parse = median(RUNS, || {
        black_box(tdms::parse(&tdms_file, "run.tdms").expect("parses"));
    });
    let copy = median(RUNS, || {
        black_box(tdms_file.to_vec());
    });
    let mat_read = median(RUNS, || {
        black_box(mat::read(&mat_path).expect("reads"));
    });
    let inflate = median(RUNS, || {
        for s in &streams {
            black_box(miniz_oxide::inflate::decompress_to_vec_zlib(s).expect("inflates"));
        }
    });
    eprintln!(
        "readers: TDMS {:.1} MB: read {:.0} MB/s, parse in memory {:.0} MB/s, copy {:.0} MB/s \
         (read / copy time {:.2}); MAT {:.1} MB compressed ({:.1} MB inflated): read {:.0} MB/s, \
         inflate alone {:.0} MB/s (read / inflate time {:.2})",
        tdms_bytes as f64 / 1e6,
        mb_s(tdms_bytes, tdms_read),
        mb_s(tdms_bytes, tdms_parse),
        mb_s(tdms_bytes, copy),
        tdms_read.as_secs_f64() / copy.as_secs_f64(),
        mat_bytes as f64 / 1e6,
        inflated as f64 / 1e6,
        mb_s(mat_bytes, mat_read),
        mb_s(mat_bytes, inflate),
        mat_read.as_secs_f64() / inflate.as_secs_f64()
    );
}

criterion_group!(benches, readers);
criterion_main!(benches);
