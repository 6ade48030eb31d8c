//! W16 — homing (§8, §4.10) and the MC_Home part of W15.
mod common;
use axis_engine::*;
use common::*;

fn home(position: f64, mode: HomingMode, options: HomingOptions, cam: bool) -> AxisCommand {
    AxisCommand::Home(Home {
        axis: AX.into(),
        position,
        use_default_position: false,
        homing_mode: mode,
        buffer_mode: BufferMode::Aborting,
        options,
        calibration_cam: cam,
    })
}

fn cam_rig(cam: [f64; 2]) -> Rig {
    Rig::powered_with(AxisConfig {
        home_cam: Some(cam),
        ..Default::default()
    })
}

/// Runs to Done, recording the sequence of HomingState values.
fn run(r: &mut Rig, id: motion_core::CmdId) -> Vec<u32> {
    let mut phases = vec![r.st().homing_state];
    r.until(200000, |r| {
        let p = r.st().homing_state;
        if *phases.last().unwrap() != p {
            phases.push(p);
        }
        assert!(!r.out(id).error, "{:?}", r.out(id));
        r.out(id).done
    });
    phases
}

#[test]
fn phases_plc_cam_and_hardware_sync() {
    let mut r = cam_rig([10.0, 20.0]);
    let id = r.id(home(
        0.0,
        HomingMode::DefaultHoming,
        HomingOptions::default(),
        false,
    ));
    assert_eq!(r.st().motion_state, MotionState::Homing);
    assert!(r.st().bit(snapshot::bits::HOMING_BUSY));
    let phases = run(&mut r, id);
    assert_eq!(phases, vec![1, 2, 3, 4, 6, 0], "PLCCAM: phase 5 skipped");
    assert!(r.st().homed);
    assert_eq!(r.st().motion_state, MotionState::Standstill);

    let mut r = cam_rig([10.0, 20.0]);
    let opts = HomingOptions {
        reference_mode: 2,
        ..Default::default()
    };
    let id = r.id(home(0.0, HomingMode::DefaultHoming, opts, false));
    assert_eq!(run(&mut r, id), vec![1, 2, 3, 4, 5, 6, 0]);
}

#[test]
fn cam_already_active_starts_at_phase_3() {
    let mut r = cam_rig([-5.0, 20.0]);
    let id = r.id(home(
        0.0,
        HomingMode::DefaultHoming,
        HomingOptions::default(),
        false,
    ));
    let phases = run(&mut r, id);
    assert_eq!(phases, vec![3, 4, 6, 0]);
}

#[test]
fn reference_edge_is_exact_and_the_axis_stops_one_braking_distance_later() {
    // Position 0, v_s 5, d 1000, j 1e4: braking distance 5·√(5/1e4) ≈ 0.112.
    let mut r = cam_rig([10.0, 20.0]);
    let opts = HomingOptions {
        sync_velocity: 5.0,
        ..Default::default()
    };
    let id = r.id(home(0.0, HomingMode::DefaultHoming, opts, false));
    run(&mut r, id);
    let st = r.st();
    // The falling edge at raw 20 has the coordinate 0 exactly.
    assert!(
        (st.act_pos - (st.raw_pos - 20.0)).abs() < 1e-9,
        "act {} raw {}",
        st.act_pos,
        st.raw_pos
    );
    let brake = 5.0 * (5.0f64 / 1e4).sqrt();
    assert!(
        st.act_pos >= brake - 1e-9 && st.act_pos <= brake + 5.0 * DT + 1e-9,
        "final ActPos {}",
        st.act_pos
    );
}

#[test]
fn without_physical_cam_the_client_drives_the_cam_input() {
    let mut r = Rig::powered();
    r.set_pos(0.3);
    let opts = HomingOptions {
        reference_mode: 2,
        ..Default::default()
    };
    let id = r.id(home(100.0, HomingMode::DefaultHoming, opts, true));
    assert_eq!(r.st().homing_state, 3);
    r.until(10000, |r| r.st().homing_state >= 4);
    r.steps(5);
    let edge_raw = r.st().raw_pos;
    r.cmd(AxisCommand::HomeCalibrationCam {
        id,
        calibration_cam: false,
    })
    .unwrap();
    run(&mut r, id);
    let st = r.st();
    // Reference = next sync pulse (integer raw position) after the falling edge.
    let pulse = st.raw_pos - (st.act_pos - 100.0);
    assert!((pulse - pulse.round()).abs() < 1e-9, "pulse at {pulse}");
    assert!(
        pulse > edge_raw && pulse <= edge_raw + 1.0 + 1e-9,
        "pulse {pulse}, edge {edge_raw}"
    );
}

#[test]
fn direct_force_and_reset_calibration() {
    let mut r = Rig::powered();
    r.set_pos(7.0);
    let id = r.id(home(
        123.4,
        HomingMode::Direct,
        HomingOptions::default(),
        false,
    ));
    assert_eq!(
        r.st().motion_state,
        MotionState::Standstill,
        "no motion, no Homing state"
    );
    r.step();
    assert!(r.out(id).done);
    assert!((r.st().act_pos - 123.4).abs() < 1e-12 && r.st().homed);
    assert_eq!(r.st().set_velo, 0.0);
    let id = r.id(home(
        0.0,
        HomingMode::ResetCalibration,
        HomingOptions::default(),
        false,
    ));
    r.step();
    assert!(r.out(id).done && !r.st().homed);
    assert!((r.st().act_pos - 123.4).abs() < 1e-12, "position unchanged");
    let id = r.id(home(
        0.0,
        HomingMode::ForceCalibration,
        HomingOptions::default(),
        false,
    ));
    r.step();
    assert!(r.out(id).done && r.st().homed);
    assert!((r.st().act_pos - 123.4).abs() < 1e-12);
    // Not allowed outside Standstill.
    r.id(vel(10.0));
    let e = r
        .cmd(home(
            0.0,
            HomingMode::Direct,
            HomingOptions::default(),
            false,
        ))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B01));
}

#[test]
fn stop_during_homing_aborts_and_keeps_homed_false() {
    let mut r = cam_rig([100.0, 120.0]);
    let id = r.id(home(
        0.0,
        HomingMode::DefaultHoming,
        HomingOptions::default(),
        false,
    ));
    r.steps(50);
    let e = r
        .cmd(home(
            0.0,
            HomingMode::DefaultHoming,
            HomingOptions::default(),
            false,
        ))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B01), "a second MC_Home while homing");
    let e = r.cmd(abs(0.0, 10.0)).unwrap_err();
    assert_eq!(e.error_id, err(0x4B01), "motion while homing");
    r.id(stop(0.0, 0.0));
    assert!(r.out(id).command_aborted);
    assert!(!r.st().homed);
    assert_eq!(r.st().motion_state, MotionState::Stopping);
}

#[test]
fn cam_not_found_within_the_search_limit() {
    let mut r = Rig::powered_with(AxisConfig {
        homing_search_limit: 5.0,
        ..Default::default()
    });
    let id = r.id(home(
        0.0,
        HomingMode::DefaultHoming,
        HomingOptions::default(),
        false,
    ));
    r.until(10000, |r| r.out(id).error);
    assert_eq!(r.out(id).error_id, err(0x4D05));
    r.until(1000, |r| r.st().set_velo == 0.0);
    assert_eq!(r.st().motion_state, MotionState::Standstill);
}

#[test]
fn homing_clears_the_set_position_offset() {
    let mut r = cam_rig([10.0, 20.0]);
    r.id(AxisCommand::SetPosition(SetPosition {
        axis: AX.into(),
        position: 100.0,
        mode: true,
        options: Default::default(),
    }));
    r.step();
    assert_eq!(r.st().set_position_offset, 100.0);
    let id = r.id(home(
        0.0,
        HomingMode::DefaultHoming,
        HomingOptions::default(),
        false,
    ));
    run(&mut r, id);
    assert_eq!(r.st().set_position_offset, 0.0);
}

#[test]
fn homing_bad_inputs() {
    let mut r = Rig::powered();
    let before = r.st();
    let e = r
        .cmd(home(
            f64::NAN,
            HomingMode::Direct,
            HomingOptions::default(),
            false,
        ))
        .unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::NOT_FINITE);
    let o = HomingOptions {
        search_direction: Direction::ShortestWay,
        ..Default::default()
    };
    assert_eq!(
        r.cmd(home(0.0, HomingMode::DefaultHoming, o, false))
            .unwrap_err()
            .error_id,
        err(0x4B04)
    );
    let o = HomingOptions {
        search_velocity: -1.0,
        ..Default::default()
    };
    assert_eq!(
        r.cmd(home(0.0, HomingMode::DefaultHoming, o, false))
            .unwrap_err()
            .error_id,
        err(0x4B06)
    );
    // Not an E_EncoderReferenceMode (0..7; the latch modes 3/4/6/7 are simulated).
    let o = HomingOptions {
        reference_mode: 8,
        ..Default::default()
    };
    assert_eq!(
        r.cmd(home(0.0, HomingMode::DefaultHoming, o, false))
            .unwrap_err()
            .error_id,
        err(0x4B04)
    );
    assert_eq!(r.st(), before);
}

#[test]
fn stopping_beyond_a_narrow_cam_is_an_error() {
    // Search at 30 u/s stops ≈ 1.64 u after the rising edge: beyond a 1 u wide cam, so the
    // cam is no longer active at standstill (phase 3 check) → Error 0x4D05.
    let mut r = cam_rig([1.0, 2.0]);
    let id = r.id(home(
        0.0,
        HomingMode::DefaultHoming,
        HomingOptions::default(),
        false,
    ));
    r.until(10000, |r| r.out(id).error);
    assert_eq!(r.out(id).error_id, err(0x4D05));
    assert!(!r.st().homed);
    assert_eq!(r.st().motion_state, MotionState::Standstill);
}
