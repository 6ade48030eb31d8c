//! Track helpers for the track examples (xplanar.md §7) on top of `common::Sim`.
#![allow(dead_code)]

use crate::common::*;
use motion_core::CommandState;
use planar_engine::*;

pub fn p(x: f64, y: f64) -> PositionXYC {
    PositionXYC::new(x, y, 0.0)
}

/// A config with movers at (x, y) and the named tracks (no parts).
pub fn cfg(movers: &[(&str, f64, f64)], tracks: &[&str]) -> PlanarConfig {
    PlanarConfig {
        movers: movers
            .iter()
            .map(|(n, x, y)| MoverConfig::new(n, *x, *y, 0.0))
            .collect(),
        tracks: tracks.iter().map(|t| TrackConfig::new(t)).collect(),
        ..Default::default()
    }
}

pub fn line(track: &str, a: (f64, f64), b: (f64, f64)) -> PlanarCommand {
    PlanarCommand::TrackAppendLine {
        track: track.into(),
        start: p(a.0, a.1),
        end: p(b.0, b.1),
    }
}

pub fn join(mover: &str, track: &str, use_orientation: bool) -> PlanarCommand {
    PlanarCommand::JoinTrack {
        mover: mover.into(),
        track: track.into(),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions { use_orientation },
    }
}

pub fn mot(mover: &str, track: &str, target: f64) -> PlanarCommand {
    mot_opt(mover, track, target, MoveOnTrackOptions::default())
}

pub fn mot_opt(
    mover: &str,
    track: &str,
    target: f64,
    options: MoveOnTrackOptions,
) -> PlanarCommand {
    PlanarCommand::MoveOnTrack {
        mover: mover.into(),
        track: track.into(),
        target_position: target,
        constraint: DynamicConstraint::default(),
        options,
    }
}

pub fn dir_opt(direction: Direction, turns: u32, tol: f64) -> MoveOnTrackOptions {
    MoveOnTrackOptions {
        direction,
        additional_turns: turns,
        modulo_tolerance: tol,
        ..Default::default()
    }
}

pub fn enable_track(s: &mut Sim, t: &str) {
    let id = s.ok(PlanarCommand::TrackEnable { track: t.into() });
    assert_eq!(
        s.wait_final(id, 5.0),
        CommandState::Done,
        "enable track {t}"
    );
}

pub fn track(s: &Sim, t: &str) -> TrackSnapshot {
    s.snap().track(t).unwrap().clone()
}

pub fn on_track(s: &Sim, m: &str) -> OnTrackSnapshot {
    s.mover(m).on_track.expect("mover on a track")
}

pub fn length(s: &mut Sim, t: &str) -> f64 {
    match s
        .cmd(PlanarCommand::TrackGetLength { track: t.into() })
        .unwrap()
        .value
    {
        ReplyValue::Scalar(v) => v,
        v => panic!("GetLength answered {v:?}"),
    }
}

pub fn position_at(s: &mut Sim, t: &str, arc: f64) -> PositionXYC {
    match s
        .cmd(PlanarCommand::TrackGetPositionAt {
            track: t.into(),
            arc_length: arc,
        })
        .unwrap()
        .value
    {
        ReplyValue::Position(v) => v,
        v => panic!("GetPositionAt answered {v:?}"),
    }
}

/// Joins and waits until the mover is OnTrack.
pub fn join_wait(s: &mut Sim, mover: &str, t: &str, use_orientation: bool) {
    let id = s.ok(join(mover, t, use_orientation));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done, "join {mover}");
    s.step();
    assert_eq!(
        s.mover(mover).command_mode,
        CommandMode::OnTrack,
        "{mover} OnTrack"
    );
}

/// One closed loop "L": a circle of radius `r` around (0, 0) starting at (r, 0), CCW.
pub fn circle_loop(s: &mut Sim, r: f64) {
    circle_loop_named(s, "L", r);
}

/// A closed circular loop named `t` (radius `r` around (0, 0), starting at (r, 0), CCW).
pub fn circle_loop_named(s: &mut Sim, t: &str, r: f64) {
    s.ok(PlanarCommand::TrackAppendCircle {
        track: t.into(),
        start: p(r, 0.0),
        end: p(r, 0.0),
        center: p(0.0, 0.0),
        clockwise: false,
    });
    s.ok(PlanarCommand::TrackCloseLoop { track: t.into() });
    enable_track(s, t);
}

/// True if the on-track state is on `track` inside the collision range `range` at the end of
/// that track (length `length`): the mover's part of a merging switch's zone (§5.6.4).
pub fn in_end_range(o: &OnTrackSnapshot, track: &str, length: f64, range: f64) -> bool {
    o.track == track && o.set_pos > length - range + 1e-6
}

/// W19's configuration: the movers, track T and group G.
pub fn group_config(movers: &[(&str, f64, f64)]) -> PlanarConfig {
    let mut c = cfg(movers, &["T"]);
    c.groups = vec![GroupConfig {
        name: "G".into(),
        oid: 0,
    }];
    c
}

/// W19's machine: track T (0,0)–(400,0) and group G enabled, the movers enabled, `members` and
/// T added to G.
pub fn group_with_track(movers: &[(&str, f64, f64)], members: &[&str]) -> Sim {
    let mut s = Sim::new(group_config(movers));
    s.ok(line("T", (0.0, 0.0), (400.0, 0.0)));
    enable_track(&mut s, "T");
    s.enable_group("G");
    for (m, _, _) in movers {
        s.enable(m);
    }
    for m in members {
        s.ok(PlanarCommand::MoverAddToGroup {
            mover: m.to_string(),
            group: "G".into(),
        });
    }
    s.ok(PlanarCommand::TrackAddToGroup {
        track: "T".into(),
        group: "G".into(),
    });
    s
}
