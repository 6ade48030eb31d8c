//! planar_node tracks over real DDS, in-process (xplanar.md §3.2, §3.3, §5.4–§5.6, §9): a
//! closed loop built from `~/track_append_line|circle` and `~/track_close_loop`, enabled;
//! two movers join (one by action, one by service); the follower's `~/mover_move_on_track`
//! action runs into the leader and is held at the gap (seen on `~/state`); a join while the
//! track is Moving is refused with E_TRACK_MODE_CONFLICT; `~/track_get_length`,
//! `~/track_get_position_at`; `~/track_set_init_parameters` (Disabled only); bad requests (unknown track, NaN, enum); the track drawn in
//! `~/markers`; LeaveTrack as an action; a virtual axis powered; a gear-in on a master mover as an action (in_sync feedback, cancel). With both request/reply mappings.

use motion_msgs::action::{
    self as act, MoverGearInPosOnTrackWithMasterMoverFeedback,
    MoverGearInPosOnTrackWithMasterMoverGoal, MoverGearInPosOnTrackWithMasterMoverResult,
    MoverJoinTrackFeedback, MoverJoinTrackGoal, MoverJoinTrackResult, MoverLeaveTrackFeedback,
    MoverLeaveTrackGoal, MoverLeaveTrackResult, MoverMoveOnTrackFeedback, MoverMoveOnTrackGoal,
    MoverMoveOnTrackResult,
};
use motion_msgs::deps::visualization_msgs::msg::{Marker, MarkerArray};
use motion_msgs::msg::{CommandStatus, PlanarMoverState, PlanarState, PlanarTrackState};
use motion_msgs::srv::{self, *};
use planar_engine::errors::E_TRACK_MODE_CONFLICT;
use planar_node::PlanarNode;
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{ServiceMapping, Subscription};
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

/// Three movers without stators (free plane); one track, geometry from the services.
const CONFIG: &str = "
movers:
  - {name: m1, initial_pose: {x: 1000, y: 200}}
  - {name: m2, initial_pose: {x: 1500, y: 200}}
  - {name: m3, initial_pose: {x: 1300, y: 500}}
tracks: [{name: loop, max_mover_width: 160, collision_range_mode: manual, collision_range_start: 0, collision_range_end: 0}]
axes: [{name: v1}]
";

fn start_node(domain: u16, mapping: ServiceMapping) -> PlanarNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    planar_node::start(&common("planar_node", true, mapping), cfg, "test", domain)
        .expect("planar node")
}

async fn wait_state(
    states: &Subscription<PlanarState>,
    secs: f64,
    what: &str,
    pred: impl Fn(&PlanarState) -> bool,
) -> PlanarState {
    within(secs, what, async {
        loop {
            let (s, _) = states.async_take().await.unwrap();
            if pred(&s) {
                return s;
            }
        }
    })
    .await
}

fn mover<'a>(s: &'a PlanarState, name: &str) -> &'a PlanarMoverState {
    s.movers.iter().find(|m| m.name == name).unwrap()
}

macro_rules! call {
    ($client:expr, $what:expr, $req:expr) => {
        within(5.0, $what, $client.async_call_service($req))
            .await
            .unwrap()
    };
}

async fn scenario(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", mapping);

    let states = c.subscribe::<PlanarState>("/planar_node/state", PlanarState::type_name());
    let statuses =
        c.subscribe::<CommandStatus>("/planar_node/command_status", CommandStatus::type_name());
    let markers = c.subscribe::<MarkerArray>("/planar_node/markers", MarkerArray::type_name());
    let (first, _) = within(20.0, "first state sample", states.async_take())
        .await
        .unwrap();
    assert_eq!(first.tracks.len(), 1);
    assert_eq!(first.tracks[0].name, "loop");
    assert_eq!(
        first.tracks[0].operation_mode,
        PlanarTrackState::MODE_UNINITIALIZED
    );
    assert_eq!(first.tracks[0].length, 0.0);
    // The §1.6 init parameters as configured (height and the static check at their defaults).
    let t = &first.tracks[0];
    assert_eq!(
        (
            t.max_mover_width,
            t.max_mover_height,
            t.check_static_collision
        ),
        (160.0, 155.0, false)
    );
    assert_eq!(
        t.collision_range_mode,
        PlanarTrackState::COLLISION_RANGE_MANUAL
    );

    // The loop: bottom straight, right half circle, top straight, left half circle (the
    // gaps between them get generated transitions), closed.
    let line = c
        .client::<TrackAppendLineRequest, TrackAppendLineResponse>(
            "/planar_node/track_append_line",
            TrackAppendLine::service_type_name(),
        )
        .await;
    let circle = c
        .client::<TrackAppendCircleRequest, TrackAppendCircleResponse>(
            "/planar_node/track_append_circle",
            TrackAppendCircle::service_type_name(),
        )
        .await;
    let l = |sx, sy, ex, ey| TrackAppendLineRequest {
        track: "loop".into(),
        start_x: sx,
        start_y: sy,
        end_x: ex,
        end_y: ey,
        reference_id: 0,
    };
    let arc = |s: (f64, f64), e: (f64, f64), m: (f64, f64)| TrackAppendCircleRequest {
        track: "loop".into(),
        start_x: s.0,
        start_y: s.1,
        end_x: e.0,
        end_y: e.1,
        center_x: m.0,
        center_y: m.1,
        clockwise: false,
        reference_id: 0,
    };
    let r = call!(line, "line 1", l(800.0, 200.0, 1800.0, 200.0));
    assert!(r.accepted, "{}", r.message);
    let r = call!(
        circle,
        "circle 1",
        arc((2100.0, 200.0), (2100.0, 800.0), (2100.0, 500.0))
    );
    assert!(r.accepted, "{}", r.message);
    let r = call!(line, "line 2", l(1800.0, 800.0, 800.0, 800.0));
    assert!(r.accepted, "{}", r.message);
    let r = call!(
        circle,
        "circle 2",
        arc((500.0, 800.0), (500.0, 200.0), (500.0, 500.0))
    );
    assert!(r.accepted, "{}", r.message);
    // Unknown track and NaN.
    let r = call!(
        line,
        "line unknown",
        TrackAppendLineRequest {
            track: "nope".into(),
            ..l(0.0, 0.0, 1.0, 0.0)
        }
    );
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F01, "{}", r.message);
    let r = call!(line, "line NaN", l(f64::NAN, 0.0, 1.0, 0.0));
    assert_eq!(r.error_id, 0x7F02, "{}", r.message);
    let close = c
        .client::<TrackCloseLoopRequest, TrackCloseLoopResponse>(
            "/planar_node/track_close_loop",
            TrackCloseLoop::service_type_name(),
        )
        .await;
    let r = call!(
        close,
        "close loop",
        TrackCloseLoopRequest {
            track: "loop".into()
        }
    );
    assert!(r.accepted, "{}", r.message);
    // The closed loop is drawn (sampled with GetPositionAt through the read-only query
    // path): no command of the sampler appears on ~/command_status, only the clients' own
    // labelled commands (their Done events went out before the marker could be drawn).
    within(20.0, "sampled loop marker", async {
        loop {
            let (a, _) = markers.async_take().await.unwrap();
            if a.markers
                .iter()
                .any(|m| m.ns == "tracks" && m.action == Marker::ADD && m.points.len() > 100)
            {
                return;
            }
        }
    })
    .await;
    let mut seen = Vec::new();
    while let Ok(Some((st, _))) = statuses.take() {
        seen.push(st);
    }
    assert!(!seen.is_empty(), "the track commands' statuses");
    assert!(
        seen.iter()
            .all(|st| !st.command.is_empty() && st.command != "get_position_at"),
        "{:?}",
        seen.iter()
            .map(|st| (&st.object, &st.command))
            .collect::<Vec<_>>()
    );
    // The §1.6 init parameters by service while the track is Disabled; an out-of-range mode
    // is refused with its id.
    let set_params = c
        .client::<TrackSetInitParametersRequest, TrackSetInitParametersResponse>(
            "/planar_node/track_set_init_parameters",
            TrackSetInitParameters::service_type_name(),
        )
        .await;
    let params = |mode: u8| TrackSetInitParametersRequest {
        track: "loop".into(),
        max_mover_width: 160.0,
        max_mover_height: 170.0,
        check_static_collision: true,
        collision_range_mode: mode,
        collision_range_start: 0.0,
        collision_range_end: 0.0,
    };
    let r = call!(set_params, "set init parameters, bad mode", params(2));
    assert!(!r.accepted);
    assert_eq!(r.error_id, motion_core::ErrorId::ENUM_OUT_OF_RANGE.0);
    let r = call!(
        set_params,
        "set init parameters",
        params(TrackSetInitParametersRequest::COLLISION_RANGE_MANUAL)
    );
    assert!(r.accepted, "{}", r.message);
    let s = wait_state(&states, 10.0, "init parameters set", |s| {
        s.tracks[0].max_mover_height == 170.0 && s.tracks[0].check_static_collision
    })
    .await;
    assert_eq!(s.tracks[0].max_mover_width, 160.0);
    let enable = c
        .client::<TrackEnableRequest, TrackEnableResponse>(
            "/planar_node/track_enable",
            TrackEnable::service_type_name(),
        )
        .await;
    let r = call!(
        enable,
        "track enable",
        TrackEnableRequest {
            track: "loop".into()
        }
    );
    assert!(r.accepted, "{}", r.message);
    let mover_enable = c
        .client::<MoverEnableRequest, MoverEnableResponse>(
            "/planar_node/mover_enable",
            MoverEnable::service_type_name(),
        )
        .await;
    for m in ["m1", "m2", "m3"] {
        let r = call!(
            mover_enable,
            "mover enable",
            MoverEnableRequest { mover: m.into() }
        );
        assert!(r.accepted, "{}", r.message);
    }
    let s = wait_state(&states, 20.0, "track Standing, movers Enabled", |s| {
        s.tracks[0].operation_mode == PlanarTrackState::MODE_STANDING
            && s.movers
                .iter()
                .all(|m| m.state == PlanarMoverState::STATE_ENABLED)
    })
    .await;
    // Enabled: the init parameters are fixed.
    let r = call!(
        set_params,
        "set init parameters while Enabled",
        params(TrackSetInitParametersRequest::COLLISION_RANGE_AUTOMATIC)
    );
    assert!(!r.accepted);
    assert_eq!(r.error_id, planar_engine::errors::E_INVALID_STATE.0);
    assert!(s.tracks[0].closed_loop);
    let length = s.tracks[0].length;
    assert!(
        length > 2000.0 + 2.0 * std::f64::consts::PI * 300.0,
        "{length}"
    );

    // Queries.
    let get_length = c
        .client::<TrackGetLengthRequest, TrackGetLengthResponse>(
            "/planar_node/track_get_length",
            TrackGetLength::service_type_name(),
        )
        .await;
    let r = call!(
        get_length,
        "get length",
        TrackGetLengthRequest {
            track: "loop".into()
        }
    );
    assert!(r.accepted, "{}", r.message);
    assert_eq!(r.length, length);
    let r = call!(
        get_length,
        "get length unknown",
        TrackGetLengthRequest {
            track: "nope".into()
        }
    );
    assert_eq!((r.accepted, r.error_id), (false, 0x7F01), "{}", r.message);
    let position_at = c
        .client::<TrackGetPositionAtRequest, TrackGetPositionAtResponse>(
            "/planar_node/track_get_position_at",
            TrackGetPositionAt::service_type_name(),
        )
        .await;
    let r = call!(
        position_at,
        "position at 100",
        TrackGetPositionAtRequest {
            track: "loop".into(),
            arc_length: 100.0,
        }
    );
    assert!(r.accepted, "{}", r.message);
    assert!(
        (r.x - 900.0).abs() < 1e-6 && (r.y - 200.0).abs() < 1e-6 && r.c.abs() < 1e-6,
        "{r:?}"
    );

    // m1 joins by action, m2 by service.
    let join_ac = c
        .action::<MoverJoinTrackGoal, MoverJoinTrackResult, MoverJoinTrackFeedback>(
            "/planar_node/mover_join_track",
            &act::MoverJoinTrack::action_type_name(),
        )
        .await;
    let goal = MoverJoinTrackGoal {
        mover: "m1".into(),
        track: "loop".into(),
        use_orientation: true,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&join_ac, "join m1", goal).await;
    assert!(resp.accepted);
    let (status, result) = within(30.0, "join result", join_ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert_eq!(result.track, "loop");
    assert!((result.track_position - 200.0).abs() < 1.0, "{result:?}");
    let join = c
        .client::<MoverJoinTrackRequest, MoverJoinTrackResponse>(
            "/planar_node/mover_join_track",
            srv::MoverJoinTrack::service_type_name(),
        )
        .await;
    let jreq = |m: &str, t: &str| MoverJoinTrackRequest {
        mover: m.into(),
        track: t.into(),
        use_orientation: true,
        ..Default::default()
    };
    let r = call!(join, "join m2", jreq("m2", "loop"));
    assert!(r.accepted, "{}", r.message);
    let r = call!(join, "join unknown track", jreq("m3", "nope"));
    assert_eq!((r.accepted, r.error_id), (false, 0x7F01), "{}", r.message);
    let s = wait_state(&states, 20.0, "m2 on the loop", |s| {
        mover(s, "m2").track == "loop"
            && s.tracks[0].operation_mode == PlanarTrackState::MODE_STANDING
    })
    .await;
    assert_eq!(s.tracks[0].movers, ["m1", "m2"]);
    assert!((mover(&s, "m2").track_position - 700.0).abs() < 1.0);
    assert_eq!(
        mover(&s, "m1").command_mode,
        PlanarMoverState::MODE_ON_TRACK
    );

    // The follower m1 into the leader m2: held back 300 mm behind it (gap control).
    let move_ac = c
        .action::<MoverMoveOnTrackGoal, MoverMoveOnTrackResult, MoverMoveOnTrackFeedback>(
            "/planar_node/mover_move_on_track",
            &act::MoverMoveOnTrack::action_type_name(),
        )
        .await;
    let goal = MoverMoveOnTrackGoal {
        mover: "m1".into(),
        target_position: 1200.0,
        velocity: 500.0,
        gap: 300.0,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&move_ac, "move m1", goal).await;
    assert!(resp.accepted);
    let s = wait_state(&states, 30.0, "m1 waiting at the gap", |s| {
        let m1 = mover(s, "m1");
        m1.waiting && m1.track_velocity == 0.0 && m1.track_acceleration == 0.0
    })
    .await;
    let (m1, m2) = (mover(&s, "m1"), mover(&s, "m2"));
    assert_eq!(m1.gap, 300.0);
    assert!(
        m2.track_position - m1.track_position >= 300.0 - 1e-6
            && m2.track_position - m1.track_position < 301.0,
        "{} {}",
        m1.track_position,
        m2.track_position
    );
    assert_eq!(s.tracks[0].operation_mode, PlanarTrackState::MODE_MOVING);

    // Moving: a join is refused (xplanar.md §2.5).
    let r = call!(join, "join while Moving", jreq("m3", "loop"));
    assert!(!r.accepted);
    assert_eq!(r.error_id, E_TRACK_MODE_CONFLICT.0, "{}", r.message);

    // Bad MoveOnTrack requests: NaN, direction out of range.
    let mv = c
        .client::<MoverMoveOnTrackRequest, MoverMoveOnTrackResponse>(
            "/planar_node/mover_move_on_track",
            srv::MoverMoveOnTrack::service_type_name(),
        )
        .await;
    let mreq = |m: &str, target: f64| MoverMoveOnTrackRequest {
        mover: m.into(),
        target_position: target,
        velocity: 500.0,
        gap: 300.0,
        ..Default::default()
    };
    let r = call!(mv, "move NaN", mreq("m2", f64::NAN));
    assert_eq!((r.accepted, r.error_id), (false, 0x7F02), "{}", r.message);
    let r = call!(
        mv,
        "move bad direction",
        MoverMoveOnTrackRequest {
            direction: 7,
            ..mreq("m2", 1700.0)
        }
    );
    assert_eq!((r.accepted, r.error_id), (false, 0x7F03), "{}", r.message);

    // The leader moves on: the follower reaches its target, keeping the gap.
    let r = call!(mv, "move m2", mreq("m2", 1700.0));
    assert!(r.accepted, "{}", r.message);
    let (status, result) = within(40.0, "move m1 result", move_ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done);
    assert_eq!(result.track, "loop");
    assert!((result.track_position - 1200.0).abs() < 0.1, "{result:?}");
    let s = wait_state(&states, 30.0, "both at rest", |s| {
        s.tracks[0].operation_mode == PlanarTrackState::MODE_STANDING
    })
    .await;
    assert!((mover(&s, "m2").track_position - 1700.0).abs() < 0.1);
    assert!(!mover(&s, "m1").waiting);

    // Gear-in on the master mover m2 (§5.8): synchronous at once (m1 is 500 mm behind,
    // as the sync positions say); m1 follows m2's move; the goal never succeeds on its own,
    // cancel = m1's Halt ends it CANCELED.
    let gear_ac = c
        .action::<
            MoverGearInPosOnTrackWithMasterMoverGoal,
            MoverGearInPosOnTrackWithMasterMoverResult,
            MoverGearInPosOnTrackWithMasterMoverFeedback,
        >(
            "/planar_node/mover_gear_in_pos_on_track_with_master_mover",
            &act::MoverGearInPosOnTrackWithMasterMover::action_type_name(),
        )
        .await;
    let goal = MoverGearInPosOnTrackWithMasterMoverGoal {
        mover: "m1".into(),
        master_mover: "m2".into(),
        master_sync_position: 1700.0,
        master_sync_position_track: "loop".into(),
        slave_sync_position: 1200.0,
        slave_sync_position_track: "loop".into(),
        gap: 200.0,
        allowed_slave_sync_directions: 1,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&gear_ac, "gear m1", goal).await;
    assert!(resp.accepted);
    within(20.0, "in_sync feedback", async {
        use futures::StreamExt;
        let fb = gear_ac.feedback_stream(gid);
        futures::pin_mut!(fb);
        loop {
            let f = fb.next().await.expect("feedback").expect("feedback");
            if f.in_sync {
                assert!(f.busy && f.active, "{f:?}");
                assert_eq!(f.track, "loop");
                return;
            }
        }
    })
    .await;
    let r = call!(mv, "move master m2", mreq("m2", 2000.0));
    assert!(r.accepted, "{}", r.message);
    let s = wait_state(&states, 30.0, "m1 geared, m2 at 2000", |s| {
        (mover(s, "m2").track_position - 2000.0).abs() < 1e-6 && mover(s, "m1").in_sync
    })
    .await;
    assert_eq!(mover(&s, "m1").gear_master, "m2");
    assert!(
        (mover(&s, "m1").track_position - 1500.0).abs() < 0.1,
        "{}",
        mover(&s, "m1").track_position
    );
    let cr = within(
        10.0,
        "cancel gear",
        gear_ac.async_cancel_goal(gid, ros2_client::builtin_interfaces::Time::ZERO),
    )
    .await
    .unwrap();
    assert_eq!(cr.goals_canceling.len(), 1, "cancel accepted");
    let (status, result) = within(20.0, "gear result", gear_ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Canceled, "{result:?}");
    assert!(result.command_aborted && !result.done, "{result:?}");

    // ~/markers: the loop as a LINE_STRIP (metres), starting at the first line's start.
    let m = within(20.0, "track marker", async {
        loop {
            let (a, _) = markers.async_take().await.unwrap();
            if let Some(m) = a
                .markers
                .into_iter()
                .find(|m| m.ns == "tracks" && m.action == Marker::ADD)
            {
                return m;
            }
        }
    })
    .await;
    assert_eq!(m.r#type, Marker::LINE_STRIP);
    assert!(m.points.len() > 100, "{}", m.points.len());
    assert!(
        (m.points[0].x - 0.8).abs() < 1e-9 && (m.points[0].y - 0.2).abs() < 1e-9,
        "{:?}",
        m.points[0]
    );
    let last = m.points.last().unwrap();
    assert!((last.x - 0.8).abs() < 1e-6 && (last.y - 0.2).abs() < 1e-6);

    // m1 leaves the loop by action to a free target (the track is Standing again).
    wait_state(&states, 30.0, "Standing after the cancel", |s| {
        s.tracks[0].operation_mode == PlanarTrackState::MODE_STANDING
    })
    .await;
    let leave_ac = c
        .action::<MoverLeaveTrackGoal, MoverLeaveTrackResult, MoverLeaveTrackFeedback>(
            "/planar_node/mover_leave_track",
            &act::MoverLeaveTrack::action_type_name(),
        )
        .await;
    let goal = MoverLeaveTrackGoal {
        mover: "m1".into(),
        x: 1700.0,
        y: 500.0,
        c: 0.0,
        use_orientation: true,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&leave_ac, "leave m1", goal).await;
    assert!(resp.accepted);
    let (status, result) = within(30.0, "leave result", leave_ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert_eq!(result.track, "");
    assert!(
        (result.x - 1700.0).abs() < 0.1 && (result.y - 500.0).abs() < 0.1,
        "{result:?}"
    );
    let s = wait_state(&states, 20.0, "m1 free", |s| {
        mover(s, "m1").command_mode == PlanarMoverState::MODE_FREE_MOVEMENT
    })
    .await;
    assert_eq!(s.tracks[0].movers, ["m2"]);

    // Virtual master axes: power, unknown axis.
    let power = c
        .client::<AxisPowerRequest, AxisPowerResponse>(
            "/planar_node/axis_power",
            AxisPower::service_type_name(),
        )
        .await;
    let r = call!(
        power,
        "axis power",
        AxisPowerRequest {
            axis: "v1".into(),
            enable: true
        }
    );
    assert!(r.accepted, "{}", r.message);
    let r = call!(
        power,
        "axis power unknown",
        AxisPowerRequest {
            axis: "nope".into(),
            enable: true
        }
    );
    assert_eq!((r.accepted, r.error_id), (false, 0x7F01), "{}", r.message);
    wait_state(&states, 20.0, "v1 powered", |s| s.axes[0].powered).await;

    drop(c);
    node.stop().await;
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn planar_tracks_over_dds_both_mappings() {
    require_netns();
    scenario(ServiceMapping::Cyclone).await;
    scenario(ServiceMapping::Enhanced).await;
}
