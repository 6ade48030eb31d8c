//! W13 – Track network (manual 6.2.10) and W16 – Advanced link options with options 0
//! (manual 6.2.13): identical network. Plus a cross-track MoveOnTrack through the switch
//! (§5.6.5) with gap control across the junction.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn build(s: &mut Sim, advanced: bool) {
    s.ok(line("T1", (250.0, 120.0), (650.0, 120.0)));
    s.ok(line("T1", (700.0, 170.0), (800.0, 450.0)));
    s.ok(line("T1", (650.0, 500.0), (250.0, 500.0)));
    let start = |t: &str| {
        if advanced {
            PlanarCommand::TrackStartFromTrackAdvanced {
                track: t.into(),
                other: "T1".into(),
                options: TrackLinkAdvancedOptions::default(),
            }
        } else {
            PlanarCommand::TrackStartFromTrack {
                track: t.into(),
                other: "T1".into(),
            }
        }
    };
    s.ok(start("T2"));
    s.ok(line("T2", (200.0, 450.0), (200.0, 170.0)));
    s.ok(if advanced {
        PlanarCommand::TrackEndAtTrackAdvanced {
            track: "T2".into(),
            other: "T1".into(),
            options: TrackLinkAdvancedOptions::default(),
        }
    } else {
        PlanarCommand::TrackEndAtTrack {
            track: "T2".into(),
            other: "T1".into(),
        }
    });
    s.ok(start("T3"));
    s.ok(line("T3", (200.0, 500.0), (120.0, 500.0)));
    s.ok(start("T4"));
    s.ok(line("T4", (200.0, 550.0), (200.0, 750.0)));
    for t in ["T1", "T2", "T3", "T4"] {
        enable_track(s, t);
    }
}

fn network(advanced: bool) -> Sim {
    let mut s = Sim::new(cfg(
        &[("M", 500.0, 120.0), ("F", 300.0, 120.0)],
        &["T1", "T2", "T3", "T4"],
    ));
    build(&mut s, advanced);
    s
}

fn check_network(s: &mut Sim) {
    let t = |s: &Sim, n: &str| track(s, n);
    for n in ["T1", "T2", "T3", "T4"] {
        assert_eq!(t(s, n).state, PlanarState::Enabled, "{n} Enabled");
    }
    assert!(!t(s, "T1").closed_loop, "T1 is not a closed loop");
    assert_eq!(
        t(s, "T1").subsequent_tracks,
        vec!["T2", "T3", "T4"],
        "switch at (250,500)"
    );
    assert_eq!(t(s, "T1").previous_tracks, vec!["T2"]);
    assert_eq!(t(s, "T2").previous_tracks, vec!["T1"]);
    assert_eq!(t(s, "T2").subsequent_tracks, vec!["T1"]);
    assert_eq!(t(s, "T3").previous_tracks, vec!["T1"]);
    assert_eq!(t(s, "T4").previous_tracks, vec!["T1"]);
    assert!(
        close(t(s, "T3").length, 130.0, 1e-6),
        "T3 = 50 mm collinear + 80 mm"
    );
    let l1 = t(s, "T1").length;
    assert!(l1 > 1097.32 && l1 < 1400.0, "L1 = {l1}");
    assert!(t(s, "T2").length > 280.0 && t(s, "T4").length > 200.0);
    // Junction continuity: T1 end vs T2/T3/T4 start, T2 end vs T1 start.
    let pose = |s: &mut Sim, n: &str, arc: f64| position_at(s, n, arc);
    let e1 = pose(s, "T1", l1);
    for n in ["T2", "T3", "T4"] {
        let b = pose(s, n, 0.0);
        assert!(
            close(b.x, e1.x, 1e-9) && close(b.y, e1.y, 1e-9),
            "{n} starts at T1's end"
        );
        assert!(close(b.c, e1.c, 1e-6), "{n} heading {} vs {}", b.c, e1.c);
    }
    let l2 = t(s, "T2").length;
    let e2 = pose(s, "T2", l2);
    let b1 = pose(s, "T1", 0.0);
    assert!(close(e2.x, b1.x, 1e-9) && close(e2.y, b1.y, 1e-9) && close(e2.c, b1.c, 1e-6));
}

#[test]
fn w13_track_network() {
    let mut s = network(false);
    check_network(&mut s);
    // Curvature continuity inside T1 and T2 (all generated junctions), from the geometry.
    let mut g = TrackGeometry::default();
    g.append_line(
        nalgebra::Vector2::new(250.0, 120.0),
        nalgebra::Vector2::new(650.0, 120.0),
    )
    .unwrap();
    g.append_line(
        nalgebra::Vector2::new(700.0, 170.0),
        nalgebra::Vector2::new(800.0, 450.0),
    )
    .unwrap();
    g.append_line(
        nalgebra::Vector2::new(650.0, 500.0),
        nalgebra::Vector2::new(250.0, 500.0),
    )
    .unwrap();
    assert!(close(g.length(), track(&s, "T1").length, 1e-9));
    for j in g.junctions() {
        let a = g.pose_at_side(j, true);
        let b = g.pose_at_side(j, false);
        assert!(
            planar_engine::track::geometry::angle_diff(a.theta, b.theta)
                .abs()
                .to_degrees()
                < 1e-6
                && (a.kappa - b.kappa).abs() < 1e-9,
            "junction at s = {j}: {a:?} vs {b:?}"
        );
    }
}

#[test]
fn w16_advanced_options_zero_is_plain() {
    let mut a = network(false);
    let mut b = network(true);
    check_network(&mut b);
    for n in ["T1", "T2", "T3", "T4"] {
        assert_eq!(track(&a, n), track(&b, n), "track {n}");
        for arc in [0.0, 17.0, 100.0] {
            assert_eq!(position_at(&mut a, n, arc), position_at(&mut b, n, arc));
        }
    }
}

/// Linking rules (§3.3): a second StartFromTrack on the same part, a locked track, a closed
/// loop as the other track.
#[test]
fn linking_errors() {
    let mut s = network(false);
    // T1 is enabled now; geometry changes need Disabled.
    assert_eq!(
        s.err(line("T1", (0.0, 0.0), (1.0, 0.0))).error_id,
        E_INVALID_STATE
    );
    let mut s2 = Sim::new(cfg(&[], &["A", "B", "C", "D"]));
    s2.ok(line("A", (0.0, 0.0), (100.0, 0.0)));
    s2.ok(PlanarCommand::TrackStartFromTrack {
        track: "B".into(),
        other: "A".into(),
    });
    assert_eq!(
        s2.err(line("A", (100.0, 0.0), (200.0, 0.0))).error_id,
        E_TRACK_LOCKED,
        "A is locked by B's link"
    );
    assert_eq!(
        s2.err(PlanarCommand::TrackStartFromTrack {
            track: "B".into(),
            other: "A".into()
        })
        .error_id,
        E_ALREADY_CONNECTED
    );
    s2.ok(PlanarCommand::TrackAppendCircle {
        track: "C".into(),
        start: p(500.0, 0.0),
        end: p(500.0, 0.0),
        center: p(400.0, 0.0),
        clockwise: true,
    });
    s2.ok(PlanarCommand::TrackCloseLoop { track: "C".into() });
    assert_eq!(
        s2.err(PlanarCommand::TrackStartFromTrack {
            track: "D".into(),
            other: "C".into()
        })
        .error_id,
        E_GEOMETRY_INVALID,
        "a closed loop has no free end"
    );
    assert_eq!(
        s2.err(line("C", (0.0, 0.0), (1.0, 0.0))).error_id,
        E_TRACK_LOCKED,
        "nothing can be appended to a closed loop"
    );
    // Clear B: A is free again.
    s2.ok(PlanarCommand::TrackClear { track: "B".into() });
    s2.ok(line("A", (100.0, 0.0), (200.0, 0.0)));
    assert_eq!(length(&mut s2, "A"), 200.0);
}

/// §5.6.5: M on T1 moves to T3 through the switch; the TrackOID changes at the junction
/// (new s = s − L1); F follows to T4's end and keeps 200 mm (arc length along the route)
/// behind M while both pass the junction; a route backwards (Negative) is unreachable.
#[test]
fn cross_track_move_through_the_switch() {
    let mut s = network(false);
    s.enable("M");
    s.enable("F");
    join_wait(&mut s, "M", "T1", true);
    join_wait(&mut s, "F", "T1", true);
    let l1 = track(&s, "T1").length;
    assert!(close(on_track(&s, "M").set_pos, 250.0, 1e-6));
    assert!(close(on_track(&s, "F").set_pos, 50.0, 1e-6));
    assert_eq!(
        s.err(mot_opt(
            "M",
            "T3",
            50.0,
            dir_opt(Direction::Negative, 0, 0.0)
        ))
        .error_id,
        E_TARGET_UNREACHABLE
    );
    assert_eq!(
        s.err(mot("M", "T3", 131.0)).error_id,
        E_TARGET_UNREACHABLE,
        "beyond T3"
    );
    let m = s.ok(mot("M", "T3", 100.0));
    let f = s.ok(mot("F", "T3", 130.0));
    let mut seen_t3 = false;
    let mut n = 0;
    // Run until M is done and F has come to rest (F cannot reach its target, see below).
    while !(s.state(m) == Some(CommandState::Done)
        && on_track(&s, "F").set_velo == 0.0
        && on_track(&s, "F").waiting)
    {
        s.step();
        let (om, of) = (on_track(&s, "M"), on_track(&s, "F"));
        let cum = |o: &OnTrackSnapshot| {
            if o.track == "T1" {
                o.set_pos
            } else {
                l1 + o.set_pos
            }
        };
        let d = cum(&om) - cum(&of);
        assert!(d >= 200.0 - 1e-6, "gap across the junction: {d}");
        if om.track == "T3" {
            seen_t3 = true;
        }
        n += 1;
        assert!(n < 20_000);
    }
    assert!(seen_t3);
    let om = on_track(&s, "M");
    assert_eq!(om.track, "T3");
    assert!(close(om.set_pos, 100.0, POS_TOL));
    let q = position_at(&mut s, "T3", 100.0);
    assert_pos(&s.mover("M"), q.x, q.y);
    assert_eq!(track(&s, "T3").movers, vec!["M"]);
    // F cannot reach 130 (M stands at 100, gap 200): it waits on T1, the command stays Busy.
    assert_eq!(s.state(f), Some(CommandState::Active));
    let of = on_track(&s, "F");
    assert!(of.waiting);
    let f_cum = if of.track == "T1" {
        of.set_pos
    } else {
        l1 + of.set_pos
    };
    assert!(
        close(l1 + 100.0 - 200.0, f_cum, POS_TOL),
        "F waits at {f_cum}, gap boundary {}",
        l1 - 100.0
    );
}

/// §5.6.4 collision avoidance near the switch at (250,500): M (ahead) goes to T2's end, F to
/// T3. While M is inside T2's collision range, F does not enter the collision range of T1's
/// end (it waits at its border); once M is clear, F passes. Automatic ranges exist exactly at
/// the switch ends.
#[test]
fn switch_zone_is_exclusive() {
    let mut s = network(false);
    let t1 = track(&s, "T1");
    assert!(t1.collision_range_end > 0.0 && t1.collision_range_start == 0.0);
    for n in ["T2", "T3", "T4"] {
        let t = track(&s, n);
        assert!(t.collision_range_start > 0.0, "{n} starts at the switch");
    }
    assert_eq!(
        track(&s, "T2").collision_range_end,
        0.0,
        "T2 → T1 start: no switch"
    );
    s.enable("M");
    s.enable("F");
    join_wait(&mut s, "M", "T1", true);
    join_wait(&mut s, "F", "T1", true);
    let (l1, r1) = (t1.length, t1.collision_range_end);
    let r2 = track(&s, "T2").collision_range_start;
    let l2 = track(&s, "T2").length;
    assert!(r2 < l2, "T2 leaves the range");
    let m = s.ok(mot("M", "T2", l2));
    let f = s.ok(mot("F", "T3", 100.0));
    let mut waited = false;
    let mut n = 0;
    while !(s.state(m) == Some(CommandState::Done) && s.state(f) == Some(CommandState::Done)) {
        s.step();
        let (om, of) = (on_track(&s, "M"), on_track(&s, "F"));
        let m_in = om.track == "T2" && om.set_pos < r2;
        let f_in = (of.track == "T1" && of.set_pos > l1 - r1 + 1e-6) || of.track == "T3";
        assert!(
            !(m_in && f_in),
            "both in the switch zone: M {om:?}, F {of:?}"
        );
        if m_in && of.waiting && of.set_velo == 0.0 {
            waited = true;
            assert!(
                close(of.set_pos, l1 - r1, POS_TOL),
                "F waits at the range border"
            );
        }
        n += 1;
        assert!(n < 20_000, "not finished");
    }
    assert!(waited, "F had to wait for M");
    assert_eq!(on_track(&s, "F").track, "T3");
    assert_eq!(on_track(&s, "M").track, "T2");
}
