//! The IVF iteration does not touch the heap: a counting global allocator sees no allocation
//! during `IvfSolver::iterate` (after the solver is built), for several sizes.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use bearing_ident::Coefficients;
use bearing_ident::frf::Frf;
use bearing_ident::solve::{IvfOptions, IvfSolver};
use faer::{Mat, c64};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator and only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// An n-DOF system's flexibility on `lines` lines with a deterministic 2 % perturbation, so
/// that IVF has work to do.
fn perturbed_frf(n: usize, lines: usize) -> Frf {
    let m = Mat::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.05 });
    let k = Mat::from_fn(n, n, |i, j| {
        let w = 2.0 * std::f64::consts::PI * (10.0 + 30.0 * i as f64 / n as f64);
        if i == j {
            2.0 * w * w
        } else {
            150.0 * (i as f64 - j as f64)
        }
    });
    let c = Mat::from_fn(n, n, |i, j| if i == j { 30.0 } else { 1.0 });
    let sys = Coefficients::new(m, c, k).unwrap();
    let freqs: Vec<f64> = (0..lines)
        .map(|l| 5.0 + 40.0 * l as f64 / lines as f64)
        .collect();
    let g: Vec<Mat<c64>> = freqs
        .iter()
        .enumerate()
        .map(|(l, &f)| {
            let g = sys.flexibility_at(f).unwrap();
            let e = 0.02 * (((l * 7919) % 101) as f64 / 50.0 - 1.0);
            Mat::from_fn(n, n, |i, j| g[(i, j)] * c64::new(1.0 + e, -e))
        })
        .collect();
    Frf::from_flexibility(freqs, &g).unwrap()
}

#[test]
fn ivf_iteration_does_not_allocate() {
    // The counter sees allocations (so a zero below means something).
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    let probe = std::hint::black_box(vec![1u8; 16]);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) > before);
    drop(probe);

    for (n, lines) in [(1, 20), (2, 49), (4, 200), (8, 100)] {
        let frf = perturbed_frf(n, lines);
        let mut solver = IvfSolver::new(&frf, IvfOptions::default()).unwrap();
        solver.iterate().expect("warm-up iteration");
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for _ in 0..3 {
            solver.iterate().expect("regular model");
        }
        let during = ALLOCATIONS.load(Ordering::SeqCst) - before;
        assert_eq!(
            during, 0,
            "n = {n}, N = {lines}: {during} allocations in 3 iterations"
        );
        assert_eq!(solver.history().len(), 4);
    }
}
