//! E2 — start-up (plcopen_platform.md §13, §9 R-INIT-1): an order in cycles 0…9 → Error 4013
//! (ERR_PO_AX_TNA_INIT_STATE), the axis stays INIT_STATE, then DISABLED; no motion after
//! start-up; a new rising edge after cycle 10 (axis powered) starts the move.
mod p4rig;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

#[test]
fn e2_order_during_startup() {
    let mut r = P4::isg_cold(PlatformConfig::default());
    assert_eq!(err(r.cmd(rel(A0, 1000.0, 10000.0))), ErrorId(4013));
    assert_eq!(
        err(r.power(A0, true)),
        ErrorId(4013),
        "MC_Power is an order too"
    );
    for c in 0..10 {
        let snap = motion_core::Engine::snapshot(&r.e);
        assert_eq!(
            snap.axes[0].motion_state,
            MotionState::Undefined,
            "INIT_STATE in cycle {c}"
        );
        assert!(!snap.platform.hli_initialized);
        assert_eq!(
            err(r.cmd(rel(A0, 1000.0, 10000.0))),
            ErrorId(4013),
            "cycle {c}"
        );
        r.step();
    }
    let snap = motion_core::Engine::snapshot(&r.e);
    assert!(snap.platform.hli_initialized && snap.platform.platform_base_done);
    assert_eq!(snap.platform.init_cycles, 10);
    assert_eq!(r.a0().motion_state, MotionState::Disabled);
    r.steps(100);
    assert_eq!(r.a0().set_pos, 0.0, "no motion after start-up");
    r.power(A0, true).unwrap();
    r.step();
    let id = r.id(rel(A0, 1000.0, 10000.0));
    r.until(5000, |r| r.out(id).done);
    assert_eq!(r.a0().set_pos, 1000.0);
}

#[test]
fn e2_auto_power_gives_standstill_after_startup() {
    let mut r = P4::isg_cold(PlatformConfig {
        auto_power: true,
        ..PlatformConfig::default()
    });
    r.steps(10);
    r.step();
    assert_eq!(r.a0().motion_state, MotionState::Standstill);
}

/// Issue 17 item 3: start-up lasts exactly 10 cycles. With `auto_power` an order placed in
/// cycle 10 (after 10 steps) is taken: the axis is STANDSTILL then, not one cycle later.
#[test]
fn e2_auto_power_takes_an_order_in_cycle_10() {
    let mut r = P4::isg_cold(PlatformConfig {
        auto_power: true,
        ..PlatformConfig::default()
    });
    r.steps(9);
    assert_eq!(
        err(r.cmd(rel(A0, 1000.0, 10000.0))),
        ErrorId(4013),
        "cycle 9 is start-up"
    );
    r.step();
    assert_eq!(r.a0().motion_state, MotionState::Standstill, "cycle 10");
    let id = r.id(rel(A0, 1000.0, 10000.0));
    r.until(5000, |r| r.out(id).done);
    assert_eq!(r.a0().set_pos, 1000.0);
}
