//! pick_and_place.md §4.2: every transition T1 … T24, the controlled start of §2.3 and the
//! warnings for ignored edges (90008, 90009, 90010).
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use motion_core::{CommandState, Engine};
use pickplace_engine::{PickPlaceCommand, ServiceRequest, StopInputs, TmState};

fn stops(path_stop: bool, path_halt: bool, stop_all: bool) -> PickPlaceCommand {
    PickPlaceCommand::SetStopInputs(StopInputs {
        path_stop: Some(path_stop),
        path_halt: Some(path_halt),
        stop_all: Some(stop_all),
        path_interrupt: None,
    })
}

fn interrupt(v: bool) -> PickPlaceCommand {
    PickPlaceCommand::SetStopInputs(StopInputs {
        path_interrupt: Some(v),
        ..Default::default()
    })
}

fn jog(axis: u8, pos: bool, neg: bool) -> PickPlaceCommand {
    PickPlaceCommand::Jog {
        select_axis: axis,
        jog_pos: pos,
        jog_neg: neg,
    }
}

/// READY cell with a long move to X = 300 started and cruising.
fn moving() -> Cell {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(300);
    assert_eq!(c.state(), TmState::MovePp);
    c
}

#[test]
fn t1_t2_enable_false_disables_and_stops_individually() {
    let mut c = moving();
    c.cmd(PickPlaceCommand::SetEnable(false));
    c.step();
    assert_eq!(c.state(), TmState::Disabled);
    assert!(!c.last().outputs.path_hold, "queue and held path discarded");
    c.steps(200);
    assert_eq!(c.last().tcp_velocity[0], 0.0);
    let x = c.last().tcp[0];
    c.cmd(PickPlaceCommand::SetEnable(true));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    c.steps(100);
    assert_eq!(c.last().tcp[0], x, "no motion after re-enable");
}

#[test]
fn t2_with_error_present_goes_to_error() {
    let mut c = Cell::ready(common_config());
    c.cmd(PickPlaceCommand::SimInjectFault {
        axis: 1,
        kind: pickplace_engine::FaultKind::DriveFault,
    });
    c.step();
    assert_eq!(c.state(), TmState::Error);
    c.cmd(PickPlaceCommand::SetEnable(false));
    c.step();
    assert_eq!(c.state(), TmState::Disabled);
    c.cmd(PickPlaceCommand::SetEnable(true));
    c.step();
    assert_eq!(c.state(), TmState::Error);
}

#[test]
fn t3_t4_error_and_reset_only_at_standstill() {
    let mut c = moving();
    c.cmd(PickPlaceCommand::SimInjectFault {
        axis: 1,
        kind: pickplace_engine::FaultKind::FollowingError,
    });
    c.step();
    assert_eq!(c.state(), TmState::Error);
    assert!(!c.last().outputs.path_hold);
    // Reset while still decelerating is refused.
    c.cmd(PickPlaceCommand::ResetError);
    c.step();
    assert_eq!(c.state(), TmState::Error);
    c.steps(100);
    c.cmd(PickPlaceCommand::ResetError);
    c.steps(2);
    assert_eq!(c.state(), TmState::Ready);
    assert_eq!(c.last().outputs.error_id, 0);
}

#[test]
fn t5_t6_stop_from_every_allowed_state() {
    // READY
    let mut c = Cell::ready(common_config());
    c.cmd(stops(true, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Stop);
    c.cmd(stops(false, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    // PREPARING_PATH
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.step();
    assert_eq!(c.state(), TmState::PreparingPath);
    c.cmd(stops(false, true, false));
    c.step();
    assert_eq!(c.state(), TmState::Stop);
    c.cmd(stops(false, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    // JOGPOS
    c.cmd(jog(1, true, false));
    c.steps(50);
    assert_eq!(c.state(), TmState::JogPos);
    c.cmd(stops(false, false, true));
    c.step();
    assert_eq!(c.state(), TmState::Stop);
    assert!(c.last().outputs.busy, "busy while decelerating");
    c.cmd(jog(1, false, false));
    c.cmd(stops(false, false, false));
    c.until(100, |s| s.state == TmState::Ready);
    assert_eq!(c.last().tcp_velocity[0], 0.0);
    // HOMING
    c.set_par(|p| p.homing_order[0] = 1);
    c.cmd(PickPlaceCommand::GroupHome);
    c.step();
    assert_eq!(c.state(), TmState::Homing);
    c.cmd(stops(true, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Stop);
    c.cmd(stops(false, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    // MOVE_PP and PATH_INTERRUPT
    let mut c = moving();
    c.cmd(interrupt(true));
    c.steps(5);
    assert_eq!(c.state(), TmState::PathInterrupt);
    c.cmd(stops(true, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Stop);
    c.cmd(stops(false, false, false));
    c.cmd(interrupt(false));
    c.until(500, |s| s.state == TmState::Ready);
    assert!(c.last().outputs.path_hold);
}

#[test]
fn t6_stays_in_stop_while_any_stop_input_is_true_or_moving() {
    let mut c = moving();
    c.cmd(stops(false, true, false));
    c.step();
    c.cmd(stops(false, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Stop, "not yet at standstill");
    c.until(1000, |s| s.state == TmState::Ready);
    assert_eq!(c.last().outputs.set_path_vel_out, 0.0);
}

#[test]
fn controlled_start_jog_level_present_while_disabled() {
    // §2.3: xJogPos TRUE while disabled, enable → READY, no motion; only a new edge jogs.
    let mut c = Cell::new(common_config());
    c.cmd(jog(1, true, false));
    c.cmd(PickPlaceCommand::SetEnable(true));
    c.steps(5);
    c.cmd(PickPlaceCommand::SetRegulatorOn(true));
    c.steps(50);
    assert_eq!(c.state(), TmState::Ready);
    assert_eq!(c.last().tcp[0], 0.0);
    c.cmd(jog(1, false, false));
    c.step();
    c.cmd(jog(1, true, false));
    c.steps(10);
    assert_eq!(c.state(), TmState::JogPos);
    assert!(c.last().tcp[0] > 0.0);
}

#[test]
fn controlled_start_execute_while_disabled_is_dropped_with_90009() {
    let mut c = Cell::new(common_config());
    c.cmd(PickPlaceCommand::SetEnable(true));
    c.step();
    c.set_par(|p| p.target_pos[0] = 50.0);
    let id = c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.step();
    assert_eq!(c.last().outputs.error_id, 90009);
    assert!(c
        .events
        .iter()
        .any(|e| e.id == id && e.state == CommandState::Error(motion_core::ErrorId(90009))));
    c.cmd(PickPlaceCommand::SetRegulatorOn(true));
    c.steps(50);
    assert_eq!(c.state(), TmState::Ready);
    assert_eq!(c.last().tcp[0], 0.0, "no motion on enabling");
}

#[test]
fn t7_t9_jog_first_direction_wins_until_both_released() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.cartesian_jog = pickplace_engine::params::JogPar {
            vel: 10.0,
            acc: 100.0,
            dec: 100.0,
            jerk: 10000.0,
        }
    });
    c.cmd(jog(2, true, false));
    c.steps(500);
    assert_eq!(c.state(), TmState::JogPos);
    assert_close("jog velocity", c.last().tcp_velocity[1], 10.0, 1e-6);
    c.cmd(jog(2, true, true));
    c.steps(10);
    assert_eq!(c.state(), TmState::JogPos, "running jog not replaced");
    assert!(c.last().tcp_velocity[1] > 9.0);
    c.cmd(jog(2, false, true));
    c.steps(400);
    assert_eq!(
        c.state(),
        TmState::JogPos,
        "stays JOGPOS while jog_neg TRUE"
    );
    assert_eq!(c.last().tcp_velocity[1], 0.0, "decelerated, not reversed");
    c.cmd(jog(2, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    // T8
    c.cmd(jog(13, false, true));
    c.steps(200);
    assert_eq!(c.state(), TmState::JogNeg);
    assert!(c.last().tcp[6] < 0.0, "Aux1 jogged −");
    c.cmd(jog(13, false, false));
    c.until(1000, |s| s.state == TmState::Ready);
}

#[test]
fn jog_real_axis_and_orientation() {
    let mut c = Cell::ready(common_config());
    c.cmd(jog(9, true, false)); // A3 = Z with identity kinematics
    c.steps(300);
    assert!(c.last().tcp[2] > 100.0);
    assert!(c.last().outputs.act_pos[8] > 100.0);
    c.cmd(jog(9, false, false));
    c.until(1000, |s| s.state == TmState::Ready);
    c.cmd(jog(6, false, true)); // C
    c.steps(300);
    assert!(c.last().tcp[5] < 0.0);
}

#[test]
fn jog_stops_at_sw_limit_with_error() {
    let mut cfg = common_config();
    cfg.axes.insert(
        "x".into(),
        pickplace_engine::AxisConfig {
            sw_limit_pos: 1.0,
            sw_limit_neg: -1.0,
            sw_limit_enabled: true,
            ..Default::default()
        },
    );
    let mut c = Cell::ready(cfg);
    c.cmd(jog(1, true, false));
    c.until(2000, |s| s.state == TmState::Error);
    assert_eq!(c.last().outputs.error_id, 20306);
}

#[test]
fn t10_t11_homing_stages_in_order() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.homing_order = [1, 1, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        p.home_position = [5.0, 6.0, 7.0, 0.0, 0.0, 0.0, 99.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    });
    let id = c.cmd(PickPlaceCommand::GroupHome);
    c.step();
    assert_eq!(c.state(), TmState::Homing);
    assert!(c.last().outputs.busy);
    c.steps(101);
    // Stage 1 done (A1, A2 together), stage 2 (A3) running.
    assert_eq!((c.last().tcp[0], c.last().tcp[1]), (5.0, 6.0));
    assert_eq!(c.last().tcp[2], 100.0);
    c.until(200, |s| s.state == TmState::Ready);
    let s = c.last();
    assert_eq!(s.tcp[2], 7.0);
    assert_eq!(s.tcp[6], 0.0, "Aux1 not homed (NoHoming)");
    assert!(s.outputs.done && s.outputs.axes_group_homed);
    assert!(c
        .events
        .iter()
        .any(|e| e.id == id && e.state == CommandState::Done));
}

#[test]
fn t12_homing_switch_search_and_failure() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.homing_order[0] = 1;
        p.use_home_ext_parameter = true;
        p.home_position[0] = 10.0;
        p.home_ext_parameter[0] = pickplace_engine::params::HomeParameter {
            mode: 1,
            vel: 20.0,
            acc: 200.0,
            positive_direction: true,
            max_search_dist: 50.0,
        };
    });
    c.cmd(PickPlaceCommand::GroupHome);
    c.steps(500);
    assert!(c.last().tcp[0] > 5.0, "searching +");
    let mut sw = [false; 12];
    sw[0] = true;
    c.cmd(PickPlaceCommand::SimSetDigitalInputs {
        hw_limit_pos: [false; 18],
        hw_limit_neg: [false; 18],
        home_switch: sw,
        enable_hw_limit: false,
    });
    c.until(1000, |s| s.state == TmState::Ready);
    assert!(c.last().outputs.done);
    // Switch point = 10; the stop continues 20²/(2·200) = 1 beyond it.
    assert_close("homed position", c.last().tcp[0], 11.0, 1e-6);
    // Without a switch: search distance exceeded → 90014.
    c.cmd(PickPlaceCommand::SimSetDigitalInputs {
        hw_limit_pos: [false; 18],
        hw_limit_neg: [false; 18],
        home_switch: [false; 12],
        enable_hw_limit: false,
    });
    c.cmd(PickPlaceCommand::GroupHome);
    c.until(5000, |s| s.state == TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90014);
}

#[test]
fn t13_t14_service_move() {
    let mut c = Cell::ready(common_config());
    let req = ServiceRequest {
        move_abs: true,
        axis: 13,
        pos: 20.0,
        vel: 100.0,
        acc: 1000.0,
        dec: 1000.0,
        jerk: 1e5,
    };
    c.cmd(PickPlaceCommand::Service(req));
    c.step();
    assert_eq!(c.state(), TmState::Service);
    c.steps(500);
    assert_eq!(c.last().tcp[6], 20.0);
    assert_eq!(c.state(), TmState::Service, "request still pending");
    c.cmd(PickPlaceCommand::Service(ServiceRequest {
        move_abs: false,
        ..req
    }));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
}

#[test]
fn t15_t16_t18_preparation_delay_then_motion_then_done() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 10.0;
        p.target_pos[2] = 100.0;
    });
    let id = c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.step();
    assert_eq!(c.state(), TmState::PreparingPath);
    assert!(c.last().outputs.profile_in_preparation && c.last().outputs.busy);
    c.steps(2);
    assert_eq!(c.state(), TmState::MovePp, "path_prep_cycles = 3");
    assert_close(
        "lrPathPreparationTime",
        c.last().outputs.path_preparation_time,
        0.003,
        1e-12,
    );
    assert_eq!(
        c.last().outputs.set_path_vel_out,
        0.0,
        "motion starts in the next cycle"
    );
    c.step();
    assert!(c.last().outputs.set_path_vel_out > 0.0);
    c.until(1000, |s| s.state == TmState::Ready);
    assert!(c.last().outputs.done && c.last().outputs.in_target);
    c.step();
    assert!(
        c.last().outputs.in_position,
        "set-point at the target and standstill"
    );
    let states: Vec<CommandState> = c
        .events
        .iter()
        .filter(|e| e.id == id)
        .map(|e| e.state)
        .collect();
    assert_eq!(
        states,
        vec![CommandState::Busy, CommandState::Active, CommandState::Done]
    );
    // xDone is cleared by the next command leaving READY.
    c.cmd(jog(1, true, false));
    c.steps(2);
    assert!(!c.last().outputs.done);
}

#[test]
fn t19_t20_t21_interrupt_continue_and_abort() {
    let mut c = moving();
    c.cmd(interrupt(true));
    c.step();
    assert_eq!(c.state(), TmState::PathInterrupt);
    c.steps(100);
    assert_eq!(c.last().outputs.set_path_vel_out, 0.0);
    c.cmd(interrupt(false));
    c.step();
    assert_eq!(c.state(), TmState::MovePp);
    c.steps(50);
    assert!(c.last().outputs.set_path_vel_out > 0.0);
    c.cmd(interrupt(true));
    c.steps(2);
    c.cmd(PickPlaceCommand::Abort);
    c.step();
    assert_eq!(
        c.state(),
        TmState::PathInterrupt,
        "abort only at standstill"
    );
    c.steps(100);
    c.cmd(PickPlaceCommand::Abort);
    c.steps(3);
    assert_eq!(c.state(), TmState::Ready);
    assert!(!c.last().outputs.path_hold);
}

#[test]
fn interrupt_is_only_effective_in_move_pp() {
    let mut c = Cell::ready(common_config());
    c.cmd(interrupt(true));
    c.steps(3);
    assert_eq!(c.state(), TmState::Ready);
}

#[test]
fn t22_abort_in_stop_at_standstill() {
    let mut c = moving();
    c.cmd(stops(true, false, false));
    c.until(500, |s| !s.outputs.busy);
    assert!(c.last().outputs.path_hold);
    c.cmd(PickPlaceCommand::Abort);
    c.steps(2);
    assert_eq!(c.state(), TmState::Stop, "state unchanged");
    assert!(!c.last().outputs.path_hold);
    c.cmd(stops(false, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(2);
    assert_eq!(
        c.state(),
        TmState::PreparingPath,
        "a new profile, not a resume"
    );
}

#[test]
fn t23_jog_with_held_path_returns_to_stop() {
    let mut c = moving();
    c.cmd(stops(true, false, false));
    c.until(500, |s| !s.outputs.busy);
    c.cmd(jog(3, true, false));
    c.steps(100);
    assert_eq!(c.state(), TmState::JogPos);
    c.cmd(jog(3, false, false));
    c.until(500, |s| s.state != TmState::JogPos);
    assert_eq!(c.state(), TmState::Stop, "stop input still TRUE");
    assert!(c.last().outputs.path_hold);
    let z = c.last().tcp[2];
    assert!(z > 100.0);
    // The resume moves straight from the jogged pose to the next profile point (here T, as
    // there are no IPs), then ends at the target (§9.2).
    c.cmd(stops(false, false, false));
    c.step();
    c.trace.clear();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(8000, |s| s.state == TmState::Ready && s.outputs.done);
    assert_close("X", c.last().tcp[0], 300.0, 1e-9);
    assert_close("Z", c.last().tcp[2], 100.0, 1e-9);
    let start = c.trace[c.motion_start()].tcp;
    for s in &c.trace {
        // On the straight line from the jogged pose to T.
        let u = (s.tcp[0] - start[0]) / (300.0 - start[0]);
        assert_close(
            "Z on the straight move",
            s.tcp[2],
            start[2] + u * (100.0 - start[2]),
            1e-6,
        );
    }
}

#[test]
fn resume_after_jog_goes_straight_to_the_next_profile_point() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 200.0;
        p.target_pos[2] = 50.0;
        p.z_start_dist = 50.0;
        p.z_target_dist = 30.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| {
        s.outputs.profile_point_passed == 1 && s.tcp[0] > 50.0
    });
    c.cmd(stops(true, false, false));
    c.until(500, |s| !s.outputs.busy);
    c.cmd(jog(2, true, false));
    c.steps(300);
    c.cmd(jog(2, false, false));
    c.until(500, |s| s.state == TmState::Stop);
    let y = c.last().tcp[1];
    assert!(y > 1.0);
    c.cmd(stops(false, false, false));
    c.step();
    c.trace.clear();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(8000, |s| s.state == TmState::Ready && s.outputs.done);
    // Passes IP2 = (200, 0, 80) exactly (stop there, r = 0), then lowers to T.
    let at_ip2 = c.trace.iter().any(|s| {
        let d = ((s.tcp[0] - 200.0).powi(2) + s.tcp[1].powi(2) + (s.tcp[2] - 80.0).powi(2)).sqrt();
        d < 1e-3 && s.outputs.set_path_vel_out < 0.1
    });
    assert!(at_ip2, "straight move ends at IP2");
    assert_close("Y at end", c.last().tcp[1], 0.0, 1e-9);
    assert_close("Z at end", c.last().tcp[2], 50.0, 1e-9);
    // Never rises again to IP1 height (150): no full re-plan.
    assert!(c.trace.iter().all(|s| s.tcp[2] < 150.0 + 1e-6));
}

#[test]
fn t24_append_profiles_and_buffer_full_90008() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| p.target_pos[0] = 50.0);
    let a = c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(100);
    c.set_par(|p| p.target_pos[0] = 100.0);
    let b = c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.step();
    assert!(c.last().outputs.profile_in_preparation);
    // A second edge during preparation: warning 90008, dropped.
    let d = c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(3);
    assert_eq!(c.last().outputs.error_id, 90008);
    assert!(c
        .events
        .iter()
        .any(|e| e.id == d && e.state == CommandState::Error(motion_core::ErrorId(90008))));
    c.until(3000, |s| s.state == TmState::Ready);
    assert_close("X", c.last().tcp[0], 100.0, 1e-9);
    for id in [a, b] {
        assert!(c
            .events
            .iter()
            .any(|e| e.id == id && e.state == CommandState::Done));
    }
    // The appended profile started at the previous target with a rest there.
    let at50 = c.trace.iter().filter(|s| s.tcp[0] == 50.0).count();
    assert!(at50 >= 1);
}

#[test]
fn command_not_allowed_warning_90010() {
    let mut c = moving();
    c.cmd(jog(1, true, false));
    c.step();
    // A jog level in MOVE_PP is ignored (no edge command warning for levels).
    assert_eq!(c.state(), TmState::MovePp);
    c.cmd(PickPlaceCommand::GroupHome);
    c.steps(2);
    assert_eq!(c.state(), TmState::MovePp);
    c.cmd(PickPlaceCommand::Abort);
    c.steps(2);
    assert_eq!(
        c.last().outputs.error_id,
        90010,
        "abort in MOVE_PP of mode 0"
    );
}

#[test]
fn stop_all_loses_the_path_and_replans_the_whole_profile() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 200.0;
        p.target_pos[2] = 50.0;
        p.z_start_dist = 50.0;
        p.z_target_dist = 30.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.tcp[0] > 100.0);
    c.cmd(stops(false, false, true));
    c.until(500, |s| !s.outputs.busy);
    assert_eq!(c.state(), TmState::Stop);
    c.cmd(stops(false, false, false));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    let z_hold = c.last().tcp[2];
    c.trace.clear();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    // "Run again from the beginning": IP1 = hold + 50 in Z is visited.
    let top = c.trace.iter().map(|s| s.tcp[2]).fold(f64::MIN, f64::max);
    assert_close("IP1 of the re-planned profile", top, z_hold + 50.0, 1e-6);
    assert_close("X", c.last().tcp[0], 200.0, 1e-9);
}

#[test]
fn axes_disabled_outputs() {
    let mut c = Cell::new(common_config());
    c.cmd(PickPlaceCommand::SetEnable(true));
    c.step();
    assert_eq!(c.state(), TmState::Ready);
    assert!(!c.last().outputs.axes_enabled);
    c.cmd(PickPlaceCommand::SetRegulatorOn(true));
    c.step();
    assert!(c.last().outputs.axes_enabled && c.last().outputs.axes_group_enabled);
    let r = c.eng.command(PickPlaceCommand::SetBeltParams {
        belt: 0,
        params: Default::default(),
    });
    assert!(r.is_err());
}

#[test]
fn ignored_home_edge_in_move_pp_answers_its_command() {
    let mut c = moving();
    let id = c.cmd(PickPlaceCommand::GroupHome);
    c.steps(2);
    assert_eq!(c.state(), TmState::MovePp);
    assert_eq!(c.last().outputs.error_id, 90010);
    assert!(c
        .events
        .iter()
        .any(|e| e.id == id && e.state == CommandState::Error(motion_core::ErrorId(90010))));
    let mut c = moving();
    c.cmd(jog(1, true, false));
    c.steps(2);
    assert_eq!(c.last().outputs.error_id, 90010, "jog edge in MOVE_PP");
    assert_eq!(c.state(), TmState::MovePp);
}

#[test]
fn zero_length_profile_completes_at_once() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| p.target_pos = [0.0, 0.0, 100.0, 180.0, 0.0, 0.0, 0.0]);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(10, |s| s.state == TmState::Ready && s.outputs.done);
    assert_eq!(c.last().tcp, [0.0, 0.0, 100.0, 180.0, 0.0, 0.0, 0.0]);
}

#[test]
fn queue_capacity_keeps_profile_in_preparation_true() {
    let mut cfg = common_config();
    cfg.profile_queue_capacity = 2;
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.target_pos[0] = 100.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(10);
    assert!(!c.last().outputs.profile_in_preparation);
    c.set_par(|p| p.target_pos[0] = 0.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(10);
    assert_eq!(c.last().queued_profiles, 1);
    assert!(
        c.last().outputs.profile_in_preparation,
        "running + 1 queued = capacity 2"
    );
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(2);
    assert_eq!(c.last().outputs.error_id, 90008);
    c.until(5000, |s| s.state == TmState::Ready);
    assert_close("back at X = 0", c.last().tcp[0], 0.0, 1e-9);
}

#[test]
fn jog_dynamics_are_latched_at_the_jog_start() {
    let mut c = Cell::ready(common_config());
    c.cmd(jog(1, true, false));
    c.steps(300);
    // A parameter change during the jog has no effect on the running jog (§5).
    c.set_par(|p| p.cartesian_jog.dec = 1.0);
    c.cmd(jog(1, false, false));
    c.until(1000, |s| s.state == TmState::Ready);
    // Stopped with dec 100 from 10 units/s: ≈ 0.1 s + jerk phase, not 10 s.
    assert!(
        c.trace.len() < 300 + 300,
        "stopped within {} cycles",
        c.trace.len() - 300
    );
}

#[test]
fn cancel_halts_then_aborts_the_running_profile() {
    let mut c = moving();
    assert!(c.eng.snapshot().active_profile.is_some());
    // The id of the running profile: the Execute of `moving()`.
    let exec = c
        .events
        .iter()
        .find(|e| e.state == CommandState::Active)
        .unwrap()
        .id;
    c.eng.cancel(exec).unwrap();
    c.step();
    assert_eq!(c.state(), TmState::Stop);
    c.until(1000, |s| s.state == TmState::Ready);
    assert!(!c.last().outputs.path_hold, "halted path discarded");
    assert!(c
        .events
        .iter()
        .any(|e| e.id == exec && e.state == CommandState::Aborted));
    assert_eq!(c.last().tcp_velocity[0], 0.0);
}

#[test]
fn cancel_of_a_queued_profile_drops_it() {
    let mut c = moving();
    c.set_par(|p| p.target_pos[0] = 0.0);
    let queued = c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(10);
    assert_eq!(c.last().queued_profiles, 1);
    c.eng.cancel(queued).unwrap();
    c.step();
    assert_eq!(c.last().queued_profiles, 0);
    assert!(c
        .events
        .iter()
        .any(|e| e.id == queued && e.state == CommandState::Aborted));
    c.until(5000, |s| s.state == TmState::Ready);
    assert_close("first target only", c.last().tcp[0], 300.0, 1e-9);
}
