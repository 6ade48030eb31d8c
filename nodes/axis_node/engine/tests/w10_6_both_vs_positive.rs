//! collision_avoidance.md §10.6 "Direction Both vs Positive with reverse motion" (open rail
//! 5000, A at 1000 idle, B at 1300; B → 1050 with V 500, A = D = 5000, J = 50000).

mod ca_common;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::CommandState;

fn mv(r: &mut CaRig, axis: &str, p: f64) -> motion_core::CmdId {
    r.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: axis.into(),
        position: McLreal::Value(p),
        velocity: McLreal::Value(500.0),
        acceleration: McLreal::Value(5000.0),
        deceleration: McLreal::Value(5000.0),
        jerk: McLreal::Value(50000.0),
        ..Default::default()
    }))
}

fn rig(dir: GapControlDirection) -> CaRig {
    let cfg = CaGroupConfig {
        gap_control_direction: dir,
        ..open(5000.0)
    };
    CaRig::new(&[("A", 1000.0), ("B", 1300.0)], cfg)
}

#[test]
fn both_reverse_move_stops_at_the_gap_and_continues_when_a_leaves() {
    let mut r = rig(GapControlDirection::Both);
    let b = mv(&mut r, "B", 1050.0);
    for _ in 0..2000 {
        r.step();
        assert!(r.axis("A").gap_actual >= 100.0 - 1e-6);
    }
    assert!(
        (r.pos("B") - 1100.0).abs() < 1e-3,
        "B stops at 1100: {}",
        r.pos("B")
    );
    assert_eq!(r.cmd_state(b), CommandState::Active, "B Busy");
    let a = mv(&mut r, "A", 800.0);
    r.until(5000, |r| {
        r.cmd_state(a) == CommandState::Done && r.cmd_state(b) == CommandState::Done
    });
    assert_eq!(r.pos("A"), 800.0);
    assert_eq!(r.pos("B"), 1050.0);
}

#[test]
fn positive_reverse_move_is_not_limited_and_reports_the_violation() {
    let mut r = rig(GapControlDirection::Positive);
    let b = mv(&mut r, "B", 1050.0);
    r.until(3000, |r| r.cmd_state(b) == CommandState::Done);
    assert_eq!(r.pos("B"), 1050.0);
    let a = r.axis("A");
    assert!((a.gap_actual - 50.0).abs() < 1e-9, "gap_actual 50");
    assert!(a.gap_violation, "gap_violation TRUE");
    assert!(
        (a.min_gap_margin + 50.0).abs() < 1e-6,
        "min_gap_margin ≈ −50: {}",
        a.min_gap_margin
    );
}
