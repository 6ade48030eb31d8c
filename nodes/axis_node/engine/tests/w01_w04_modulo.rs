//! W1–W4 — MC_MoveModulo (§8, §4.8.4, §4.8.5): every row of both manual tables, the special
//! cases and the reset effect.
mod common;
use axis_engine::*;
use common::*;
use Direction::{Negative as Neg, Positive as Pos, ShortestWay};

fn rig(tf: f64) -> Rig {
    Rig::powered_with(AxisConfig {
        modulo_tolerance_window: tf,
        ..Default::default()
    })
}

/// From set position `start` at standstill: returns (end absolute, moved at all).
fn run(r: &mut Rig, target: f64, dir: Direction) -> (f64, bool) {
    let start = r.st().set_pos;
    let id = r.id(modulo(target, dir));
    let mut moved = false;
    r.until(100000, |r| {
        moved |= r.st().set_velo != 0.0;
        r.out(id).done
    });
    let end = r.st().set_pos;
    assert!(moved || end == start);
    (end, moved)
}

fn row(tf: f64, dir: Direction, start: f64, target: f64, rel: f64, end_abs: f64, end_mod: f64) {
    let mut r = rig(tf);
    r.set_pos(start);
    let (end, moved) = run(&mut r, target, dir);
    let tag = format!("{dir:?} start {start} target {target} TF {tf}");
    assert!(
        (end - end_abs).abs() < 1e-6,
        "{tag}: end {end} vs {end_abs}"
    );
    assert!(
        (end - start - rel).abs() < 1e-6,
        "{tag}: rel {} vs {rel}",
        end - start
    );
    assert!(
        (r.st().modulo_set_pos - end_mod).abs() < 1e-6
            || (end_mod == 0.0 && (r.st().modulo_set_pos - 360.0).abs() < 1e-6),
        "{tag}: modulo {}",
        r.st().modulo_set_pos
    );
    assert_eq!(moved, rel != 0.0, "{tag}: no motion when rel = 0");
}

#[test]
fn w1_table_1() {
    row(0.0, Pos, 90.0, 0.0, 270.0, 360.0, 0.0);
    row(0.0, Pos, 90.0, 360.0, 630.0, 720.0, 0.0);
    row(0.0, Pos, 90.0, 720.0, 990.0, 1080.0, 0.0);
    row(0.0, Neg, 90.0, 0.0, -90.0, 0.0, 0.0);
    row(0.0, Neg, 90.0, 360.0, -450.0, -360.0, 0.0);
    row(0.0, Neg, 90.0, 720.0, -810.0, -720.0, 0.0);
    row(0.0, ShortestWay, 90.0, 0.0, -90.0, 0.0, 0.0);
}

#[test]
fn w2_table_2_positive() {
    let t = [
        (90.00, 90.0, 0.00, 90.0),
        (90.90, 90.0, -0.90, 90.0),
        (91.10, 90.0, 358.90, 450.0),
        (89.10, 90.0, 0.90, 90.0),
        (88.90, 90.0, 1.10, 90.0),
        (90.00, 450.0, 360.00, 450.0),
        (90.90, 450.0, 359.10, 450.0),
        (91.10, 450.0, 718.90, 810.0),
        (89.10, 450.0, 360.90, 450.0),
        (88.90, 450.0, 361.10, 450.0),
        (90.00, 810.0, 720.00, 810.0),
        (90.90, 810.0, 719.10, 810.0),
        (91.10, 810.0, 1078.90, 1170.0),
        (89.10, 810.0, 720.90, 810.0),
        (88.90, 810.0, 721.10, 810.0),
    ];
    for (s, tgt, rel, end) in t {
        row(1.0, Pos, s, tgt, rel, end, 90.0);
    }
}

#[test]
fn w2_table_2_negative() {
    let t = [
        (90.00, 90.0, 0.00, 90.0),
        (90.90, 90.0, -0.90, 90.0),
        (91.10, 90.0, -1.10, 90.0),
        (89.10, 90.0, 0.90, 90.0),
        (88.90, 90.0, -358.90, -270.0),
        (90.00, 450.0, -360.00, -270.0),
        (90.90, 450.0, -360.90, -270.0),
        (91.10, 450.0, -361.10, -270.0),
        (89.10, 450.0, -359.10, -270.0),
        (88.90, 450.0, -718.90, -630.0),
        (90.00, 810.0, -720.00, -630.0),
        (90.90, 810.0, -720.90, -630.0),
        (91.10, 810.0, -721.10, -630.0),
        (89.10, 810.0, -719.10, -630.0),
        (88.90, 810.0, -1078.90, -990.0),
    ];
    for (s, tgt, rel, end) in t {
        row(1.0, Neg, s, tgt, rel, end, 90.0);
    }
}

#[test]
fn w3_special_cases() {
    for dir in [Pos, Neg, ShortestWay] {
        row(0.0, dir, 90.0, 90.0, 0.0, 90.0, 90.0);
    }
    row(0.0, Pos, 90.0, 450.0, 360.0, 450.0, 90.0);
    row(0.0, Pos, 270.0, 0.0, 90.0, 360.0, 0.0);
    row(0.0, Pos, 270.0, 360.0, 450.0, 720.0, 0.0);
    row(0.0, ShortestWay, 90.0, 270.0, 180.0, 270.0, 270.0); // tie → positive
    let mut r = rig(0.0);
    r.set_pos(90.0);
    let before = r.st();
    let e = r.cmd(modulo(360.0, ShortestWay)).unwrap_err();
    assert_eq!(e.error_id, err(0x4B06), "{}", e.message);
    for dir in [Pos, Neg, ShortestWay] {
        let e = r.cmd(modulo(-10.0, dir)).unwrap_err();
        assert_eq!(e.error_id, err(0x4B06), "{}", e.message);
    }
    let e = r.cmd(modulo(10.0, Direction::Undefined)).unwrap_err();
    assert_eq!(e.error_id, err(0x4B04));
    let e = r.cmd(modulo(10.0, Direction::Current)).unwrap_err();
    assert_eq!(
        e.error_id,
        err(0x4B04),
        "MC_Current_Direction at standstill"
    );
    assert_eq!(r.st(), before);
}

/// Reset with a following error: SetPos := ActPos.
fn reset_at(r: &mut Rig, act: f64) {
    let off = act - r.st().set_pos;
    r.cmd(AxisCommand::Sim(Sim::SetFollowingOffset {
        axis: AX.into(),
        offset: off,
    }))
    .unwrap();
    r.step();
    let id = r.id(reset());
    r.step();
    assert!(r.out(id).done);
    assert!((r.st().set_pos - act).abs() < 1e-9);
}

#[test]
fn w4_reset_effect_without_window() {
    for (after_reset, rel, end) in [(449.8, 0.2, 450.0), (450.2, 359.8, 810.0)] {
        let mut r = rig(0.0);
        r.set_pos(90.0);
        assert_eq!(run(&mut r, 450.0, Pos).0, 450.0);
        reset_at(&mut r, after_reset);
        let (e, _) = run(&mut r, 90.0, Pos);
        assert!(
            (e - end).abs() < 1e-6 && (e - after_reset - rel).abs() < 1e-6,
            "{after_reset}: {e}"
        );
    }
}

#[test]
fn w4_reset_effect_with_window() {
    for after_reset in [449.8, 450.2] {
        let mut r = rig(1.0);
        r.set_pos(450.0);
        reset_at(&mut r, after_reset);
        let (e, _) = run(&mut r, 90.0, Pos);
        assert!((e - 450.0).abs() < 1e-6, "{after_reset} → 90: {e}");
        let mut r = rig(1.0);
        r.set_pos(450.0);
        reset_at(&mut r, after_reset);
        let (e, _) = run(&mut r, 450.0, Pos);
        assert!((e - 810.0).abs() < 1e-6, "{after_reset} → 450: {e}");
    }
}

#[test]
fn w4_rotary_table_application() {
    let mut r = rig(1.5);
    r.set_pos(90.0);
    for want in [450.0, 810.0, 1170.0] {
        assert!((run(&mut r, 450.0, Pos).0 - want).abs() < 1e-6);
    }
    // After an error: reset leaves the set position at e.g. 1171.2 → MoveModulo(90, Pos) → −1.2.
    r.cmd(inject(0x4550)).unwrap();
    reset_at(&mut r, 1171.2);
    let (e, _) = run(&mut r, 90.0, Pos);
    assert!((e - 1170.0).abs() < 1e-6, "{e}");
    // Already there: no motion.
    let (e2, moved) = run(&mut r, 90.0, Pos);
    assert!(!moved && e2 == e);
}

#[test]
fn moving_start_picks_the_first_matching_position_beyond_the_stopping_point() {
    let mut r = rig(0.0);
    r.id(vel(100.0));
    r.steps(500); // ≈ 1 s, around 95
    let p = r.st().set_pos;
    let id = r.id(modulo(90.0, Pos));
    r.until(100000, |r| r.out(id).done);
    let end = r.st().set_pos;
    assert!((end - 450.0).abs() < 1e-6, "from {p} moving: {end}");
    // Opposite direction while moving → Error 0x4B04 and the axis is stopped safely.
    let mut r = rig(0.0);
    let v = r.id(vel(100.0));
    r.steps(100);
    let m = r.id(modulo(90.0, Neg));
    assert!(r.out(v).command_aborted);
    r.step();
    assert_eq!(r.out(m).error_id, err(0x4B04));
    r.until(1000, |r| r.st().motion_state == MotionState::Standstill);
    assert_eq!(r.st().set_velo, 0.0);
}
