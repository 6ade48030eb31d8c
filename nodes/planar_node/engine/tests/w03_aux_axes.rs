//! W3 – Auxiliary axes (manual 6.1.5): MoveA(1), MoveB(−1), MoveC(3), MoveZ(5) in one cycle
//! run concurrently; final a 1, b −1, c 3, z 5; mode stays FreeMovement (3° inside ±15°).

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

fn aux(kind: usize, t: f64) -> PlanarCommand {
    let (mover, target_position, constraint) = ("M".to_string(), t, DynamicConstraint::default());
    match kind {
        0 => PlanarCommand::MoveZ {
            mover,
            target_position,
            constraint,
        },
        1 => PlanarCommand::MoveA {
            mover,
            target_position,
            constraint,
        },
        _ => PlanarCommand::MoveB {
            mover,
            target_position,
            constraint,
        },
    }
}

#[test]
fn w03_aux_axes_run_concurrently() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let a = s.ok(aux(1, 1.0));
    let b = s.ok(aux(2, -1.0));
    let c = s.ok(move_c("M", 3.0));
    let z = s.ok(aux(0, 5.0));
    s.step();
    let m = s.mover("M");
    assert!(
        m.busy.busy_a && m.busy.busy_b && m.busy.busy_c && m.busy.busy_z,
        "all four domains busy at once: {:?}",
        m.busy
    );
    assert_eq!(m.command_mode, CommandMode::FreeMovement);
    for id in [a, b, c, z] {
        assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    }
    let m = s.mover("M");
    assert!(close(m.set_pos.a, 1.0, ANG_TOL));
    assert!(close(m.set_pos.b, -1.0, ANG_TOL));
    assert!(close(m.set_pos.c, 3.0, ANG_TOL));
    assert!(close(m.set_pos.z, 5.0, POS_TOL));
    assert_eq!(
        m.command_mode,
        CommandMode::FreeMovement,
        "3° lies inside the ±15° window"
    );
    assert!(!m.busy.busy_mover);
}

/// §3.2 MoveZ/A/B: outside the configured range → E_INVALID_PARAMETER, nothing changes.
#[test]
fn w03_aux_range_checked() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    for (k, t) in [(0, 6.5), (0, -0.1), (1, 5.5), (2, -7.0)] {
        let e = s.err(aux(k, t));
        assert_eq!(e.error_id, errors::E_INVALID_PARAMETER, "{e}");
        assert!(
            e.message.contains(&format!("{t}")),
            "message names the value: {e}"
        );
    }
    s.step();
    assert!(!s.mover("M").busy.busy_mover);
}

/// §2.4: a new command of a domain aborts the active one of that domain only.
#[test]
fn w03_new_command_aborts_same_domain_only() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let z1 = s.ok(aux(0, 5.0));
    let a1 = s.ok(aux(1, 2.0));
    s.steps(20);
    let z2 = s.ok(aux(0, 1.0));
    s.step();
    assert_eq!(s.state(z1), Some(CommandState::Aborted));
    assert_eq!(s.state(a1), Some(CommandState::Active));
    assert_eq!(s.wait_final(z2, 10.0), CommandState::Done);
    assert_eq!(s.wait_final(a1, 10.0), CommandState::Done);
    assert!(close(s.mover("M").set_pos.z, 1.0, POS_TOL));
}
