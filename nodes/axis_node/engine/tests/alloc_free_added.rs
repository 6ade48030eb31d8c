//! `step` does not allocate in steady state with the added functions running: a
//! MC_GearInMultiMaster slave (AdvancedSlaveDynamics, POSSYNC2) being phased, a GearIn slave
//! being phased, an axis fed by the external setpoint generator, and backlash, table and
//! limiter corrections.
use axis_engine::*;
use motion_core::{Engine, Tick};
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
fn steady_state_steps_with_the_added_functions_do_not_allocate() {
    let cfg = AxisConfig {
        enable_pos_correction: true,
        ..Default::default()
    };
    let names = ["m1", "m2", "s", "g", "x"];
    let mut e =
        AxisEngine::new(names.iter().map(|n| (n.to_string(), cfg.clone())).collect()).unwrap();
    for n in names {
        e.command(AxisCommand::Power(Power {
            axis: n.into(),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .unwrap();
    }
    let mut ev = Vec::with_capacity(1024);
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
    step(&mut e, &mut ev);
    e.command(AxisCommand::GearInMultiMaster(GearInMultiMaster {
        slave: "s".into(),
        master1: "m1".into(),
        master2: "m2".into(),
        master3: String::new(),
        master4: String::new(),
        enable: true,
        gear_ratio1: 1.0,
        gear_ratio2: 0.5,
        gear_ratio3: 0.0,
        gear_ratio4: 0.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: GearInMultiMasterOptions {
            advanced_slave_dynamics: true,
            sync_mode: GearInMultiMasterSyncMode::PosSync2,
        },
    }))
    .unwrap();
    e.command(AxisCommand::GearIn(GearIn {
        master: "m1".into(),
        slave: "g".into(),
        ratio_numerator: 2.0,
        ratio_denominator: 1,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
    }))
    .unwrap();
    for (m, v) in [("m1", 50.0), ("m2", 80.0)] {
        e.command(AxisCommand::MoveVelocity(MoveVelocity {
            axis: m.into(),
            velocity: v,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            direction: Direction::Positive,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }))
        .unwrap();
    }
    for (slave, master) in [("s", "m2"), ("g", "m1")] {
        e.command(AxisCommand::PhasingAbsolute(PhasingAbsolute {
            master: master.into(),
            slave: slave.into(),
            continuous_update: false,
            phase_shift: 1000.0,
            velocity: 10.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .unwrap();
    }
    e.command(AxisCommand::ExtSetPointGenEnable(ExtSetPointGenEnable {
        axis: "x".into(),
        position: 0.0,
        position_type: PositionType::Absolute,
        options: ExtSetPointEnableOptions::default(),
    }))
    .unwrap();
    e.command(AxisCommand::ExtSetPointGenFeed(ExtSetPointGenFeed {
        axis: "x".into(),
        position: 1.0,
        velocity: 10.0,
        acceleration: 0.0,
        direction: 1,
    }))
    .unwrap();
    for axis in ["m1", "s"] {
        e.command(AxisCommand::BacklashCompensation(BacklashCompensation {
            axis: axis.into(),
            enable: true,
            backlash: 0.05,
            compensation_in_positive_direction: true,
            ramp: 0.001,
            disable_mode: DisableMode::Hold,
        }))
        .unwrap();
        e.command(AxisCommand::PositionCorrectionLimiter(
            PositionCorrectionLimiter {
                axis: axis.into(),
                enable: true,
                position_correction_value: 1.0,
                correction_mode: PositionCorrectionMode::FullLength,
                acceleration: 0.0,
                correction_length: 1e6,
            },
        ))
        .unwrap();
        e.command(AxisCommand::TableBasedPositionCompensation(
            TableBasedPositionCompensation {
                axis: axis.into(),
                enable: true,
                table: (0..11)
                    .map(|k| PositionCompensationTableElement {
                        position: k as f64 * 100.0,
                        compensation: k as f64 * 0.01,
                    })
                    .collect(),
                table_parameter: PositionCompensationTableParameter {
                    min_position: 0.0,
                    max_position: 1000.0,
                    no_of_table_elements: 11,
                    direction: WorkDirection::Both,
                    modulo: true,
                },
                ramp: 0.01,
                disable_mode: DisableMode::Hold,
            },
        ))
        .unwrap();
    }
    // Synchronizing (the limiter plans) takes well below 2 s.
    for _ in 0..2000 {
        step(&mut e, &mut ev);
    }
    ALLOCS.store(0, Ordering::Relaxed);
    MEASURING.with(|m| m.set(true));
    for _ in 0..5000 {
        step(&mut e, &mut ev);
    }
    MEASURING.with(|m| m.set(false));
    assert_eq!(ALLOCS.load(Ordering::Relaxed), 0, "allocations in step");
    let x = e.ext_status("s").unwrap();
    assert!(x.phasing_active && x.position_correction != 0.0);
    assert!(e.ext_status("x").unwrap().ext_set_point_gen_enabled);
}
