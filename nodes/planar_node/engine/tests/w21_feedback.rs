//! W21 – Feedback (manual 6.7.1): Enable(fb) → Done; MoveToPosition(fb, (1000,1000)) → Busy/
//! Active during the motion, then Done; final (1000,1000). Lifecycle of §6.1.

mod common;
use common::*;
use motion_core::{CommandState, ExecuteOutputs};
use planar_engine::*;

#[test]
fn w21_feedback_lifecycle() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    let en = s.ok(PlanarCommand::MoverEnable { mover: "M".into() });
    s.step();
    assert_eq!(s.state(en), Some(CommandState::Active));
    assert_eq!(s.wait_final(en, 5.0), CommandState::Done);
    // Enabling takes enable_time (0.1 s).
    assert!(s.history[&en] == vec![CommandState::Active, CommandState::Done]);
    let mv = s.ok(mtp("M", 1000.0, 1000.0, 0.0));
    s.steps(10);
    let o = ExecuteOutputs::from(s.state(mv).unwrap());
    assert!(o.busy && o.active && !o.done && !o.error && !o.command_aborted);
    assert_eq!(s.wait_final(mv, 10.0), CommandState::Done);
    assert_eq!(
        s.history[&mv],
        vec![CommandState::Active, CommandState::Done],
        "no flag flicker"
    );
    assert_pos(&s.mover("M"), 1000.0, 1000.0);
}

/// §6.1: superseded → Aborted; the new command starts from the current set state (no jump).
#[test]
fn w21_superseded_command_is_aborted_without_jump() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let a = s.ok(mtp("M", 1000.0, 0.0, 0.0));
    s.steps(200);
    let before = s.mover("M");
    let b = s.ok(mtp("M", 500.0, 400.0, 0.0));
    s.step();
    assert_eq!(s.state(a), Some(CommandState::Aborted));
    let after = s.mover("M");
    let dv = (after.set_velo.x - before.set_velo.x).hypot(after.set_velo.y - before.set_velo.y);
    assert!(
        dv < 30.0,
        "velocity continuous over the re-plan (Δv {dv} mm/s in one cycle)"
    );
    let dp = (after.set_pos.x - before.set_pos.x).hypot(after.set_pos.y - before.set_pos.y);
    assert!(dp < 1.1, "position continuous ({dp} mm in one cycle)");
    let mut prev = s.mover("M");
    while s.state(b) != Some(CommandState::Done) {
        s.step();
        let m = s.mover("M");
        let step = (m.set_pos.x - prev.set_pos.x).hypot(m.set_pos.y - prev.set_pos.y);
        assert!(step < 1.5, "continuous path, step {step}");
        prev = m;
        assert!(s.index < 10_000);
    }
    assert_pos(&s.mover("M"), 500.0, 400.0);
}

/// §2.4 Halt: aborts every domain, stops, Done at standstill; §5.1 warning on clamped limits.
#[test]
fn w21_halt_and_dynamics_warning() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let r = s
        .cmd(PlanarCommand::MoveToPosition {
            mover: "M".into(),
            target_position: PositionXYC::new(2000.0, 0.0, 0.0),
            constraint: DynamicConstraint {
                velocity: 9000.0,
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
            },
            options: MoveToPositionOptions::default(),
        })
        .unwrap();
    assert_eq!(
        r.warning_id,
        errors::W_DYNAMICS_REDUCED,
        "9000 mm/s above the 4000 maximum"
    );
    s.step();
    assert_eq!(
        s.mover("M").warning_id,
        errors::W_DYNAMICS_REDUCED,
        "STD.WarningId of the latest command"
    );
    let z = s.ok(PlanarCommand::MoveZ {
        mover: "M".into(),
        target_position: 5.0,
        constraint: DynamicConstraint::default(),
    });
    s.steps(300);
    let v = s.mover("M").set_velo.x;
    assert!(
        v > 1000.0 && v <= 4000.0 + 1e-6,
        "runs with the reduced (maximum) velocity, v = {v}"
    );
    let h = s.ok(PlanarCommand::Halt {
        mover: "M".into(),
        constraint: DynamicConstraint::default(),
    });
    s.step();
    assert_eq!(s.state(r.id), Some(CommandState::Aborted));
    assert_eq!(s.state(z), Some(CommandState::Aborted));
    assert_eq!(s.wait_final(h, 5.0), CommandState::Done);
    let m = s.mover("M");
    assert_eq!(m.set_velo, MoverVector::default());
    assert!(m.set_pos.x < 2000.0 && m.set_pos.x > 0.0);
    assert!(!m.busy.busy_mover);
}
