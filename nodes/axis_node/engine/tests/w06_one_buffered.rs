//! W6 — one buffered command only (single_axis.md §8, §3.6 rules 1 and 2).
mod common;
use axis_engine::*;
use common::*;

#[test]
fn third_buffered_command_is_rejected_with_buffer_full_and_aborting_clears_all() {
    for mode in [
        BufferMode::Buffered,
        BufferMode::BlendingLow,
        BufferMode::BlendingPrevious,
        BufferMode::BlendingNext,
        BufferMode::BlendingHigh,
    ] {
        let mut r = Rig::powered();
        let a = r.id(abs(100.0, 50.0));
        r.steps(10);
        let b = r.id(abs_bm(200.0, 50.0, BufferMode::Buffered));
        let before = r.st();
        let c = r.cmd(abs_bm(300.0, 50.0, mode)).unwrap_err();
        assert_eq!(c.error_id, err(0x4292), "{mode:?}: {}", c.message);
        assert_eq!(r.st(), before, "A and B unaffected");
        assert!(r.out(a).active && r.out(b).busy && !r.out(b).active);
        let d = r.id(abs_bm(-50.0, 50.0, BufferMode::Aborting));
        assert!(
            r.out(a).command_aborted && r.out(b).command_aborted,
            "{mode:?}"
        );
        assert!(r.out(d).active);
        assert!(!r.st().cmd_buffered);
        r.until(20000, |r| r.out(d).done);
        assert_eq!(r.st().set_pos, -50.0);
    }
}
