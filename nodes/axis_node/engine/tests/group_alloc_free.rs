//! `step` does not allocate in steady state with moving Part 4 groups and the `isg_mcp`
//! monitors active (plcopen_platform.md §12.3 R-PERF-1: cost per active object only).
use axis_engine::group::*;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::{CommandEvent, Engine, Tick};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
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
fn moving_groups_do_not_allocate() {
    let names: Vec<String> = (0..6).map(|i| format!("a{i}")).collect();
    let cfg = EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        groups: vec![
            GroupConfig {
                name: "g1".into(),
                axes: names[0..3].to_vec(),
            },
            GroupConfig {
                name: "g2".into(),
                axes: names[3..6].to_vec(),
            },
        ],
        ..EngineConfig::default()
    };
    let ax = AxisConfig {
        cycle_time: 0.001,
        ..AxisConfig::default()
    };
    let mut e = AxisEngine::with_config(
        names.iter().map(|n| (n.clone(), ax.clone())).collect(),
        &cfg,
    )
    .unwrap();
    let mut events: Vec<CommandEvent> = Vec::with_capacity(64);
    let mut tick = 0u64;
    let mut step = |e: &mut AxisEngine, events: &mut Vec<CommandEvent>| {
        e.step(
            Tick {
                index: tick,
                dt: 0.001,
            },
            events,
        );
        events.clear();
        tick += 1;
    };
    for _ in 0..10 {
        step(&mut e, &mut events);
    }
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
    step(&mut e, &mut events);
    for g in ["g1", "g2"] {
        e.command(AxisCommand::Group(GroupCommand::MoveLinearAbsolute(
            MoveLinear {
                group: g.into(),
                position: vec![1000.0, 2000.0, -500.0],
                velocity: 100.0,
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
                coord_system: CoordSystem::Acs,
                buffer_mode: BufferMode::Aborting,
                transition_mode: TransitionMode::None,
            },
        )))
        .unwrap();
    }
    for _ in 0..50 {
        step(&mut e, &mut events);
    }
    MEASURING.with(|m| m.set(true));
    for _ in 0..2000 {
        step(&mut e, &mut events);
    }
    MEASURING.with(|m| m.set(false));
    assert_eq!(
        e.group("g1").unwrap().state,
        GroupState::Moving,
        "still moving"
    );
    assert_eq!(
        ALLOCS.load(Ordering::Relaxed),
        0,
        "allocations in steady state"
    );
}
