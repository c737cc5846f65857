//! CSV parse over many files: 36 record files of 8192 rows × 7 columns (time, 3 forces, 3
//! displacements, Rust's shortest float forms, ~1.1 MB each) written to a temporary directory
//! at the start, read one after another with one [`CsvReader`] (its buffers reused), and read
//! on two threads; the identification of the same records beside them, so the read stage is
//! seen against the rest. MB/s (10⁶ bytes of text per second) and the ratio are printed after
//! the group.
//!
//! `cargo bench -p bearing-ident-benches --bench csv_parse` (or `-- --quick`). With `CSV_PARSE_FILE=path` (a file of
//! the default two-degree-of-freedom layout, e.g. from `bearing-ident simulate --kind random
//! --duration 600`) only that file is read, a few times, and its MB/s per core printed.

mod common;
use common::median;

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use bearing_ident::io::{CsvLayout, CsvReader, write_record};
use bearing_ident::simulate::{AntiAlias, Simulator};
use bearing_ident::{Identifier, Record, Uncertainty};
use criterion::{Criterion, criterion_group, criterion_main};
use faer::mat;

const FILES: usize = 36;
const ROWS: usize = 8192;

/// 36 random-excitation records of a 3-DOF system, as CSV files in `dir`.
fn write_files(dir: &std::path::Path) -> Vec<PathBuf> {
    let system = bearing_ident::model::Coefficients::new(
        mat![[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]],
        mat![[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
        mat![[4e5, 6e4, -1e4], [2e4, 6e5, 5e4], [-2e4, 1e4, 9e5]],
    )
    .expect("valid system");
    let mut sim = Simulator::new(&system, 4096.0, ROWS, AntiAlias::default()).expect("simulator");
    let layout = CsvLayout::for_dofs(3);
    (0..FILES)
        .map(|r| {
            let rec = sim
                .random_record(format!("r{r:02}"), 50.0, r as u64)
                .expect("record");
            let path = dir.join(format!("r{r:02}.csv"));
            write_record(&path, &rec, &layout).expect("written");
            path
        })
        .collect()
}

fn read_all(reader: &mut CsvReader, files: &[PathBuf]) -> Vec<Record> {
    files
        .iter()
        .map(|p| reader.read(p).expect("reads"))
        .collect()
}

/// The files read on `threads` threads, each with its own reader (the CLI's way).
fn read_parallel(layout: &CsvLayout, files: &[PathBuf], threads: usize) -> usize {
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|w| {
                s.spawn(move || {
                    let mut reader = CsvReader::new(layout.clone());
                    files
                        .iter()
                        .skip(w)
                        .step_by(threads)
                        .map(|p| reader.read(p).expect("reads").len())
                        .sum::<usize>()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().expect("joins")).sum()
    })
}

/// This thread's time on a CPU (Linux `/proc/thread-self/schedstat`), `None` elsewhere: on a
/// shared machine the wall time counts other processes' turns too.
fn cpu_time() -> Option<Duration> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(Duration::from_nanos(ns))
}

/// Median CPU time of this thread over `runs` calls of `f`.
fn median_cpu(runs: usize, mut f: impl FnMut()) -> Option<Duration> {
    let mut times = Vec::new();
    for _ in 0..runs {
        let t = cpu_time()?;
        f();
        times.push(cpu_time()? - t);
    }
    times.sort();
    Some(times[runs / 2])
}

/// Reads the file `path` (layout `t,fx,fy,x,y`) `runs` times and prints the median MB/s per
/// core (CPU time) and wall.
fn one_file(path: &str, runs: usize) {
    let bytes = std::fs::metadata(path).expect("metadata").len();
    let mut reader = CsvReader::new(CsvLayout::default());
    let mut read = || {
        black_box(reader.read(path).expect("reads"));
    };
    let wall = median(runs, &mut read);
    let mb_s = |d: Duration| bytes as f64 / 1e6 / d.as_secs_f64();
    let cpu = median_cpu(runs, &mut read).map_or(f64::NAN, mb_s);
    eprintln!(
        "csv_parse {path}: {:.1} MB, {cpu:.0} MB/s per core (CPU time), {:.0} MB/s wall",
        bytes as f64 / 1e6,
        mb_s(wall)
    );
}

fn csv_parse(c: &mut Criterion) {
    if let Ok(path) = std::env::var("CSV_PARSE_FILE") {
        one_file(&path, 5);
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let files = write_files(dir.path());
    let bytes: u64 = files
        .iter()
        .map(|p| std::fs::metadata(p).expect("metadata").len())
        .sum();
    let layout = CsvLayout::for_dofs(3);
    let mut reader = CsvReader::new(layout.clone());
    let records = read_all(&mut reader, &files);
    let id = Identifier::new(20.0, 250.0)
        .max_iterations(4)
        .uncertainty(Uncertainty::None);
    id.identify(&records).expect("identifies");

    let mut group = c.benchmark_group("csv_parse");
    group.sample_size(10);
    group.throughput(criterion::Throughput::Bytes(bytes));
    group.bench_function("read_36_files", |b| {
        b.iter(|| black_box(read_all(&mut reader, &files)))
    });
    group.bench_function("read_36_files_2_threads", |b| {
        b.iter(|| black_box(read_parallel(&layout, &files, 2)))
    });
    group.bench_function("identify_36_records", |b| {
        b.iter(|| black_box(id.identify(&records).expect("identifies")))
    });
    group.finish();

    const RUNS: usize = 7;
    let one = median(RUNS, || {
        black_box(read_all(&mut reader, &files));
    });
    let two = median(RUNS, || {
        black_box(read_parallel(&layout, &files, 2));
    });
    let rest = median(RUNS, || {
        black_box(id.identify(&records).expect("identifies"));
    });
    let mb_s = |d: Duration| bytes as f64 / 1e6 / d.as_secs_f64();
    if let (Some(read), Some(rest)) = (
        median_cpu(RUNS, || {
            black_box(read_all(&mut reader, &files));
        }),
        median_cpu(RUNS, || {
            black_box(id.identify(&records).expect("identifies"));
        }),
    ) {
        eprintln!(
            "csv_parse (CPU time of the thread): read {:.1} ms ({:.0} MB/s per core); identify \
             {:.1} ms; read / identify {:.2}",
            read.as_secs_f64() * 1e3,
            mb_s(read),
            rest.as_secs_f64() * 1e3,
            read.as_secs_f64() / rest.as_secs_f64()
        );
    }
    eprintln!(
        "csv_parse: {FILES} files, {:.1} MB; read {:.1} ms ({:.0} MB/s one thread, {:.0} MB/s \
         two threads); identify {:.1} ms; read / identify {:.2}",
        bytes as f64 / 1e6,
        one.as_secs_f64() * 1e3,
        mb_s(one),
        mb_s(two),
        rest.as_secs_f64() * 1e3,
        one.as_secs_f64() / rest.as_secs_f64()
    );
}

criterion_group!(benches, csv_parse);
criterion_main!(benches);
