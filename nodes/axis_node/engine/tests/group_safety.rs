//! Safety functions on Part 4 group motions (plcopen_platform.md §8 with §3.2): R-SAF-1a
//! command check per member (60241, FB ErrorID 1, GROUP_ERROR_STOP), R-SAF-6 (absolute group
//! moves need referenced members → 4903; relative ones at the reduced speed), R-SAF-5 (T1
//! speed cap per member).
mod p4rig;
use axis_engine::group::*;
use axis_engine::platform::*;
use motion_core::ErrorId;
use p4rig::*;

fn rig(pc: PlatformConfig) -> P4 {
    P4::isg_xy(pc)
}

#[test]
fn member_programmed_velocity_above_250_mm_s_is_60241() {
    let mut r = rig(PlatformConfig::default());
    // Path 400 mm/s at 3:4 → x 240 mm/s (fine), y 320 mm/s (60241).
    assert_eq!(
        err(r.g(lin_abs(vec![30000.0, 40000.0], 400000.0))),
        ErrorId(1)
    );
    assert_eq!(r.ax("y").error_code, 60241);
    assert_eq!(r.ax("x").error_code, 0);
    r.step();
    assert_eq!(r.gs().state, GroupState::ErrorStop);
    assert_eq!(r.gs().error_id, ErrorId(1));
}

#[test]
fn member_below_the_limit_runs() {
    let mut r = rig(PlatformConfig::default());
    let m = r.gid(lin_abs(vec![300000.0, 400000.0], 300000.0));
    let mut vy: f64 = 0.0;
    r.until(5000, |r| {
        vy = vy.max(r.ax("y").set_velo.abs());
        r.out(m).done
    });
    assert!(
        vy <= 240000.0 + 1e-6 && vy > 239000.0,
        "y at 0.8 × 300 mm/s: {vy}"
    );
}

#[test]
fn non_referenced_member_absolute_4903_relative_reduced() {
    let mut r = rig(PlatformConfig {
        axes: [(
            "y".to_string(),
            AxisPlatformConfig {
                referenced: false,
                vb_not_referenced: 20000.0,
                ..Default::default()
            },
        )]
        .into(),
        ..PlatformConfig::default()
    });
    assert_eq!(
        err(r.g(lin_abs(vec![3000.0, 4000.0], 100000.0))),
        ErrorId(4903)
    );
    assert_eq!(r.gs().state, GroupState::Standby);
    let m = r.gid(lin_rel(vec![3000.0, 4000.0], 100000.0));
    let mut vy: f64 = 0.0;
    r.until(5000, |r| {
        vy = vy.max(r.ax("y").set_velo.abs());
        r.out(m).done
    });
    assert!(
        vy <= 20000.0 + 1e-6 && vy > 19000.0,
        "y at vb_not_referenced: {vy}"
    );
}

#[test]
fn t1_caps_every_member_at_250_mm_s() {
    let mut r = rig(PlatformConfig::default());
    r.p(PlatformCommand::OperatingMode {
        mode: OperatingMode::T1,
    })
    .unwrap();
    r.p(PlatformCommand::EnablingSwitch { pressed: true })
        .unwrap();
    r.p(PlatformCommand::StartButton { pressed: true }).unwrap();
    r.power("x", true).unwrap();
    r.power("y", true).unwrap();
    r.steps(2);
    // Along x only at 400 mm/s: clamped to 250 mm/s first, so no 60241.
    let m = r.gid(lin_rel(vec![200000.0, 0.0], 400000.0));
    let mut vx: f64 = 0.0;
    r.until(5000, |r| {
        vx = vx.max(r.ax("x").set_velo.abs());
        r.out(m).done
    });
    assert!((vx - 250000.0).abs() < 1e-6, "x capped: {vx}");
}
