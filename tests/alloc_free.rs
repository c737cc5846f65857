//! The IVF iteration does not touch the heap: a counting global allocator sees no allocation
//! during `IvfSolver::iterate` (after the solver is built), for several sizes.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

mod common;

use bearing_ident::solve::{IvfOptions, IvfSolver};
use common::perturbed_frf;

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

#[test]
fn ivf_iteration_does_not_allocate() {
    // The counter sees allocations (so a zero below means something).
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    let probe = std::hint::black_box(vec![1u8; 16]);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) > before);
    drop(probe);

    for (n, lines) in [(1, 20), (2, 49), (4, 200), (8, 100)] {
        let frf = perturbed_frf(n, lines, 0.02);
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
