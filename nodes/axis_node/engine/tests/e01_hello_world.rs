//! E1 — HelloWorld (plcopen_platform.md §13): MC_Power, MC_ReadActualPosition, then
//! MC_MoveRelative(100000, v 10000, a = d = 2000, j = 2000): 16.000 s (+ ≤ 2 cycles), final
//! position start + 100000 ± 1, Done stays TRUE until Execute falls.
mod p4rig;
use axis_engine::*;
use p4rig::*;

#[test]
fn e1_hello_world() {
    let mut r = P4::isg();
    let s = r.safety(A0);
    assert!(s.drive_enabled, "DriveEnabled after MC_Power");
    assert_eq!(r.a0().motion_state, MotionState::Standstill);
    let start = match r
        .cmd(AxisCommand::ReadActualPosition(ReadActualPosition {
            axis: A0.into(),
        }))
        .unwrap()
        .value
    {
        ReplyValue::Real(p) => p,
        v => panic!("{v:?}"),
    };
    let id = r.id(rel_full(A0, 100000.0, 10000.0, 2000.0, 2000.0, 2000.0));
    assert_eq!(r.a0().motion_state, MotionState::DiscreteMotion);
    let n = r.until(20000, |r| r.out(id).done);
    let t = n as f64 * DT;
    assert!(
        (16.0 - 1e-9..=16.0 + 2.0 * DT + 1e-9).contains(&t),
        "motion time {t} s"
    );
    assert!((r.a0().act_pos - (start + 100000.0)).abs() <= 1.0);
    assert_eq!(r.a0().motion_state, MotionState::Standstill);
    assert!(
        r.e.status(A0).unwrap().error_code == 0,
        "10 mm/s < 250 mm/s: no 60241"
    );
    // Done stays TRUE until Execute falls.
    r.steps(500);
    assert!(r.out(id).done);
    r.set_execute(id, false);
    assert!(!r.out(id).done);
}
