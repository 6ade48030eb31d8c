//! §2.2 transition table, row by row. Rows tested elsewhere: T8, T9, T10, T10b in
//! `w10_gearing.rs`, T12/T13 in `w16_homing.rs`, T16 in `move_continuous.rs`, T9b
//! (MC_GearInMultiMaster with AdvancedSlaveDynamics) in `gear_in_multi_master.rs`.
mod common;
use axis_engine::*;
use common::*;
use motion_core::{CommandState, Engine};
use MotionState::*;

/// Brings a powered axis into `state` (Standstill, DiscreteMotion, ContinuousMotion, Stopping).
fn rig_in(state: MotionState) -> Rig {
    let mut r = Rig::powered();
    match state {
        Standstill => {}
        DiscreteMotion => {
            r.id(abs(1000.0, 100.0));
            r.steps(5);
        }
        ContinuousMotion => {
            r.id(vel(100.0));
            r.steps(5);
        }
        Stopping => {
            r.id(vel(100.0));
            r.steps(50);
            r.id(stop(0.0, 0.0));
            r.step();
        }
        _ => unreachable!(),
    }
    assert_eq!(r.st().motion_state, state);
    r
}

#[test]
fn t1_axis_error_from_any_state_enters_errorstop_at_once() {
    for s in [Standstill, DiscreteMotion, ContinuousMotion, Stopping] {
        let mut r = rig_in(s);
        r.cmd(inject(0x4550)).unwrap();
        let st = r.st();
        assert_eq!(st.motion_state, ErrorStop, "from {s:?}");
        assert_eq!(st.error_code, 0x4550);
        assert!(st.bit(snapshot::bits::ERROR));
    }
    // From Disabled as well.
    let mut r = Rig::new();
    r.cmd(inject(0x4550)).unwrap();
    assert_eq!(r.st().motion_state, ErrorStop);
}

#[test]
fn t2_power_off_enters_disabled_from_every_non_error_state() {
    for s in [Standstill, DiscreteMotion, ContinuousMotion, Stopping] {
        let mut r = rig_in(s);
        r.power(false);
        let st = r.st();
        assert_eq!(st.motion_state, Disabled, "from {s:?}");
        assert_eq!(st.set_velo, 0.0, "a moving axis stops at once");
        assert!(!st.power_status);
    }
}

#[test]
fn t2_power_off_with_buffered_mode_waits_for_the_end_of_the_job() {
    let mut r = Rig::powered();
    let id = r.id(abs(10.0, 100.0));
    r.steps(3);
    r.power_full(false, true, true, 100.0, BufferMode::Buffered)
        .unwrap();
    assert_eq!(r.st().motion_state, DiscreteMotion, "still moving");
    r.until(2000, |r| r.st().motion_state == Disabled);
    assert_eq!(r.st().set_pos, 10.0, "the job ran to its end");
    assert_ne!(r.state_of(id), Some(CommandState::Error(err(0x4B01))));
}

#[test]
fn t2_not_from_errorstop() {
    let mut r = Rig::powered();
    r.cmd(inject(0x4550)).unwrap();
    r.power(false);
    assert_eq!(r.st().motion_state, ErrorStop);
}

#[test]
fn t3_enable_with_status_enters_standstill_in_the_next_cycle() {
    let mut r = Rig::new();
    assert_eq!(r.st().motion_state, Disabled);
    r.power(true);
    assert_eq!(
        r.st().motion_state,
        Disabled,
        "Status becomes TRUE in the next cycle"
    );
    r.step();
    assert_eq!(r.st().motion_state, Standstill);
    assert!(r.st().power_status);
}

#[test]
fn t3e_enable_with_drive_fault_enters_errorstop() {
    let mut r = Rig::new();
    r.cmd(AxisCommand::Sim(Sim::DriveFault {
        axis: AX.into(),
        error_id: 0x4650,
    }))
    .unwrap();
    r.power(true);
    r.step();
    let st = r.st();
    assert_eq!(st.motion_state, ErrorStop);
    assert!(!st.power_status, "the power stage is off");
    assert!(st.bit(snapshot::bits::DRIVE_DEVICE_ERROR));
}

#[test]
fn t4_reset_with_status_and_enable_enters_standstill() {
    let mut r = Rig::powered();
    r.cmd(inject(0x4550)).unwrap();
    r.step();
    let id = r.id(reset());
    r.step();
    assert!(r.out(id).done);
    assert_eq!(r.st().motion_state, Standstill);
    assert_eq!(r.st().error_code, 0);
}

#[test]
fn t5_reset_with_status_false_enters_disabled() {
    let mut r = Rig::powered();
    r.cmd(inject(0x4550)).unwrap();
    r.power(false);
    let id = r.id(reset());
    r.step();
    assert!(r.out(id).done);
    assert_eq!(r.st().motion_state, Disabled);
}

#[test]
fn t6_discrete_commands_enter_discretemotion() {
    for s in [Standstill, DiscreteMotion, ContinuousMotion] {
        for c in [
            abs(500.0, 100.0),
            rel(500.0, 100.0),
            add(500.0, 100.0),
            modulo(350.0, Direction::Positive),
        ] {
            let mut r = rig_in(s);
            r.id(c.clone());
            assert_eq!(r.st().motion_state, DiscreteMotion, "{c:?} from {s:?}");
        }
    }
    for s in [DiscreteMotion, ContinuousMotion] {
        let mut r = rig_in(s);
        r.id(halt(0.0, 0.0, BufferMode::Aborting));
        assert_eq!(r.st().motion_state, DiscreteMotion, "MC_Halt from {s:?}");
    }
}

#[test]
fn t7_move_velocity_enters_continuousmotion() {
    for s in [Standstill, DiscreteMotion, ContinuousMotion] {
        let mut r = rig_in(s);
        r.id(vel(50.0));
        assert_eq!(r.st().motion_state, ContinuousMotion, "from {s:?}");
        assert!(r.st().bit(snapshot::bits::CONTINUOUS_MOTION));
    }
}

#[test]
fn t11_discrete_motion_ends_in_standstill() {
    let mut r = Rig::powered();
    r.id(abs(5.0, 100.0));
    r.until(1000, |r| !r.st().has_job);
    assert_eq!(r.st().motion_state, Standstill);
    // MC_Halt from standstill: Dis-M → SS, Done after one cycle.
    let h = r.id(halt(0.0, 0.0, BufferMode::Aborting));
    r.step();
    assert!(r.out(h).done);
    assert_eq!(r.st().motion_state, Standstill);
}

#[test]
fn t14_stop_enters_stopping() {
    for s in [Standstill, DiscreteMotion, ContinuousMotion, Stopping] {
        let mut r = rig_in(s);
        r.id(stop(0.0, 0.0));
        assert_eq!(r.st().motion_state, Stopping, "from {s:?}");
        assert!(r.st().bit(snapshot::bits::MOTION_COMMANDS_LOCKED));
    }
}

#[test]
fn t15_stopping_to_standstill_after_done_and_execute_false_and_unlock_delay() {
    let mut r = rig_in(ContinuousMotion);
    let id = r.id(stop(0.0, 0.0));
    r.until(2000, |r| r.out(id).done);
    let o = r.out(id);
    assert!(
        o.done && o.busy && o.active,
        "MC_Stop: Done with Busy/Active while locked: {o:?}"
    );
    r.steps(20);
    assert_eq!(
        r.st().motion_state,
        Stopping,
        "stays locked while Execute is TRUE (N6)"
    );
    r.cmd(execute(id, false)).unwrap();
    r.step();
    r.step();
    assert_eq!(r.st().motion_state, Stopping, "unlocking takes 2 cycles");
    assert!(r.out(id).busy);
    r.step();
    assert_eq!(r.st().motion_state, Standstill);
    assert_eq!(
        r.out(id),
        Default::default(),
        "Busy/Active FALSE, Done reset"
    );
}

#[test]
fn t15b_reset_releases_the_stop_lock() {
    let mut r = rig_in(Stopping);
    let id = r.id(reset());
    // The axis was still braking: Standstill once at rest.
    r.until(3000, |r| r.out(id).done);
    assert_eq!(r.st().motion_state, Standstill);
    assert!(!r.st().bit(snapshot::bits::MOTION_COMMANDS_LOCKED));
}

#[test]
fn t17_reset_while_moving_stops_fast_then_standstill() {
    let mut r = rig_in(ContinuousMotion);
    r.steps(200);
    let mv = r.log.last().map(|(_, e)| e.id);
    let id = r.id(reset());
    assert_eq!(r.st().motion_state, DiscreteMotion, "fast stop in progress");
    let n = r.until(3000, |r| r.out(id).done);
    assert_eq!(r.st().motion_state, Standstill);
    // v = 100 with AxisFastDec 5000 / AxisFastJerk 1e5: 100/5000 + 5000/1e5 = 0.07 s at most.
    assert!(
        n as f64 * DT <= 0.07 + 2.0 * DT,
        "stop took {} s",
        n as f64 * DT
    );
    let _ = mv;
    let snap = r.e.snapshot();
    assert_eq!(snap.axes[0].motion_state, Standstill);
}

#[test]
fn t12_t13_homing_enters_and_leaves_homing() {
    let mut r = Rig::powered_with(AxisConfig {
        home_cam: Some([1.0, 10.0]),
        ..Default::default()
    });
    let id = r.id(AxisCommand::Home(Home {
        axis: AX.into(),
        position: 0.0,
        use_default_position: true,
        homing_mode: HomingMode::DefaultHoming,
        buffer_mode: BufferMode::Aborting,
        options: HomingOptions::default(),
        calibration_cam: false,
    }));
    assert_eq!(r.st().motion_state, Homing, "T12");
    r.until(100000, |r| r.out(id).done);
    assert_eq!(r.st().motion_state, Standstill, "T13");
}
