//! `step` with a moving CA ring does not allocate in steady state (collision_avoidance.md
//! §8.3: the group cycle reuses its scratch memory), also while followers queue and brake.
use axis_engine::*;
use motion_core::{Engine, Tick};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    // Only the measuring thread counts: libtest's own threads allocate at any time.
    static MEASURING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

fn count() {
    if MEASURING.with(|m| m.get()) {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static A: Counting = Counting;

#[test]
fn ca_ring_step_is_allocation_free() {
    let mut e = bench_ring(50);
    let mut ev = Vec::with_capacity(1024);
    // A hard halt of one mover makes its followers CA-limited and then queue.
    e.command(AxisCommand::Ca(ca::CaCommand::Halt(ca::HaltCa {
        axis: "m10".into(),
        deceleration: ca::McLreal::Maximum,
        ..Default::default()
    })))
    .unwrap();
    for k in 0..100 {
        ev.clear();
        e.step(
            Tick {
                index: 5000 + k,
                dt: 0.001,
            },
            &mut ev,
        );
    }
    MEASURING.with(|m| m.set(true));
    for k in 0..3000 {
        ev.clear();
        e.step(
            Tick {
                index: 6000 + k,
                dt: 0.001,
            },
            &mut ev,
        );
    }
    MEASURING.with(|m| m.set(false));
    assert_eq!(ALLOCS.load(Ordering::Relaxed), 0, "allocations in step");
    let g = &e.snapshot().ca_groups[0];
    assert!(
        g.axes.iter().any(|a| a.ca_limited),
        "followers were limited by CA"
    );
}
