//! The benchmark scene: `n` movers circulating on one closed-loop track with gap control.

use crate::command::PlanarCommand;
use crate::config::{MoverConfig, PlanarConfig, TrackConfig};
use crate::engine::PlanarEngine;
use crate::geometry::V2;
use crate::track::geometry::TrackGeometry;
use crate::track::MoveOnTrackOptions;
use crate::types::{Direction, DynamicConstraint, MoveToPositionOptions, PositionXYC};
use motion_core::{Engine, Tick};

/// Spacing of the movers along the loop at the start \[mm\].
const SPACING: f64 = 260.0;
/// Corner gap of the rectangle loop (filled by generated transitions) \[mm\].
const CORNER: f64 = 400.0;

fn loop_corners(n: usize) -> (f64, f64) {
    // Rectangle with rounded corners; length ≈ 2(W + H) − 4·(2 − π/2)·CORNER ≥ n·SPACING.
    let need = (n.max(4) as f64) * SPACING + 8.0 * CORNER;
    let w = (need / 2.0 * 0.6).max(2000.0);
    let h = (need / 2.0 - w).max(1500.0);
    (w, h)
}

/// The loop geometry used by [`bench_loop`] (lines with generated corner transitions).
pub fn bench_loop_geometry(n: usize) -> TrackGeometry {
    let (w, h) = loop_corners(n);
    let c = CORNER;
    let mut g = TrackGeometry::default();
    let lines = [
        (V2::new(c, 0.0), V2::new(w - c, 0.0)),
        (V2::new(w, c), V2::new(w, h - c)),
        (V2::new(w - c, h), V2::new(c, h)),
        (V2::new(0.0, h - c), V2::new(0.0, c)),
    ];
    for (a, b) in lines {
        g.append_line(a, b).expect("bench loop geometry");
    }
    g.close_loop().expect("bench loop closes");
    g
}

/// An engine with `n_movers` movers on one closed loop (track "loop"), all joined (C
/// dependent) and circulating: every mover runs `MoveOnTrack` in the positive direction with
/// additional turns for about 1 km of travel, velocities 800/1000/1200 mm/s so that gap control (200 mm) keeps
/// the faster ones behind the slower ones. The engine is returned after it has run 0.5 s of
/// motion, ready for timing `step` (cycle 1 ms).
pub fn bench_loop(n_movers: usize) -> PlanarEngine {
    let geo = bench_loop_geometry(n_movers);
    let l = geo.length();
    let (w, h) = loop_corners(n_movers);
    let c = CORNER;
    let movers = (0..n_movers)
        .map(|k| {
            let p = geo.pose_at(l * k as f64 / n_movers as f64);
            MoverConfig::new(&format!("m{k}"), p.p.x, p.p.y, 0.0)
        })
        .collect();
    let cfg = PlanarConfig {
        movers,
        tracks: vec![TrackConfig::new("loop")],
        ..Default::default()
    };
    let mut e = PlanarEngine::new(cfg).expect("bench config");
    let pt = |x: f64, y: f64| PositionXYC::new(x, y, 0.0);
    let cmds = [
        PlanarCommand::TrackAppendLine {
            track: "loop".into(),
            start: pt(c, 0.0),
            end: pt(w - c, 0.0),
        },
        PlanarCommand::TrackAppendLine {
            track: "loop".into(),
            start: pt(w, c),
            end: pt(w, h - c),
        },
        PlanarCommand::TrackAppendLine {
            track: "loop".into(),
            start: pt(w - c, h),
            end: pt(c, h),
        },
        PlanarCommand::TrackAppendLine {
            track: "loop".into(),
            start: pt(0.0, h - c),
            end: pt(0.0, c),
        },
        PlanarCommand::TrackCloseLoop {
            track: "loop".into(),
        },
        PlanarCommand::TrackEnable {
            track: "loop".into(),
        },
    ];
    for cmd in cmds {
        e.command(cmd).expect("bench track");
    }
    for k in 0..n_movers {
        e.command(PlanarCommand::MoverEnable {
            mover: format!("m{k}"),
        })
        .expect("bench enable");
    }
    let mut ev = Vec::new();
    let mut index = 0;
    let mut run = |e: &mut PlanarEngine, cycles: usize| {
        for _ in 0..cycles {
            e.step(Tick { index, dt: 0.001 }, &mut ev);
            index += 1;
            ev.clear();
        }
    };
    run(&mut e, 150);
    for k in 0..n_movers {
        e.command(PlanarCommand::JoinTrack {
            mover: format!("m{k}"),
            track: "loop".into(),
            constraint: DynamicConstraint::default(),
            options: MoveToPositionOptions::default(),
        })
        .expect("bench join");
    }
    for _ in 0..30 {
        run(&mut e, 100);
        let s = e.snapshot();
        if s.tracks[0].operation_mode == crate::track::TrackOperationMode::Standing {
            break;
        }
    }
    // About 1 km of travel each (≥ 15 min at 1 m/s), within the planner's numeric range.
    let turns = (1.0e6 / l).ceil() as u32;
    for k in 0..n_movers {
        e.command(PlanarCommand::MoveOnTrack {
            mover: format!("m{k}"),
            track: String::new(),
            target_position: 0.0,
            constraint: DynamicConstraint {
                velocity: [800.0, 1000.0, 1200.0][k % 3],
                ..Default::default()
            },
            options: MoveOnTrackOptions {
                direction: Direction::Positive,
                additional_turns: turns,
                ..Default::default()
            },
        })
        .expect("bench move");
    }
    run(&mut e, 500);
    e
}
