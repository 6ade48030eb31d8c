//! W14 – Network on movable parts (manual 6.2.11): Part 1 (2 × 4 tiles at (0,0), static),
//! Part 2 (1 × 2 tiles) at position 1 = (480,0) "lower" or 2 = (480,480) "upper". Track 3 on
//! Part 2; Tracks 2 and 1 on Part 1 linked to Track 3 with the Advanced options. Lower: T2.end
//! ↔ T3.start at (480,360) and T3.end ↔ T1.start at (480,120) traversable, T1.end open;
//! upper: T1.end ↔ T3.start at (480,840) and T3.end ↔ T2.start at (480,600), T2.end open;
//! |L(T2) − L(T3)| < 0.01 (mirror images).

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;
use track_common::*;

const P1: u32 = 0x0101_0020;
const P2: u32 = 0x0101_0030;

fn config() -> PlanarConfig {
    let tiles1: Vec<[f64; 2]> = (0..2)
        .flat_map(|i| (0..4).map(move |j| [240.0 * i as f64, 240.0 * j as f64]))
        .collect();
    PlanarConfig {
        coordinate_systems: vec![CS],
        parts: vec![
            PartConfig {
                name: "P1".into(),
                oid: P1,
                tiles: tiles1,
                positions: [(
                    1,
                    PartPositionConfig {
                        cs: CS,
                        x: 0.0,
                        y: 0.0,
                    },
                )]
                .into_iter()
                .collect(),
                initial_index: 1,
            },
            PartConfig {
                name: "P2".into(),
                oid: P2,
                tiles: vec![[0.0, 0.0], [0.0, 240.0]],
                positions: [
                    (
                        1,
                        PartPositionConfig {
                            cs: CS,
                            x: 480.0,
                            y: 0.0,
                        },
                    ),
                    (
                        2,
                        PartPositionConfig {
                            cs: CS,
                            x: 480.0,
                            y: 480.0,
                        },
                    ),
                ]
                .into_iter()
                .collect(),
                initial_index: 1,
            },
        ],
        environment: EnvironmentConfig {
            name: "env".into(),
            oid: 0x0101_0001,
            processing_unit_oid: 0x0101_0002,
        },
        tracks: vec![
            TrackConfig {
                name: "T1".into(),
                oid: 0,
                part_oid: P1,
                ..Default::default()
            },
            TrackConfig {
                name: "T2".into(),
                oid: 0,
                part_oid: P1,
                ..Default::default()
            },
            TrackConfig {
                name: "T3".into(),
                oid: 0,
                part_oid: P2,
                ..Default::default()
            },
        ],
        ..Default::default()
    }
}

fn ln(t: &str, a: (f64, f64), b: (f64, f64), part: u32) -> PlanarCommand {
    PlanarCommand::TrackAppendLine {
        track: t.into(),
        start: PositionXYC::with_ref(a.0, a.1, 0.0, part),
        end: PositionXYC::with_ref(b.0, b.1, 0.0, part),
    }
}

fn adv(this: u32, other: u32) -> TrackLinkAdvancedOptions {
    TrackLinkAdvancedOptions {
        this_track_part_position_index: this,
        other_track_part_position_index: other,
        link_only_in_specified_part_positions: false,
    }
}

#[test]
fn w14_network_on_movable_parts() {
    let mut s = Sim::new(config());
    s.ok(ln("T3", (0.0, 360.0), (80.0, 360.0), P2));
    s.ok(ln("T3", (120.0, 320.0), (120.0, 160.0), P2));
    s.ok(ln("T3", (80.0, 120.0), (0.0, 120.0), P2));
    s.ok(PlanarCommand::TrackStartFromTrackAdvanced {
        track: "T2".into(),
        other: "T3".into(),
        options: adv(1, 2),
    });
    s.ok(ln("T2", (440.0, 600.0), (400.0, 600.0), P1));
    s.ok(ln("T2", (360.0, 560.0), (360.0, 400.0), P1));
    s.ok(ln("T2", (400.0, 360.0), (440.0, 360.0), P1));
    s.ok(PlanarCommand::TrackEndAtTrackAdvanced {
        track: "T2".into(),
        other: "T3".into(),
        options: adv(1, 1),
    });
    s.ok(PlanarCommand::TrackStartFromTrackAdvanced {
        track: "T1".into(),
        other: "T3".into(),
        options: adv(1, 1),
    });
    s.ok(ln("T1", (440.0, 120.0), (160.0, 120.0), P1));
    s.ok(ln("T1", (120.0, 160.0), (120.0, 800.0), P1));
    s.ok(ln("T1", (160.0, 840.0), (440.0, 840.0), P1));
    s.ok(PlanarCommand::TrackEndAtTrackAdvanced {
        track: "T1".into(),
        other: "T3".into(),
        options: adv(1, 2),
    });
    for t in ["T3", "T2", "T1"] {
        enable_track(&mut s, t);
    }
    // Geometry of the link points.
    let end_of = |s: &mut Sim, t: &str| {
        let l = track(s, t).length;
        position_at(s, t, l)
    };
    let e2 = end_of(&mut s, "T2");
    assert!(close(e2.x, 480.0, 1e-9) && close(e2.y, 360.0, 1e-9));
    let b1 = position_at(&mut s, "T1", 0.0);
    assert!(close(b1.x, 480.0, 1e-9) && close(b1.y, 120.0, 1e-9));
    let e1 = end_of(&mut s, "T1");
    assert!(close(e1.x, 480.0, 1e-9) && close(e1.y, 840.0, 1e-9));
    let b2 = position_at(&mut s, "T2", 0.0);
    assert!(close(b2.x, 480.0, 1e-9) && close(b2.y, 600.0, 1e-9));
    let (l2, l3) = (track(&s, "T2").length, track(&s, "T3").length);
    assert!((l2 - l3).abs() < 0.01, "mirror images: {l2} vs {l3}");
    // Part 2 lower.
    let trav = |s: &Sim, t: &str| track(s, t).traversable_subsequent_tracks;
    assert_eq!(trav(&s, "T2"), vec!["T3"]);
    assert_eq!(trav(&s, "T3"), vec!["T1"]);
    assert!(trav(&s, "T1").is_empty(), "T1.end open");
    // Part 2 upper.
    s.ok(PlanarCommand::PartInitialize {
        part: "P2".into(),
        part_oid: P2,
    });
    let id = s.ok(PlanarCommand::ActivatePosition {
        part: "P2".into(),
        position_index: 2,
    });
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    assert_eq!(trav(&s, "T1"), vec!["T3"]);
    assert_eq!(trav(&s, "T3"), vec!["T2"]);
    assert!(trav(&s, "T2").is_empty(), "T2.end open");
    // All links exist logically.
    assert_eq!(track(&s, "T3").subsequent_tracks, vec!["T2", "T1"]);
    assert_eq!(track(&s, "T3").previous_tracks, vec!["T2", "T1"]);
}

/// linkOnlyInSpecifiedPartPositions: the link T3.end → T2.start exists only with Part 2 in
/// position 2; a non-existing position index is refused (E_INVALID_POSITION_INDEX).
#[test]
fn link_only_in_specified_positions() {
    let mut s = Sim::new(config());
    s.ok(ln("T3", (120.0, 360.0), (0.0, 360.0), P2));
    let e = s.err(PlanarCommand::TrackStartFromTrackAdvanced {
        track: "T2".into(),
        other: "T3".into(),
        options: adv(1, 7),
    });
    assert_eq!(e.error_id, planar_engine::errors::E_INVALID_POSITION_INDEX);
    s.ok(PlanarCommand::TrackStartFromTrackAdvanced {
        track: "T2".into(),
        other: "T3".into(),
        options: TrackLinkAdvancedOptions {
            link_only_in_specified_part_positions: true,
            ..adv(1, 2)
        },
    });
    s.ok(ln("T2", (440.0, 840.0), (200.0, 840.0), P1));
    enable_track(&mut s, "T3");
    enable_track(&mut s, "T2");
    let b2 = position_at(&mut s, "T2", 0.0);
    assert!(
        close(b2.x, 480.0, 1e-9) && close(b2.y, 840.0, 1e-9),
        "T3's end with P2 upper"
    );
    assert!(
        track(&s, "T3").traversable_subsequent_tracks.is_empty(),
        "P2 lower"
    );
    s.ok(PlanarCommand::PartInitialize {
        part: "P2".into(),
        part_oid: P2,
    });
    let id = s.ok(PlanarCommand::ActivatePosition {
        part: "P2".into(),
        position_index: 2,
    });
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    assert_eq!(track(&s, "T3").traversable_subsequent_tracks, vec!["T2"]);
}

/// Tracks move with their part (§1.6): a mover on Track 3 rides along when Part 2 moves up,
/// stays on the track, and then drives over the link that is traversable in that position
/// onto Track 2 (§5.6.5); the link not traversable there is refused as a route.
#[test]
fn mover_rides_with_the_part_and_crosses_the_link() {
    let mut c = config();
    let mut m = MoverConfig::new("M", 120.0, 240.0, 0.0);
    m.part_oid = P2;
    c.movers = vec![m];
    let mut s = Sim::new(c);
    s.ok(ln("T3", (0.0, 360.0), (80.0, 360.0), P2));
    s.ok(ln("T3", (120.0, 320.0), (120.0, 160.0), P2));
    s.ok(ln("T3", (80.0, 120.0), (0.0, 120.0), P2));
    s.ok(PlanarCommand::TrackStartFromTrackAdvanced {
        track: "T2".into(),
        other: "T3".into(),
        options: adv(1, 2),
    });
    s.ok(ln("T2", (440.0, 600.0), (400.0, 600.0), P1));
    s.ok(ln("T2", (360.0, 560.0), (360.0, 400.0), P1));
    s.ok(ln("T2", (400.0, 360.0), (440.0, 360.0), P1));
    for t in ["T3", "T2"] {
        enable_track(&mut s, t);
    }
    s.enable("M");
    join_wait(&mut s, "M", "T3", false);
    let s0 = on_track(&s, "M").set_pos;
    assert_pos(&s.mover("M"), 600.0, 240.0);
    // Lower position: T3 → T2 is not traversable.
    assert_eq!(
        s.err(mot("M", "T2", 100.0)).error_id,
        planar_engine::errors::E_TARGET_UNREACHABLE
    );
    s.ok(PlanarCommand::PartInitialize {
        part: "P2".into(),
        part_oid: P2,
    });
    let id = s.ok(PlanarCommand::ActivatePosition {
        part: "P2".into(),
        position_index: 2,
    });
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    assert_pos(&s.mover("M"), 600.0, 720.0);
    assert!(
        close(on_track(&s, "M").set_pos, s0, 1e-9),
        "still on T3 at the same arc length"
    );
    let q = position_at(&mut s, "T3", s0);
    assert!(
        close(q.x, 600.0, 1e-9) && close(q.y, 720.0, 1e-9),
        "T3 moved with P2"
    );
    let id = s.ok(mot("M", "T2", 100.0));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    let o = on_track(&s, "M");
    assert_eq!(o.track, "T2");
    let q = position_at(&mut s, "T2", 100.0);
    assert_pos(&s.mover("M"), q.x, q.y);
    assert_eq!(s.mover("M").part.as_deref(), Some("P1"));
}
