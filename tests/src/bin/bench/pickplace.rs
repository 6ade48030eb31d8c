//! Pick-and-place cell step cost (issue 5, pick_and_place.md §17): identity kinematics, two
//! belts with 30 tracked workpieces each, a blended ellipse profile running; mean and p99.9
//! over the measured steps, and the cycles from an execute edge to the first moving set point.
//! Reference: the manual's module, 200 µs mean / 511 µs peak on a 1.6 GHz Atom.

use motion_core::Engine;
use pickplace_engine::{
    AxisConfig, BeltConfig, ConveyorBeltPar, PickPlaceCommand, PickPlaceConfig, PickPlaceEngine,
    ScPar, TmState,
};
use std::time::Instant;

fn belt(y: f64, z_dist: f64, sync_time: f64) -> BeltConfig {
    BeltConfig {
        params: ConveyorBeltPar {
            park_pos: [-400.0, y, 300.0, 180.0, 0.0, 180.0],
            z_dist_belt: z_dist,
            conveyor_belt_origin: [400.0, y, 100.0, 0.0, 0.0, 180.0],
            sync_time_on_belt: sync_time,
            lower_sync_limit: 200.0,
            upper_sync_limit: 800.0,
        },
        initial_velocity: 1.0,
        initial_position: 0.0,
    }
}

/// The §19 common setup with belts 1 and 2 of W8, enabled and READY.
fn cell(path_prep_cycles: u32) -> PickPlaceEngine {
    let mut cfg = PickPlaceConfig {
        params: ScPar {
            max_vel: [0.0; 7],
            max_acc_dec: [0.0; 7],
            max_jerk: [0.0; 7],
            path_vel: 5.0,
            path_acc: 5000.0,
            path_dec: 5000.0,
            path_jerk: 1e6,
            path_mode: 1,
            z_dist_elliptical: 60.0,
            blending_radius: 10.0,
            z_start_dist: 20.0,
            z_target_dist: 40.0,
            target_pos: [300.0, 0.0, 140.0, 180.0, 0.0, 90.0, 0.0],
            ..ScPar::default()
        },
        initial_tcp: Some([0.0, 0.0, 200.0, 180.0, 0.0, 180.0, 0.0]),
        path_prep_cycles,
        ..Default::default()
    };
    cfg.belts.insert("1".into(), belt(500.0, 50.0, 0.2));
    cfg.belts.insert("2".into(), belt(-500.0, 40.0, 0.1));
    let mut e = PickPlaceEngine::new(cfg).expect("cell config");
    e.command(PickPlaceCommand::SetEnable(true))
        .expect("enable");
    e.command(PickPlaceCommand::SetRegulatorOn(true))
        .expect("regulator");
    e
}

/// One cycle; the cell's single-cycle events are dropped as a node would publish them.
fn step(e: &mut PickPlaceEngine, tick: &mut u64, ev: &mut Vec<motion_core::CommandEvent>) {
    super::step(e, tick, ev);
    e.drain_events();
}

/// Cycles between the cycle that takes the execute edge and the first cycle with a non-zero
/// path set-point velocity (§17: the observable delay is `path_prep_cycles`).
fn start_delay(path_prep_cycles: u32) -> u64 {
    let mut e = cell(path_prep_cycles);
    let (mut tick, mut ev) = (0, Vec::new());
    step(&mut e, &mut tick, &mut ev);
    assert_eq!(e.snapshot().state, TmState::Ready);
    e.command(PickPlaceCommand::Execute { set_target: 0 })
        .expect("execute");
    for k in 0..100 {
        step(&mut e, &mut tick, &mut ev);
        if e.snapshot().outputs.set_path_vel_out > 1e-9 {
            return k;
        }
    }
    u64::MAX
}

pub fn step_cost(steps: u64) {
    let mut e = cell(3);
    let (mut tick, mut ev) = (0, Vec::new());
    step(&mut e, &mut tick, &mut ev);
    for b in [1u8, 2] {
        for k in 0..30 {
            e.command(PickPlaceCommand::DetectWorkpiece {
                belt: b,
                position: [-3000.0 + k as f64, 0.0, 0.0, 0.0, 0.0, 0.0],
                valid_delay_cycles: 0,
            })
            .expect("workpiece");
        }
    }
    for _ in 0..100 {
        step(&mut e, &mut tick, &mut ev);
    }
    let tracked: Vec<usize> = e
        .snapshot()
        .belts
        .iter()
        .map(|b| b.workpieces.len())
        .filter(|n| *n > 0)
        .collect();
    let mut times = Vec::with_capacity(steps as usize);
    let mut moving = 0u64;
    for k in 0..steps {
        if k.is_multiple_of(20_000) {
            e.command(PickPlaceCommand::Execute { set_target: 0 })
                .expect("execute");
        }
        let t0 = Instant::now();
        step(&mut e, &mut tick, &mut ev);
        times.push(t0.elapsed().as_secs_f64());
        if e.snapshot().outputs.set_path_vel_out > 1e-9 {
            moving += 1;
        }
    }
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    let p999 = super::percentile(&mut times, 0.999);
    let max = times.iter().cloned().fold(0.0, f64::max);
    println!(
        "pickplace cell step: belts with {tracked:?} workpieces, path moving in {moving} of {steps} steps: mean {:.2} us, p99.9 {:.2} us, max {:.1} us | manual's module 200 us mean, 511 us peak (ratio {:.3} / {:.3}) | target <= 10 us mean, <= 50 us p99.9",
        mean * 1e6,
        p999 * 1e6,
        max * 1e6,
        mean / 200e-6,
        p999 / 511e-6
    );
    println!(
        "pickplace execute edge -> first moving set point: {} cycle(s) after the edge's cycle with path_prep_cycles = 1, {} with the default 3 (the manual's module: up to 25)",
        start_delay(1),
        start_delay(3)
    );
    clamped_step_cost(if steps < 100_000 { 2 } else { 40 });
}

/// §7.8 (2) at work: belt picks (belt 1 at 200 units/s) approached with the belt, where path
/// plus belt velocity exceed X's AXIS_REF maximum of 450 units/s, so the path is slowed in
/// many cycles. Step cost over all cycles of `picks` picks.
fn clamped_step_cost(picks: usize) {
    let mut times = Vec::new();
    for _ in 0..picks {
        let mut cfg = PickPlaceConfig {
            params: ScPar {
                max_vel: [0.0; 7],
                max_acc_dec: [0.0; 7],
                max_jerk: [0.0; 7],
                path_vel: 500.0,
                path_acc: 5000.0,
                path_dec: 5000.0,
                path_jerk: 1e6,
                blending_radius: 10.0,
                z_start_dist: 0.0,
                ..ScPar::default()
            },
            initial_tcp: Some([450.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]),
            ..Default::default()
        };
        let mut b = belt(500.0, 50.0, 0.2);
        b.initial_velocity = 200.0;
        cfg.belts.insert("1".into(), b);
        let x = AxisConfig {
            max_vel: 450.0,
            max_acc: 30_000.0,
            max_jerk: 1e7,
            ..AxisConfig::default()
        };
        cfg.axes.insert("x".into(), x);
        let mut e = PickPlaceEngine::new(cfg).expect("cell config");
        e.command(PickPlaceCommand::SetEnable(true))
            .expect("enable");
        e.command(PickPlaceCommand::SetRegulatorOn(true))
            .expect("regulator");
        let (mut tick, mut ev) = (0, Vec::new());
        step(&mut e, &mut tick, &mut ev);
        e.command(PickPlaceCommand::BeltInput {
            belt: 1,
            receive: true,
            valid_pos: true,
            initial_object_position: [210.0, -50.0, 10.0, 0.0, 0.0, 0.0],
            aux1_target_pos: 0.0,
        })
        .expect("workpiece");
        e.command(PickPlaceCommand::Execute { set_target: 1 })
            .expect("execute");
        for _ in 0..5000 {
            let t0 = Instant::now();
            step(&mut e, &mut tick, &mut ev);
            times.push(t0.elapsed().as_secs_f64());
            let s = e.snapshot();
            if s.state == TmState::Ready && s.outputs.done {
                break;
            }
        }
    }
    let n = times.len();
    let mean = times.iter().sum::<f64>() / n as f64;
    let p999 = super::percentile(&mut times, 0.999);
    println!(
        "pickplace cell step with the AXIS_REF clamp slowing the path (§7.8 (2), {picks} belt picks, {n} steps): mean {:.2} us, p99.9 {:.2} us | target <= 10 us mean, <= 50 us p99.9",
        mean * 1e6,
        p999 * 1e6
    );
}
