//! The raw FB layer (plcopen_platform.md §12.2) with Part 4 group FBs in `isg_mcp`: group
//! instances follow R-FB-1 and the handshake rules on the group's channel exactly as axis
//! instances do on their axis:
//! - R-HS-1/R-HS-2: Busy at the edge, Active once ACCEPTED is taken (next call), Done latched
//!   while Execute stays TRUE, cleared by the falling edge; order numbers from `g_order_id`;
//! - R-HS-3/R-HS-4: a second order on the same group in one cycle → FB error 4, MC_GroupStop
//!   overwrites (the first order ends CommandAborted), the falling edge releases the stop;
//! - R-HS-5: an instance that placed an order and is no longer called clogs the group's
//!   acknowledgement queue; after > 2 cycles warning 4906 names the group; one call unclogs.
mod p4rig;
use axis_engine::group::*;
use axis_engine::platform::raw::FbState;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

fn rig() -> P4 {
    P4::isg_xy(PlatformConfig::default())
}

fn gcall(instance: &str, execute: bool, c: GroupCommand) -> axis_engine::platform::raw::FbCall {
    call(instance, execute, AxisCommand::Group(c))
}

#[test]
fn group_fb_handshake_busy_active_done_latched() {
    let mut r = rig();
    let mv = || gcall("M", true, lin_abs(vec![3000.0, 4000.0], 100_000.0));
    let first = r.g_order_id();
    let o = r.cycle(&[mv()]);
    assert!(o[0].busy && !o[0].active && !o[0].done, "{o:?}");
    assert_eq!(o[0].order_id, first);
    assert_eq!(o[0].fb_state, FbState::Active);
    assert_eq!(r.g_order_id(), first + 1);
    // ACCEPTED is taken at the next call.
    let o = r.cycle(&[mv()]);
    assert!(o[0].busy && o[0].active, "{o:?}");
    let mut n = 0;
    loop {
        let o = r.cycle(&[mv()]);
        if o[0].done {
            assert!(!o[0].busy && !o[0].active && o[0].fb_state == FbState::Idle);
            break;
        }
        n += 1;
        assert!(n < 2000, "not done");
    }
    assert_eq!(r.ax("x").set_pos, 3000.0);
    assert_eq!(r.ax("y").set_pos, 4000.0);
    // Done stays while Execute is held (R-HS-2) ...
    for _ in 0..5 {
        assert!(r.cycle(&[mv()])[0].done);
    }
    // ... and falls with Execute.
    let o = r.cycle(&[gcall("M", false, lin_abs(vec![3000.0, 4000.0], 100_000.0))]);
    assert!(!o[0].done && !o[0].busy);
}

#[test]
fn one_order_per_group_and_cycle_group_stop_overwrites() {
    let mut r = rig();
    let a = || gcall("A", true, lin_abs(vec![30_000.0, 0.0], 100_000.0));
    let b = || gcall("B", true, lin_abs(vec![0.0, 30_000.0], 100_000.0));
    // A and B in the same cycle: B's order finds the slot used → FB error 4 (R-HS-3).
    let o = r.cycle(&[a(), b()]);
    assert!(o[0].busy && !o[0].error);
    assert!(o[1].error && !o[1].busy, "{o:?}");
    assert_eq!(o[1].error_id, ErrorId(4));
    assert_eq!(o[1].fb_state, FbState::Error);
    r.cycle(&[a()]);
    // A moving; in one cycle a new order of C takes the slot and MC_GroupStop S still gets
    // it: S overwrites C's order (R-HS-4).
    let c = || gcall("C", true, lin_abs(vec![0.0, 30_000.0], 100_000.0));
    let s = |execute| gcall("S", execute, gstop());
    let o = r.cycle(&[a(), c(), s(true)]);
    assert!(o[1].busy && !o[1].error, "C placed its order: {o:?}");
    assert!(o[2].busy && !o[2].error, "S overwrote: {o:?}");
    assert_eq!(o[2].order_id, o[1].order_id + 1);
    // A and C end CommandAborted, S is Done at standstill, held while Execute stays TRUE.
    let (mut a_aborted, mut c_aborted) = (false, false);
    let mut n = 0;
    loop {
        let o = r.cycle(&[a(), c(), s(true)]);
        a_aborted |= o[0].command_aborted;
        c_aborted |= o[1].command_aborted;
        if o[2].done {
            break;
        }
        n += 1;
        assert!(n < 3000, "stop not done");
    }
    assert!(c_aborted, "C ended CommandAborted");
    // Its outputs are consistent: ACCEPTED was acknowledged before ABORTED.
    let o = r.cycle(&[a(), c(), s(true)]);
    assert!(o[1].command_aborted && !o[1].busy && !o[1].active, "{o:?}");
    assert!(a_aborted, "A ended CommandAborted");
    assert_eq!(r.gs().state, GroupState::Stopping);
    // Motion refused while the stop is held; the falling edge releases the group.
    let o = r.cycle(&[
        gcall("D", true, lin_abs(vec![0.0, 0.0], 100_000.0)),
        s(true),
    ]);
    assert!(o[0].error, "{o:?}");
    r.cycle(&[s(false)]);
    r.cycle(&[]);
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn an_uncalled_group_instance_clogs_the_group_channel() {
    let mut r = rig();
    let m = || gcall("M", true, lin_abs(vec![100_000.0, 0.0], 100_000.0));
    let h = || gcall("H", true, ghalt());
    let o = r.cycle(&[m()]);
    let n = o[0].order_id;
    // H's order (next cycle) aborts M in the MC; M is not called any more.
    let o = r.cycle(&[h()]);
    assert_eq!(o[0].order_id, n + 1);
    let mut warned_at = None;
    for c in 0..300 {
        let o = r.cycle(&[h()]);
        assert!(o[0].busy && !o[0].done, "H blocked (cycle {c})");
        if warned_at.is_none() && !r.e.raw_warnings().is_empty() {
            warned_at = Some(c);
        }
    }
    assert_eq!(
        r.gs().state,
        GroupState::Standby,
        "the halt itself has finished"
    );
    let w = &r.e.raw_warnings()[0];
    assert_eq!((w.id, w.order_id, w.axis.as_str()), (ErrorId(4906), n, G));
    assert!(
        warned_at.unwrap() <= 2,
        "warning after > 2 cycles at the head"
    );
    // M called once: its acknowledgements are consumed, H's Done follows.
    let o = r.cycle(&[m()]);
    assert!(o[0].command_aborted && !o[0].busy, "{o:?}");
    let o = r.cycle(&[h()]);
    assert!(o[0].done, "{o:?}");
}

/// Issue 17 item 2, §6.2: an Enable-type FB with cyclic inputs (MC_GroupSetOverride, and
/// MC_SetOverride on an axis) applies changed inputs while Enable is held TRUE, every call,
/// as the service does: 0.5, then 0.0 (path-true stop), then 1.0 during a group move.
#[test]
fn enable_type_fbs_apply_changed_inputs_while_enable_is_held() {
    let mut r = rig();
    let ov = |f: f64| {
        gcall(
            "OV",
            true,
            GroupCommand::GroupSetOverride(GroupSetOverride {
                group: G.into(),
                enable: true,
                vel_factor: f,
                acc_factor: 1.0,
                jerk_factor: 1.0,
            }),
        )
    };
    let mv = || gcall("M", true, lin_abs(vec![300_000.0, 400_000.0], 100_000.0));
    r.cycle(&[ov(0.5), mv()]);
    for _ in 0..200 {
        r.cycle(&[ov(0.5), mv()]);
    }
    assert_eq!(r.gs().override_factor, 0.5);
    for _ in 0..400 {
        r.cycle(&[ov(0.0), mv()]);
    }
    assert_eq!(
        r.gs().override_factor,
        0.0,
        "a changed VelFactor applies at once"
    );
    let (x, y) = (r.ax("x").set_pos, r.ax("y").set_pos);
    r.cycle(&[ov(0.0), mv()]);
    assert_eq!(
        (r.ax("x").set_pos, r.ax("y").set_pos),
        (x, y),
        "stopped by VelFactor 0"
    );
    r.cycle(&[ov(1.0), mv()]);
    assert_eq!(r.gs().override_factor, 1.0);
    // The axis-level MC_SetOverride likewise.
    let aov = |f: f64| {
        call(
            "AOV",
            true,
            AxisCommand::SetOverride(SetOverride {
                axis: "x".into(),
                enable: true,
                vel_factor: f,
                acc_factor: 1.0,
                jerk_factor: 1.0,
            }),
        )
    };
    r.cycle(&[aov(0.25)]);
    r.cycle(&[aov(0.75)]);
    r.step();
    assert_eq!(
        r.ax("x").override_percent,
        75.0,
        "axis override follows the held instance's input"
    );
}
