//! §2.1 planar state machine, row by row (T1–T14) for movers and groups, with the
//! command-outcome proposals of the same section.

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;
use PlanarState::*;

fn en(s: &mut Sim) -> motion_core::CmdId {
    s.ok(PlanarCommand::MoverEnable { mover: "M".into() })
}
fn dis(s: &mut Sim) -> motion_core::CmdId {
    s.ok(PlanarCommand::MoverDisable { mover: "M".into() })
}
fn inject(s: &mut Sim, reaction: ErrorReaction) {
    s.ok(PlanarCommand::InjectError {
        kind: ObjectKind::Mover,
        name: "M".into(),
        reaction,
    });
}

#[test]
fn t1_t2_enable_takes_enable_time() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    let id = en(&mut s);
    s.step();
    assert_eq!(s.mover("M").state, Enabling, "T1");
    s.steps(98);
    assert_eq!(s.mover("M").state, Enabling);
    s.steps(2);
    assert_eq!(s.mover("M").state, Enabled, "T2 after 0.1 s");
    assert_eq!(s.state(id), Some(CommandState::Done));
}

#[test]
fn t3_disable_aborts_enabling() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    let e = en(&mut s);
    s.steps(10);
    let d = dis(&mut s);
    s.step();
    assert_eq!(s.state(e), Some(CommandState::Aborted));
    assert_eq!(s.mover("M").state, Disabling, "T3");
    assert_eq!(s.wait_final(d, 1.0), CommandState::Done);
    assert_eq!(s.mover("M").state, Disabled, "T5");
}

#[test]
fn t4_t5_disable_stops_first() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let mv = s.ok(mtp("M", 1000.0, 0.0, 0.0));
    s.steps(300);
    let d = dis(&mut s);
    s.step();
    assert_eq!(
        s.state(mv),
        Some(CommandState::Aborted),
        "running commands aborted"
    );
    assert_eq!(s.mover("M").state, Disabling, "T4");
    assert_eq!(s.mover("M").command_mode, CommandMode::Invalid);
    assert_eq!(s.wait_final(d, 2.0), CommandState::Done);
    let m = s.mover("M");
    assert_eq!(m.state, Disabled, "T5");
    assert_eq!(
        m.set_velo,
        MoverVector::default(),
        "stopped with default deceleration before power-off"
    );
    assert!(m.set_pos.x > 300.0 && m.set_pos.x < 1000.0);
}

#[test]
fn t6_enable_aborts_disabling() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let d = dis(&mut s);
    s.steps(10);
    let e = en(&mut s);
    s.step();
    assert_eq!(s.state(d), Some(CommandState::Aborted), "T6");
    assert_eq!(s.wait_final(e, 1.0), CommandState::Done);
    assert_eq!(s.mover("M").state, Enabled);
}

#[test]
fn t7_t8_t10_quickstop_error_and_reset_to_enabled() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let mv = s.ok(mtp("M", 1000.0, 0.0, 0.0));
    s.steps(300);
    inject(&mut s, ErrorReaction::QuickStop);
    s.step();
    assert_eq!(
        s.state(mv),
        Some(CommandState::Error(errors::E_OBJECT_ERROR)),
        "running commands end with the error"
    );
    assert_eq!(s.mover("M").state, ErrorPending, "T7");
    s.run_until(1.0, |p| p.mover("M").unwrap().state == Error);
    let m = s.mover("M");
    assert_eq!(
        m.set_velo,
        MoverVector::default(),
        "QuickStop brought the mover to rest (T8)"
    );
    assert_eq!(
        (m.error_id, m.error_reaction),
        (errors::E_OBJECT_ERROR, ErrorReaction::QuickStop)
    );
    // Commands in Error are refused; Enable too.
    assert_eq!(
        s.err(mtp("M", 0.0, 0.0, 0.0)).error_id,
        errors::E_INVALID_STATE
    );
    assert_eq!(
        s.err(PlanarCommand::MoverEnable { mover: "M".into() })
            .error_id,
        errors::E_INVALID_STATE
    );
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    s.step();
    assert_eq!(s.mover("M").state, Resetting, "T9");
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    let m = s.mover("M");
    assert_eq!(
        (m.state, m.command_mode, m.error_id),
        (
            Enabled,
            CommandMode::FreeMovement,
            motion_core::ErrorId::NONE
        ),
        "T10"
    );
}

#[test]
fn t11_abort_reset_ends_disabled() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let z = s.ok(PlanarCommand::MoveZ {
        mover: "M".into(),
        target_position: 5.0,
        constraint: DynamicConstraint::default(),
    });
    s.steps(100);
    inject(&mut s, ErrorReaction::Abort);
    s.step();
    assert_eq!(
        s.state(z),
        Some(CommandState::Error(errors::E_OBJECT_ERROR))
    );
    assert_eq!(s.mover("M").set_pos.z, 0.0, "Abort: z drops");
    s.run_until(1.0, |p| p.mover("M").unwrap().state == Error);
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(s.mover("M").state, Disabled, "T11");
}

#[test]
fn t12_disable_in_error_forces_abort() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    inject(&mut s, ErrorReaction::QuickStop);
    s.run_until(1.0, |p| p.mover("M").unwrap().state == Error);
    let d = dis(&mut s);
    s.step();
    assert_eq!(s.mover("M").state, Error, "T12: state unchanged");
    assert_eq!(s.mover("M").error_reaction, ErrorReaction::Abort);
    assert_eq!(s.state(d), Some(CommandState::Done));
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(
        s.mover("M").state,
        Disabled,
        "the later reset ends in Disabled"
    );
}

#[test]
fn t14_error_in_error_escalates_never_deescalates() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    inject(&mut s, ErrorReaction::Abort);
    s.run_until(1.0, |p| p.mover("M").unwrap().state == Error);
    inject(&mut s, ErrorReaction::QuickStop);
    s.step();
    assert_eq!(s.mover("M").state, ErrorPending, "T14 via T7");
    assert_eq!(
        s.mover("M").error_reaction,
        ErrorReaction::Abort,
        "no de-escalation"
    );
    s.run_until(1.0, |p| p.mover("M").unwrap().state == Error);
}

#[test]
fn no_op_commands_are_done_at_once() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    let d = dis(&mut s);
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    s.step();
    assert_eq!(s.state(d), Some(CommandState::Done), "Disable in Disabled");
    assert_eq!(s.state(r), Some(CommandState::Done), "Reset without error");
    s.enable("M");
    let e = en(&mut s);
    s.step();
    assert_eq!(s.state(e), Some(CommandState::Done), "Enable in Enabled");
    // SetPosition only while Disabled.
    let e = s.err(PlanarCommand::SetPosition {
        mover: "M".into(),
        position: PositionXYC::new(50.0, 0.0, 0.0),
    });
    assert_eq!(e.error_id, errors::E_INVALID_STATE);
    let d = dis(&mut s);
    s.wait_final(d, 1.0);
    s.ok(PlanarCommand::SetPosition {
        mover: "M".into(),
        position: PositionXYC::new(50.0, 20.0, 30.0),
    });
    s.step();
    let m = s.mover("M");
    assert_eq!((m.set_pos.x, m.set_pos.y, m.set_pos.c), (50.0, 20.0, 30.0));
    // Enabled outside all C windows → CRotationFreeMovement (§2.2).
    s.enable("M");
    assert_eq!(
        s.mover("M").command_mode,
        CommandMode::CRotationFreeMovement
    );
}

#[test]
fn group_state_machine() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    let g = |s: &Sim| s.snap().group("G").unwrap().state;
    assert_eq!(g(&s), Disabled);
    s.enable_group("G");
    assert_eq!(g(&s), Enabled);
    s.ok(PlanarCommand::InjectError {
        kind: ObjectKind::Group,
        name: "G".into(),
        reaction: ErrorReaction::QuickStop,
    });
    s.step();
    assert_eq!(g(&s), ErrorPending);
    s.steps(60);
    assert_eq!(g(&s), Error);
    let r = s.ok(PlanarCommand::GroupReset { group: "G".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(g(&s), Enabled);
    let d = s.ok(PlanarCommand::GroupDisable { group: "G".into() });
    assert_eq!(s.wait_final(d, 1.0), CommandState::Done);
    assert_eq!(g(&s), Disabled);
}

/// T13 and §2.6: a mover reset fails while its part is still in error; the part reset
/// (MC_PlanarPart.Reset) clears the part only; then the mover reset succeeds.
#[test]
fn t13_reset_fails_while_part_in_error() {
    let mut s = Sim::new(two_parts());
    s.enable("M");
    s.ok(PlanarCommand::PartInitialize {
        part: "L".into(),
        part_oid: PART_L,
    });
    inject(&mut s, ErrorReaction::QuickStop);
    s.run_until(1.0, |p| p.mover("M").unwrap().state == Error);
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    s.ok(PlanarCommand::InjectError {
        kind: ObjectKind::Part,
        name: "L".into(),
        reaction: ErrorReaction::QuickStop,
    });
    assert_eq!(
        s.wait_final(r, 1.0),
        CommandState::Error(errors::E_PART_DISABLED),
        "T13"
    );
    assert_eq!(s.mover("M").state, Error);
    assert_eq!(s.snap().part("L").unwrap().state, Error);
    let pr = s.ok(PlanarCommand::PartReset { part: "L".into() });
    assert_eq!(s.wait_final(pr, 1.0), CommandState::Done);
    assert_eq!(
        s.mover("M").state,
        Error,
        "a part reset leaves mover errors alone"
    );
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(s.mover("M").state, Enabled);
    assert_eq!(
        s.snap().part("L").unwrap().state,
        Enabled,
        "QuickStop keeps the parts enabled"
    );
}

/// §2.6: a part error forces errors on the movers on that part (QuickStop); a mover Reset
/// resets the erroneous part of its CS first.
#[test]
fn part_error_propagates_to_movers() {
    let mut s = Sim::new(two_parts());
    s.enable("M");
    s.ok(PlanarCommand::InjectError {
        kind: ObjectKind::Part,
        name: "L".into(),
        reaction: ErrorReaction::QuickStop,
    });
    s.step();
    let m = s.mover("M");
    assert_eq!(
        (m.state, m.error_id, m.error_reaction),
        (
            ErrorPending,
            errors::E_PART_DISABLED,
            ErrorReaction::QuickStop
        )
    );
    s.run_until(1.0, |p| {
        p.mover("M").unwrap().state == Error && p.part("L").unwrap().state == Error
    });
    assert_eq!(
        s.snap().part("R").unwrap().state,
        Enabled,
        "other parts of the CS unaffected"
    );
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(s.mover("M").state, Enabled);
    assert_eq!(s.snap().part("L").unwrap().state, Enabled);
}
