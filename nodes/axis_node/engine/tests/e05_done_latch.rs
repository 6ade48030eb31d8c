//! E5 — Done latch and chaining pitfall (plcopen_platform.md §13, R-HS-2): FB1
//! MC_MoveRelative(1000, v 10000, a = d = 100000, j = 1e7) triggered with Execute TRUE in one
//! cycle only; FB2.Execute := FB1.Done. FB1.Done becomes TRUE (~0.2 s later) and stays TRUE;
//! FB2 starts once; re-triggering FB1 does not clear Done until that Execute falls.
mod p4rig;
use axis_engine::*;
use motion_core::CmdId;
use p4rig::*;

#[test]
fn e5_done_latched_until_the_next_falling_edge() {
    let mut r = P4::isg();
    r.steps(9); // cycle 20 of the node
    let fb1 = r.id(rel_full(A0, 1000.0, 10000.0, 100000.0, 100000.0, 1e7));
    r.step();
    r.set_execute(fb1, false); // trigger style
    let (mut prev, mut fb2_edges, mut fb2): (bool, u32, Option<CmdId>) = (false, 0, None);
    let mut first_done = None;
    for c in 0..1000 {
        let done = r.out(fb1).done;
        if done && first_done.is_none() {
            first_done = Some(c);
        }
        if done && !prev {
            fb2_edges += 1;
            fb2 = Some(r.id(AxisCommand::ReadStatus(ReadStatus { axis: A0.into() })));
        }
        prev = done;
        r.step();
    }
    let t = first_done.expect("FB1 Done") as f64 * DT;
    assert!((0.15..0.3).contains(&t), "Done after ~0.2 s: {t}");
    assert!(r.out(fb1).done, "still TRUE ~0.8 s later (Execute FALSE)");
    assert_eq!(fb2_edges, 1, "FB2 saw exactly one edge");
    assert!(fb2.is_some());
    // Re-trigger FB1: Execute TRUE one cycle: Done stays until that Execute falls.
    r.set_execute(fb1, true);
    r.step();
    assert!(r.out(fb1).done, "not cleared by the rising edge");
    r.set_execute(fb1, false);
    assert!(!r.out(fb1).done, "cleared by the falling edge");
}

#[test]
fn e5_tc2_mc2_shows_done_for_one_cycle_only() {
    // Profile contrast (single_axis.md §3.1 rule 6).
    let mut r = P4::xy_powered();
    let id = r.id(rel("x", 1.0, 100.0));
    r.set_execute(id, false);
    r.until(5000, |r| r.out(id).done);
    r.step();
    assert!(!r.out(id).done);
}

#[test]
fn e5_raw_layer_chaining_pitfall() {
    // FB2.Execute := FB1.Done each cycle; FB1 trigger-style in cycle 20.
    use axis_engine::platform::raw::FbCall;
    let mut r = P4::isg();
    r.steps(9);
    let fb1 = |e: bool| {
        call(
            "FB1",
            e,
            rel_full(A0, 1000.0, 10000.0, 100000.0, 100000.0, 1e7),
        )
    };
    let fb2 = |e: bool| -> FbCall { call("FB2", e, rel(A0, 10.0, 10000.0)) };
    let (mut fb1_done, mut fb2_orders, mut last_fb2) = (false, 0u32, 0u32);
    let mut run = |r: &mut P4, fb1_exec: bool, n: usize, fb1_done: &mut bool| {
        for k in 0..n {
            let o = r.cycle(&[fb1(fb1_exec && k == 0), fb2(*fb1_done)]);
            *fb1_done = o[0].done;
            if o[1].order_id != last_fb2 {
                last_fb2 = o[1].order_id;
                fb2_orders += 1;
            }
        }
    };
    run(&mut r, true, 1000, &mut fb1_done);
    assert!(fb1_done, "FB1.Done latched with Execute FALSE");
    // Re-trigger FB1 for one cycle: its Done stays TRUE until that Execute falls.
    let o = r.cycle(&[fb1(true), fb2(fb1_done)]);
    assert!(
        o[0].done && o[0].busy,
        "Done not cleared by the rising edge"
    );
    run(&mut r, false, 1000, &mut fb1_done);
    assert_eq!(
        fb2_orders, 2,
        "FB2 started once per complete FB1 trigger cycle"
    );
}
