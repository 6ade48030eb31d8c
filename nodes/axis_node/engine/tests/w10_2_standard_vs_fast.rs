//! collision_avoidance.md §10.2 "Standard vs Fast" (ring 3000; M1 at 0, M2 −100, M3 −200,
//! M4 −300; all MoveAbsoluteCA 3000, gap 100).

mod ca_common;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::CommandState;

/// Returns (max gap seen, rest time of M4 [s]).
fn run(mode: DefaultGapControlMode) -> (f64, f64) {
    let cfg = CaGroupConfig {
        default_gap_control_mode: mode,
        ..ring(3000.0)
    };
    let mut r = CaRig::new(
        &[("M1", 0.0), ("M2", -100.0), ("M3", -200.0), ("M4", -300.0)],
        cfg,
    );
    let ids: Vec<_> = ["M1", "M2", "M3", "M4"]
        .iter()
        .map(|n| r.mv_abs(n, 3000.0, 1000.0))
        .collect();
    let mut max_gap: f64 = 0.0;
    let mut rest = None;
    for k in 1..=6000 {
        r.step();
        for a in r.group().axes {
            assert!(
                a.gap_actual >= 100.0 - 1e-6,
                "{} gap {}",
                a.name,
                a.gap_actual
            );
            if a.name != "M1" {
                max_gap = max_gap.max(a.gap_actual);
            }
        }
        let m4 = r.axis("M4");
        if rest.is_none() && m4.velocity == 0.0 && (m4.position - 2700.0).abs() < 1e-3 {
            rest = Some(k as f64 * T);
        }
    }
    assert_eq!(r.cmd_state(ids[0]), CommandState::Done);
    assert_eq!(r.pos("M1"), 3000.0);
    assert!(r.axis("M1").modulo_position.abs() < 1e-9);
    for (i, x) in [2900.0, 2800.0, 2700.0].iter().enumerate() {
        let n = format!("M{}", i + 2);
        assert!(
            (r.pos(&n) - x).abs() < 1e-3,
            "{n} rests at {x}: {}",
            r.pos(&n)
        );
        assert_eq!(r.cmd_state(ids[i + 1]), CommandState::Active);
    }
    (max_gap, rest.expect("M4 came to rest"))
}

#[test]
fn fast_keeps_gaps_closer_and_arrives_earlier() {
    let (gs, ts) = run(DefaultGapControlMode::Standard);
    let (gf, tf) = run(DefaultGapControlMode::Fast);
    eprintln!("Standard: max gap {gs:.1}, M4 rest {ts:.3} s; Fast: {gf:.1}, {tf:.3} s");
    assert!(gf < gs, "max gap Fast {gf} < Standard {gs}");
    assert!(tf < ts, "rest time Fast {tf} < Standard {ts}");
}
