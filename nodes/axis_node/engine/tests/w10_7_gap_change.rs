//! collision_avoidance.md §10.7 "Gap change and active gap establishing" (open rail 5000,
//! L at 2500 idle, F at 1000; F → 3000 with ContinuousUpdate, gap 100, waits at 2400).

mod ca_common;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::CommandState;

fn rig(establishing: bool) -> (CaRig, motion_core::CmdId) {
    let cfg = CaGroupConfig {
        active_gap_establishing: establishing,
        ..open(5000.0)
    };
    let mut r = CaRig::new(&[("L", 2500.0), ("F", 1000.0)], cfg);
    let f = r.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: "F".into(),
        continuous_update: true,
        position: McLreal::Value(3000.0),
        velocity: McLreal::Value(1000.0),
        gap: McLreal::Value(100.0),
        ..Default::default()
    }));
    r.steps(3000);
    assert!(
        (r.pos("F") - 2400.0).abs() < 1e-3,
        "F waits at 2400: {}",
        r.pos("F")
    );
    r.ok(CaCommand::UpdateGap {
        axis: "F".into(),
        gap: McLreal::Value(150.0),
    });
    (r, f)
}

#[test]
fn establishing_off_f_stays_then_follows_with_the_new_gap() {
    let (mut r, f) = rig(false);
    r.steps(1000);
    assert!(
        (r.pos("F") - 2400.0).abs() < 1e-3,
        "no motion: {}",
        r.pos("F")
    );
    assert_eq!(r.axis("F").gap_target, 150.0);
    let l = r.mv_rel("L", 300.0, 1000.0);
    r.until(3000, |r| r.cmd_state(l) == CommandState::Done);
    r.steps(2000);
    assert_eq!(r.pos("L"), 2800.0);
    assert!(
        (r.pos("F") - 2650.0).abs() < 1e-3,
        "F at 2650: {}",
        r.pos("F")
    );
    assert_eq!(r.cmd_state(f), CommandState::Active, "Busy");
}

#[test]
fn establishing_on_f_retreats_then_follows() {
    let (mut r, f) = rig(true);
    r.steps(1000);
    assert!(
        (r.pos("F") - 2350.0).abs() < 1e-3,
        "F retreats to 2350: {}",
        r.pos("F")
    );
    let l = r.mv_rel("L", 300.0, 1000.0);
    r.until(3000, |r| r.cmd_state(l) == CommandState::Done);
    r.steps(2000);
    assert!(
        (r.pos("F") - 2650.0).abs() < 1e-3,
        "F at 2650: {}",
        r.pos("F")
    );
    assert_eq!(r.cmd_state(f), CommandState::Active);
}

#[test]
fn update_gap_without_continuous_update_is_refused() {
    let mut r = CaRig::new(&[("L", 2500.0), ("F", 1000.0)], open(5000.0));
    let f = r.mv_abs("F", 3000.0, 1000.0);
    r.steps(3000);
    let e = r.err(CaCommand::UpdateGap {
        axis: "F".into(),
        gap: McLreal::Value(150.0),
    });
    assert_eq!(e, CONTINUOUS_UPDATE_NOT_ENABLED);
    assert_eq!(r.axis("F").gap_target, 100.0, "running command unaffected");
    assert_eq!(r.cmd_state(f), CommandState::Active);
}
