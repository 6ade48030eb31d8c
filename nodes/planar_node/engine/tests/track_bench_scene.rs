//! The benchmark scene (`bench_loop`): every mover circulates on the closed loop under gap
//! control (200 mm arc length, never violated), and the engine is deterministic: two runs give
//! identical snapshots (style: determinism is a tested contract).

use motion_core::{Engine, Tick};
use planar_engine::*;

fn run(n: usize, cycles: u64) -> PlanarEngine {
    let mut e = bench_loop(n);
    let mut ev = vec![];
    for k in 0..cycles {
        e.step(
            Tick {
                index: 10_000 + k,
                dt: 0.001,
            },
            &mut ev,
        );
        ev.clear();
        let s = e.snapshot();
        let l = s.tracks[0].length;
        let mut pos: Vec<f64> = s
            .movers
            .iter()
            .map(|m| m.on_track.as_ref().expect("on the loop").set_pos_modulo)
            .collect();
        pos.sort_by(f64::total_cmp);
        for w in 0..pos.len() {
            let d = (pos[(w + 1) % pos.len()] - pos[w]).rem_euclid(l);
            assert!(d >= 200.0 - 1e-6, "cycle {k}: neighbours {d} mm apart");
        }
    }
    e
}

#[test]
fn bench_loop_circulates_with_gap_control() {
    let e = run(40, 1500);
    let s = e.snapshot();
    assert_eq!(s.tracks[0].mover_count, 40);
    assert!(s.tracks[0].closed_loop);
    assert_eq!(s.tracks[0].operation_mode, TrackOperationMode::Moving);
    assert!(s
        .movers
        .iter()
        .all(|m| m.command_mode == CommandMode::OnTrack && m.active.xy.is_some()));
    let moving = s
        .movers
        .iter()
        .filter(|m| m.on_track.as_ref().unwrap().set_velo > 1.0)
        .count();
    assert!(moving > 0, "the movers circulate");
}

#[test]
fn two_runs_give_identical_snapshots() {
    let a = run(25, 600).snapshot();
    let b = run(25, 600).snapshot();
    assert_eq!(a, b);
}
