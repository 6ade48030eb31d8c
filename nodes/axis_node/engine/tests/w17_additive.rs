//! W17 — MC_MoveAdditive vs MC_MoveRelative (§8, §4.8.2, §4.8.3).
mod common;
use axis_engine::*;
use common::*;

fn interrupted_at_40(c: AxisCommand) -> (f64, f64) {
    let mut r = Rig::powered();
    r.id(abs(100.0, 100.0));
    r.until(5000, |r| r.st().set_pos >= 40.0);
    let takeover = r.st().set_pos;
    let id = r.id(c);
    r.until(20000, |r| r.out(id).done);
    (takeover, r.st().set_pos)
}

#[test]
fn additive_adds_to_the_last_commanded_target() {
    let (_, end) = interrupted_at_40(add(50.0, 100.0));
    assert_eq!(end, 150.0);
}

#[test]
fn relative_adds_to_the_set_position_at_takeover() {
    let (takeover, end) = interrupted_at_40(rel(50.0, 100.0));
    assert!((end - (takeover + 50.0)).abs() < 1e-9);
    assert!((end - 90.0).abs() < 100.0 * DT, "≈ 90: {end}");
}

#[test]
fn additive_after_done() {
    let mut r = Rig::powered();
    let a = r.id(abs(100.0, 100.0));
    r.until(5000, |r| r.out(a).done);
    let b = r.id(add(20.0, 100.0));
    r.until(5000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 120.0);
}

#[test]
fn additive_during_move_velocity_uses_the_set_position() {
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.steps(200);
    let takeover = r.st().set_pos;
    let b = r.id(add(50.0, 100.0));
    r.until(5000, |r| r.out(b).done);
    assert!((r.st().set_pos - (takeover + 50.0)).abs() < 1e-9);
}
