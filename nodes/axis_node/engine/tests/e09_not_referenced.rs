//! E9 — non-referenced axis (plcopen_platform.md §13, R-SAF-6): vb_not_referenced = 20000 u/s.
//! MC_MoveAbsolute → 4903, axis unchanged; MC_MoveVelocity(100000) runs at 20000 (InVelocity
//! at 20000); MC_MoveRelative(40000, v 100000) runs at 20000; MC_Home Done → referenced.
mod p4rig;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

fn unreferenced() -> P4 {
    P4::isg_with(PlatformConfig {
        axes: [(
            A0.to_string(),
            AxisPlatformConfig {
                referenced: false,
                vb_not_referenced: 20000.0,
                ..Default::default()
            },
        )]
        .into(),
        ..PlatformConfig::default()
    })
}

#[test]
fn e9_absolute_refused_relative_and_velocity_reduced() {
    let mut r = unreferenced();
    assert!(!r.safety(A0).referenced);
    assert_eq!(err(r.cmd(abs(A0, 1000.0, 10000.0))), ErrorId(4903));
    assert_eq!(r.a0().motion_state, MotionState::Standstill);
    let v = r.id(vel(A0, 100000.0));
    r.until(1000, |r| r.e.fb_outputs(v).unwrap().in_velocity);
    assert!(
        (r.a0().set_velo - 20000.0).abs() < 1e-6,
        "{}",
        r.a0().set_velo
    );
    r.step();
    let m = r.id(rel(A0, 40000.0, 100000.0));
    let mut vmax: f64 = 0.0;
    r.until(10000, |r| {
        vmax = vmax.max(r.a0().set_velo.abs());
        r.out(m).done
    });
    assert!(vmax <= 20000.0 + 1e-6, "reduced speed: {vmax}");
}

#[test]
fn e9_home_marks_referenced() {
    let mut r = unreferenced();
    let h = r.id(AxisCommand::Home(Home {
        axis: A0.into(),
        position: 0.0,
        use_default_position: false,
        homing_mode: HomingMode::Direct,
        buffer_mode: BufferMode::Aborting,
        options: HomingOptions::default(),
        calibration_cam: false,
    }));
    r.until(10, |r| r.out(h).done);
    r.step();
    assert!(r.safety(A0).referenced);
    r.id(abs(A0, 1000.0, 10000.0));
}

#[test]
fn e9_set_referenced_hook() {
    let mut r = P4::isg();
    r.p(PlatformCommand::SetReferenced {
        axis: A0.into(),
        referenced: false,
    })
    .unwrap();
    assert_eq!(err(r.cmd(abs(A0, 1000.0, 10000.0))), ErrorId(4903));
}

#[test]
fn e9_software_limits_not_monitored_until_referenced() {
    let cfg = axis_engine::platform::EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        platform: PlatformConfig {
            axes: [(
                A0.to_string(),
                AxisPlatformConfig {
                    referenced: false,
                    ..Default::default()
                },
            )]
            .into(),
            ..PlatformConfig::default()
        },
        ..Default::default()
    };
    let lim = AxisConfig {
        en_max_soft_pos_limit: true,
        max_soft_pos_limit: 10000.0,
        ..a0_cfg()
    };
    let mut r = P4::build(vec![(A0.into(), lim)], cfg);
    r.steps(10);
    r.power(A0, true).unwrap();
    r.step();
    let m = r.id(rel(A0, 40000.0, 20000.0));
    r.until(10000, |r| r.out(m).done);
    assert_eq!(r.a0().set_pos, 40000.0, "beyond the (unmonitored) limit");
    let h = r.id(AxisCommand::Home(Home {
        axis: A0.into(),
        position: 0.0,
        use_default_position: false,
        homing_mode: HomingMode::Direct,
        buffer_mode: BufferMode::Aborting,
        options: HomingOptions::default(),
        calibration_cam: false,
    }));
    r.until(10, |r| r.out(h).done);
    r.step();
    assert!(r.safety(A0).referenced);
    assert_eq!(
        err(r.cmd(abs(A0, 50000.0, 10000.0))),
        ErrorId(0x4D01),
        "limits back"
    );
}
