//! §1.6 track init parameters "Starts from tracks", "Geometric information", "Ends at
//! tracks", "Closed loop" (V3.1.10.44: "act exactly like the PLC commands") and "PartOID"
//! (positions in the part system): a config-built track equals the command-built one, and
//! every bad geometry is refused at load with its §6.2 id, the key and the track.

mod common;
mod track_common;
use common::*;
use motion_core::{CommandState, Engine, ErrorId, Rejection};
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn config(yaml: &str) -> PlanarConfig {
    serde_yaml::from_str(yaml).unwrap_or_else(|e| panic!("{yaml}: {e}"))
}

fn load_err(yaml: &str) -> Rejection {
    match PlanarEngine::new(config(yaml)) {
        Ok(_) => panic!("accepted: {yaml}"),
        Err(e) => e,
    }
}

/// A ring of four tracks (corners are generated transitions), a full circle closed into a
/// loop and a track built with AppendPosition.
const RING: &str = "
movers: [{name: M, initial_pose: {x: 480, y: 120}}]
tracks:
  - name: bottom
    geometry: [{line: {start: [300, 120], end: [660, 120]}}]
  - name: right
    starts_from: [bottom]
    geometry: [{line: {start: [840, 200], end: [840, 280]}}]
  - name: top
    starts_from: [right]
    geometry: [{line: {start: [660, 360], end: [300, 360]}}]
  - name: left
    starts_from: [top]
    geometry: [{line: {start: [120, 280], end: [120, 200]}}]
    ends_at: [bottom]
  - name: circle
    geometry: [{circle: {start: [480, 600], end: [480, 600], center: [480, 720]}}]
    closed_loop: true
  - name: hook
    geometry:
      - {position: {x: 0, y: 1000, c: 0}}
      - {position: {x: 300, y: 1100, c: 90}}
      - {line: {start: [400, 1300], end: [400, 1400]}}
";

fn ring_by_commands() -> Sim {
    let names = ["bottom", "right", "top", "left", "circle", "hook"];
    let mut s = Sim::new(cfg(&[("M", 480.0, 120.0)], &names));
    let from = |t: &str, o: &str| PlanarCommand::TrackStartFromTrack {
        track: t.into(),
        other: o.into(),
    };
    s.ok(line("bottom", (300.0, 120.0), (660.0, 120.0)));
    s.ok(from("right", "bottom"));
    s.ok(line("right", (840.0, 200.0), (840.0, 280.0)));
    s.ok(from("top", "right"));
    s.ok(line("top", (660.0, 360.0), (300.0, 360.0)));
    s.ok(from("left", "top"));
    s.ok(line("left", (120.0, 280.0), (120.0, 200.0)));
    s.ok(PlanarCommand::TrackEndAtTrack {
        track: "left".into(),
        other: "bottom".into(),
    });
    s.ok(PlanarCommand::TrackAppendCircle {
        track: "circle".into(),
        start: p(480.0, 600.0),
        end: p(480.0, 600.0),
        center: p(480.0, 720.0),
        clockwise: false,
    });
    s.ok(PlanarCommand::TrackCloseLoop {
        track: "circle".into(),
    });
    for (x, y, c) in [(0.0, 1000.0, 0.0), (300.0, 1100.0, 90.0)] {
        s.ok(PlanarCommand::TrackAppendPosition {
            track: "hook".into(),
            position: PositionXYC::new(x, y, c),
        });
    }
    s.ok(line("hook", (400.0, 1300.0), (400.0, 1400.0)));
    s
}

/// Same length, links, closed flag and poses (every 10 % of the length) on both sims.
fn assert_same_tracks(a: &mut Sim, b: &mut Sim, names: &[&str]) {
    for t in names {
        let (ta, tb) = (track(a, t), track(b, t));
        assert!(ta.length > 0.0, "{t} has geometry");
        assert_eq!(ta.length, tb.length, "{t} length");
        assert_eq!(ta.closed_loop, tb.closed_loop, "{t} closed loop");
        assert_eq!(ta.previous_tracks, tb.previous_tracks, "{t} previous");
        assert_eq!(ta.subsequent_tracks, tb.subsequent_tracks, "{t} subsequent");
        assert_eq!(ta.state, PlanarState::Disabled, "{t} starts Disabled");
        assert_eq!(ta.operation_mode, TrackOperationMode::Uninitialized);
        for k in 0..=10 {
            let s = ta.length * k as f64 / 10.0;
            assert_eq!(position_at(a, t, s), position_at(b, t, s), "{t} at {s}");
        }
    }
}

#[test]
fn config_built_tracks_equal_command_built_ones() {
    let mut a = Sim::new(config(RING));
    let mut b = ring_by_commands();
    let names = ["bottom", "right", "top", "left", "circle", "hook"];
    assert_same_tracks(&mut a, &mut b, &names);
    // The spec's geometry: straight pieces exact, the circle 2πr, the ring linked around.
    assert_eq!(track(&a, "bottom").length, 360.0);
    assert!(close(
        track(&a, "circle").length,
        240.0 * std::f64::consts::PI,
        1e-6
    ));
    assert!(track(&a, "circle").closed_loop);
    assert_eq!(track(&a, "bottom").previous_tracks, vec!["left"]);
    assert_eq!(track(&a, "left").subsequent_tracks, vec!["bottom"]);
    let l = track(&a, "hook").length;
    let h = position_at(&mut a, "hook", l);
    assert!(close(h.x, 400.0, 1e-9) && close(h.y, 1400.0, 1e-9) && close(h.c, 90.0, 1e-9));
    // The start-up commands left no events behind; ids start at 1 as without tracks.
    let mut a = Sim::new(config(RING));
    assert!(a.step().is_empty(), "no start-up events");
    let id = a.ok(PlanarCommand::TrackEnable {
        track: "bottom".into(),
    });
    assert_eq!(id, motion_core::CmdId(1));
}

#[test]
fn a_config_built_ring_carries_movers_around() {
    let mut s = Sim::new(config(RING));
    for t in ["bottom", "right", "top", "left"] {
        enable_track(&mut s, t);
    }
    s.enable("M");
    join_wait(&mut s, "M", "bottom", false);
    assert!(close(on_track(&s, "M").set_pos, 180.0, POS_TOL));
    // Around the ring onto the start of `bottom` again: through right, top, left.
    let l = track(&s, "left").length;
    let id = s.ok(mot("M", "left", l));
    assert_eq!(s.wait_final(id, 30.0), CommandState::Done);
    let m = s.mover("M");
    let q = m.set_pos;
    assert!(
        close(q.x, 300.0, POS_TOL) && close(q.y, 120.0, POS_TOL),
        "{q:?}"
    );
}

const PART: u32 = 0x0101_0020;

/// One part whose origin lies at (240, 0): the geometry is given part-local.
fn on_part(track: &str) -> String {
    format!(
        "
coordinate_systems: [0x01010060]
parts:
  - {{name: P, oid: 0x01010020, tiles: [[0, 0], [240, 0], [0, 240], [240, 240]],
     positions: {{1: {{cs: 0x01010060, x: 240, y: 0}}}}}}
tracks:
{track}"
    )
}

#[test]
fn positions_are_in_the_part_system() {
    let mut a = Sim::new(config(&on_part(
        "  - {name: T, part_oid: 0x01010020, geometry: [{line: {start: [40, 120], end: [440, 120]}}]}\n",
    )));
    let mut cfg_b = config(&on_part("  - {name: T, part_oid: 0x01010020}\n"));
    cfg_b.movers.clear();
    let mut b = Sim::new(cfg_b);
    b.ok(PlanarCommand::TrackAppendLine {
        track: "T".into(),
        start: PositionXYC::with_ref(40.0, 120.0, 0.0, PART),
        end: PositionXYC::with_ref(440.0, 120.0, 0.0, PART),
    });
    assert_same_tracks(&mut a, &mut b, &["T"]);
    let q = position_at(&mut a, "T", 0.0);
    assert_eq!((q.x, q.y), (280.0, 120.0), "CS = part origin + local");
    // Without part_oid the only part is the track's part.
    let mut c = Sim::new(config(&on_part(
        "  - {name: T, geometry: [{line: {start: [40, 120], end: [440, 120]}}]}\n",
    )));
    assert_same_tracks(&mut a, &mut c, &["T"]);
}

/// The W14 network (manual 6.2.11) from the config: Advanced links with part positions.
#[test]
fn advanced_links_from_the_config() {
    let yaml = "
coordinate_systems: [0x01010060]
parts:
  - {name: P1, oid: 0x01010020, tiles: [[0, 0], [0, 240], [0, 480], [0, 720], [240, 0], [240, 240], [240, 480], [240, 720]],
     positions: {1: {cs: 0x01010060, x: 0, y: 0}}}
  - {name: P2, oid: 0x01010030, tiles: [[0, 0], [0, 240]],
     positions: {1: {cs: 0x01010060, x: 480, y: 0}, 2: {cs: 0x01010060, x: 480, y: 480}}}
environment: {name: env, oid: 0x01010001, processing_unit_oid: 0x01010002}
tracks:
  - name: T1
    part_oid: 0x01010020
    starts_from: [{track: T3, this_track_part_position_index: 1, other_track_part_position_index: 1}]
    geometry:
      - {line: {start: [440, 120], end: [160, 120]}}
      - {line: {start: [120, 160], end: [120, 800]}}
      - {line: {start: [160, 840], end: [440, 840]}}
    ends_at: [{track: T3, this_track_part_position_index: 1, other_track_part_position_index: 2}]
  - name: T2
    part_oid: 0x01010020
    starts_from: [{track: T3, this_track_part_position_index: 1, other_track_part_position_index: 2}]
    geometry:
      - {line: {start: [440, 600], end: [400, 600]}}
      - {line: {start: [360, 560], end: [360, 400]}}
      - {line: {start: [400, 360], end: [440, 360]}}
    ends_at:
      - {track: T3, this_track_part_position_index: 1, other_track_part_position_index: 1,
         link_only_in_specified_part_positions: true}
  - name: T3
    part_oid: 0x01010030
    geometry:
      - {line: {start: [0, 360], end: [80, 360]}}
      - {line: {start: [120, 320], end: [120, 160]}}
      - {line: {start: [80, 120], end: [0, 120]}}
";
    // T3 is listed last but built first: T1 and T2 wait for it.
    let mut s = Sim::new(config(yaml));
    let l1 = track(&s, "T1").length;
    let e1 = position_at(&mut s, "T1", l1);
    assert!(
        close(e1.x, 480.0, 1e-9) && close(e1.y, 840.0, 1e-9),
        "{e1:?}"
    );
    let b2 = position_at(&mut s, "T2", 0.0);
    assert!(
        close(b2.x, 480.0, 1e-9) && close(b2.y, 600.0, 1e-9),
        "{b2:?}"
    );
    let (l2, l3) = (track(&s, "T2").length, track(&s, "T3").length);
    assert!((l2 - l3).abs() < 0.01, "mirror images: {l2} vs {l3}");
    let trav = |s: &Sim, t: &str| track(s, t).traversable_subsequent_tracks;
    assert_eq!(
        trav(&s, "T2"),
        vec!["T3"],
        "lower: T2.end → T3 (link only here)"
    );
    assert_eq!(trav(&s, "T3"), vec!["T1"]);
    assert!(trav(&s, "T1").is_empty(), "T1.end open");
    for t in ["T1", "T2", "T3"] {
        enable_track(&mut s, t);
    }
    s.ok(PlanarCommand::PartInitialize {
        part: "P2".into(),
        part_oid: 0x0101_0030,
    });
    let id = s.ok(PlanarCommand::ActivatePosition {
        part: "P2".into(),
        position_index: 2,
    });
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    assert_eq!(trav(&s, "T1"), vec!["T3"]);
    assert_eq!(trav(&s, "T3"), vec!["T2"]);
    assert!(trav(&s, "T2").is_empty());
}

/// Every bad init geometry: (tracks section, expected id, texts the message must contain).
const BAD: &[(&str, ErrorId, &[&str])] = &[
    (
        "  - {name: A, geometry: [{line: {start: [0, 0], end: [0, 0]}}]}",
        E_GEOMETRY_INVALID,
        &["tracks[0].geometry[0]", "track 'A'"],
    ),
    (
        "  - {name: A, geometry: [{line: {start: [0, 0], end: [100, 0]}}, {line: {start: [100, 0], end: [100, 100]}}]}",
        E_GEOMETRY_INVALID,
        &["tracks[0].geometry[1]"],
    ),
    (
        "  - {name: A, geometry: [{circle: {start: [0, 0], end: [100, 150], center: [0, 100]}}]}",
        E_GEOMETRY_INVALID,
        &["tracks[0].geometry[0]"],
    ),
    (
        "  - {name: A, geometry: [{circle: {start: [0, 0], end: [0, 0], center: [0, 0]}}]}",
        E_GEOMETRY_INVALID,
        &["tracks[0].geometry[0]"],
    ),
    (
        "  - {name: A, geometry: [{line: {start: [.nan, 0], end: [100, 0]}}]}",
        ErrorId::NOT_FINITE,
        &["tracks[0].geometry[0]", "start.x"],
    ),
    (
        "  - {name: A, geometry: [{position: {x: 0, y: .inf}}]}",
        ErrorId::NOT_FINITE,
        &["tracks[0].geometry[0]", "position.y"],
    ),
    (
        "  - {name: A, starts_from: [Z], geometry: [{line: {start: [0, 0], end: [100, 0]}}]}",
        ErrorId::UNKNOWN_OBJECT,
        &["tracks[0].starts_from[0]", "Z"],
    ),
    (
        "  - {name: A, ends_at: [{track: Z}], geometry: [{line: {start: [0, 0], end: [100, 0]}}]}",
        ErrorId::UNKNOWN_OBJECT,
        &["tracks[0].ends_at[0]", "Z"],
    ),
    (
        "  - {name: L, geometry: [{circle: {start: [0, 0], end: [0, 0], center: [0, 100]}}], closed_loop: true}\n  - {name: B, starts_from: [L]}",
        E_GEOMETRY_INVALID,
        &["tracks[1].starts_from[0]", "track 'B'", "closed loop"],
    ),
    (
        "  - {name: A, geometry: [{line: {start: [0, 0], end: [100, 0]}}]}\n  - {name: C, geometry: [{line: {start: [0, 200], end: [100, 200]}}]}\n  - {name: B, starts_from: [A, C]}",
        E_ALREADY_CONNECTED,
        &["tracks[2].starts_from[1]"],
    ),
    (
        "  - {name: A, geometry: [{line: {start: [0, 0], end: [100, 0]}}]}\n  - {name: B, geometry: [{line: {start: [300, 100], end: [400, 100]}}], ends_at: [A], closed_loop: true}",
        E_TRACK_LOCKED,
        &["tracks[1].closed_loop"],
    ),
    (
        "  - {name: A, closed_loop: true}",
        E_GEOMETRY_INVALID,
        &["tracks[0].closed_loop"],
    ),
    (
        "  - {name: A, geometry: [{line: {start: [0, 0], end: [100, 0]}}]}\n  - {name: B, ends_at: [A]}",
        E_GEOMETRY_INVALID,
        &["tracks[1].ends_at[0]", "non-empty"],
    ),
    (
        "  - {name: A, geometry: [{line: {start: [0, 0], end: [100, 0]}}]}\n  - {name: B, ends_at: [C], geometry: [{line: {start: [300, 100], end: [400, 100]}}]}\n  - {name: C}",
        E_GEOMETRY_INVALID,
        &["tracks[1].ends_at[0]", "empty"],
    ),
    (
        "  - {name: A, starts_from: [B], geometry: [{line: {start: [0, 0], end: [100, 0]}}]}\n  - {name: B, starts_from: [A], geometry: [{line: {start: [300, 0], end: [400, 0]}}]}",
        E_GEOMETRY_INVALID,
        &["tracks[0].starts_from[0]", "circular"],
    ),
    (
        "  - {name: A, geometry: [{line: {start: [0, 0], end: [100, 0]}}]}\n  - {name: B, starts_from: [A], geometry: [{line: {start: [200, 0], end: [300, 0]}}], ends_at: [B]}",
        E_GEOMETRY_INVALID,
        &["tracks[1].ends_at[0]"],
    ),
];

#[test]
fn bad_init_geometry_is_refused_at_load() {
    for (tracks, id, needles) in BAD {
        let e = load_err(&format!("tracks:\n{tracks}\n"));
        assert_eq!(e.error_id, *id, "{tracks}: {e}");
        for n in *needles {
            assert!(e.message.contains(n), "{tracks}: '{n}' not in {e}");
        }
    }
}

#[test]
fn bad_part_geometry_is_refused_at_load() {
    // Off the part (the line leaves the 2 × 2 tiles at x = 480 local).
    let e = load_err(&on_part(
        "  - {name: T, geometry: [{line: {start: [40, 120], end: [600, 120]}}]}\n",
    ));
    assert_eq!(e.error_id, E_GEOMETRY_INVALID, "{e}");
    assert!(e.message.contains("tracks[0].geometry") && e.message.contains("part 'P'"));
    // A position index the part does not have.
    let e = load_err(&on_part(
        "  - {name: A, geometry: [{line: {start: [40, 120], end: [200, 120]}}]}
  - {name: B, starts_from: [{track: A, other_track_part_position_index: 3}]}\n",
    ));
    assert_eq!(e.error_id, E_INVALID_POSITION_INDEX, "{e}");
    assert!(e.message.contains("tracks[1].starts_from[0]"), "{e}");
    // With two parts the PartOID is required (§1.6).
    let two = "
coordinate_systems: [0x01010060]
parts:
  - {name: P, oid: 0x01010020, tiles: [[0, 0]], positions: {1: {cs: 0x01010060, x: 0, y: 0}}}
  - {name: Q, oid: 0x01010030, tiles: [[0, 0]], positions: {1: {cs: 0x01010060, x: 240, y: 0}}}
tracks:
  - {name: T, geometry: [{line: {start: [40, 120], end: [200, 120]}}]}
";
    let e = load_err(two);
    assert_eq!(e.error_id, E_GEOMETRY_INVALID, "{e}");
    assert!(e.message.contains("tracks[0].part_oid"), "{e}");
    // A config without init geometry still loads (geometry then comes from commands).
    assert!(PlanarEngine::new(config(&two.replace(
        ", geometry: [{line: {start: [40, 120], end: [200, 120]}}]",
        ""
    )))
    .is_ok());
}

#[test]
fn unknown_keys_in_init_geometry_are_refused() {
    for yaml in [
        "tracks: [{name: A, geometry: [{lin: {start: [0, 0], end: [1, 0]}}]}]",
        "tracks: [{name: A, geometry: [{line: {start: [0, 0], end: [1, 0], centre: [0, 0]}}]}]",
        "tracks: [{name: A, starts_from: [{track: B, this_index: 1}]}]",
        "tracks: [{name: A, geometry: [{line: {start: [0, 0, 0], end: [1, 0]}}]}]",
    ] {
        assert!(
            serde_yaml::from_str::<PlanarConfig>(yaml).is_err(),
            "accepted: {yaml}"
        );
    }
    // The engine never saw them, and a valid one still goes through `command` semantics.
    let mut e = PlanarEngine::new(config(
        "tracks: [{name: A, geometry: [{line: {start: [0, 0], end: [100, 0]}}]}]",
    ))
    .unwrap();
    let r = e.command(PlanarCommand::TrackAppendLine {
        track: "A".into(),
        start: p(100.0, 0.0),
        end: p(200.0, 0.0),
    });
    assert!(r.is_ok(), "appending after the init geometry: {r:?}");
}
