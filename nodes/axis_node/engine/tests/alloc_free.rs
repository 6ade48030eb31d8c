//! `step` does not allocate in steady state (moving axes, settling, errors ramps, events).
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

fn mv(axis: &str, position: f64) -> AxisCommand {
    AxisCommand::MoveAbsolute(MoveAbsolute {
        axis: axis.into(),
        position,
        velocity: 100.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    })
}

#[test]
fn steady_state_steps_do_not_allocate() {
    let names: Vec<String> = (0..20).map(|i| format!("a{i}")).collect();
    let mut e = AxisEngine::new(
        names
            .iter()
            .map(|n| (n.clone(), AxisConfig::default()))
            .collect(),
    )
    .unwrap();
    for n in &names {
        e.command(AxisCommand::Power(Power {
            axis: n.clone(),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .unwrap();
    }
    let mut events = Vec::with_capacity(1024);
    let mut tick = 0;
    let mut step = |e: &mut AxisEngine, ev: &mut Vec<_>| {
        e.step(
            Tick {
                index: tick,
                dt: 0.001,
            },
            ev,
        );
        ev.clear();
        tick += 1;
    };
    step(&mut e, &mut events);
    for (i, n) in names.iter().enumerate() {
        // Short and long moves: some finish (Done events, settling) during the measurement.
        e.command(mv(n, if i % 2 == 0 { 5.0 } else { 1e5 }))
            .unwrap();
    }
    e.command(AxisCommand::MoveVelocity(MoveVelocity {
        axis: "a3".into(),
        velocity: 50.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        direction: Direction::Negative,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }))
    .unwrap();
    e.command(AxisCommand::Sim(Sim::InjectAxisError {
        axis: "a5".into(),
        error_id: 0x4550,
    }))
    .unwrap();
    step(&mut e, &mut events);
    let before = ALLOCS.load(Ordering::Relaxed);
    MEASURING.with(|m| m.set(true));
    for _ in 0..2000 {
        step(&mut e, &mut events);
    }
    MEASURING.with(|m| m.set(false));
    let n = ALLOCS.load(Ordering::Relaxed) - before;
    assert_eq!(n, 0, "allocations during 2000 steps");
}
