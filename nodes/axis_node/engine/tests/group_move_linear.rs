//! MC_MoveLinearAbsolute / MC_MoveLinearRelative, MC_GroupHalt, MC_PathSelect/MC_MovePath,
//! MC_GroupSetOverride and the group reads (plcopen_platform.md §3.2): a straight line in
//! axis space, jerk-limited along the path, no member beyond its own limits.
mod p4rig;
use axis_engine::group::*;
use axis_engine::*;
use motion_core::{CommandState, ErrorId};
use p4rig::*;

/// Tracks the largest |v|, |a| of an axis from the set values every cycle.
#[derive(Default)]
struct Peak {
    v: f64,
    a: f64,
}

fn run_tracking(r: &mut P4, id: motion_core::CmdId, max: usize) -> (Peak, Peak, usize) {
    let (mut px, mut py) = (Peak::default(), Peak::default());
    let n = r.until(max, |r| {
        let (x, y) = (r.ax("x"), r.ax("y"));
        px.v = px.v.max(x.set_velo.abs());
        px.a = px.a.max(x.set_acc.abs());
        py.v = py.v.max(y.set_velo.abs());
        py.a = py.a.max(y.set_acc.abs());
        r.out(id).done
    });
    (px, py, n)
}

#[test]
fn line_is_straight_and_ends_exactly_at_the_target() {
    let mut r = P4::xy_powered();
    let id = r.gid(lin_abs(vec![300.0, -400.0], 250.0));
    r.until(20000, |r| {
        let (x, y) = (r.ax("x").set_pos, r.ax("y").set_pos);
        assert!((x * -4.0 - y * 3.0).abs() < 1e-6, "off the line: {x} {y}");
        r.out(id).done
    });
    assert_eq!((r.ax("x").set_pos, r.ax("y").set_pos), (300.0, -400.0));
    assert_eq!(r.ax("x").act_pos, 300.0);
}

#[test]
fn rest_to_rest_time_follows_the_profile_formula() {
    // L = 500, v = 100, a = d = 200, j = 2000 (all below the members' limits):
    // T = L/v + v/(2a) + v/(2d) + a/(2j) + d/(2j) = 5 + 0.25 + 0.25 + 0.05 + 0.05 = 5.6 s.
    let mut r = P4::xy_powered();
    let mut c = lin(vec![300.0, 400.0], 100.0);
    c.acceleration = 200.0;
    c.deceleration = 200.0;
    c.jerk = 2000.0;
    let id = r.gid(GroupCommand::MoveLinearAbsolute(c));
    let (px, py, n) = run_tracking(&mut r, id, 20000);
    let t = n as f64 * DT;
    assert!(
        (t - 5.6).abs() <= 2.0 * DT,
        "motion time {t} s, expected 5.6 s"
    );
    // Path velocity 100 split 0.6 / 0.8.
    assert!(
        (px.v - 60.0).abs() < 1e-6 && (py.v - 80.0).abs() < 1e-6,
        "{} {}",
        px.v,
        py.v
    );
    assert!((py.a - 160.0).abs() < 1e-3, "path a 200 × 0.8: {}", py.a);
}

#[test]
fn no_member_exceeds_its_own_limits() {
    // Requested far above every limit: the path is capped by the most loaded member.
    let mut r = P4::xy_powered();
    let id = r.gid(lin_abs(vec![30000.0, 40000.0], 1e6));
    let (px, py, _) = run_tracking(&mut r, id, 100000);
    let c = AxisConfig::default();
    let tol = 1e-6;
    assert!(
        py.v <= c.max_velocity + tol && py.v > c.max_velocity - 1e-3,
        "y velocity {}",
        py.v
    );
    assert!(px.v <= c.max_velocity * 0.75 + tol, "x velocity {}", px.v);
    assert!(
        py.a <= c.acceleration + tol && py.a > 0.99 * c.acceleration,
        "y acc {}",
        py.a
    );
    assert!(px.a <= c.acceleration + tol);
}

#[test]
fn per_axis_limits_bind_the_path_for_different_axes() {
    // y is slow (max 50 u/s): the path velocity becomes 50 / 0.8 = 62.5.
    let cfg = EngineConfig {
        groups: vec![GroupConfig {
            name: G.into(),
            axes: vec!["x".into(), "y".into()],
        }],
        ..EngineConfig::default()
    };
    let slow = AxisConfig {
        max_velocity: 50.0,
        ..axis_cfg()
    };
    let mut r = P4::build(
        vec![
            ("x".into(), axis_cfg()),
            ("y".into(), slow),
            ("z".into(), axis_cfg()),
        ],
        cfg,
    );
    for a in ["x", "y"] {
        r.power(a, true).unwrap();
    }
    r.step();
    let id = r.gid(lin_abs(vec![300.0, 400.0], 1000.0));
    let (px, py, _) = run_tracking(&mut r, id, 100000);
    assert!((py.v - 50.0).abs() < 1e-6, "y at its limit: {}", py.v);
    assert!((px.v - 37.5).abs() < 1e-6, "x at 0.6 × 62.5: {}", px.v);
}

#[test]
fn relative_move_adds_to_the_set_position() {
    let mut r = P4::xy_powered();
    let a = r.gid(lin_abs(vec![10.0, 20.0], 100.0));
    r.until(5000, |r| r.out(a).done);
    let b = r.gid(lin_rel(vec![5.0, -5.0], 100.0));
    r.until(5000, |r| r.out(b).done);
    assert_eq!((r.ax("x").set_pos, r.ax("y").set_pos), (15.0, 15.0));
}

#[test]
fn zero_length_move_is_done_next_cycle() {
    let mut r = P4::xy_powered();
    let id = r.gid(lin_rel(vec![0.0, 0.0], 100.0));
    r.step();
    assert!(r.out(id).done);
}

#[test]
fn parallel_takeover_keeps_moving_without_stop() {
    let mut r = P4::xy_powered();
    r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(1500);
    let v0 = r.gs().path_velocity;
    assert!(v0 > 199.0, "at speed: {v0}");
    let b = r.gid(lin_abs(vec![600.0, 800.0], 200.0));
    let mut vmin = f64::MAX;
    r.until(20000, |r| {
        if r.gs().path_velocity > 0.0 || !r.out(b).done {
            vmin = vmin.min(r.gs().path_velocity);
        }
        r.out(b).done || r.ax("x").set_pos > 500.0
    });
    assert!(
        vmin > 150.0,
        "no stop at the takeover: min path velocity {vmin}"
    );
}

#[test]
fn corner_takeover_stops_path_true_then_moves_within_limits() {
    let mut r = P4::xy_powered();
    r.gid(lin_abs(vec![1000.0, 0.0], 500.0));
    r.steps(1500);
    let b = r.gid(lin_abs(vec![0.0, 500.0], 500.0));
    let (px, py, _) = run_tracking(&mut r, b, 100000);
    let c = AxisConfig::default();
    assert!(
        px.a <= c.acceleration.max(c.deceleration) + 1e-6,
        "x acc {}",
        px.a
    );
    assert!(py.v <= c.max_velocity + 1e-6);
    assert_eq!((r.ax("x").set_pos, r.ax("y").set_pos), (0.0, 500.0));
}

#[test]
fn single_axis_motion_on_a_member_is_refused_while_the_group_moves() {
    let mut r = P4::xy_powered();
    r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.step();
    assert_eq!(
        err(r.cmd(rel("x", 1.0, 10.0))),
        ErrorId(0x4B01),
        "tc2_mc2 id"
    );
    assert_eq!(err(r.cmd(abs("y", 1.0, 10.0))), ErrorId(0x4B01));
    assert_eq!(
        err(r.cmd(AxisCommand::Reset(Reset { axis: "y".into() }))),
        ErrorId(0x4B01),
        "MC_Reset of a healthy member would break the path"
    );
    // A non-member is free.
    r.id(rel("z", 1.0, 10.0));
    // Reads on members work.
    r.cmd(AxisCommand::ReadActualPosition(ReadActualPosition {
        axis: "x".into(),
    }))
    .unwrap();
}

#[test]
fn group_move_refused_while_a_member_moves_on_its_own() {
    let mut r = P4::xy_powered();
    r.id(rel("x", 100.0, 10.0));
    r.step();
    assert_eq!(err(r.g(lin_abs(vec![1.0, 1.0], 10.0))), ErrorId(4901));
}

#[test]
fn override_zero_pauses_and_one_resumes() {
    let mut r = P4::xy_powered();
    let id = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(500);
    let ov = |f: f64| {
        GroupCommand::GroupSetOverride(GroupSetOverride {
            group: G.into(),
            enable: true,
            vel_factor: f,
            acc_factor: 1.0,
            jerk_factor: 1.0,
        })
    };
    r.g(ov(0.0)).unwrap();
    r.steps(2000);
    assert_eq!(r.gs().path_velocity, 0.0, "stopped");
    assert!(r.out(id).busy && !r.out(id).done, "still active");
    let held = r.ax("x").set_pos;
    r.steps(100);
    assert_eq!(r.ax("x").set_pos, held);
    r.g(ov(0.5)).unwrap();
    r.steps(2000);
    assert!(
        (r.gs().path_velocity - 100.0).abs() < 1e-6,
        "half speed: {}",
        r.gs().path_velocity
    );
    r.until(20000, |r| r.out(id).done);
    assert_eq!((r.ax("x").set_pos, r.ax("y").set_pos), (300.0, 400.0));
}

#[test]
fn move_path_visits_every_point_at_rest() {
    let mut r = P4::xy_powered();
    let pts = vec![vec![100.0, 0.0], vec![100.0, 100.0], vec![0.0, 100.0]];
    r.gid(GroupCommand::PathSelect(PathSelect {
        group: G.into(),
        points: pts.clone(),
    }));
    assert_eq!(r.gs().path_points, 3);
    let id = r.gid(GroupCommand::MovePath(MovePath {
        group: G.into(),
        velocity: 200.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        coord_system: CoordSystem::Acs,
        buffer_mode: BufferMode::Aborting,
    }));
    let mut visited = 0;
    r.until(50000, |r| {
        let (x, y) = (r.ax("x"), r.ax("y"));
        if visited < 3 && x.set_pos == pts[visited][0] && y.set_pos == pts[visited][1] {
            assert_eq!(
                (x.set_velo, y.set_velo),
                (0.0, 0.0),
                "rest at point {visited}"
            );
            visited += 1;
        }
        r.out(id).done
    });
    assert_eq!(visited, 3);
    assert!(r.when(id, CommandState::Done).is_some());
}

#[test]
fn reads_status_error_positions_velocities_configuration() {
    let mut r = P4::xy_powered();
    let v = |r: &mut P4, c| match r.g(c).unwrap().value {
        ReplyValue::Group(g) => g,
        other => panic!("{other:?}"),
    };
    let id = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(1500);
    match v(&mut r, GroupCommand::GroupReadStatus { group: G.into() }) {
        GroupReply::Status(s) => {
            assert!(s.group_moving && !s.group_standby);
            assert!(s.constant_velocity, "at 200 after 1.5 s");
        }
        o => panic!("{o:?}"),
    }
    match v(
        &mut r,
        GroupCommand::GroupReadActualVelocity {
            group: G.into(),
            coord_system: CoordSystem::Acs,
        },
    ) {
        GroupReply::Values(vs) => assert!(
            (vs[0] - 120.0).abs() < 1e-6 && (vs[1] - 160.0).abs() < 1e-6,
            "{vs:?}"
        ),
        o => panic!("{o:?}"),
    }
    r.until(20000, |r| r.out(id).done);
    match v(
        &mut r,
        GroupCommand::GroupReadActualPosition {
            group: G.into(),
            coord_system: CoordSystem::Acs,
        },
    ) {
        GroupReply::Values(p) => assert_eq!(p, vec![300.0, 400.0]),
        o => panic!("{o:?}"),
    }
    match v(&mut r, GroupCommand::GroupReadStatus { group: G.into() }) {
        GroupReply::Status(s) => assert!(s.group_standby && s.in_position && !s.group_moving),
        o => panic!("{o:?}"),
    }
    assert_eq!(
        v(&mut r, GroupCommand::GroupReadError { group: G.into() }),
        GroupReply::Error(ErrorId::NONE)
    );
    assert_eq!(
        v(
            &mut r,
            GroupCommand::GroupReadConfiguration {
                group: G.into(),
                ident_in_group: 2
            }
        ),
        GroupReply::Configuration(vec![("y".into(), 2)])
    );
    let snap = motion_core::Engine::snapshot(&r.e);
    assert_eq!(snap.groups.len(), 1);
    assert_eq!(snap.groups[0].state, GroupState::Standby);
}

#[test]
fn cancel_of_a_group_move_halts_path_true() {
    let mut r = P4::xy_powered();
    let id = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(800);
    motion_core::Engine::cancel(&mut r.e, id).unwrap();
    assert!(r.out(id).command_aborted);
    r.until(10000, |r| r.gs().state == GroupState::Standby);
    let (x, y) = (r.ax("x").set_pos, r.ax("y").set_pos);
    assert!((x * 4.0 - y * 3.0).abs() < 1e-6 && x < 300.0);
}

#[test]
fn soft_limits_of_members_refuse_the_target() {
    let cfg = EngineConfig {
        groups: vec![GroupConfig {
            name: G.into(),
            axes: vec!["x".into(), "y".into()],
        }],
        ..EngineConfig::default()
    };
    let lim = AxisConfig {
        en_max_soft_pos_limit: true,
        max_soft_pos_limit: 100.0,
        ..axis_cfg()
    };
    let mut r = P4::build(vec![("x".into(), axis_cfg()), ("y".into(), lim)], cfg);
    r.power("x", true).unwrap();
    r.power("y", true).unwrap();
    r.step();
    assert_eq!(err(r.g(lin_abs(vec![0.0, 101.0], 10.0))), ErrorId(0x4D01));
    assert_eq!(r.gs().state, GroupState::Standby);
}

/// A lockstep stream refills old snapshots in place (`snapshot_into`): the result is the
/// same as a fresh snapshot, also from a snapshot of another engine with other axes and
/// groups (nothing of the old one is left behind).
#[test]
fn snapshot_into_an_old_snapshot_equals_a_fresh_one() {
    use motion_core::Engine;
    let mut r = P4::xy_powered();
    let mut old = r.e.snapshot();
    let mut other = AxisEngine::new(vec![("w".to_string(), AxisConfig::default())])
        .expect("engine")
        .snapshot();
    r.gid(lin_abs(vec![300.0, -400.0], 250.0));
    r.steps(50);
    r.e.snapshot_into(&mut old);
    r.e.snapshot_into(&mut other);
    let fresh = r.e.snapshot();
    assert!(fresh.axes[0].set_velo > 0.0, "moving");
    assert_eq!(old, fresh);
    assert_eq!(other, fresh);
}
