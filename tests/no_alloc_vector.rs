//! `VecEnv::step` allocates nothing after construction, on any of its threads (a process-wide
//! counting allocator; this binary holds this one test so nothing else allocates meanwhile).
#![allow(clippy::unwrap_used)] // Test helpers outside `#[test]` functions unwrap too.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

use envc::{Autoreset, VecEnv};

struct Counting;

static COUNTING: AtomicBool = AtomicBool::new(false);
static COUNT: AtomicU64 = AtomicU64::new(0);

// SAFETY: forwards to the system allocator; counting touches only atomics.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Relaxed) {
            COUNT.fetch_add(1, Relaxed);
        }
        // SAFETY: the caller's `GlobalAlloc` contract, passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as in `alloc`.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new: usize) -> *mut u8 {
        if COUNTING.load(Relaxed) {
            COUNT.fetch_add(1, Relaxed);
        }
        // SAFETY: as in `alloc`.
        unsafe { System.realloc(ptr, layout, new) }
    }
}

#[global_allocator]
static A: Counting = Counting;

#[test]
fn vector_step_does_not_allocate() {
    for (id, mode) in [
        ("Hopper-v5", Autoreset::NextStep),
        ("Ant-v5", Autoreset::SameStep),
        ("Humanoid-v5", Autoreset::NextStep),
        // A goal task: its goal rows, SameStep's final ones too (episodes of 50 steps).
        ("FetchPush-v4", Autoreset::SameStep),
    ] {
        let mut v = VecEnv::make(id, &[], 4, 2, mode).unwrap();
        v.reset(Some(3));
        let actions = vec![0.3; v.num_envs() * v.act_dim()];
        // Warm up (first episode ends, worker threads parked and woken at least once).
        for _ in 0..50 {
            v.step(&actions).unwrap();
        }
        COUNT.store(0, Relaxed);
        COUNTING.store(true, Relaxed);
        for _ in 0..300 {
            v.step(&actions).unwrap();
        }
        COUNTING.store(false, Relaxed);
        let n = COUNT.load(Relaxed);
        assert_eq!(n, 0, "{id}: {n} allocations in 300 vector steps");
    }
}
