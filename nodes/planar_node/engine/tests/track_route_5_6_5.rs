//! §5.6.5 cross-track moves on a ring of four open tracks (bottom → right → top → left →
//! bottom, each starting where the previous one ends): a target behind the mover on another
//! track is reached by going round (shortest forward route, cumulative arc length positive),
//! a target on the mover's own track follows the same-track rules of §5.6.1 (Positive behind
//! the mover → E_TARGET_UNREACHABLE; NonModulo drives back directly), a route through a
//! disabled track does not exist (E_TARGET_UNREACHABLE), and gap control holds along the
//! route across every junction.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

const RING: [&str; 4] = ["bottom", "right", "top", "left"];

fn ring() -> Sim {
    let yaml = "
movers:
  - {name: A, initial_pose: {x: 500, y: 120}}
  - {name: B, initial_pose: {x: 300, y: -200}}
tracks:
  - {name: bottom, geometry: [{line: {start: [300, 120], end: [660, 120]}}]}
  - {name: right, starts_from: [bottom], geometry: [{line: {start: [840, 200], end: [840, 280]}}]}
  - {name: top, starts_from: [right], geometry: [{line: {start: [660, 360], end: [300, 360]}}]}
  - {name: left, starts_from: [top], geometry: [{line: {start: [120, 280], end: [120, 200]}}], ends_at: [bottom]}
";
    let cfg: PlanarConfig = serde_yaml::from_str(yaml).unwrap();
    let mut s = Sim::new(cfg);
    for t in RING {
        enable_track(&mut s, t);
    }
    s
}

fn lengths(s: &Sim) -> [f64; 4] {
    RING.map(|t| track(s, t).length)
}

/// Cumulative arc length of a mover along the ring, counted from bottom's start (one lap).
fn ring_pos(l: &[f64; 4], o: &OnTrackSnapshot) -> f64 {
    let k = RING.iter().position(|t| *t == o.track).unwrap();
    l[..k].iter().sum::<f64>() + o.set_pos
}

#[test]
fn a_target_behind_on_another_track_is_reached_by_going_round() {
    let mut s = ring();
    s.enable("A");
    join_wait(&mut s, "A", "bottom", true);
    let l = lengths(&s);
    assert!(l.iter().all(|&x| x > 0.0));
    // A at 200 on bottom; `left` ends where bottom starts, i.e. just behind A: forwards the
    // route is right, top, left (three junctions).
    assert!(close(on_track(&s, "A").set_pos, 200.0, 1e-6));
    let start = ring_pos(&l, &on_track(&s, "A"));
    let id = s.ok(mot("A", "left", 40.0));
    let mut seen = vec!["bottom".to_string()];
    let mut travelled = 0.0;
    let mut last = start;
    let mut n = 0;
    while s.state(id) != Some(CommandState::Done) {
        s.step();
        let o = on_track(&s, "A");
        if seen.last() != Some(&o.track) {
            seen.push(o.track.clone());
        }
        let p = ring_pos(&l, &o);
        // Forward only: never backwards across junctions.
        assert!(p >= last - 1e-9, "moved back: {last} → {p} on {}", o.track);
        travelled += p - last;
        last = p;
        n += 1;
        assert!(n < 20_000, "not done: {:?}", s.history.get(&id));
    }
    assert_eq!(seen, vec!["bottom", "right", "top", "left"]);
    let o = on_track(&s, "A");
    assert!(close(o.set_pos, 40.0, POS_TOL), "{o:?}");
    // The exact route length: rest of bottom + right + top + 40 on left.
    let expected = (l[0] - 200.0) + l[1] + l[2] + 40.0;
    assert!(
        close(travelled, expected, POS_TOL),
        "{travelled} vs {expected}"
    );
    let q = position_at(&mut s, "left", 40.0);
    assert_pos(&s.mover("A"), q.x, q.y);
    assert_eq!(track(&s, "left").movers, vec!["A"]);
    // From `left` back to `bottom`, behind where A started: forward through the link.
    let id = s.ok(mot("A", "bottom", 100.0));
    assert_eq!(s.wait_final(id, 20.0), CommandState::Done);
    let o = on_track(&s, "A");
    assert_eq!(o.track, "bottom");
    assert!(close(o.set_pos, 100.0, POS_TOL));
}

#[test]
fn the_own_track_follows_the_same_track_rules() {
    let mut s = ring();
    s.enable("A");
    join_wait(&mut s, "A", "bottom", true);
    // Positive behind the mover on its own open track: unreachable (§5.6.1), even though a
    // route round the ring exists; naming the own track is the same track (§3.2).
    for track in ["", "bottom"] {
        let e = s.err(mot_opt(
            "A",
            track,
            50.0,
            dir_opt(Direction::Positive, 0, 0.0),
        ));
        assert_eq!(e.error_id, E_TARGET_UNREACHABLE, "{track:?}: {e}");
    }
    // NonModulo drives back directly.
    let id = s.ok(mot("A", "bottom", 50.0));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    let o = on_track(&s, "A");
    assert_eq!(o.track, "bottom");
    assert!(close(o.set_pos, 50.0, POS_TOL));
    // Cross-track moves go forward only.
    let e = s.err(mot_opt(
        "A",
        "top",
        50.0,
        dir_opt(Direction::Negative, 0, 0.0),
    ));
    assert_eq!(e.error_id, E_TARGET_UNREACHABLE, "{e}");
}

#[test]
fn no_route_through_a_disabled_track() {
    let mut s = ring();
    s.enable("A");
    join_wait(&mut s, "A", "bottom", true);
    let id = s.ok(PlanarCommand::TrackDisable {
        track: "top".into(),
    });
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    // `left` lies behind `top`: no traversable route; `right` is still reachable.
    let e = s.err(mot("A", "left", 40.0));
    assert_eq!(e.error_id, E_TARGET_UNREACHABLE, "{e}");
    assert!(e.message.contains("no route"), "{e}");
    let id = s.ok(mot("A", "right", 40.0));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    assert_eq!(on_track(&s, "A").track, "right");
    // A disabled target track is not ready (E_TRACK_NOT_READY), whatever the route.
    let e = s.err(mot("A", "top", 40.0));
    assert_eq!(e.error_id, E_TRACK_NOT_READY, "{e}");
}

#[test]
fn gap_control_holds_along_the_route() {
    // B follows A round the ring with a gap of 350 mm; A stops on `top`, so B waits exactly
    // one gap behind it, measured along the route across the junctions. (The ring's corners
    // are tight: with the default 200 mm the footprints would overlap in a corner, and the
    // no-overlap guard would stop the movers with E_COLLISION.)
    let mut s = ring();
    s.enable("A");
    s.enable("B");
    join_wait(&mut s, "A", "bottom", true);
    join_wait(&mut s, "B", "bottom", true);
    let l = lengths(&s);
    assert!(close(on_track(&s, "A").set_pos, 200.0, 1e-6));
    // B joins at the closest point, bottom's start.
    assert!(close(on_track(&s, "B").set_pos, 0.0, 1e-6));
    let a = s.ok(mot("A", "top", 60.0));
    let gap = 350.0;
    let b = s.ok(mot_opt(
        "B",
        "left",
        40.0,
        MoveOnTrackOptions {
            gap,
            ..Default::default()
        },
    ));
    // They start 200 mm apart: B waits until A is one gap ahead, and the distance never
    // falls below what it has reached (up to the gap).
    let mut floor = 200.0;
    let mut n = 0;
    while !(s.state(a) == Some(CommandState::Done)
        && on_track(&s, "B").set_velo == 0.0
        && on_track(&s, "B").waiting)
    {
        s.step();
        let (oa, ob) = (on_track(&s, "A"), on_track(&s, "B"));
        let d = ring_pos(&l, &oa) - ring_pos(&l, &ob);
        assert!(
            d >= floor - 1e-6,
            "gap along the route: {d} (A {oa:?} B {ob:?})"
        );
        floor = f64::max(floor, d.min(gap));
        n += 1;
        assert!(
            n < 30_000,
            "A {:?} B {:?} {oa:?} {ob:?} {:?} {:?}",
            s.history.get(&a),
            s.history.get(&b),
            s.mover("A"),
            s.mover("B")
        );
    }
    let (oa, ob) = (on_track(&s, "A"), on_track(&s, "B"));
    assert_eq!(oa.track, "top");
    assert!(close(oa.set_pos, 60.0, POS_TOL));
    let d = ring_pos(&l, &oa) - ring_pos(&l, &ob);
    assert!(close(d, gap, POS_TOL), "B waits one gap behind: {d}");
    assert_eq!(s.state(b), Some(CommandState::Active));
    // A moves on round to `bottom`, out of the way: B reaches its target.
    let a = s.ok(mot("A", "bottom", 300.0));
    assert_eq!(s.wait_final(b, 20.0), CommandState::Done);
    assert_eq!(s.wait_final(a, 20.0), CommandState::Done);
    assert_eq!(on_track(&s, "B").track, "left");
    assert!(close(on_track(&s, "B").set_pos, 40.0, POS_TOL));
}
