//! E7 — velocity monitoring (plcopen_platform.md §13, R-SAF-0, R-SAF-1): a programmed 300 mm/s
//! on a linear axis → MC error 60241, ERROR_STOP, no motion, FB ErrorID 1. With the monitor
//! leased off (lease 100, refreshed every 50 ms) the move runs; without refresh the monitor
//! is active again ≤ 100 cycles later → 70225, brake + enable off, DriveEnabled FALSE.
mod p4rig;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

fn lease() -> PlatformCommand {
    PlatformCommand::SafetyDeactivate {
        axis: A0.into(),
        function: SafetyFunction::VelocityMonitoring,
        lease_cycles: 100,
    }
}

fn fast() -> AxisCommand {
    rel_full(A0, 100000.0, 300000.0, 1e7, 1e7, 1e9)
}

#[test]
fn e7_command_check_60241() {
    let mut r = P4::isg();
    assert_eq!(err(r.cmd(fast())), ErrorId(1), "FB ErrorID 1");
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    assert_eq!(r.a0().error_code, 60241);
    r.steps(10);
    assert_eq!(r.a0().set_pos, 0.0, "no motion");
    assert_eq!(r.messages(A0)[0].error_id, 60241);
}

#[test]
fn e7_leased_off_the_move_runs_and_expiry_triggers_70225() {
    let mut r = P4::isg();
    r.p(lease()).unwrap();
    assert!(!r.safety(A0).velocity_monitoring);
    let id = r.id(fast());
    // Refreshed every 50 cycles: runs to the end.
    let mut n = 0;
    while !r.out(id).done {
        assert!(n < 2000, "not done");
        if n % 50 == 0 {
            r.p(lease()).unwrap();
        }
        r.step();
        n += 1;
    }
    // Path: 100000/300000 s + ramps (a = 1e7, j = 1e9: v/a + a/j = 0.04 s).
    let t = n as f64 * DT;
    assert!((t - (1.0 / 3.0 + 0.04)).abs() < 0.003, "time {t}");
    assert_eq!(r.a0().set_pos, 100000.0);
    // Again, refreshed only twice: the monitor comes back during the move.
    r.steps(200);
    r.p(lease()).unwrap();
    let id = r.id(fast());
    let start = r.tick;
    while r.a0().error_code == 0 {
        let k = r.tick - start;
        assert!(k < 2000, "monitor never came back");
        if k == 0 || k == 50 {
            r.p(lease()).unwrap();
        }
        r.step();
    }
    assert_eq!(r.a0().error_code, 70225);
    assert!(
        r.tick - start <= 200,
        "within the lease after the last refresh"
    );
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    assert!(!r.safety(A0).drive_enabled, "DriveEnabled FALSE");
    assert!(
        !r.e.power_outputs(A0).unwrap().status,
        "MC_Power.Status FALSE"
    );
    assert_eq!(r.out(id).error_id, ErrorId(1));
    assert!(r.safety(A0).velocity_monitoring, "active again");
}

#[test]
fn e7_default_lease_is_100_cycles() {
    let mut r = P4::isg();
    r.p(PlatformCommand::SafetyDeactivate {
        axis: A0.into(),
        function: SafetyFunction::VelocityMonitoring,
        lease_cycles: 0,
    })
    .unwrap();
    r.steps(99);
    assert!(!r.safety(A0).velocity_monitoring);
    r.steps(1);
    assert!(
        r.safety(A0).velocity_monitoring,
        "re-activated after 100 cycles"
    );
}
