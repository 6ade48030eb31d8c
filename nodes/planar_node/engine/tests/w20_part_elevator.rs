//! W20 – Part elevator (manual 6.6.1): Part 3 moves between CS1 and CS2 carrying the mover;
//! part enable coupling of §2.6.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;
use track_common::{enable_track, join, on_track, position_at};

const CS1: u32 = 0x0101_0090;
const CS2: u32 = 0x0101_00A0;
const P1: u32 = 0x0101_0020;
const P2: u32 = 0x0101_0030;
const P3: u32 = 0x0101_0080;

fn cfg() -> PlanarConfig {
    let part = |name: &str, oid: u32, pos: &[(u32, u32, f64, f64)], init: u32| PartConfig {
        name: name.into(),
        oid,
        tiles: vec![[0.0, 0.0]],
        positions: pos
            .iter()
            .map(|&(i, cs, x, y)| (i, PartPositionConfig { cs, x, y }))
            .collect(),
        initial_index: init,
    };
    let mut m = MoverConfig::new("M", 120.0, 120.0, 0.0);
    m.part_oid = P1;
    PlanarConfig {
        coordinate_systems: vec![CS1, CS2],
        parts: vec![
            part("part1", P1, &[(1, CS1, 0.0, 0.0)], 1),
            part("part2", P2, &[(1, CS2, 0.0, 0.0)], 1),
            part(
                "part3",
                P3,
                &[(1, CS1, 0.0, 240.0), (2, CS2, 0.0, 240.0)],
                2,
            ),
        ],
        environment: EnvironmentConfig {
            name: "env".into(),
            oid: 0x0101_0001,
            processing_unit_oid: 0x0101_0002,
        },
        movers: vec![m],
        ..Default::default()
    }
}

fn states(s: &Sim) -> [PlanarState; 3] {
    let p = s.snap();
    [
        p.part("part1").unwrap().state,
        p.part("part2").unwrap().state,
        p.part("part3").unwrap().state,
    ]
}

#[test]
fn w20_part_elevator() {
    use PlanarState::*;
    let mut s = Sim::new(cfg());
    assert_eq!(
        s.err(PlanarCommand::ActivatePosition {
            part: "part3".into(),
            position_index: 1
        })
        .error_id,
        errors::E_PART_NOT_INITIALIZED
    );
    assert_eq!(
        s.err(PlanarCommand::PartInitialize {
            part: "part3".into(),
            part_oid: P2
        })
        .error_id,
        errors::E_INVALID_PART
    );
    s.ok(PlanarCommand::PartInitialize {
        part: "part3".into(),
        part_oid: P3,
    });
    s.step();
    assert!(s.snap().part("part3").unwrap().is_initialized);
    s.enable("M");
    assert_eq!(
        states(&s),
        [Enabled, Disabled, Disabled],
        "CS1 parts on, CS2 parts off [manual]"
    );
    let a = s.ok(PlanarCommand::ActivatePosition {
        part: "part3".into(),
        position_index: 1,
    });
    assert_eq!(s.wait_final(a, 2.0), CommandState::Done);
    assert_eq!(s.snap().part("part3").unwrap().position_index, 1);
    s.steps(150);
    assert_eq!(
        states(&s),
        [Enabled, Disabled, Enabled],
        "Part 3 now in CS1 with an enabled mover"
    );
    // Several CS: ReferenceId 0 is invalid (§1.4).
    assert_eq!(
        s.err(mtp_ref("M", 120.0, 120.0, 0.0, 0)).error_id,
        errors::E_INVALID_REFERENCE_ID
    );
    // A target in CS2 is unreachable from CS1.
    assert_eq!(
        s.err(mtp_ref("M", 120.0, 120.0, 0.0, P2)).error_id,
        errors::E_TARGET_UNREACHABLE
    );
    let mv = s.ok(mtp_ref("M", 120.0, 120.0, 0.0, P3));
    assert_eq!(s.wait_final(mv, 5.0), CommandState::Done);
    let m = s.mover("M");
    assert_pos(&m, 120.0, 360.0);
    assert_eq!((m.coordinate_system_oid, m.part_oid), (CS1, P3));
    let a = s.ok(PlanarCommand::ActivatePosition {
        part: "part3".into(),
        position_index: 2,
    });
    s.step();
    assert_eq!(
        s.err(mtp_ref("M", 100.0, 100.0, 0.0, P3)).error_id,
        errors::E_INVALID_STATE,
        "no XY while the part moves"
    );
    assert_eq!(s.wait_final(a, 2.0), CommandState::Done);
    let m = s.mover("M");
    assert_pos(&m, 120.0, 360.0);
    assert_eq!(m.coordinate_system_oid, CS2);
    s.steps(150);
    assert_eq!(
        states(&s),
        [Disabled, Enabled, Enabled],
        "CS2 parts on, CS1 parts off"
    );
    let mv = s.ok(mtp_ref("M", 120.0, 120.0, 0.0, P2));
    assert_eq!(s.wait_final(mv, 5.0), CommandState::Done);
    let m = s.mover("M");
    assert_pos(&m, 120.0, 120.0);
    assert_eq!(m.part_oid, P2);
    // Unknown position index.
    assert_eq!(
        s.err(PlanarCommand::ActivatePosition {
            part: "part3".into(),
            position_index: 3
        })
        .error_id,
        errors::E_INVALID_POSITION_INDEX
    );
    // Disabling the last mover of CS2 switches its parts off (§2.6).
    let d = s.ok(PlanarCommand::MoverDisable { mover: "M".into() });
    assert_eq!(s.wait_final(d, 2.0), CommandState::Done);
    s.steps(150);
    assert_eq!(states(&s), [Disabled, Disabled, Disabled]);
}

/// §2.6 ForceDisable: movers on the part go to error (Abort), mover Enable then fails with
/// E_PART_DISABLED until AllowEnable.
#[test]
fn w20_force_disable() {
    let mut s = Sim::new(cfg());
    s.ok(PlanarCommand::PartInitialize {
        part: "part1".into(),
        part_oid: P1,
    });
    s.enable("M");
    s.ok(PlanarCommand::ForceDisable {
        part: "part1".into(),
    });
    s.step();
    let m = s.mover("M");
    assert_eq!(
        (m.state, m.error_id, m.error_reaction),
        (
            PlanarState::ErrorPending,
            errors::E_PART_DISABLED,
            ErrorReaction::Abort
        )
    );
    s.steps(200);
    assert_eq!(s.snap().part("part1").unwrap().state, PlanarState::Disabled);
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(
        s.mover("M").state,
        PlanarState::Disabled,
        "Abort → reset ends Disabled (T11)"
    );
    assert_eq!(
        s.err(PlanarCommand::MoverEnable { mover: "M".into() })
            .error_id,
        errors::E_PART_DISABLED
    );
    s.ok(PlanarCommand::AllowEnable {
        part: "part1".into(),
    });
    s.enable("M");
    assert_eq!(s.snap().part("part1").unwrap().state, PlanarState::Enabled);
}

/// §1.6 / §1.3: a track on Part 3 rides the elevator into the other coordinate system: its
/// positions are reported in the part's current CS, and a mover that came with the part joins
/// it and stays on it (s unchanged) through the next move between the systems.
#[test]
fn w20_track_follows_its_part_into_the_other_cs() {
    let mut c = cfg();
    c.tracks.push(TrackConfig {
        name: "T3".into(),
        part_oid: P3,
        geometry: vec![TrackGeometryItem::Line(TrackLineConfig {
            start: [30.0, 120.0],
            end: [210.0, 120.0],
        })],
        ..Default::default()
    });
    let mut s = Sim::new(c);
    s.ok(PlanarCommand::PartInitialize {
        part: "part3".into(),
        part_oid: P3,
    });
    s.step();
    s.enable("M");
    // Part 3 starts in CS2 (position index 2).
    let at = position_at(&mut s, "T3", 90.0);
    assert_eq!(at.reference_id, CS2);
    let a = s.ok(PlanarCommand::ActivatePosition {
        part: "part3".into(),
        position_index: 1,
    });
    assert_eq!(s.wait_final(a, 2.0), CommandState::Done);
    s.steps(150);
    let at = position_at(&mut s, "T3", 90.0);
    assert_eq!(
        at.reference_id, CS1,
        "the track is now in CS1 with its part"
    );
    assert!(
        (at.x - 120.0).abs() < 1e-9 && (at.y - 360.0).abs() < 1e-9,
        "{at:?}"
    );
    let mv = s.ok(mtp_ref("M", 120.0, 120.0, 0.0, P3));
    assert_eq!(s.wait_final(mv, 5.0), CommandState::Done);
    enable_track(&mut s, "T3");
    let j = s.ok(join("M", "T3", false));
    assert_eq!(
        s.wait_final(j, 5.0),
        CommandState::Done,
        "join in the new CS"
    );
    s.step();
    assert!((on_track(&s, "M").set_pos - 90.0).abs() < 1e-6);
    let a = s.ok(PlanarCommand::ActivatePosition {
        part: "part3".into(),
        position_index: 2,
    });
    assert_eq!(s.wait_final(a, 2.0), CommandState::Done);
    s.steps(150);
    let at = position_at(&mut s, "T3", 90.0);
    assert_eq!(at.reference_id, CS2);
    let m = s.mover("M");
    assert_eq!(m.coordinate_system_oid, CS2);
    assert_pos(&m, at.x, at.y);
    assert!(
        (on_track(&s, "M").set_pos - 90.0).abs() < 1e-6,
        "s kept on the ride"
    );
}
