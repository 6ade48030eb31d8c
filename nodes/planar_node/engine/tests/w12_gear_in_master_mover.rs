//! W12 – Gear-in with a master mover (manual 6.2.9) and W15 – follow a master mover through a
//! switch (manual 6.2.12); trail rules of §3.7 / W23 (order matters).

mod common;
mod track_common;
use common::*;
use motion_core::{CmdId, CommandState};
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

#[allow(clippy::too_many_arguments)]
fn gear(
    slave: &str,
    master: &str,
    trail: &[&str],
    m_sync: f64,
    m_track: &str,
    s_sync: f64,
    s_track: &str,
    follow: bool,
) -> PlanarCommand {
    PlanarCommand::GearInPosOnTrackWithMasterMover {
        mover: slave.into(),
        master_mover: master.into(),
        track_trail: trail.iter().map(|t| t.to_string()).collect(),
        master_sync_position: m_sync,
        master_sync_position_track: m_track.into(),
        slave_sync_position: s_sync,
        slave_sync_position_track: s_track.into(),
        constraint: DynamicConstraint::default(),
        options: GearInPosOnTrackWithMasterMoverOptions {
            follow_mover: follow,
            ..Default::default()
        },
    }
}

/// W12's machine: MA on TM, SL on TS, both joined; MA.MoveOnTrack(500), and a cycle later SL
/// geared to MA (sync 100 ↔ 100). Returns the simulation, the MoveOnTrack's and the GearIn's
/// ids.
fn w12_coupled() -> (Sim, CmdId, CmdId) {
    let mut s = Sim::new(w12_config());
    s.ok(line("TM", (100.0, 620.0), (860.0, 620.0)));
    s.ok(line("TS", (100.0, 100.0), (860.0, 100.0)));
    enable_track(&mut s, "TM");
    enable_track(&mut s, "TS");
    s.enable("MA");
    s.enable("SL");
    join_wait(&mut s, "MA", "TM", true);
    join_wait(&mut s, "SL", "TS", true);
    let mid = s.ok(mot("MA", "", 500.0));
    s.step();
    let g = s.ok(gear("SL", "MA", &[], 100.0, "TM", 100.0, "TS", false));
    (s, mid, g)
}

fn w12_config() -> PlanarConfig {
    cfg(&[("MA", 100.0, 620.0), ("SL", 100.0, 100.0)], &["TM", "TS"])
}

/// W12: master track (100,620)–(860,620), slave track (100,100)–(860,100); both join at s = 0;
/// master.MoveOnTrack(500); next cycle the slave gears in (sync 100 ↔ 100): it comes to rest at
/// s = 500 with the master (offset 0); the feedback stays Active (never Done), inSync at rest.
#[test]
fn w12_gear_in_with_master_mover() {
    let (mut s, mid, g) = w12_coupled();
    assert_eq!(s.wait_final(mid, 10.0), CommandState::Done);
    s.steps(2000);
    assert_eq!(s.state(g), Some(CommandState::Active), "GearIn has no Done");
    let o = on_track(&s, "SL");
    assert!(close(o.set_pos, 500.0, POS_TOL), "slave at {}", o.set_pos);
    assert_eq!(o.set_velo, 0.0);
    assert!(o.in_sync);
    assert_eq!(o.gear_master.as_deref(), Some("MA"));
    assert_eq!(
        track(&s, "TS").operation_mode,
        TrackOperationMode::Moving,
        "trail Moving"
    );
    // The master moves on: the slave follows 1:1 and is in sync at rest again.
    let mid = s.ok(mot("MA", "", 650.0));
    assert_eq!(s.wait_final(mid, 10.0), CommandState::Done);
    s.steps(1000);
    assert!(close(on_track(&s, "SL").set_pos, 650.0, POS_TOL));
    // A following command aborts the coupling.
    let id = s.ok(mot("SL", "", 300.0));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    assert_eq!(s.state(g), Some(CommandState::Aborted));
}

/// §5.8.1: when the master drives the slave past the end of its trail, the slave stops exactly
/// at the end, reports E_TRACK_BOUNDARY_REACHED and no longer follows.
#[test]
fn gear_in_stops_at_the_trail_end() {
    let mut s = Sim::new(cfg(
        &[("MA", 100.0, 620.0), ("SL", 100.0, 100.0)],
        &["TM", "TS"],
    ));
    s.ok(line("TM", (100.0, 620.0), (1860.0, 620.0)));
    s.ok(line("TS", (100.0, 100.0), (860.0, 100.0)));
    enable_track(&mut s, "TM");
    enable_track(&mut s, "TS");
    s.enable("MA");
    s.enable("SL");
    join_wait(&mut s, "MA", "TM", true);
    join_wait(&mut s, "SL", "TS", true);
    let g = s.ok(gear("SL", "MA", &[], 0.0, "TM", 0.0, "TS", false));
    s.ok(mot("MA", "", 1500.0));
    assert_eq!(
        s.wait_final(g, 20.0),
        CommandState::Error(E_TRACK_BOUNDARY_REACHED)
    );
    let o = on_track(&s, "SL");
    assert!(
        close(o.set_pos, 760.0, 1e-6),
        "stopped exactly at the end: {}",
        o.set_pos
    );
    assert_eq!(o.set_velo, 0.0);
    s.steps(200);
    assert!(
        close(on_track(&s, "SL").set_pos, 760.0, 1e-6),
        "no longer follows"
    );
}

/// W15: track_in (100,360)–(400,360); track_out1 and track_out2 start from track_in. Master at
/// 200, slave at 0 on track_in; master → track_out1 500; slave gears in with followMover
/// (master sync 210, slave sync 10, both on track_in): it follows 200 mm behind, takes the
/// master's branch and stops at 300 on track_out1; it is never on track_out2.
#[test]
fn w15_follow_master_through_a_switch() {
    let mut s = Sim::new(cfg(
        &[("MA", 100.0, 360.0), ("SL", 100.0, 160.0)],
        &["in", "out1", "out2"],
    ));
    s.ok(line("in", (100.0, 360.0), (400.0, 360.0)));
    enable_track(&mut s, "in");
    s.ok(PlanarCommand::TrackStartFromTrack {
        track: "out1".into(),
        other: "in".into(),
    });
    s.ok(line("out1", (450.0, 410.0), (860.0, 620.0)));
    s.ok(PlanarCommand::TrackStartFromTrack {
        track: "out2".into(),
        other: "in".into(),
    });
    s.ok(line("out2", (450.0, 310.0), (860.0, 100.0)));
    enable_track(&mut s, "out1");
    enable_track(&mut s, "out2");
    s.enable("MA");
    s.enable("SL");
    join_wait(&mut s, "MA", "in", true);
    let id = s.ok(mot("MA", "in", 200.0));
    assert_eq!(s.wait_final(id, 10.0), CommandState::Done);
    join_wait(&mut s, "SL", "in", true);
    assert!(close(on_track(&s, "SL").set_pos, 0.0, 1e-6));
    let mid = s.ok(mot("MA", "out1", 500.0));
    s.step();
    let g = s.ok(gear("SL", "MA", &[], 210.0, "in", 10.0, "in", true));
    assert_eq!(s.wait_final(mid, 20.0), CommandState::Done);
    for _ in 0..3000 {
        s.step();
        assert_ne!(on_track(&s, "SL").track, "out2");
    }
    assert_eq!(s.state(g), Some(CommandState::Active));
    let o = on_track(&s, "SL");
    assert_eq!(o.track, "out1");
    assert!(close(o.set_pos, 300.0, POS_TOL), "slave at {}", o.set_pos);
    assert!(close(on_track(&s, "MA").set_pos, 500.0, POS_TOL));
}

/// §3.7 / W23: a trail must start with the slave's track, be contiguous and distinct.
#[test]
fn invalid_trails() {
    let mut s = Sim::new(cfg(
        &[("MA", 100.0, 620.0), ("SL", 100.0, 100.0)],
        &["T1", "T2", "TM"],
    ));
    s.ok(line("T1", (100.0, 100.0), (400.0, 100.0)));
    enable_track(&mut s, "T1");
    s.ok(PlanarCommand::TrackStartFromTrack {
        track: "T2".into(),
        other: "T1".into(),
    });
    s.ok(line("T2", (500.0, 100.0), (860.0, 100.0)));
    s.ok(line("TM", (100.0, 620.0), (860.0, 620.0)));
    enable_track(&mut s, "T2");
    enable_track(&mut s, "TM");
    s.enable("MA");
    s.enable("SL");
    join_wait(&mut s, "MA", "TM", true);
    join_wait(&mut s, "SL", "T1", true);
    for (trail, why) in [
        (&["T2", "T1"][..], "order matters"),
        (&["T1", "T1"][..], "distinct"),
        (&["T1", "TM"][..], "contiguous"),
    ] {
        let e = s.err(gear("SL", "MA", trail, 100.0, "TM", 100.0, "T1", false));
        assert_eq!(e.error_id, E_TRACKTRAIL_INVALID, "{why}");
    }
    let e = s.err(gear("SL", "MA", &[], 100.0, "TM", 100.0, "T2", false));
    assert_eq!(
        e.error_id, E_TRACKTRAIL_INVALID,
        "sync track not in the trail"
    );
    let e = s.err(gear("SL", "SL", &[], 100.0, "T1", 100.0, "T1", false));
    assert_eq!(e.error_id, E_INVALID_PARAMETER, "master = slave");
    // Valid trail [T1, T2]: accepted.
    s.ok(gear(
        "SL",
        "MA",
        &["T1", "T2"],
        100.0,
        "TM",
        100.0,
        "T2",
        false,
    ));
}

/// A lockstep state stream builds each snapshot in an older one's buffers
/// (`Engine::snapshot_into`): the result equals a fresh snapshot, whatever the old one held:
/// here a geared slave (gear master named) and a group with a member track and a mover moving
/// on it, each refilled into the other's snapshot and into its own from before the motion.
#[test]
fn snapshot_into_an_old_snapshot_equals_a_fresh_one() {
    use motion_core::Engine;
    // W12's coupling: SL geared to MA, MA moving.
    let mut geared_before = Sim::new(w12_config()).eng.snapshot();
    let (mut geared, _, _) = w12_coupled();
    geared.steps(200);
    // W19's group: movers A, B and track T members of G (C not), A moving on T.
    let movers = [("A", 0.0, 0.0), ("B", 240.0, 320.0), ("C", 700.0, 500.0)];
    let mut grouped_before = Sim::new(group_config(&movers)).eng.snapshot();
    let mut grouped = group_with_track(&movers, &["A", "B"]);
    join_wait(&mut grouped, "A", "T", true);
    grouped.ok(mot("A", "", 150.0));
    grouped.steps(100);

    let (g, p) = (geared.eng.snapshot(), grouped.eng.snapshot());
    let sl = on_track(&geared, "SL");
    assert_eq!(sl.gear_master.as_deref(), Some("MA"), "{sl:?}");
    assert!(on_track(&geared, "MA").set_velo > 0.0, "MA moving");
    assert!(on_track(&grouped, "A").set_velo > 0.0, "A moving");
    let group = p.group("G").expect("G");
    assert_eq!(
        (group.member_count, &group.movers, &group.tracks),
        (
            3,
            &vec!["A".to_string(), "B".into()],
            &vec!["T".to_string()]
        )
    );
    assert_eq!(p.mover("A").and_then(|m| m.group.as_deref()), Some("G"));
    let mut into_other = (g.clone(), p.clone());
    grouped.eng.snapshot_into(&mut into_other.0);
    geared.eng.snapshot_into(&mut into_other.1);
    assert_eq!(into_other.0, p);
    assert_eq!(into_other.1, g);
    geared.eng.snapshot_into(&mut geared_before);
    grouped.eng.snapshot_into(&mut grouped_before);
    assert_eq!(geared_before, g);
    assert_eq!(grouped_before, p);
}
