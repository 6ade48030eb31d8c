//! E11 — clogging (plcopen_platform.md §13, §6.3 R-HS-5, raw FB layer §12.2): FB A places an
//! order in cycle 1 and is not called any more; FB B's order (cycle 2) aborts A in the MC.
//! A's acknowledgements block the axis' acknowledgement slot: B stays Busy and never sees
//! InVelocity although the axis is at speed; after > 2 cycles warning 4906 is recorded.
//! Calling A once consumes its acknowledgements (A.CommandAborted) and B's flow again.
mod p4rig;
use motion_core::ErrorId;
use p4rig::*;

#[test]
fn e11_unconsumed_acknowledgements_clog_the_axis() {
    let mut r = P4::isg();
    let a = || call("A", true, rel(A0, 100000.0, 10000.0));
    let b = || call("B", true, vel(A0, 10000.0));
    let o = r.cycle(&[a()]);
    let n = o[0].order_id;
    assert!(o[0].busy && n > 0);
    let o = r.cycle(&[b()]);
    assert_eq!(o[0].order_id, n + 1);
    let mut warned_at = None;
    for c in 0..300 {
        let o = r.cycle(&[b()]);
        assert!(o[0].busy && !o[0].in_velocity, "B blocked (cycle {c})");
        if warned_at.is_none() && !r.e.raw_warnings().is_empty() {
            warned_at = Some(c);
        }
    }
    assert!(
        (r.a0().set_velo - 10000.0).abs() < 1e-6,
        "the axis is at speed"
    );
    let w = &r.e.raw_warnings()[0];
    assert_eq!((w.id, w.order_id, w.axis.as_str()), (ErrorId(4906), n, A0));
    assert!(
        warned_at.unwrap() <= 2,
        "warning after > 2 cycles at the head"
    );
    assert_eq!(r.e.raw_warnings().len(), 1, "one warning per clog");
    assert_eq!(
        motion_core::Engine::snapshot(&r.e).platform.clog_warnings,
        1
    );
    // A called once: its ACCEPTED and ABORTED are consumed.
    let o = r.cycle(&[a()]);
    assert!(o[0].command_aborted && !o[0].busy);
    let mut k = 0;
    loop {
        let o = r.cycle(&[b()]);
        if o[0].in_velocity {
            break;
        }
        k += 1;
        assert!(k <= 2, "B.InVelocity within 2 cycles");
    }
}

#[test]
fn e11_called_every_cycle_nothing_clogs() {
    // R-HS-6: calling all instances every cycle never clogs.
    let mut r = P4::isg();
    r.cycle(&[call("A", true, rel(A0, 100000.0, 10000.0))]);
    let mut seen = false;
    for _ in 0..1000 {
        let o = r.cycle(&[
            call("A", true, rel(A0, 100000.0, 10000.0)),
            call("B", true, vel(A0, 10000.0)),
        ]);
        if o[1].in_velocity {
            seen = true;
            assert!(o[0].command_aborted);
            break;
        }
    }
    assert!(seen);
    assert!(r.e.raw_warnings().is_empty());
}
