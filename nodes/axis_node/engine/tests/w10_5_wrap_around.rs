//! collision_avoidance.md §10.5 "Wrap-around on a ring" (ring 3000, M1 at 2900, M2 at 2700).

mod ca_common;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::CommandState;

fn mv(
    r: &mut CaRig,
    axis: &str,
    p: f64,
    dir: CaDirection,
) -> Result<axis_engine::AxisReply, motion_core::Rejection> {
    r.ca(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: axis.into(),
        position: McLreal::Value(p),
        velocity: McLreal::Value(1000.0),
        direction: dir,
        ..Default::default()
    }))
}

#[test]
fn seam_crossing_blocking_and_resume() {
    let mut r = CaRig::new(&[("M1", 2900.0), ("M2", 2700.0)], ring(3000.0));
    // 1. M1 → 100 Positive: +200, absolute 3100.
    let a = mv(&mut r, "M1", 100.0, CaDirection::Positive).unwrap().id;
    r.until(3000, |r| r.cmd_state(a) == CommandState::Done);
    assert_eq!(r.pos("M1"), 3100.0);
    assert!((r.axis("M1").modulo_position - 100.0).abs() < 1e-9);
    // 2. M2 → 150 Positive: goal 3150, blocked at 3000 (gap 100 across the seam).
    let b = mv(&mut r, "M2", 150.0, CaDirection::Positive).unwrap().id;
    r.steps(2000);
    assert_eq!(r.cmd_state(b), CommandState::Active, "M2 Busy");
    assert!(
        (r.pos("M2") - 3000.0).abs() < 1e-3,
        "M2 rests at 3000: {}",
        r.pos("M2")
    );
    assert!(
        r.axis("M2")
            .modulo_position
            .min(3000.0 - r.axis("M2").modulo_position)
            < 1e-3
    );
    assert!((r.axis("M2").gap_actual - 100.0).abs() < 1e-3);
    // 3. M1 +500 relative: 3600; M2 continues to 3150.
    let c = r.mv_rel("M1", 500.0, 1000.0);
    r.until(3000, |r| {
        r.cmd_state(c) == CommandState::Done && r.cmd_state(b) == CommandState::Done
    });
    assert_eq!(r.pos("M1"), 3600.0);
    assert_eq!(r.pos("M2"), 3150.0);
    assert!((r.axis("M2").modulo_position - 150.0).abs() < 1e-9);
    // 4. M1 → 400 ShortestWay: −200, 3400.
    let d = mv(&mut r, "M1", 400.0, CaDirection::ShortestWay)
        .unwrap()
        .id;
    r.until(3000, |r| r.cmd_state(d) == CommandState::Done);
    assert_eq!(r.pos("M1"), 3400.0);
}

#[test]
fn open_rail_variant_rejects_modulo_direction() {
    let mut r = CaRig::new(&[("M1", 2900.0), ("M2", 2700.0)], open(3000.0));
    assert_eq!(
        mv(&mut r, "M1", 100.0, CaDirection::Positive)
            .unwrap_err()
            .error_id,
        MODULO_ON_OPEN_RAIL
    );
}
