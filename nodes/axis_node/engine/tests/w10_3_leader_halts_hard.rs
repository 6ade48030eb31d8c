//! collision_avoidance.md §10.3 "Leader halts hard; follower resumes" (open rail 10000,
//! L at 1000, F at 800; V 1000, A = D = 5000, J = 50000; HaltCA MAXIMUM / 200000 at 1.5 s).

mod ca_common;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::CommandState;

fn mv(r: &mut CaRig, axis: &str, pos: f64) -> motion_core::CmdId {
    r.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: axis.into(),
        position: McLreal::Value(pos),
        velocity: McLreal::Value(1000.0),
        acceleration: McLreal::Value(5000.0),
        deceleration: McLreal::Value(5000.0),
        jerk: McLreal::Value(50000.0),
        ..Default::default()
    }))
}

fn scenario(mode: DefaultGapControlMode) -> (f64, f64) {
    let cfg = CaGroupConfig {
        default_gap_control_mode: mode,
        ..open(10000.0)
    };
    let mut r = CaRig::new(&[("L", 1000.0), ("F", 800.0)], cfg);
    let l = mv(&mut r, "L", 5000.0);
    let f = mv(&mut r, "F", 3000.0);
    let mut max_cruise_gap: f64 = 0.0;
    let mut prev_a = 0.0;
    let check = |r: &CaRig, prev_a: &mut f64| {
        let fa = r.axis("F");
        assert!(fa.gap_actual >= 100.0 - 1e-6, "gap {}", fa.gap_actual);
        assert!(
            fa.acceleration >= -20000.0 * (1.0 + 1e-6),
            "F decel {}",
            fa.acceleration
        );
        assert!(
            (fa.acceleration - *prev_a).abs() <= 200000.0 * T * (1.0 + 1e-6),
            "F jerk"
        );
        *prev_a = fa.acceleration;
        fa.gap_actual
    };
    for k in 0..1500 {
        r.step();
        let g = check(&r, &mut prev_a);
        if k == 300 {
            assert!(
                (r.axis("L").velocity - 1000.0).abs() < 1e-3,
                "L at 1000 mm/s after 0.3 s"
            );
        }
        if k > 1000 {
            max_cruise_gap = max_cruise_gap.max(g);
        }
    }
    let xl = r.pos("L");
    assert!((xl - 2350.0).abs() < 0.5, "L at 2350 at t = 1.5 s: {xl}");
    let h = r.ok(CaCommand::Halt(HaltCa {
        axis: "L".into(),
        deceleration: McLreal::Maximum,
        jerk: McLreal::Value(200000.0),
        ..Default::default()
    }));
    for _ in 0..1500 {
        r.step();
        check(&r, &mut prev_a);
    }
    assert_eq!(
        r.cmd_state(l),
        CommandState::Aborted,
        "L's move CommandAborted"
    );
    assert_eq!(r.cmd_state(h), CommandState::Done, "halt Done");
    let rest = r.pos("L");
    assert!(
        (rest - (xl + 70.711)).abs() < 1e-3,
        "L stops after 70.711 mm: {}",
        rest - xl
    );
    assert!(
        (r.pos("F") - (rest - 100.0)).abs() < 1e-3,
        "F rests 100 behind: {}",
        r.pos("F")
    );
    assert_eq!(r.cmd_state(f), CommandState::Active, "F Busy, not Done");
    // Resume.
    let l2 = mv(&mut r, "L", 5000.0);
    r.until(10000, |r| {
        r.cmd_state(f) == CommandState::Done && r.cmd_state(l2) == CommandState::Done
    });
    assert_eq!(r.pos("F"), 3000.0);
    assert_eq!(r.pos("L"), 5000.0);
    (max_cruise_gap, rest)
}

#[test]
fn standard_follower_rests_100_behind_and_resumes() {
    let (gap, _) = scenario(DefaultGapControlMode::Standard);
    assert!(
        (gap - 250.0).abs() < 5.0,
        "Standard cruise gap ≈ 250: {gap}"
    );
}

#[test]
fn fast_follower_same_rest_point_gap_stays_near_start() {
    let (gap, _) = scenario(DefaultGapControlMode::Fast);
    assert!((gap - 200.0).abs() < 5.0, "Fast cruise gap ≈ 200: {gap}");
}
