//! §5.11 group area reservation conflicts beyond W17: the blocker is named (objectInfo and
//! message), reservations shrink when commands end, MoveC reserves its rotation area, the
//! environment boundary of parts, and independence of groups.

mod common;
use common::*;
use motion_core::{CommandState, Engine};
use planar_engine::*;

fn two_groups() -> Sim {
    let cfg = PlanarConfig {
        movers: vec![
            MoverConfig::new("A", 0.0, 0.0, 0.0),
            MoverConfig::new("B", 240.0, 0.0, 0.0),
            MoverConfig::new("C", -480.0, 480.0, 0.0),
        ],
        groups: vec![
            GroupConfig {
                name: "G".into(),
                oid: 0,
            },
            GroupConfig {
                name: "H".into(),
                oid: 0,
            },
        ],
        ..Default::default()
    };
    let mut s = Sim::new(cfg);
    for m in ["A", "B", "C"] {
        s.enable(m);
    }
    s.enable_group("G");
    s.enable_group("H");
    s
}

fn join(s: &mut Sim, m: &str, g: &str) {
    s.ok(PlanarCommand::MoverAddToGroup {
        mover: m.into(),
        group: g.into(),
    });
}

#[test]
fn reservation_blocks_until_the_command_ends() {
    let mut s = two_groups();
    join(&mut s, "A", "G");
    join(&mut s, "B", "G");
    let a = s.ok(mtp("A", 0.0, 300.0, 0.0));
    s.steps(10);
    // A reserves the corridor x ∈ [−77.5, 77.5], y ∈ [−77.5, 377.5]; B at (120, 0) would
    // cover x from 42.5.
    let e = s.err(mtp("B", 120.0, 0.0, 0.0));
    assert_eq!(e.error_id, errors::E_COLLISION);
    assert_eq!(
        s.eng.last_object_info(),
        PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id: s.mover("A").oid
        }
    );
    assert_eq!(s.wait_final(a, 5.0), CommandState::Done);
    // The reservation shrank to A's footprint at (0, 300): the same command is free now.
    let b = s.ok(mtp("B", 120.0, 0.0, 0.0));
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    // A Halt ends a command early: the reservation shrinks once A stands.
    let a = s.ok(mtp("A", 0.0, 1000.0, 0.0));
    s.steps(50);
    let h = s.ok(PlanarCommand::Halt {
        mover: "A".into(),
        constraint: DynamicConstraint::default(),
    });
    assert_eq!(s.wait_final(h, 2.0), CommandState::Done);
    assert_eq!(s.state(a), Some(CommandState::Aborted));
    let ya = s.mover("A").set_pos.y;
    assert!(ya > 300.0 && ya < 700.0, "halted at {ya}");
    // B goes around and then into the aborted corridor above A: accepted, since A now
    // reserves only its footprint.
    let b = s.ok(mtp("B", 300.0, ya + 300.0, 0.0));
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    let b = s.ok(mtp("B", 60.0, ya + 300.0, 0.0));
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    // Straight down onto A is refused, naming A.
    let e = s.err(mtp("B", 60.0, ya + 100.0, 0.0));
    assert_eq!(e.error_id, errors::E_COLLISION);
    assert!(e.message.contains("'A'"), "{e}");
}

#[test]
fn movec_reserves_the_rotation_square() {
    let mut s = Sim::with_movers(&[("A", 0.0, 0.0), ("B", 170.0, 0.0)]);
    s.enable("A");
    s.enable("B");
    s.enable_group("G");
    join(&mut s, "A", "G");
    join(&mut s, "B", "G");
    // Rotating A needs a square of side 155·√2 = 219 mm: B (footprint from 92.5) is inside.
    let e = s.err(move_c("A", 45.0));
    assert_eq!(e.error_id, errors::E_COLLISION);
    assert!(e.message.contains("'B'"), "{e}");
    let b = s.ok(mtp("B", 300.0, 0.0, 0.0));
    s.wait_final(b, 5.0);
    let c = s.ok(move_c("A", 45.0));
    assert_eq!(s.wait_final(c, 5.0), CommandState::Done);
}

#[test]
fn groups_are_independent() {
    let mut s = two_groups();
    join(&mut s, "A", "G");
    join(&mut s, "C", "H");
    // C (group H) does not see A's reservation in G; its path is physically free.
    let a = s.ok(mtp("A", 0.0, 200.0, 0.0));
    let c = s.ok(mtp("C", 400.0, 480.0, 0.0));
    assert_eq!(s.wait_final(a, 5.0), CommandState::Done);
    assert_eq!(s.wait_final(c, 5.0), CommandState::Done);
    let g = s.snap().group("G").unwrap().clone();
    assert_eq!(
        (g.member_count, g.movers.clone()),
        (1, vec!["A".to_string()])
    );
}

#[test]
fn environment_of_parts_bounds_group_members() {
    let mut cfg = two_parts();
    cfg.groups = vec![GroupConfig {
        name: "G".into(),
        oid: 0,
    }];
    let mut s = Sim::new(cfg);
    s.enable("M");
    s.enable_group("G");
    join(&mut s, "M", "G");
    // With the processing unit the parts model is the boundary: no CreateBoundary needed.
    s.ok(PlanarCommand::EnvironmentAddToGroup { group: "G".into() });
    // (400, 120): the footprint reaches x = 477.5 < 480 → inside both parts.
    let id = s.ok(mtp_ref("M", 400.0, 120.0, 0.0, CS));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    // (420, 120): the footprint reaches 497.5 → leaves the parts.
    let e = s.err(mtp_ref("M", 420.0, 120.0, 0.0, CS));
    assert_eq!(e.error_id, errors::E_COLLISION);
    assert_eq!(
        s.eng.last_object_info().object_type,
        PlanarObjectType::Environment
    );
    // Environment Clear is refused while it is a group member.
    assert_eq!(
        s.err(PlanarCommand::EnvironmentClear).error_id,
        errors::E_INVALID_STATE
    );
}

/// `Engine::cancel` applies Halt semantics to the cancelled command's mover.
#[test]
fn cancel_halts() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let id = s.ok(mtp("M", 1000.0, 0.0, 0.0));
    s.steps(100);
    s.eng.cancel(id).unwrap();
    s.step();
    assert_eq!(s.state(id), Some(CommandState::Aborted));
    s.run_until(2.0, |p| {
        p.mover("M").unwrap().set_velo == MoverVector::default()
    });
    assert!(s.mover("M").set_pos.x < 1000.0);
}

/// Halt during absolute ESG ends ESG: the mover brakes and returns to FreeMovement.
#[test]
fn halt_ends_absolute_esg() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    s.ok(PlanarCommand::StartExternalSetpointGeneration {
        mover: "M".into(),
        options: Default::default(),
    });
    let base = s.mover("M").set_pos;
    for (p, v, a) in jerk_stream(0.0, 10000.0, 2000.0, 0.001)
        .into_iter()
        .take(250)
    {
        let (sp, sv, sa) = sp_x(p, v, a, base);
        s.ok(PlanarCommand::SetExternalSetpoint {
            mover: "M".into(),
            set_position: sp,
            set_velocity: sv,
            set_acceleration: sa,
        });
        s.step();
    }
    let h = s.ok(PlanarCommand::Halt {
        mover: "M".into(),
        constraint: DynamicConstraint::default(),
    });
    assert_eq!(s.wait_final(h, 2.0), CommandState::Done);
    let m = s.mover("M");
    assert_eq!(m.command_mode, CommandMode::FreeMovement);
    assert_eq!(m.external_setpoint_mode, ExternalSetpointMode::None);
    assert_eq!(m.set_velo.x, 0.0);
}
