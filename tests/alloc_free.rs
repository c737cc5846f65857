//! The IVF iteration does not touch the heap: a counting global allocator sees no allocation
//! during `IvfSolver::iterate` (after the solver is built), for several sizes (n = 17: the
//! vectorised kernels' full registers and scalar tail rows).
//!
//! Only the test's own thread is counted: the test harness's other threads (output capture,
//! "running for over 60 s" notices under load) allocate when they like.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

mod common;

use bearing_ident::solve::{IvfOptions, IvfSolver};
use common::perturbed_frf;

struct Counting;

thread_local! {
    /// Allocations made by this thread (a const-initialised `Cell`: reading it never allocates).
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: during thread teardown the slot may be gone; those allocations are not ours.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

// SAFETY: forwards to the system allocator and only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn ivf_iteration_does_not_allocate() {
    // The counter sees allocations (so a zero below means something).
    let before = allocations();
    let probe = std::hint::black_box(vec![1u8; 16]);
    assert!(allocations() > before);
    drop(probe);

    for (n, lines) in [(1, 20), (2, 49), (4, 200), (8, 100), (17, 40)] {
        let frf = perturbed_frf(n, lines, 0.02);
        let mut solver = IvfSolver::new(&frf, IvfOptions::default()).unwrap();
        solver.iterate().expect("warm-up iteration");
        let before = allocations();
        for _ in 0..3 {
            solver.iterate().expect("regular model");
        }
        let during = allocations() - before;
        assert_eq!(
            during, 0,
            "n = {n}, N = {lines}: {during} allocations in 3 iterations"
        );
        assert_eq!(solver.history().len(), 4);
    }
}
