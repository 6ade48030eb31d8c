//! W8 – Tracks on two parts (manual 6.2.5). Layout of W2 (CS 0x01010060, Part L at (0,0),
//! Part R at (240,0)). Track 1 on L: (40,120)–(240,120); Track 2 on R: StartFromTrack(Track 1)
//! and (260,120)–(440,120). M at (120,120) joins Track 1 at s = 80 and moves to Track 2,
//! s = 150: lengths 200 and 200 (the collinear 20 mm transition is exact), M ends at CS
//! (390,120) on R.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn config() -> PlanarConfig {
    let mut c = two_parts();
    c.tracks = vec![
        TrackConfig {
            name: "T1".into(),
            oid: 0,
            part_oid: PART_L,
            ..Default::default()
        },
        TrackConfig {
            name: "T2".into(),
            oid: 0,
            part_oid: PART_R,
            ..Default::default()
        },
    ];
    c
}

fn cs(x: f64, y: f64) -> PositionXYC {
    PositionXYC::with_ref(x, y, 0.0, CS)
}

#[test]
fn w08_tracks_on_two_parts() {
    let mut s = Sim::new(config());
    s.ok(PlanarCommand::TrackAppendLine {
        track: "T1".into(),
        start: cs(40.0, 120.0),
        end: cs(240.0, 120.0),
    });
    s.ok(PlanarCommand::TrackStartFromTrack {
        track: "T2".into(),
        other: "T1".into(),
    });
    s.ok(PlanarCommand::TrackAppendLine {
        track: "T2".into(),
        start: cs(260.0, 120.0),
        end: cs(440.0, 120.0),
    });
    enable_track(&mut s, "T1");
    enable_track(&mut s, "T2");
    assert_eq!(track(&s, "T1").length, 200.0);
    assert_eq!(track(&s, "T2").length, 200.0);
    assert_eq!(track(&s, "T1").part_oid, PART_L);
    assert_eq!(track(&s, "T2").part_oid, PART_R);
    s.enable("M");
    join_wait(&mut s, "M", "T1", true);
    assert!(close(on_track(&s, "M").set_pos, 80.0, POS_TOL));
    let id = s.ok(mot("M", "T2", 150.0));
    let mut crossed = false;
    while s.state(id) != Some(CommandState::Done) {
        s.step();
        crossed |= on_track(&s, "M").track == "T2";
        assert!(s.snap().time < 10.0);
    }
    assert!(crossed);
    let m = s.mover("M");
    let o = m.on_track.clone().unwrap();
    assert_eq!(o.track, "T2");
    assert!(close(o.set_pos, 150.0, POS_TOL));
    assert_pos(&m, 390.0, 120.0);
    assert_eq!(m.part_oid, PART_R);
    assert_eq!(track(&s, "T1").mover_count, 0);
    assert_eq!(track(&s, "T2").movers, vec!["M"]);
}

/// A track that leaves its part cannot be enabled (§5.4); a missing PartOID with two parts
/// neither.
#[test]
fn track_must_lie_on_its_part() {
    let mut c = config();
    c.tracks.push(TrackConfig::new("T3"));
    let mut s = Sim::new(c);
    s.ok(PlanarCommand::TrackAppendLine {
        track: "T1".into(),
        start: cs(40.0, 120.0),
        end: cs(300.0, 120.0),
    });
    let e = s.err(PlanarCommand::TrackEnable { track: "T1".into() });
    assert_eq!(e.error_id, E_GEOMETRY_INVALID);
    assert_eq!(track(&s, "T1").state, PlanarState::Disabled);
    s.ok(PlanarCommand::TrackAppendLine {
        track: "T3".into(),
        start: cs(40.0, 120.0),
        end: cs(100.0, 120.0),
    });
    let e = s.err(PlanarCommand::TrackEnable { track: "T3".into() });
    assert_eq!(
        e.error_id, E_GEOMETRY_INVALID,
        "PartOID missing with two parts"
    );
    // ReferenceId 0 is valid here (one CS, static parts); unknown ids are not.
    let e = s.err(PlanarCommand::TrackAppendLine {
        track: "T3".into(),
        start: PositionXYC::with_ref(0.0, 0.0, 0.0, 0x0BAD_0BAD),
        end: cs(10.0, 0.0),
    });
    assert_eq!(e.error_id, E_INVALID_REFERENCE_ID);
}
