//! W6 – CRotationFreeMovement (manual 6.1.8): c 0, limits ±15°; MoveC(20) → CRotation during
//! and after; MoveC(90) → FreeMovement (90 ∈ [75, 105]).

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

#[test]
fn w06_crotation_free_movement() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let id = s.ok(move_c("M", 20.0));
    s.step();
    assert_eq!(
        s.mover("M").command_mode,
        CommandMode::CRotationFreeMovement,
        "during the rotation"
    );
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    s.step();
    let m = s.mover("M");
    assert!(close(m.set_pos.c, 20.0, ANG_TOL));
    assert_eq!(
        m.command_mode,
        CommandMode::CRotationFreeMovement,
        "20° outside every window"
    );
    // §5.7: no XY in CRotation.
    let e = s.err(mtp("M", 10.0, 0.0, 20.0));
    assert_eq!(e.error_id, errors::E_INVALID_COMMAND_MODE);
    let id = s.ok(move_c("M", 90.0));
    s.step();
    assert_eq!(
        s.mover("M").command_mode,
        CommandMode::CRotationFreeMovement
    );
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    s.step();
    let m = s.mover("M");
    assert!(close(m.set_pos.c, 90.0, ANG_TOL));
    assert_eq!(m.command_mode, CommandMode::FreeMovement);
    // XY accepted again.
    let id = s.ok(mtp("M", 10.0, 0.0, 90.0));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
}

/// §5.3: modulo C targets with direction and additional turns.
#[test]
fn w06_modulo_c() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let mc = |t: f64, direction: Direction, turns: u32| PlanarCommand::MoveC {
        mover: "M".into(),
        target_position: t,
        constraint: DynamicConstraint::default(),
        options: MoveCOptions {
            additional_turns: turns,
            direction,
        },
    };
    let id = s.ok(mc(90.0, Direction::Positive, 1));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    assert!(
        close(s.mover("M").set_pos.c, 450.0, ANG_TOL),
        "90 + one turn: {}",
        s.mover("M").set_pos.c
    );
    s.step();
    assert_eq!(
        s.mover("M").command_mode,
        CommandMode::FreeMovement,
        "450 lies in a window"
    );
    let id = s.ok(mc(0.0, Direction::ShortestWay, 0));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    assert!(close(s.mover("M").set_pos.c, 360.0, ANG_TOL));
    let id = s.ok(mc(350.0, Direction::Negative, 0));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    assert!(close(s.mover("M").set_pos.c, 350.0, ANG_TOL));
    // Turns with NonModulo/ShortestWay → E_INVALID_PARAMETER [manual].
    for d in [Direction::NonModulo, Direction::ShortestWay] {
        let e = s.err(mc(10.0, d, 1));
        assert_eq!(e.error_id, errors::E_INVALID_PARAMETER, "{e}");
    }
}

/// §2.4: MoveC entering a CRotation mode while XY moves → E_AXIS_BUSY; MoveC while an XY
/// command controls C → E_AXIS_BUSY; MoveC inside the window during XY motion is fine.
#[test]
fn w06_movec_vs_xy() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let xy = s.ok(PlanarCommand::MoveToPosition {
        mover: "M".into(),
        target_position: PositionXYC::new(300.0, 0.0, 0.0),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions {
            use_orientation: false,
        },
    });
    s.steps(5);
    assert_eq!(s.err(move_c("M", 40.0)).error_id, errors::E_AXIS_BUSY);
    let c = s.ok(move_c("M", 10.0));
    assert_eq!(s.wait_final(c, 5.0), CommandState::Done);
    assert_eq!(s.wait_final(xy, 5.0), CommandState::Done);
    let xy = s.ok(mtp("M", 0.0, 0.0, 0.0));
    s.steps(5);
    assert_eq!(
        s.err(move_c("M", 5.0)).error_id,
        errors::E_AXIS_BUSY,
        "C is carried by the XY command"
    );
    assert_eq!(s.wait_final(xy, 5.0), CommandState::Done);
    let m = s.mover("M");
    assert!(close(m.set_pos.c, 0.0, ANG_TOL));
}
