//! collision_avoidance.md §8.2 G5 (same configuration and commands ⇒ bit-identical states)
//! and §9.3 cancel (a cancelled goal halts its axis with the command's dynamics).

mod ca_common;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::{CommandState, Engine};

fn run() -> Vec<String> {
    let names: Vec<String> = (1..=6).map(|i| format!("M{i}")).collect();
    let m: Vec<(&str, f64)> = names
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), 2500.0 - 400.0 * i as f64))
        .collect();
    let mut r = CaRig::new(&m, ring(3000.0));
    let mut out = Vec::new();
    for (i, n) in names.iter().enumerate() {
        r.mv_rel(n, 500.0 + 300.0 * i as f64, 400.0 + 200.0 * i as f64);
    }
    for k in 0..3000 {
        if k == 700 {
            r.ok(CaCommand::Halt(HaltCa {
                axis: "M1".into(),
                deceleration: McLreal::Maximum,
                ..Default::default()
            }));
        }
        if k == 1500 {
            r.mv_rel("M1", 2000.0, 1500.0);
        }
        r.step();
        out.push(serde_json::to_string(&r.e.snapshot()).unwrap());
    }
    out
}

#[test]
fn g5_two_runs_are_bit_identical() {
    let a = run();
    let b = run();
    assert_eq!(a.len(), b.len());
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x, y, "cycle {k} differs");
    }
}

#[test]
fn cancel_halts_with_the_command_dynamics() {
    let mut r = CaRig::new(&[("A", 0.0)], open(10000.0));
    let id = r.mv_abs("A", 5000.0, 1000.0);
    r.steps(1000);
    let x0 = r.pos("A");
    r.e.cancel(id).unwrap();
    r.step();
    assert_eq!(r.cmd_state(id), CommandState::Aborted);
    r.until(1000, |r| r.group().all_axes_standing);
    // From 1000 mm/s with D 10000, J 100000 (axis defaults): v²/(2D) + v·D/(2J) = 100 mm.
    assert!(
        (r.pos("A") - x0 - 100.0).abs() < 2.0,
        "braked over ≈ 100 mm: {}",
        r.pos("A") - x0
    );
    assert_eq!(r.state(), GroupState::GroupStandby);
}
