//! W11 – Gear-in with an axis (manual 6.2.8) and W23 – synchronisation over two tracks
//! (manual 6.8.1), with a virtual master axis X (§5.8.4).

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn sim(tracks: &[&str]) -> Sim {
    let mut c = cfg(&[("M", 0.0, 0.0)], tracks);
    c.axes = vec![VirtualAxisConfig {
        name: "X".into(),
        oid: 0,
    }];
    Sim::new(c)
}

fn axis_move(target: f64) -> PlanarCommand {
    PlanarCommand::AxisMoveAbsolute {
        axis: "X".into(),
        position: target,
        velocity: 30.0,
        acceleration: 100.0,
        deceleration: 100.0,
        jerk: 100.0,
    }
}

fn gear(trail: &[&str], m_sync: f64, s_sync: f64, s_track: &str) -> PlanarCommand {
    PlanarCommand::GearInPosOnTrack {
        mover: "M".into(),
        master_axis: "X".into(),
        track_trail: trail.iter().map(|t| t.to_string()).collect(),
        master_sync_position: m_sync,
        slave_sync_position: s_sync,
        slave_sync_position_track: s_track.into(),
        constraint: DynamicConstraint::default(),
        options: GearInPosOnTrackOptions::default(),
    }
}

fn w11(target: f64) -> (Sim, motion_core::CmdId, motion_core::CmdId) {
    let mut s = sim(&["T"]);
    s.ok(line("T", (100.0, 100.0), (860.0, 100.0)));
    enable_track(&mut s, "T");
    assert_eq!(track(&s, "T").length, 760.0);
    s.enable("M");
    join_wait(&mut s, "M", "T", true);
    assert!(close(on_track(&s, "M").set_pos, 0.0, 1e-6));
    s.ok(PlanarCommand::AxisPower {
        axis: "X".into(),
        enable: true,
    });
    let ax = s.ok(axis_move(target));
    s.step();
    let g = s.ok(gear(&[], 100.0, 100.0, "T"));
    (s, ax, g)
}

/// W11: the mover follows the axis 1:1 (offset 0) and rests at s = 600 = (700,100) when the
/// axis stops; the feedback stays Busy/Active, never Done.
#[test]
fn w11_gear_in_with_an_axis() {
    let (mut s, ax, g) = w11(600.0);
    let mut n = 0;
    while s.state(ax) != Some(CommandState::Done) {
        s.step();
        let x = s.snap().axes[0].position;
        let o = on_track(&s, "M");
        assert!(
            (o.set_pos - x).abs() < 1.0,
            "follows 1:1: axis {x}, mover {}",
            o.set_pos
        );
        n += 1;
        assert!(n < 60_000);
    }
    s.steps(500);
    assert_eq!(s.state(g), Some(CommandState::Active));
    let o = on_track(&s, "M");
    assert!(close(o.set_pos, 600.0, POS_TOL) && o.in_sync);
    assert_eq!(o.gear_master.as_deref(), Some("X"));
    assert_pos(&s.mover("M"), 700.0, 100.0);
}

/// W11 variant: axis target 900 (> 760): the mover stops exactly at s = 760, the feedback
/// reports E_TRACK_BOUNDARY_REACHED and it no longer follows.
#[test]
fn w11_axis_beyond_the_track_end() {
    let (mut s, _ax, g) = w11(900.0);
    assert_eq!(
        s.wait_final(g, 60.0),
        CommandState::Error(E_TRACK_BOUNDARY_REACHED)
    );
    let o = on_track(&s, "M");
    assert!(close(o.set_pos, 760.0, 1e-6), "at {}", o.set_pos);
    assert_eq!(o.set_velo, 0.0);
    assert!(
        s.snap().axes[0].position < 770.0,
        "stopped while the axis still runs"
    );
    s.steps(1000);
    assert!(close(on_track(&s, "M").set_pos, 760.0, 1e-6));
}

/// The W23 trail: T1 (100,100)-(400,100), then T2 from T1's end to (860,100); M on T1 and
/// the virtual master X powered.
fn two_track_trail() -> Sim {
    let mut s = sim(&["T1", "T2"]);
    s.ok(line("T1", (100.0, 100.0), (400.0, 100.0)));
    enable_track(&mut s, "T1");
    s.ok(PlanarCommand::TrackStartFromTrack {
        track: "T2".into(),
        other: "T1".into(),
    });
    s.ok(line("T2", (500.0, 100.0), (860.0, 100.0)));
    enable_track(&mut s, "T2");
    s.enable("M");
    join_wait(&mut s, "M", "T1", true);
    s.ok(PlanarCommand::AxisPower {
        axis: "X".into(),
        enable: true,
    });
    s
}

fn w23(target: f64) -> (Sim, motion_core::CmdId) {
    let mut s = two_track_trail();
    assert_eq!(track(&s, "T1").length, 300.0);
    assert_eq!(track(&s, "T2").length, 460.0);
    s.ok(axis_move(target));
    assert_eq!(
        s.err(gear(&["T2", "T1"], 100.0, 100.0, "T1")).error_id,
        E_TRACKTRAIL_INVALID,
        "order matters"
    );
    let g = s.ok(gear(&["T1", "T2"], 100.0, 100.0, "T1"));
    (s, g)
}

/// W23: M crosses to T2 (TrackOID changes) and stops at T2 s = 400 = (800,100).
#[test]
fn w23_synchronisation_over_two_tracks() {
    let (mut s, g) = w23(700.0);
    let t1 = track(&s, "T1").oid;
    assert_eq!(on_track(&s, "M").track_oid, t1);
    s.run_until(60.0, |sn| {
        sn.axes[0].velocity == 0.0 && sn.axes[0].position > 699.0
    });
    s.steps(500);
    let o = on_track(&s, "M");
    assert_eq!(o.track, "T2");
    assert_eq!(o.track_oid, track(&s, "T2").oid);
    assert!(close(o.set_pos, 400.0, POS_TOL), "at {}", o.set_pos);
    assert_pos(&s.mover("M"), 800.0, 100.0);
    assert_eq!(s.state(g), Some(CommandState::Active));
}

/// W23 variant: axis target beyond 760: M stops at T2's end (860,100), loses sync, Error.
#[test]
fn w23_beyond_the_trail() {
    let (mut s, g) = w23(900.0);
    assert_eq!(
        s.wait_final(g, 60.0),
        CommandState::Error(E_TRACK_BOUNDARY_REACHED)
    );
    assert_pos(&s.mover("M"), 860.0, 100.0);
    assert!(!on_track(&s, "M").in_sync);
}

#[test]
fn axis_and_gear_bad_requests() {
    let mut s = sim(&["T"]);
    s.ok(line("T", (0.0, 0.0), (400.0, 0.0)));
    enable_track(&mut s, "T");
    s.enable("M");
    join_wait(&mut s, "M", "T", true);
    assert_eq!(
        s.err(axis_move(10.0)).error_id,
        E_INVALID_STATE,
        "axis not powered"
    );
    let mut bad = gear(&[], 0.0, 0.0, "T");
    if let PlanarCommand::GearInPosOnTrack { master_axis, .. } = &mut bad {
        *master_axis = "nope".into();
    }
    assert_eq!(
        s.err(bad).error_id,
        E_INVALID_PARAMETER,
        "unknown master axis"
    );
    assert_eq!(
        s.err(gear(&[], f64::INFINITY, 0.0, "T")).error_id,
        motion_core::ErrorId::NOT_FINITE
    );
    s.ok(PlanarCommand::AxisPower {
        axis: "X".into(),
        enable: true,
    });
    let e = s.err(PlanarCommand::AxisMoveAbsolute {
        axis: "X".into(),
        position: 10.0,
        velocity: -1.0,
        acceleration: 1.0,
        deceleration: 1.0,
        jerk: 1.0,
    });
    assert_eq!(e.error_id, E_INVALID_PARAMETER);
}

/// Issue 15.1 (§5.8.1): the coupling law s = s_sync + (m - m_sync) holds within the in-sync
/// tolerance while the master moves, and `in_sync` is held while on it. Master X at rest at 0
/// moves to 700 at 100 mm/s (a 1000, j 10000); sync positions 100/100, so s = X. With the
/// slave sync position 150 (s = X + 50) the slave first catches up, then follows.
fn follow_law(s_sync: f64) -> (f64, usize, usize) {
    let mut s = two_track_trail();
    let mut g = gear(&["T1", "T2"], 100.0, s_sync, "T1");
    if let PlanarCommand::GearInPosOnTrack { options, .. } = &mut g {
        options.in_sync_tolerance_distance = 0.5;
    }
    let g = s.ok(g);
    s.steps(1000);
    assert!(on_track(&s, "M").in_sync, "in sync at rest");
    s.ok(PlanarCommand::AxisMoveAbsolute {
        axis: "X".into(),
        position: 600.0,
        velocity: 100.0,
        acceleration: 1000.0,
        deceleration: 1000.0,
        jerk: 10000.0,
    });
    let (mut n, mut synced, mut worst) = (0, 0, 0.0f64);
    loop {
        s.step();
        let a = &s.snap().axes[0];
        let (x, v) = (a.position, a.velocity);
        let o = on_track(&s, "M");
        // Route coordinate: T1 is 300 long, T2 continues at 300.
        let r = if o.track == "T2" {
            300.0 + o.set_pos
        } else {
            o.set_pos
        };
        worst = worst.max((r - (x + s_sync - 100.0)).abs());
        synced += o.in_sync as usize;
        n += 1;
        if v == 0.0 && x > 599.0 {
            break;
        }
        assert!(n < 20_000);
    }
    assert_eq!(s.state(g), Some(CommandState::Active));
    (worst, synced, n)
}

#[test]
fn gear_in_follows_the_coupling_law_while_the_master_moves() {
    for s_sync in [100.0, 150.0] {
        let (worst, synced, n) = follow_law(s_sync);
        assert!(worst <= 1e-6, "s_sync {s_sync}: off the law by {worst} mm");
        assert_eq!(
            synced, n,
            "s_sync {s_sync}: in_sync held in {synced} of {n} cycles"
        );
    }
}
