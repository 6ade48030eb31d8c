//! Smaller features: PCS targets (§7.1), xAckGripper (§3.1), negative gripper lead (§10),
//! xPosInWindow (§7.10), override 0 (§12), a stop during the synchronous dwell (§9.2), the
//! configuration validation (§2.1, §18) and the events stream (§18).
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use motion_core::ErrorId;
use pickplace_engine::{
    AxisConfig, CellEvent, GripperEvent, PickPlaceCommand, PickPlaceConfig, PickPlaceEngine,
    StopInputs, TmState,
};

fn receive(c: &mut Cell, x: f64) {
    c.cmd(PickPlaceCommand::BeltInput {
        belt: 1,
        receive: true,
        valid_pos: true,
        initial_object_position: [x, -50.0, 10.0, 0.0, 0.0, 30.0],
        aux1_target_pos: 0.0,
    });
}

#[test]
fn pcs_target_is_an_offset_in_the_workpiece_frame() {
    let mut c = belt_cell(100.0, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    // PCS1 (= 3): target 20 units along belt X and 5 above the workpiece.
    c.set_par(|p| {
        p.target_coord_system = 3;
        p.target_pos[0] = 20.0;
        p.target_pos[1] = 0.0;
        p.target_pos[2] = 5.0;
    });
    receive(&mut c, 250.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.step();
    let rx = c.trace.len() - 1;
    c.until(5000, |s| s.outputs.in_target);
    let hit = c.trace.len() - 1;
    let x_b = 250.0 + c.trace[hit].belts[0].position - c.trace[rx].belts[0].position + 20.0;
    assert_close("X", c.last().tcp[0], 400.0 - x_b, 0.05);
    assert_close("Z", c.last().tcp[2], 115.0, 0.05);
    // C = belt C + workpiece C, normalised near the start C (180 + 30 = 210).
    assert_close("C", c.last().tcp[5], 210.0, 1e-9);
}

#[test]
fn ack_gripper_ends_the_dwell_early() {
    let mut c = belt_cell(100.0, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    let mut bp = w8_belt();
    bp.sync_time_on_belt = 5.0;
    c.cmd(PickPlaceCommand::SetBeltParams {
        belt: 1,
        params: bp,
    });
    receive(&mut c, 220.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(5000, |s| s.outputs.in_target);
    c.steps(100);
    assert_eq!(c.last().state, TmState::MovePp, "dwelling");
    c.cmd(PickPlaceCommand::AckGripper);
    c.steps(2);
    assert_eq!(c.last().state, TmState::Ready);
    assert!(c.last().outputs.done);
    assert!(
        c.last().belts[0].workpieces.is_empty(),
        "workpiece consumed"
    );
}

#[test]
fn sync_time_zero_dwells_exactly_one_cycle() {
    let mut c = belt_cell(100.0, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    let mut bp = w8_belt();
    bp.sync_time_on_belt = 0.0;
    c.cmd(PickPlaceCommand::SetBeltParams {
        belt: 1,
        params: bp,
    });
    receive(&mut c, 220.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(5000, |s| s.outputs.in_target);
    let hit = c.trace.len() - 1;
    c.until(10, |s| s.outputs.done);
    assert_eq!(c.trace.len() - 1 - hit, 1);
}

#[test]
fn negative_gripper_lead_pulses_after_the_end() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 50.0;
        p.target_pos[2] = 100.0;
        p.gripper_closing_time = -0.05;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    let pulses: Vec<usize> = (0..c.trace.len())
        .filter(|&i| c.trace[i].outputs.pulse_gripper)
        .collect();
    assert_eq!(pulses.len(), 1);
    assert_eq!(pulses[0] - end, 50, "|t_g| = 0.05 s after the end");
}

#[test]
fn gripper_lead_longer_than_the_profile_pulses_in_the_first_cycle() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 50.0;
        p.target_pos[2] = 100.0;
        p.gripper_closing_time = 10.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    let pulses: Vec<usize> = (0..c.trace.len())
        .filter(|&i| c.trace[i].outputs.pulse_gripper)
        .collect();
    assert_eq!(pulses, vec![t0]);
    let ev = c.eng.drain_events();
    assert!(ev.iter().any(|e| matches!(
        e,
        CellEvent::GripperPulse {
            kind: GripperEvent::Close,
            ..
        }
    )));
}

#[test]
fn no_pulses_without_gripper_times() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| p.target_pos[0] = 50.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    assert!(c
        .trace
        .iter()
        .all(|s| !s.outputs.pulse_gripper && !s.outputs.gripper_ctrl_active));
}

#[test]
fn pos_in_window_requires_the_dwell_time() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 50.0;
        p.target_pos[2] = 100.0;
        p.pos_in_window = true;
        p.pos_in_window_size = 0.5;
        p.time_pos_in_window = 50.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.outputs.in_target);
    let end = c.trace.len() - 1;
    c.until(200, |s| s.outputs.in_position);
    let inpos = c.trace.len() - 1;
    // Inside the 0.5 window already before the end; 50 ms after entering it.
    let entered = c
        .trace
        .iter()
        .position(|s| (s.tcp[0] - 50.0).abs() <= 0.5)
        .unwrap();
    assert!(inpos > end);
    assert!(
        (inpos as i64 - (entered as i64 + 50)).abs() <= 1 || inpos == end + 1,
        "entered {entered}, in position {inpos}, end {end}"
    );
}

#[test]
fn override_zero_halts_the_path_and_continues() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 100.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(300);
    c.cmd(PickPlaceCommand::SetOverride(0.0));
    c.steps(300);
    assert_eq!(c.last().state, TmState::MovePp);
    assert_eq!(c.last().outputs.set_path_vel_out, 0.0);
    let x = c.last().tcp[0];
    c.steps(100);
    assert_eq!(c.last().tcp[0], x);
    c.cmd(PickPlaceCommand::SetOverride(1.0));
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    assert_close("X", c.last().tcp[0], 100.0, 1e-9);
}

#[test]
fn stop_during_the_dwell_resumes_to_the_same_workpiece() {
    let mut c = belt_cell(100.0, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    receive(&mut c, 220.0);
    c.steps(2);
    receive(&mut c, 150.0); // level still TRUE: no second workpiece
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(5000, |s| s.outputs.in_target);
    let id = c.last().active_profile.and_then(|p| p.workpiece);
    c.steps(50);
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_stop: Some(true),
        ..Default::default()
    }));
    c.until(500, |s| s.state == TmState::Stop && !s.outputs.busy);
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_stop: Some(false),
        ..Default::default()
    }));
    c.step();
    assert!(c.last().outputs.path_hold);
    let n_before = c.last().belts[0].workpieces.len();
    assert_eq!(
        n_before, 1,
        "the reached workpiece is consumed only after the dwell"
    );
    c.trace.clear();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| !s.outputs.in_target);
    c.until(5000, |s| s.outputs.in_target);
    let hits = belt_hits(&c);
    assert_eq!(hits.len(), 1);
    assert!(hits[0].2 <= 0.1, "{hits:?}");
    assert!(id.is_some());
    assert_eq!(
        c.last().active_profile.and_then(|p| p.workpiece),
        id,
        "the same workpiece"
    );
    c.until(1000, |s| s.state == TmState::Ready);
    assert!(c.last().belts[0].workpieces.is_empty());
}

#[test]
fn config_validation_names_key_and_value() {
    let cases: Vec<(PickPlaceConfig, ErrorId, &str)> = vec![
        (
            PickPlaceConfig {
                cycle_time_s: 0.01,
                ..Default::default()
            },
            ErrorId::VALUE_OUT_OF_RANGE,
            "cycle_time_s = 0.01",
        ),
        (
            PickPlaceConfig {
                path_prep_cycles: 26,
                ..Default::default()
            },
            ErrorId::VALUE_OUT_OF_RANGE,
            "path_prep_cycles = 26",
        ),
        (
            PickPlaceConfig {
                profile_queue_capacity: 0,
                ..Default::default()
            },
            ErrorId::VALUE_OUT_OF_RANGE,
            "profile_queue_capacity = 0",
        ),
        (
            PickPlaceConfig {
                cycle_time_s: f64::NAN,
                ..Default::default()
            },
            ErrorId::NOT_FINITE,
            "cycle_time_s",
        ),
        (
            PickPlaceConfig {
                grip_capture_distance: -1.0,
                ..Default::default()
            },
            ErrorId::VALUE_OUT_OF_RANGE,
            "grip_capture_distance = -1",
        ),
    ];
    for (cfg, id, text) in cases {
        let r = PickPlaceEngine::new(cfg).unwrap_err();
        assert_eq!(r.error_id, id, "{text}");
        assert!(r.message.contains(text), "{text}: {}", r.message);
    }
    let mut cfg = PickPlaceConfig::default();
    cfg.axes.insert("q7".into(), AxisConfig::default());
    let r = PickPlaceEngine::new(cfg).unwrap_err();
    assert_eq!(r.error_id, ErrorId::UNKNOWN_OBJECT);
    assert!(r.message.contains("axes.q7"));
    let mut cfg = PickPlaceConfig::default();
    cfg.axes.insert(
        "a3".into(),
        AxisConfig {
            max_vel: -1.0,
            ..Default::default()
        },
    );
    let r = PickPlaceEngine::new(cfg).unwrap_err();
    assert!(r.message.contains("axes.a3.max_vel = -1"), "{}", r.message);
    let mut cfg = PickPlaceConfig::default();
    cfg.belts.insert("17".into(), Default::default());
    let r = PickPlaceEngine::new(cfg).unwrap_err();
    assert!(r.message.contains("belts.17"), "{}", r.message);
    let mut cfg = PickPlaceConfig::default();
    cfg.belts.insert(
        "2".into(),
        pickplace_engine::BeltConfig {
            params: pickplace_engine::ConveyorBeltPar {
                sync_time_on_belt: -1.0,
                ..w8_belt()
            },
            ..Default::default()
        },
    );
    let r = PickPlaceEngine::new(cfg).unwrap_err();
    assert_eq!(r.error_id.0, 90001);
    assert!(
        r.message.contains("belts.2") && r.message.contains("lrSyncTimeOnBelt = -1"),
        "{}",
        r.message
    );
    let mut cfg = PickPlaceConfig::default();
    cfg.params.path_mode = 7;
    let r = PickPlaceEngine::new(cfg).unwrap_err();
    assert_eq!(r.error_id.0, 90002);
    // The spec's defaults are valid.
    assert!(PickPlaceEngine::new(PickPlaceConfig::default()).is_ok());
}

#[test]
fn events_report_states_workpieces_and_diagnostics() {
    let mut c = belt_cell(100.0, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    c.eng.drain_events();
    receive(&mut c, 220.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    let ev = c.eng.drain_events();
    let has = |f: &dyn Fn(&CellEvent) -> bool| ev.iter().any(f);
    assert!(has(&|e| matches!(
        e,
        CellEvent::StateChanged {
            to: TmState::MovePp,
            ..
        }
    )));
    assert!(has(&|e| matches!(
        e,
        CellEvent::Workpiece {
            kind: pickplace_engine::belt::WorkpieceEventKind::Received,
            ..
        }
    )));
    assert!(has(&|e| matches!(
        e,
        CellEvent::Workpiece {
            kind: pickplace_engine::belt::WorkpieceEventKind::Picked,
            ..
        }
    )));
    assert!(c.eng.drain_events().is_empty());
}

#[test]
fn wcs_target_is_converted_with_wcs_to_mcs() {
    let mut cfg = common_config();
    cfg.wcs_to_mcs = [100.0, 0.0, 0.0, 0.0, 0.0, 90.0];
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.target_coord_system = 2;
        p.target_pos[0] = 10.0;
        p.target_pos[1] = 0.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    // WCS (10, 0, 100) → MCS (100, 10, 100) (rotation 90° about Z, then translation).
    assert_close("X", c.last().tcp[0], 100.0, 1e-9);
    assert_close("Y", c.last().tcp[1], 10.0, 1e-9);
}

#[test]
fn degenerate_ellipse_falls_back_to_linear_with_warning() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.path_mode = 1;
        p.z_dist_elliptical = 30.0;
        p.target_pos[0] = 0.0;
        p.target_pos[2] = 150.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    assert_eq!(c.last().outputs.error_id, 90007);
    assert!(
        c.trace.iter().all(|s| s.tcp[2] <= 150.0 + 1e-9),
        "straight up, no ellipse"
    );
}

#[test]
fn execute_with_a_new_mode_ends_the_endless_loop_after_the_leg() {
    let mut c = two_belt_cell(100.0, 0.0);
    c.set_par(|p| {
        p.tracking_mode = 2;
        p.target_pos = [0.0, 0.0, 120.0, 180.0, 0.0, 180.0, 0.0];
    });
    c.cmd(PickPlaceCommand::DetectWorkpiece {
        belt: 1,
        position: [260.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        valid_delay_cycles: 0,
    });
    c.steps(2);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(100);
    // Switch to mode 0 with a static target while the pick leg runs.
    c.set_par(|p| {
        p.tracking_mode = 0;
        p.target_pos = [-100.0, 0.0, 250.0, 180.0, 0.0, 180.0, 0.0];
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(8000, |s| s.state == TmState::Ready && s.outputs.done);
    assert_eq!(belt_hits(&c).len(), 1, "the pick leg was finished");
    assert_close("X of the mode-0 target", c.last().tcp[0], -100.0, 1e-9);
    assert_close("Z of the mode-0 target", c.last().tcp[2], 250.0, 1e-9);
}

#[test]
fn internal_control_accepts_only_hmi_and_stop_all() {
    let mut c = Cell::ready(common_config());
    use motion_core::Engine;
    // Not enabled by xEnableInternalControl: refused.
    let r = c
        .eng
        .command(PickPlaceCommand::HmiSetInternalControl(true))
        .unwrap_err();
    assert_eq!(r.error_id.0, 90010);
    c.cmd(PickPlaceCommand::SetEnableInternalControl(true));
    c.cmd(PickPlaceCommand::HmiSetInternalControl(true));
    c.step();
    assert!(c.last().outputs.internal_control_active);
    let r = c
        .eng
        .command(PickPlaceCommand::Execute { set_target: 0 })
        .unwrap_err();
    assert_eq!(r.error_id.0, 90010);
    assert!(r.message.contains("internal control"));
    // The HMI drives the TM.
    c.set_par_hmi(|p| {
        p.target_pos[0] = 20.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Hmi(Box::new(PickPlaceCommand::Execute {
        set_target: 0,
    })));
    c.steps(100);
    assert_eq!(c.last().state, TmState::MovePp);
    // xStopALL is always effective.
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        stop_all: Some(true),
        ..Default::default()
    }));
    c.step();
    assert_eq!(c.last().state, TmState::Stop);
    c.cmd(PickPlaceCommand::SetEnableInternalControl(false));
    c.step();
    assert!(!c.last().outputs.internal_control_active);
}
