//! W8 — MC_Halt with BufferMode while MoveAbsolute to 100 (v 100) runs (§8, §3.6 rule 9).
mod common;
use axis_engine::*;
use common::*;
use motion_core::CommandState;

fn run(bm: BufferMode) -> (f64, Rig) {
    let mut r = Rig::powered();
    let a = r.id(abs_dyn(
        100.0,
        100.0,
        1000.0,
        1000.0,
        1e5,
        BufferMode::Aborting,
    ));
    r.steps(100);
    let h = r.id(halt(0.0, 0.0, bm));
    assert!(r.out(h).busy && !r.out(h).active, "{bm:?}: Halt waits");
    r.until(10000, |r| r.out(h).done);
    assert_eq!(
        r.state_of(a),
        Some(CommandState::Done),
        "{bm:?}: A reaches its end position"
    );
    assert_eq!(r.st().set_velo, 0.0);
    (r.st().set_pos, r)
}

#[test]
fn buffered_low_next_stop_at_the_previous_target() {
    for bm in [
        BufferMode::Buffered,
        BufferMode::BlendingLow,
        BufferMode::BlendingNext,
    ] {
        let (p, _) = run(bm);
        assert!((p - 100.0).abs() < 1e-9, "{bm:?}: {p}");
    }
}

#[test]
fn previous_high_pass_the_target_at_full_speed_and_brake_there() {
    // d = 1000, j = 1e5 from 100 u/s: 100²/2000 + 100·1000/(2·1e5) = 5.5.
    for bm in [BufferMode::BlendingPrevious, BufferMode::BlendingHigh] {
        let (p, _) = run(bm);
        assert!((p - 105.5).abs() < 1e-6, "{bm:?}: {p}");
    }
}
