//! W5 — BufferMode velocity at the transition point (single_axis.md §8, §3.6).
mod common;
use axis_engine::*;
use common::*;
use motion_core::CommandState;

/// Runs A (0 → 100 at v1) and B (→ 200 at v2, mode `bm`) and returns the set velocity at the
/// cycle in which A reports Done, plus checks the handshake at the transition.
fn transition(v1: f64, v2: f64, bm: BufferMode) -> f64 {
    let mut r = Rig::powered();
    let a = r.id(abs_dyn(
        100.0,
        v1,
        1000.0,
        1000.0,
        100000.0,
        BufferMode::Aborting,
    ));
    r.steps(150); // A is in its constant-velocity phase (0.3 s)
    assert!(
        (r.st().set_velo - v1).abs() < 1e-9,
        "A at constant velocity"
    );
    let b = r.id(abs_dyn(200.0, v2, 1000.0, 1000.0, 100000.0, bm));
    let ob = r.out(b);
    assert!(ob.busy && !ob.active, "B waits in the buffer: {ob:?}");
    assert!(r.st().cmd_buffered);
    r.until(10000, |r| r.out(a).done);
    let st = r.st();
    assert!(
        (st.set_pos - 100.0).abs() < 1e-9,
        "A is Done when the axis passes P1 = 100, at {}",
        st.set_pos
    );
    let ob = r.out(b);
    assert!(
        ob.busy && ob.active,
        "B becomes Active at that moment: {ob:?}"
    );
    assert_eq!(
        r.when(a, CommandState::Done),
        r.when(b, CommandState::Active)
    );
    let v_t = st.set_velo;
    r.until(20000, |r| r.out(b).done);
    assert!((r.st().set_pos - 200.0).abs() < 1e-9);
    // Never faster than the larger of the two commands.
    v_t
}

#[test]
fn v1_50_v2_100() {
    let cases = [
        (BufferMode::Buffered, 0.0),
        (BufferMode::BlendingLow, 50.0),
        (BufferMode::BlendingPrevious, 50.0),
        (BufferMode::BlendingNext, 100.0),
        (BufferMode::BlendingHigh, 100.0),
    ];
    for (bm, want) in cases {
        let v = transition(50.0, 100.0, bm);
        assert!((v - want).abs() < 1e-6, "{bm:?}: {v} vs {want}");
    }
}

#[test]
fn v1_100_v2_50() {
    let cases = [
        (BufferMode::Buffered, 0.0),
        (BufferMode::BlendingLow, 50.0),
        (BufferMode::BlendingPrevious, 100.0),
        (BufferMode::BlendingNext, 50.0),
        (BufferMode::BlendingHigh, 100.0),
    ];
    for (bm, want) in cases {
        let v = transition(100.0, 50.0, bm);
        assert!((v - want).abs() < 1e-6, "{bm:?}: {v} vs {want}");
    }
}

#[test]
fn aborting_takes_over_at_once() {
    let mut r = Rig::powered();
    let a = r.id(abs_dyn(
        100.0,
        50.0,
        1000.0,
        1000.0,
        100000.0,
        BufferMode::Aborting,
    ));
    r.steps(150);
    let b = r.id(abs_dyn(
        200.0,
        100.0,
        1000.0,
        1000.0,
        100000.0,
        BufferMode::Aborting,
    ));
    assert!(r.out(a).command_aborted);
    assert!(r.out(b).active);
    // Smooth takeover: no velocity step.
    let v0 = r.st().set_velo;
    r.step();
    assert!((r.st().set_velo - v0).abs() <= 1000.0 * DT + 1e-9);
    r.until(20000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 200.0);
    assert_eq!(r.state_of(a), Some(CommandState::Aborted));
}

#[test]
fn buffered_behind_finished_move_waiting_for_in_target_starts_at_once() {
    let mut r = Rig::powered();
    let a = r.id(abs(10.0, 100.0));
    r.until(2000, |r| !r.st().has_job);
    assert!(r.out(a).busy, "A waits for InTargetPosition");
    let b = r.id(abs_bm(20.0, 100.0, BufferMode::Buffered));
    assert!(r.out(a).done, "A completes when B takes over");
    assert!(r.out(b).active);
}

#[test]
fn blending_behind_a_running_halt_starts_from_rest() {
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.steps(200);
    let h = r.id(halt(0.0, 0.0, BufferMode::Aborting));
    r.step();
    let b = r.id(abs_bm(500.0, 100.0, BufferMode::BlendingHigh));
    r.until(5000, |r| r.out(h).done);
    assert_eq!(r.st().set_velo, 0.0, "the halt ends at rest");
    assert!(r.out(b).active);
    r.until(20000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 500.0);
}

#[test]
fn power_outputs() {
    let mut r = Rig::new();
    let o = r.e.power_outputs(AX).unwrap();
    assert!(!o.status && !o.busy && !o.active);
    r.power(true);
    r.step();
    let o = r.e.power_outputs(AX).unwrap();
    assert!(o.status && o.busy && o.active);
}

#[test]
fn late_blending_uses_the_highest_reachable_velocity() {
    // §3.6 rule 5: B arrives while A brakes towards P1 = 100: the axis cannot reach
    // v2 = 100 at P1 any more, it blends with what is reachable (0 < v < 100), no reversal.
    let mut r = Rig::powered();
    let a = r.id(abs_dyn(
        100.0,
        100.0,
        1000.0,
        1000.0,
        1e5,
        BufferMode::Aborting,
    ));
    r.until(5000, |r| r.st().set_pos >= 99.0);
    let v_arrive = r.st().set_velo;
    assert!(v_arrive > 0.0 && v_arrive < 100.0, "braking: {v_arrive}");
    let b = r.id(abs_dyn(
        200.0,
        100.0,
        1000.0,
        1000.0,
        1e5,
        BufferMode::BlendingNext,
    ));
    let mut last = r.st().set_pos;
    r.until(5000, |r| {
        assert!(r.st().set_pos >= last - 1e-12, "no reversal");
        last = r.st().set_pos;
        r.out(a).done
    });
    let v_t = r.st().set_velo;
    assert!((r.st().set_pos - 100.0).abs() < 1e-9);
    assert!(v_t > 0.0 && v_t < 100.0, "transition velocity {v_t}");
    r.until(20000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 200.0);
}

#[test]
fn blending_while_override_is_zero_waits_for_the_override() {
    let mut r = Rig::powered();
    let a = r.id(abs(100.0, 50.0));
    r.steps(200);
    r.power_full(true, true, true, 0.0, BufferMode::Aborting)
        .unwrap();
    let b = r.id(abs_bm(200.0, 50.0, BufferMode::BlendingNext));
    r.steps(500);
    assert!(
        r.out(a).active && r.out(b).busy && !r.out(b).active,
        "paused, nothing completes"
    );
    assert!(r.st().set_pos < 100.0);
    r.power_full(true, true, true, 100.0, BufferMode::Aborting)
        .unwrap();
    r.until(10000, |r| r.out(a).done);
    assert!((r.st().set_pos - 100.0).abs() < 1e-9);
    assert!((r.st().set_velo - 50.0).abs() < 1e-9);
    r.until(10000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 200.0);
}
