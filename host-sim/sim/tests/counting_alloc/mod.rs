//! A counting global allocator for the tests that hold a time loop to "allocates nothing once
//! sized" (`fe_no_alloc.rs`, `safety.rs`): every allocation and reallocation made on the
//! calling thread is counted, so a test reads [`count`] before and after the loop. Including
//! this module installs it as the test binary's allocator (`#[global_allocator]`, one per
//! binary); other threads' allocations (a thread pool's) are not seen.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Allocations (and reallocations) made on this thread so far.
pub fn count() -> usize {
    COUNT.with(|c| c.get())
}
