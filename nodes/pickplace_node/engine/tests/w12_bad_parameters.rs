//! pick_and_place.md §19 W12 — "bad parameters", and the write-time validation of §3.4.
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use motion_core::Engine;
use pickplace_engine::{ConveyorBeltPar, PickPlaceCommand, ScPar, TmState};

fn reject(c: &mut Cell, f: impl FnOnce(&mut ScPar)) -> (u32, String) {
    let before = c.eng.params().clone();
    let state = c.state();
    let mut p = before.clone();
    f(&mut p);
    let r = c
        .eng
        .command(PickPlaceCommand::SetParams(Box::new(p)))
        .expect_err("rejected");
    assert_eq!(c.eng.params(), &before, "value unchanged");
    c.step();
    assert_eq!(c.state(), state, "state unchanged");
    (r.error_id.0, r.message)
}

#[test]
fn w12a_negative_path_velocity_rejected_90001() {
    let mut c = Cell::ready(common_config());
    let (id, msg) = reject(&mut c, |p| p.path_vel = -5.0);
    assert_eq!(id, 90001);
    assert!(msg.contains("lrPathVel") && msg.contains("-5"), "{msg}");
}

#[test]
fn write_time_validation_table() {
    let mut c = Cell::ready(common_config());
    type Case = (&'static str, fn(&mut ScPar), u32, &'static str);
    let cases: &[Case] = &[
        (
            "NaN path acc",
            |p| p.path_acc = f64::NAN,
            90001,
            "lrPathAcc",
        ),
        ("zero jerk", |p| p.path_jerk = 0.0, 90001, "lrPathJerk"),
        (
            "inf halt dec",
            |p| p.path_halt_dec = f64::INFINITY,
            90001,
            "lrPathHaltDec",
        ),
        (
            "negative jog",
            |p| p.cartesian_jog.vel = -1.0,
            90001,
            "lrCartesianJogVel",
        ),
        ("stop dec", |p| p.stop_dec[4] = 0.0, 90001, "alrStopDec[5]"),
        ("max vel < 0", |p| p.max_vel[2] = -1.0, 90001, "lrZMaxVel"),
        (
            "radius < 0",
            |p| p.blending_radius = -1.0,
            90001,
            "lrBlendingRadius",
        ),
        (
            "z start < 0",
            |p| p.z_start_dist = -1.0,
            90001,
            "lrZStartDist",
        ),
        (
            "gripper NaN",
            |p| p.gripper_closing_time = f64::NAN,
            90001,
            "lrGripperClosingTime",
        ),
        ("path mode", |p| p.path_mode = 2, 90002, "ePathMode"),
        (
            "tracking mode",
            |p| p.tracking_mode = 5,
            90003,
            "eTrackingMode",
        ),
        (
            "coord system",
            |p| p.target_coord_system = 19,
            90001,
            "eTargetCoordSystem",
        ),
    ];
    for (name, f, id, field) in cases {
        let (got, msg) = reject(&mut c, *f);
        assert_eq!(got, *id, "{name}");
        assert!(msg.contains(field), "{name}: {msg}");
    }
}

#[test]
fn w12b_acs_target_is_a_planning_error_90004() {
    let mut c = Cell::ready(common_config());
    // As in the spec: ACS + ePathMode 1 (lrZDistElliptical left at its default 0).
    c.set_par(|p| {
        p.target_coord_system = 0;
        p.path_mode = 1;
        p.target_pos[0] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(10);
    assert_eq!(c.last().state, TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90004);
    assert!(c.last().outputs.error);
    assert!(c.trace.iter().all(|s| s.tcp == c.trace[0].tcp), "no motion");
    c.cmd(PickPlaceCommand::ResetError);
    c.steps(2);
    assert_eq!(c.last().state, TmState::Ready);
    assert!(!c.last().outputs.error);
}

#[test]
fn w12c_ellipse_without_height_is_90001() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.path_mode = 1;
        p.z_dist_elliptical = 0.0;
        p.target_pos[0] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(10);
    assert_eq!(c.last().state, TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90001);
}

#[test]
fn w12d_unconfigured_belt_is_90005() {
    let mut c = Cell::ready(common_config());
    c.cmd(PickPlaceCommand::Execute { set_target: 3 });
    c.steps(10);
    assert_eq!(c.last().state, TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90005);
    // eSetTarget outside 0 … 5 likewise.
    c.cmd(PickPlaceCommand::ResetError);
    c.steps(2);
    c.cmd(PickPlaceCommand::Execute { set_target: 200 });
    c.steps(10);
    assert_eq!(c.last().outputs.error_id, 90005);
}

#[test]
fn belt_parameters_and_commands_are_screened() {
    let mut c = Cell::ready(common_config());
    let bad = ConveyorBeltPar {
        z_dist_belt: -1.0,
        ..w8_belt()
    };
    let r = c
        .eng
        .command(PickPlaceCommand::SetBeltParams {
            belt: 1,
            params: bad,
        })
        .unwrap_err();
    assert_eq!(r.error_id.0, 90001);
    assert!(
        r.message.contains("ascConveyorBeltPar[1].lrZDistBelt"),
        "{}",
        r.message
    );
    let r = c
        .eng
        .command(PickPlaceCommand::SetBeltParams {
            belt: 17,
            params: w8_belt(),
        })
        .unwrap_err();
    assert_eq!(r.error_id, motion_core::ErrorId::UNKNOWN_OBJECT);
    let r = c
        .eng
        .command(PickPlaceCommand::SimSetBeltVelocity {
            belt: 1,
            velocity: f64::NAN,
            acceleration: 0.0,
        })
        .unwrap_err();
    assert_eq!(r.error_id, motion_core::ErrorId::NOT_FINITE);
    let r = c
        .eng
        .command(PickPlaceCommand::Jog {
            select_axis: 14,
            jog_pos: true,
            jog_neg: false,
        })
        .unwrap_err();
    assert_eq!(r.error_id, motion_core::ErrorId::ENUM_OUT_OF_RANGE);
    let r = c
        .eng
        .command(PickPlaceCommand::SetOverride(f64::NAN))
        .unwrap_err();
    assert_eq!(r.error_id, motion_core::ErrorId::NOT_FINITE);
    c.step();
    assert_eq!(c.last().state, TmState::Ready);
}
