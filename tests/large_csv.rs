//! A record file of 10⁶ rows parses in one streaming pass: the heap never holds the text (not
//! even once), only the parsed channels, grown towards the row count the file length suggests
//! (a hint only: they never more than double).
#![cfg(feature = "csv")]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use bearing_ident::Record;
use bearing_ident::io::{CsvLayout, read_record, write_record};

/// Counts live heap bytes and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator and only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(layout.size(), Ordering::SeqCst) + layout.size();
        PEAK.fetch_max(live, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // Counted as allocate-new then free-old: the worst case of a moving realloc.
        let live = LIVE.fetch_add(new_size, Ordering::SeqCst) + new_size;
        PEAK.fetch_max(live, Ordering::SeqCst);
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
        p
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn million_row_file_streams() {
    let rows = 1_000_000;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.csv");
    let layout = CsvLayout::default();
    {
        let channel = |k: f64| {
            (0..rows)
                .map(|m| (m as f64 * k).sin() * 1e-5)
                .collect::<Vec<f64>>()
        };
        let rec = Record::new(
            "big",
            10_000.0,
            vec![channel(0.01), channel(0.02)],
            vec![channel(0.03), channel(0.04)],
        )
        .unwrap();
        write_record(&path, &rec, &layout).unwrap();
    }
    let bytes = std::fs::metadata(&path).unwrap().len() as usize;
    let before = LIVE.load(Ordering::SeqCst);
    PEAK.store(before, Ordering::SeqCst);
    let start = std::time::Instant::now();
    let rec = read_record(&path, &layout).unwrap();
    let secs = start.elapsed().as_secs_f64();
    let peak = PEAK.load(Ordering::SeqCst) - before;
    let parsed = 5 * rows * std::mem::size_of::<f64>();
    println!(
        "{rows} rows, {:.1} MB of text: {:.1} MB/s, peak heap {:.1} MB ({:.2}× the parsed \
         channels, {:.2}× the text)",
        bytes as f64 / 1e6,
        bytes as f64 / 1e6 / secs,
        peak as f64 / 1e6,
        peak as f64 / parsed as f64,
        peak as f64 / bytes as f64
    );
    assert_eq!(rec.len(), rows);
    assert!((rec.sample_rate() / 10_000.0 - 1.0).abs() < 1e-9);
    // The text is never held: the peak is below the file's size, and within 15 % of the parsed
    // channels themselves (time column included; the last growth lands on the hinted size).
    assert!(peak < bytes, "peak {peak} B ≥ text {bytes} B");
    assert!(
        (peak as f64) < 1.15 * parsed as f64,
        "peak {peak} B vs parsed {parsed} B"
    );
}
