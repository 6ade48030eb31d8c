//! §1.6 "Check collision against static objects" at TrackAddToGroup (§5.11 proposal): with the
//! parameter TRUE the track's tube (half-width = half the larger maximal mover side, 77.5 mm by
//! default) must lie inside the stator area and must not overlap the tube of another member
//! track of the group except at their connections; otherwise E_COLLISION with objectInfo
//! {Environment} or {Track}. With the parameter FALSE (default) nothing is checked.

mod common;
mod track_common;
use common::*;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn config(tracks: &str) -> PlanarConfig {
    let yaml = format!("groups: [{{name: G}}]\ntracks:\n{tracks}");
    serde_yaml::from_str(&yaml).unwrap_or_else(|e| panic!("{yaml}: {e}"))
}

/// Sim with the tracks enabled and G enabled; `stators`: lower-left corners to add.
fn sim(tracks: &str, stators: &[(f64, f64)]) -> Sim {
    let mut s = Sim::new(config(tracks));
    for &(x, y) in stators {
        s.ok(PlanarCommand::AddStator {
            lower_x: x,
            lower_y: y,
        });
    }
    let names: Vec<String> = s.snap().tracks.iter().map(|t| t.name.clone()).collect();
    for t in &names {
        enable_track(&mut s, t);
    }
    s.enable_group("G");
    s
}

fn add(s: &mut Sim, t: &str) -> Result<PlanarReply, motion_core::Rejection> {
    s.cmd(PlanarCommand::TrackAddToGroup {
        track: t.into(),
        group: "G".into(),
    })
}

fn members(s: &Sim) -> Vec<String> {
    s.snap().group("G").unwrap().tracks.clone()
}

/// Four tiles in a row: the stator area is x ∈ [0, 960], y ∈ [0, 240].
const ROW: [(f64, f64); 4] = [(0.0, 0.0), (240.0, 0.0), (480.0, 0.0), (720.0, 0.0)];

#[test]
fn the_tube_must_lie_inside_the_stator_area() {
    let tracks = "
  - {name: In, check_static_collision: true, geometry: [{line: {start: [77.5, 120], end: [882.5, 120]}}]}
  - {name: Left, check_static_collision: true, geometry: [{line: {start: [77, 120], end: [500, 120]}}]}
  - {name: Top, check_static_collision: true, geometry: [{line: {start: [100, 163], end: [800, 163]}}]}
  - {name: Unchecked, geometry: [{line: {start: [40, 120], end: [500, 120]}}]}
";
    // The tube of `In` touches the area's left and right edges exactly: inside (closed sets).
    let mut s = sim(tracks, &ROW);
    assert!(add(&mut s, "In").is_ok());
    // 0.5 mm too far left; 0.5 mm too high (163 + 77.5 = 240.5).
    let mut s = sim(tracks, &ROW);
    for t in ["Left", "Top"] {
        let e = add(&mut s, t).unwrap_err();
        assert_eq!(e.error_id, E_COLLISION, "{t}: {e}");
        assert!(e.message.contains("stator area"), "{e}");
        let env = s.snap().environment.oid;
        assert_eq!(
            e.object,
            Some(motion_core::ObjectRef { kind: 304, id: env })
        );
        let info = s.eng.last_object_info();
        assert_eq!(
            (info.object_type, info.id),
            (PlanarObjectType::Environment, env)
        );
    }
    // Without the check the same kind of track is accepted.
    assert!(add(&mut s, "Unchecked").is_ok());
    assert_eq!(members(&s), vec!["Unchecked"]);
    // A larger maximal mover widens the tube: 250 mm wide at y = 120 leaves the area (200 fits).
    let wide = "
  - {name: W, check_static_collision: true, max_mover_width: 250, geometry: [{line: {start: [100, 120], end: [800, 120]}}]}
";
    let mut s = sim(wide, &ROW);
    let e = add(&mut s, "W").unwrap_err();
    assert_eq!(e.error_id, E_COLLISION, "{e}");
    let mut s = sim(&wide.replace("250", "200"), &ROW);
    assert!(add(&mut s, "W").is_ok());
}

#[test]
fn member_tracks_must_not_overlap() {
    // Plane without stators (unbounded). Tubes are 155 mm wide: centre lines 150 mm apart
    // overlap, 155 mm apart touch (not a collision).
    let tracks = "
  - {name: A, check_static_collision: true, geometry: [{line: {start: [0, 0], end: [1000, 0]}}]}
  - {name: Near, check_static_collision: true, geometry: [{line: {start: [0, 150], end: [1000, 150]}}]}
  - {name: Touch, check_static_collision: true, geometry: [{line: {start: [0, -155], end: [1000, -155]}}]}
  - {name: Loose, geometry: [{line: {start: [0, 100], end: [1000, 100]}}]}
";
    let mut s = sim(tracks, &[]);
    assert!(add(&mut s, "A").is_ok());
    let e = add(&mut s, "Near").unwrap_err();
    assert_eq!(e.error_id, E_COLLISION, "{e}");
    let a = track(&s, "A").oid;
    assert_eq!(e.object, Some(motion_core::ObjectRef { kind: 303, id: a }));
    assert_eq!(
        s.eng.last_object_info().object_type,
        PlanarObjectType::Track
    );
    assert!(add(&mut s, "Touch").is_ok());
    // The check belongs to the track being added: an unchecked track may overlap.
    assert!(add(&mut s, "Loose").is_ok());
    // Once the unchecked overlapping track is in, a checked one meeting it is refused; after
    // A and Loose leave the group, Near is accepted.
    assert_eq!(add(&mut s, "Near").unwrap_err().error_id, E_COLLISION);
    for t in ["A", "Loose"] {
        s.ok(PlanarCommand::TrackRemoveFromGroup { track: t.into() });
    }
    assert!(add(&mut s, "Near").is_ok());
    let mut m = members(&s);
    m.sort();
    assert_eq!(m, vec!["Near", "Touch"]);
}

#[test]
fn connected_tracks_may_overlap_at_their_connections() {
    // T1 ends in a switch at (1000, 0): T2 goes straight on, T3 branches up; T4 continues T2
    // at a plain joint (2000, 0). All are checked and all are accepted.
    let tracks = "
  - {name: T1, check_static_collision: true, geometry: [{line: {start: [0, 0], end: [1000, 0]}}]}
  - {name: T2, check_static_collision: true, starts_from: [T1], geometry: [{line: {start: [1000, 0], end: [2000, 0]}}]}
  - {name: T3, check_static_collision: true, starts_from: [T1], geometry: [{line: {start: [1300, 300], end: [1300, 1000]}}]}
  - {name: T4, check_static_collision: true, starts_from: [T2], geometry: [{line: {start: [2000, 0], end: [2600, 0]}}]}
  - {name: X, check_static_collision: true, geometry: [{line: {start: [1500, -500], end: [1500, 500]}}]}
";
    let mut s = sim(tracks, &[]);
    for t in ["T1", "T2", "T3", "T4"] {
        assert!(add(&mut s, t).is_ok(), "{t}");
    }
    // A track crossing T2 without a connection is refused.
    let e = add(&mut s, "X").unwrap_err();
    assert_eq!(e.error_id, E_COLLISION, "{e}");
    assert_eq!(e.object.unwrap().id, track(&s, "T2").oid);
}

#[test]
fn bad_add_requests_keep_the_group_unchanged() {
    let tracks = "
  - {name: A, check_static_collision: true, geometry: [{line: {start: [0, 0], end: [1000, 0]}}]}
";
    let mut s = sim(tracks, &[]);
    let e = add(&mut s, "nope").unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::UNKNOWN_OBJECT, "{e}");
    let e = s
        .cmd(PlanarCommand::TrackAddToGroup {
            track: "A".into(),
            group: "nope".into(),
        })
        .unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::UNKNOWN_OBJECT, "{e}");
    assert!(members(&s).is_empty());
    assert!(add(&mut s, "A").is_ok());
    assert_eq!(members(&s), vec!["A"]);
}
