//! Safety functions R-SAF-0 … R-SAF-6 (plcopen_platform.md §8) not covered by a worked
//! example, each with its trigger and error number, and the profile switch (monitors off in
//! `tc2_mc2` unless `safety_monitors: true`).
mod p4rig;
use axis_engine::group::*;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

#[test]
fn r_saf_2_hli_mismatch_makes_every_fb_fail_with_4904() {
    let mut r = P4::isg();
    assert_eq!(
        err(r.p(PlatformCommand::SessionStart {
            hli_version: HLI_VERSION,
            hli_size: HLI_SIZE + 4
        })),
        ErrorId(4904)
    );
    assert_eq!(err(r.cmd(rel(A0, 1.0, 10.0))), ErrorId(4904));
    assert_eq!(err(r.power(A0, false)), ErrorId(4904));
    assert_eq!(
        err(r.cmd(AxisCommand::ReadStatus(ReadStatus { axis: A0.into() }))),
        ErrorId(4904)
    );
    assert!(
        motion_core::Engine::snapshot(&r.e)
            .platform
            .version_mismatch
    );
    assert!(
        !motion_core::Engine::snapshot(&r.e)
            .platform
            .platform_base_done
    );
    assert_eq!(
        motion_core::Engine::snapshot(&r.e).platform.errors,
        vec![ErrorId(4904)]
    );
    // A congruent client: everything works again.
    r.p(PlatformCommand::SessionStart {
        hli_version: HLI_VERSION,
        hli_size: HLI_SIZE,
    })
    .unwrap();
    r.id(rel(A0, 1.0, 10.0));
    match r.p(PlatformCommand::ReadVersions).unwrap().value {
        ReplyValue::Platform(PlatformReply::Versions(v)) => {
            assert_eq!((v.hli_version, v.hli_size), (HLI_VERSION, HLI_SIZE))
        }
        v => panic!("{v:?}"),
    }
}

#[test]
fn r_saf_4_velocity_during_torque_limiting_70220() {
    let mut r = P4::isg_with(PlatformConfig {
        axes: [(
            A0.to_string(),
            AxisPlatformConfig {
                vb_torq_limit_max: 5000.0,
                ..Default::default()
            },
        )]
        .into(),
        ..PlatformConfig::default()
    });
    // Without torque limiting 10000 u/s is fine.
    let v = r.id(vel(A0, 10000.0));
    r.until(1000, |r| r.e.fb_outputs(v).unwrap().in_velocity);
    r.steps(10);
    assert_eq!(r.a0().error_code, 0);
    r.p(PlatformCommand::TorqueLimit {
        axis: A0.into(),
        active: true,
    })
    .unwrap();
    r.step();
    assert_eq!(r.a0().error_code, 70220);
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    assert!(!r.safety(A0).drive_enabled, "brake closed, enable removed");
}

#[test]
fn r_saf_4_leased_off_does_not_trip() {
    let mut r = P4::isg_with(PlatformConfig {
        axes: [(
            A0.to_string(),
            AxisPlatformConfig {
                vb_torq_limit_max: 5000.0,
                ..Default::default()
            },
        )]
        .into(),
        ..PlatformConfig::default()
    });
    r.p(PlatformCommand::TorqueLimit {
        axis: A0.into(),
        active: true,
    })
    .unwrap();
    r.p(PlatformCommand::SafetyDeactivate {
        axis: A0.into(),
        function: SafetyFunction::TorqueLimitMonitoring,
        lease_cycles: 1000,
    })
    .unwrap();
    let v = r.id(vel(A0, 10000.0));
    r.until(1000, |r| r.e.fb_outputs(v).unwrap().in_velocity);
    assert_eq!(r.a0().error_code, 0);
}

#[test]
fn r_saf_1_rotary_axis_uses_vb_monitor() {
    let mut r = P4::isg_with(PlatformConfig {
        axes: [(
            A0.to_string(),
            AxisPlatformConfig {
                kind: AxisKind::Rotary,
                vb_monitor: 3000.0,
                ..Default::default()
            },
        )]
        .into(),
        ..PlatformConfig::default()
    });
    assert_eq!(r.safety(A0).velocity_limit, 3000.0);
    assert_eq!(err(r.cmd(vel(A0, 3001.0))), ErrorId(1));
    assert_eq!(r.a0().error_code, 60241);
}

#[test]
fn r_saf_1_rotary_without_vb_monitor_uses_vb_not_referenced() {
    let r = P4::isg_with(PlatformConfig {
        axes: [(
            A0.to_string(),
            AxisPlatformConfig {
                kind: AxisKind::Rotary,
                vb_not_referenced: 1234.0,
                ..Default::default()
            },
        )]
        .into(),
        ..PlatformConfig::default()
    });
    assert_eq!(r.safety(A0).velocity_limit, 1234.0);
}

#[test]
fn r_saf_1_linear_limit_follows_units_per_mm() {
    let r = P4::isg_with(PlatformConfig {
        axes: [(
            A0.to_string(),
            AxisPlatformConfig {
                units_per_mm: 1.0,
                ..Default::default()
            },
        )]
        .into(),
        ..PlatformConfig::default()
    });
    assert_eq!(r.safety(A0).velocity_limit, 250.0, "250 mm/s in mm");
}

#[test]
fn r_saf_5_t2_needs_switch_and_start_but_no_clamp() {
    let mut r = P4::isg();
    r.p(PlatformCommand::OperatingMode {
        mode: OperatingMode::T2,
    })
    .unwrap();
    r.p(PlatformCommand::EnablingSwitch { pressed: true })
        .unwrap();
    r.power(A0, true).unwrap();
    r.steps(2);
    let id = r.id(rel(A0, 10000.0, 10000.0));
    r.steps(50);
    assert_eq!(r.a0().set_pos, 0.0, "no START: no motion");
    r.p(PlatformCommand::StartButton { pressed: true }).unwrap();
    r.steps(50);
    assert!(r.a0().set_pos > 0.0);
    // Releasing the enabling switch is a feed hold too (proposal).
    r.p(PlatformCommand::EnablingSwitch { pressed: false })
        .unwrap();
    r.until(5000, |r| r.a0().set_velo == 0.0);
    assert!(r.out(id).busy && !r.out(id).command_aborted);
}

#[test]
fn r_saf_3_stop_priority_over_an_earlier_order() {
    // = R-HS-4 (E4): MC_Stop in the same cycle after a move wins; the move never runs.
    let mut r = P4::isg();
    let m = r.id(rel(A0, 1000.0, 10000.0));
    let s = r.id(stop(A0, 0.0));
    assert!(r.out(m).command_aborted);
    r.steps(20);
    assert_eq!(r.a0().set_pos, 0.0);
    assert!(r.out(s).done);
}

#[test]
fn tc2_mc2_has_no_monitors_unless_configured() {
    let axes = || vec![(A0.to_string(), a0_cfg())];
    let mut r = P4::build(axes(), EngineConfig::default());
    r.power(A0, true).unwrap();
    r.step();
    let id = r.id(rel_full(A0, 100000.0, 300000.0, 1e7, 1e7, 1e9));
    r.until(2000, |r| r.out(id).done);
    assert_eq!(r.a0().error_code, 0, "no 60241/70225 in tc2_mc2");
    let mut r = P4::build(
        axes(),
        EngineConfig {
            platform: PlatformConfig {
                safety_monitors: true,
                ..PlatformConfig::default()
            },
            ..EngineConfig::default()
        },
    );
    r.power(A0, true).unwrap();
    r.step();
    assert_eq!(
        err(r.cmd(rel_full(A0, 100000.0, 300000.0, 1e7, 1e7, 1e9))),
        ErrorId(1)
    );
    assert_eq!(r.a0().error_code, 60241);
}

#[test]
fn isg_catalogue_refuses_unlisted_fbs_with_4905() {
    let mut r = P4::isg();
    let calls = [
        AxisCommand::ReadActualVelocity(ReadActualVelocity { axis: A0.into() }),
        AxisCommand::ReadBoolParameter(ReadBoolParameter {
            axis: A0.into(),
            parameter_number: 1,
        }),
        AxisCommand::MoveModulo(MoveModulo {
            axis: A0.into(),
            position: 1.0,
            velocity: 1.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            direction: Direction::Positive,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }),
        AxisCommand::Jog(Jog {
            axis: A0.into(),
            jog_forward: true,
            jog_backwards: false,
            mode: JogMode::StandardSlow,
            position: 0.0,
            velocity: 1.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
        }),
    ];
    for c in calls {
        let name = format!("{c:?}");
        assert_eq!(err(r.cmd(c)), ErrorId(4905), "{name}");
    }
    assert_eq!(r.a0().motion_state, MotionState::Standstill);
}

#[test]
fn isg_buffer_mode_is_ignored_new_commands_abort() {
    let mut r = P4::isg();
    let a = r.id(rel(A0, 100000.0, 10000.0));
    r.step();
    let b = r.id(AxisCommand::MoveRelative(MoveRelative {
        axis: A0.into(),
        distance: 10.0,
        velocity: 10000.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Buffered,
        options: MoveOptions::default(),
    }));
    assert!(r.out(a).command_aborted, "aborting, not buffered");
    assert!(r.out(b).active);
}

#[test]
fn r_err_1_fb_errors_change_nothing_else() {
    let mut r = P4::isg();
    let a = r.id(rel(A0, 100000.0, 10000.0));
    r.step();
    assert_eq!(
        err(r.cmd(rel(A0, 1.0, -1.0))),
        ErrorId(4902),
        "invalid parameter"
    );
    assert!(r.out(a).active, "the running instance notices nothing");
    assert_eq!(r.a0().motion_state, MotionState::DiscreteMotion);
}

#[test]
fn isg_groups_startup_and_member_refusal_ids() {
    let cfg = EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        groups: vec![GroupConfig {
            name: G.into(),
            axes: vec!["x".into(), "y".into()],
        }],
        ..EngineConfig::default()
    };
    let mut r = P4::build(
        vec![("x".into(), axis_cfg()), ("y".into(), axis_cfg())],
        cfg,
    );
    assert_eq!(err(r.g(lin_abs(vec![1.0, 1.0], 10.0))), ErrorId(4013));
    r.steps(10);
    r.power("x", true).unwrap();
    r.power("y", true).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::Standby);
    r.gid(lin_abs(vec![30.0, 40.0], 10.0));
    r.step();
    assert_eq!(err(r.cmd(rel("x", 1.0, 10.0))), ErrorId(4901));
}

#[test]
fn isg_group_channel_slot_one_order_per_cycle_group_stop_overwrites() {
    let cfg = EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        groups: vec![GroupConfig {
            name: G.into(),
            axes: vec!["x".into(), "y".into()],
        }],
        ..EngineConfig::default()
    };
    let mut r = P4::build(
        vec![("x".into(), axis_cfg()), ("y".into(), axis_cfg())],
        cfg,
    );
    r.steps(10);
    r.power("x", true).unwrap();
    r.power("y", true).unwrap();
    r.step();
    let n = r.g_order_id();
    let m = r.gid(lin_abs(vec![30.0, 40.0], 10.0));
    assert_eq!(r.order_id(m), n);
    assert_eq!(err(r.g(lin_abs(vec![0.0, 40.0], 10.0))), ErrorId(4));
    assert_eq!(r.g_order_id(), n + 1);
    r.g(GroupCommand::GroupReadStatus { group: G.into() })
        .unwrap();
    let s = r.gid(gstop());
    assert!(r.out(m).command_aborted, "MC_GroupStop overwrites");
    r.step();
    assert!(r.out(s).done);
    assert_eq!(r.gs().state, GroupState::Stopping);
}

#[test]
fn r_err_3_reset_keeps_error_stop_while_the_cause_remains() {
    let mut r = P4::isg();
    r.p(PlatformCommand::InjectActualVelocity {
        axis: A0.into(),
        velocity: 300000.0,
        duration_cycles: 20,
    })
    .unwrap();
    r.step();
    assert_eq!(r.a0().error_code, 70225);
    r.cmd(AxisCommand::Reset(Reset { axis: A0.into() }))
        .unwrap();
    r.step();
    assert_eq!(
        r.a0().motion_state,
        MotionState::ErrorStop,
        "velocity still too high"
    );
    r.steps(25);
    r.cmd(AxisCommand::Reset(Reset { axis: A0.into() }))
        .unwrap();
    r.steps(2);
    assert_ne!(
        r.a0().motion_state,
        MotionState::ErrorStop,
        "cause gone: reset works"
    );
}

#[test]
fn group_instance_done_latched_in_isg_one_cycle_in_tc2() {
    for (profile, latched) in [
        (PlatformProfile::IsgMcp, true),
        (PlatformProfile::Tc2Mc2, false),
    ] {
        let cfg = EngineConfig {
            platform_profile: profile,
            groups: vec![GroupConfig {
                name: G.into(),
                axes: vec!["x".into()],
            }],
            ..EngineConfig::default()
        };
        let mut r = P4::build(vec![("x".into(), axis_cfg())], cfg);
        r.steps(10);
        r.power("x", true).unwrap();
        r.step();
        let m = r.gid(lin_rel(vec![1.0], 100.0));
        r.set_execute(m, false);
        r.until(1000, |r| r.out(m).done);
        r.steps(3);
        assert_eq!(r.out(m).done, latched, "{profile:?}");
        r.set_execute(m, true);
        r.set_execute(m, false);
        assert!(!r.out(m).done, "{profile:?}: a falling edge clears");
    }
}

#[test]
fn r_saf_5_group_feed_hold_is_path_true_and_continues() {
    let cfg = EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        groups: vec![GroupConfig {
            name: G.into(),
            axes: vec!["x".into(), "y".into()],
        }],
        ..EngineConfig::default()
    };
    let mut r = P4::build(
        vec![("x".into(), axis_cfg()), ("y".into(), axis_cfg())],
        cfg,
    );
    r.steps(10);
    r.p(PlatformCommand::OperatingMode {
        mode: OperatingMode::T1,
    })
    .unwrap();
    r.power("x", true).unwrap();
    r.power("y", true).unwrap();
    r.step();
    assert_eq!(err(r.g(lin_abs(vec![300.0, 400.0], 100.0))), ErrorId(4901));
    r.p(PlatformCommand::EnablingSwitch { pressed: true })
        .unwrap();
    r.step();
    let m = r.gid(lin_abs(vec![300.0, 400.0], 100.0));
    r.steps(100);
    assert_eq!(r.ax("x").set_pos, 0.0, "no START: no motion");
    assert!(r.out(m).busy);
    r.p(PlatformCommand::StartButton { pressed: true }).unwrap();
    r.until(10000, |r| r.ax("x").set_pos > 100.0);
    r.p(PlatformCommand::StartButton { pressed: false })
        .unwrap();
    r.until(10000, |r| {
        let (x, y) = (r.ax("x").set_pos, r.ax("y").set_pos);
        assert!((x * 4.0 - y * 3.0).abs() < 1e-6, "path-true hold");
        r.gs().path_velocity == 0.0
    });
    assert!(r.out(m).busy && !r.out(m).command_aborted);
    r.p(PlatformCommand::StartButton { pressed: true }).unwrap();
    r.until(20000, |r| r.out(m).done);
    assert_eq!((r.ax("x").set_pos, r.ax("y").set_pos), (300.0, 400.0));
}

#[test]
fn r_saf_5_stop_is_never_blocked_by_the_enabling_switch() {
    let mut r = P4::isg();
    r.p(PlatformCommand::OperatingMode {
        mode: OperatingMode::T1,
    })
    .unwrap();
    r.p(PlatformCommand::EnablingSwitch { pressed: true })
        .unwrap();
    r.power(A0, true).unwrap();
    r.steps(2);
    r.p(PlatformCommand::EnablingSwitch { pressed: false })
        .unwrap();
    r.id(stop(A0, 0.0));
    assert_eq!(r.a0().motion_state, MotionState::Stopping);
}

#[test]
fn r_hs_3_max_retrials_retries_before_error_4() {
    use axis_engine::platform::raw;
    let mut r = P4::isg_with(PlatformConfig {
        max_retrials: 2,
        ..PlatformConfig::default()
    });
    let o = r.cycle(&[
        call("A", true, rel(A0, 1000.0, 10000.0)),
        call("B", true, rel(A0, 10.0, 10000.0)),
    ]);
    assert!(!o[1].error && o[1].busy, "B waits for the slot (FB_RETRY)");
    assert_eq!(o[1].order_id, 0);
    // Next cycle B is called first and takes the free slot.
    let o = r.cycle(&[call("B", true, rel(A0, 10.0, 10000.0))]);
    assert_eq!(o[0].fb_state, raw::FbState::Active);
    assert_eq!(o[0].order_id, 2);
}

#[test]
fn r_hs_3_without_retrials_error_4_at_once() {
    let mut r = P4::isg();
    let o = r.cycle(&[
        call("A", true, rel(A0, 1000.0, 10000.0)),
        call("B", true, rel(A0, 10.0, 10000.0)),
    ]);
    assert!(o[1].error && o[1].error_id == ErrorId(4));
}

#[test]
fn r_fb_4_retrigger_with_another_axis_is_4907() {
    let cfg = EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        ..EngineConfig::default()
    };
    let mut r = P4::build(vec![(A0.into(), a0_cfg()), ("a1".into(), a0_cfg())], cfg);
    r.steps(10);
    r.power(A0, true).unwrap();
    r.power("a1", true).unwrap();
    r.step();
    r.cycle(&[call("X", true, rel(A0, 100000.0, 10000.0))]);
    r.cycle(&[call("X", false, rel(A0, 100000.0, 10000.0))]);
    let o = r.cycle(&[call("X", true, rel("a1", 10.0, 10000.0))]);
    assert!(o[0].error && o[0].error_id == ErrorId(4907));
    assert_eq!(r.ax("a1").set_pos, 0.0, "no order sent");
}
