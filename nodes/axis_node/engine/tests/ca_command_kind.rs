//! `command_kind` of CaAxisState (collision_avoidance.md §9.5): what each axis is doing - the
//! block of its active command, group braking (MC_GroupHalt, MC_GroupStop, ErrorStop), standby
//! gap control, or nothing.

mod ca_common;
use axis_engine::ca::*;
use axis_engine::{AxisCommand, Sim};
use ca_common::*;
use motion_core::Engine;

fn kind(r: &CaRig, axis: &str) -> CaCommandKind {
    r.axis(axis).command_kind
}

#[test]
fn command_kind_follows_the_blocks_and_group_braking() {
    let mut r = CaRig::new(&[("L", 1000.0), ("F", 800.0)], open(10000.0));
    assert_eq!(kind(&r, "L"), CaCommandKind::None);
    r.mv_rel("L", 3000.0, 1000.0);
    r.mv_abs("F", 3000.0, 1000.0);
    r.steps(100);
    assert_eq!(kind(&r, "L"), CaCommandKind::MoveRelative);
    assert_eq!(kind(&r, "F"), CaCommandKind::MoveAbsolute);
    r.ok(CaCommand::Halt(HaltCa {
        axis: "L".into(),
        ..Default::default()
    }));
    r.step();
    assert_eq!(kind(&r, "L"), CaCommandKind::Halt);
    r.ok(CaCommand::GroupHalt {
        group: G.into(),
        deceleration: McLreal::Unset,
        jerk: McLreal::Unset,
    });
    r.step();
    assert_eq!(kind(&r, "F"), CaCommandKind::GroupHalt);
    r.until(5000, |r| r.group().all_axes_standing);
    r.step();
    assert_eq!(kind(&r, "F"), CaCommandKind::None, "idle after the halt");
    // MC_GroupStop.
    r.mv_abs("L", 5000.0, 1000.0);
    r.steps(100);
    r.ok(CaCommand::GroupStop {
        group: G.into(),
        execute: true,
        deceleration: McLreal::Unset,
        jerk: McLreal::Unset,
    });
    r.step();
    assert_eq!(kind(&r, "L"), CaCommandKind::GroupStop);
    r.until(5000, |r| r.group().all_axes_standing);
    r.ok(CaCommand::GroupStop {
        group: G.into(),
        execute: false,
        deceleration: McLreal::Unset,
        jerk: McLreal::Unset,
    });
    r.steps(2);
    // An axis error while moving: the others brake in ErrorStop.
    r.mv_abs("L", 9000.0, 1000.0);
    r.mv_abs("F", 8000.0, 1000.0);
    r.steps(200);
    r.e.command(AxisCommand::Sim(Sim::InjectAxisError {
        axis: "L".into(),
        error_id: 0x4550,
    }))
    .unwrap();
    r.step();
    assert_eq!(r.state(), GroupState::GroupErrorStop);
    assert_eq!(kind(&r, "F"), CaCommandKind::ErrorStop);
}

#[test]
fn command_kind_shows_standby_gap_control() {
    let cfg = CaGroupConfig {
        standby_gap_control: true,
        ..open(10000.0)
    };
    let mut r = CaRig::new(&[("L", 1000.0), ("F", 950.0)], cfg);
    r.step();
    assert_eq!(kind(&r, "F"), CaCommandKind::StandbyGapControl);
    assert_eq!(kind(&r, "L"), CaCommandKind::None);
    r.until(5000, |r| {
        r.group().all_axes_standing && r.state() == GroupState::GroupStandby
    });
    assert_eq!(kind(&r, "F"), CaCommandKind::None);
    assert!((r.pos("F") - 900.0).abs() < 1e-3);
}
