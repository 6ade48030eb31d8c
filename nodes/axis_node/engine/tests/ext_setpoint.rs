//! §4.6 external setpoint generator: MC_ExtSetPointGenEnable / Disable / Feed /
//! FeedWithTorque, the state rule of §2.2 (ContinuousMotion while the fed velocity ≠ 0),
//! StateDWord bit 14, AxisAllowMotionCmdToExtSetAxis (1066), bad input.
mod common;
use axis_engine::*;
use common::*;

const EXT_GEN_BIT: u32 = 1 << 14;

fn enable(r: &mut Rig, position: f64, ty: PositionType, torque: bool) -> motion_core::CmdId {
    r.id(AxisCommand::ExtSetPointGenEnable(ExtSetPointGenEnable {
        axis: AX.into(),
        position,
        position_type: ty,
        options: ExtSetPointEnableOptions {
            use_torque_offset: torque,
        },
    }))
}

fn feed(position: f64, velocity: f64, direction: i32) -> AxisCommand {
    AxisCommand::ExtSetPointGenFeed(ExtSetPointGenFeed {
        axis: AX.into(),
        position,
        velocity,
        acceleration: 0.0,
        direction,
    })
}

fn disable() -> AxisCommand {
    AxisCommand::ExtSetPointGenDisable(ExtSetPointGenDisable { axis: AX.into() })
}

fn enabled_output(r: &mut Rig, id: motion_core::CmdId) -> bool {
    match r.cmd(AxisCommand::ReadFbOutputs { id }).unwrap().value {
        ReplyValue::Outputs(o) => match o.extra {
            Some(ExtraOutputs::ExtSetPointGen { enabled }) => enabled,
            x => panic!("{x:?}"),
        },
        v => panic!("{v:?}"),
    }
}

#[test]
fn fed_values_become_the_set_values() {
    let mut r = Rig::powered();
    let id = enable(&mut r, 10.0, PositionType::Absolute, false);
    assert!(r.out(id).busy);
    r.step();
    assert!(r.out(id).done);
    assert!(enabled_output(&mut r, id));
    assert!(r.st().bit(EXT_GEN_BIT));
    assert_eq!(r.st().motion_state, MotionState::Standstill);
    // A ramp fed cycle by cycle.
    let mut p = 0.0;
    for _ in 0..50 {
        p += 50.0 * DT;
        let reply = r.cmd(feed(p, 50.0, 1)).unwrap();
        assert_eq!(
            reply.value,
            ReplyValue::Bool(false),
            "FUNCTION returns FALSE"
        );
        assert!(!reply.tracked);
        r.step();
        let s = r.st();
        assert_eq!(s.set_pos, p);
        assert_eq!(s.set_velo, 50.0);
        assert_eq!(s.act_pos, p);
        assert_eq!(
            s.motion_state,
            MotionState::ContinuousMotion,
            "§2.2: fed velocity ≠ 0"
        );
    }
    r.cmd(feed(10.0, 0.0, 0)).unwrap();
    r.step();
    assert_eq!(r.st().motion_state, MotionState::Standstill);
    assert_eq!(r.st().set_pos, 10.0);
    // Target monitoring on Position (10): InTargetPosition after the monitoring time.
    r.steps(15);
    assert!(r.st().bit(snapshot::bits::IN_TARGET_POSITION));
    let e = r.ext_status();
    assert_eq!((e.ext_set_pos, e.ext_set_direction), (10.0, 0));
    // Disable keeps the last fed position.
    let d = r.id(disable());
    r.step();
    assert!(r.out(d).done);
    assert!(!enabled_output(&mut r, d));
    assert!(
        !enabled_output(&mut r, id),
        "Enabled is the generator's current state"
    );
    assert!(!r.st().bit(EXT_GEN_BIT));
    r.steps(5);
    assert_eq!(r.st().set_pos, 10.0);
}

#[test]
fn disable_while_fed_velocity_stops_with_axis_dec() {
    let mut r = Rig::powered();
    enable(&mut r, 0.0, PositionType::Relative, false);
    r.step();
    r.cmd(feed(1.0, 100.0, 1)).unwrap();
    r.step();
    r.id(disable());
    r.step();
    assert!(
        r.st().set_velo > 0.0 && r.st().set_velo < 100.0,
        "ramping down"
    );
    // 100 u/s at AxisDec 1000, AxisJerk 10000: about 0.2 s.
    let n = r.until(1000, |r| r.st().motion_state == MotionState::Standstill);
    assert!(n > 50, "{n}");
}

#[test]
fn motion_commands_need_parameter_1066() {
    let mut r = Rig::powered();
    enable(&mut r, 0.0, PositionType::Absolute, false);
    r.step();
    let before = r.st();
    let e = r.cmd(abs(100.0, 100.0)).unwrap_err();
    assert_eq!(e.error_id, err(0x4B01), "{}", e.message);
    assert_eq!(r.st(), before);
    // MC_Stop is always possible and disables the generator.
    let s = r.id(stop(0.0, 0.0));
    r.step();
    assert!(!r.ext_status().ext_set_point_gen_enabled);
    r.cmd(execute(s, false)).unwrap();
    r.steps(5);
    // With 1066 = TRUE the motion command takes over and disables the generator.
    let mut r = Rig::powered_with(AxisConfig {
        allow_motion_cmd_to_ext_set_axis: true,
        ..Default::default()
    });
    enable(&mut r, 0.0, PositionType::Absolute, false);
    r.step();
    let m = r.id(abs(100.0, 100.0));
    r.step();
    assert!(!r.ext_status().ext_set_point_gen_enabled);
    r.until(5000, |r| r.out(m).done);
    assert_eq!(r.st().set_pos, 100.0);
}

#[test]
fn torque_offset_only_with_use_torque_offset() {
    let fwt = |t: f64| {
        AxisCommand::ExtSetPointGenFeedWithTorque(ExtSetPointGenFeedWithTorque {
            axis: AX.into(),
            position: 0.0,
            velocity: 0.0,
            acceleration: 0.0,
            direction: 0,
            torque_offset: t,
        })
    };
    let mut r = Rig::powered();
    enable(&mut r, 0.0, PositionType::Absolute, false);
    r.cmd(fwt(12.5)).unwrap();
    assert_eq!(r.ext_status().ext_torque, 0.0);
    let mut r = Rig::powered();
    enable(&mut r, 0.0, PositionType::Absolute, true);
    r.cmd(fwt(12.5)).unwrap();
    assert_eq!(r.ext_status().ext_torque, 12.5);
}

#[test]
fn error_and_power_off_disable_the_generator() {
    let mut r = Rig::powered();
    enable(&mut r, 0.0, PositionType::Absolute, false);
    r.step();
    r.cmd(inject(0x4550)).unwrap();
    r.step();
    assert!(!r.ext_status().ext_set_point_gen_enabled);
    assert_eq!(r.st().motion_state, MotionState::ErrorStop);
}

#[test]
fn admission_and_bad_input() {
    let mut r = Rig::new();
    let c = AxisCommand::ExtSetPointGenEnable(ExtSetPointGenEnable {
        axis: AX.into(),
        position: 0.0,
        position_type: PositionType::Absolute,
        options: ExtSetPointEnableOptions::default(),
    });
    let before = r.st();
    assert_eq!(
        r.cmd(c.clone()).unwrap_err().error_id,
        err(0x4B01),
        "Disabled"
    );
    assert_eq!(r.st(), before);
    // Disable is allowed in every state (Done).
    let d = r.id(disable());
    r.step();
    assert!(r.out(d).done);
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.step();
    assert_eq!(
        r.cmd(c).unwrap_err().error_id,
        err(0x4B01),
        "ContinuousMotion"
    );
    let mut r = Rig::powered();
    let before = r.st();
    for bad in [f64::NAN, f64::INFINITY] {
        assert_eq!(r.cmd(feed(bad, 0.0, 0)).unwrap_err().error_id, err(0x7F02));
        assert_eq!(r.cmd(feed(0.0, bad, 0)).unwrap_err().error_id, err(0x7F02));
        let e = r
            .cmd(AxisCommand::ExtSetPointGenEnable(ExtSetPointGenEnable {
                axis: AX.into(),
                position: bad,
                position_type: PositionType::Absolute,
                options: ExtSetPointEnableOptions::default(),
            }))
            .unwrap_err();
        assert_eq!(e.error_id, err(0x7F02));
    }
    for d in [-2, 2, i32::MAX] {
        assert_eq!(r.cmd(feed(0.0, 0.0, d)).unwrap_err().error_id, err(0x7F03));
    }
    assert_eq!(PositionType::from_raw(0).unwrap_err().error_id, err(0x7F03));
    assert_eq!(PositionType::from_raw(3).unwrap_err().error_id, err(0x7F03));
    let e = r
        .cmd(AxisCommand::ExtSetPointGenDisable(ExtSetPointGenDisable {
            axis: "nope".into(),
        }))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x7F01));
    assert_eq!(r.st(), before);
}

trait ExtRig {
    fn ext_status(&self) -> ExtStatus;
}
impl ExtRig for Rig {
    fn ext_status(&self) -> ExtStatus {
        self.e.ext_status(AX).unwrap()
    }
}
