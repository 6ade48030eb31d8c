//! planar_node over real DDS, in-process: a ros2-client client in its own Context discovers
//! the node, reads `~/state`, `~/mover_poses` and `~/markers`, calls services (accepted and
//! rejected with error ids), runs a MoveToPosition action to its result and cancels one
//! (cancel = the mover's Halt, xplanar.md §9); with both request/reply mappings.

use motion_msgs::action::{
    MoverMoveToPosition, MoverMoveToPositionFeedback, MoverMoveToPositionGoal,
    MoverMoveToPositionResult,
};
use motion_msgs::deps::geometry_msgs::msg::PoseArray;
use motion_msgs::deps::visualization_msgs::msg::{Marker, MarkerArray};
use motion_msgs::msg::{PlanarMoverState, PlanarState};
use motion_msgs::srv::{
    self, MoverEnable, MoverEnableRequest, MoverEnableResponse, MoverMoveCRequest,
    MoverMoveCResponse,
};
use motion_msgs::srv::{MoverMoveToPositionRequest, MoverMoveToPositionResponse};
use motion_msgs::srv::{MoverReset, MoverResetRequest, MoverResetResponse};
use motion_msgs::srv::{PlanarInjectError, PlanarInjectErrorRequest, PlanarInjectErrorResponse};
use planar_engine::errors::{E_COLLISION, E_INVALID_STATE, E_OBJECT_ERROR};
use planar_node::PlanarNode;
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{ServiceMapping, Subscription};
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

/// One 3 x 2 stator part, two movers on it.
const CONFIG: &str = "
coordinate_systems: [0x01010060]
parts:
  - {name: table, oid: 0x01010020, tiles: [[0, 0], [240, 0], [480, 0], [0, 240], [240, 240], [480, 240]], positions: {1: {cs: 0x01010060, x: 0, y: 0}}}
environment: {name: env, processing_unit_oid: 0x01010002}
movers:
  - {name: m1, initial_pose: {x: 120, y: 120}}
  - {name: m2, initial_pose: {x: 600, y: 360}, width: 210}
groups: [{name: g1}]
";

fn start_node(domain: u16, mapping: ServiceMapping) -> PlanarNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    planar_node::start(&common("planar_node", true, mapping), cfg, "test", domain)
        .expect("planar node")
}

/// Takes state samples until `pred` holds for one (within `secs`).
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

async fn scenario(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    // Simulated time at 5x real time (a free-running cycle would starve DDS on 2 cores).
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", mapping);

    // ~/state: environment, movers in configuration order, Disabled at start.
    let states = c.subscribe::<PlanarState>("/planar_node/state", PlanarState::type_name());
    let (first, _) = within(20.0, "first state sample", states.async_take())
        .await
        .unwrap();
    assert_eq!(
        first
            .movers
            .iter()
            .map(|m| m.name.as_str())
            .collect::<Vec<_>>(),
        ["m1", "m2"]
    );
    assert_eq!(first.movers[0].state, PlanarMoverState::STATE_DISABLED);
    assert_eq!((first.movers[1].x, first.movers[1].y), (600.0, 360.0));
    assert_eq!(first.environment.stator_count, 6);
    assert_eq!(first.groups[0].name, "g1");
    assert_eq!(first.parts[0].name, "table");

    // ~/mover_poses (metres, frame planar_env) and ~/markers (6 stators, sized movers).
    let poses = c.subscribe::<PoseArray>("/planar_node/mover_poses", PoseArray::type_name());
    let (p, _) = within(20.0, "mover poses", poses.async_take())
        .await
        .unwrap();
    assert_eq!(p.header.frame_id, "planar_env");
    assert_eq!(p.poses.len(), 2);
    assert!(
        (p.poses[1].position.x - 0.6).abs() < 1e-9 && (p.poses[1].position.y - 0.36).abs() < 1e-9,
        "{p:?}"
    );
    let markers = c.subscribe::<MarkerArray>("/planar_node/markers", MarkerArray::type_name());
    let (m, _) = within(20.0, "markers", markers.async_take()).await.unwrap();
    let stators = m
        .markers
        .iter()
        .find(|m| m.ns == "stators")
        .expect("stators marker");
    assert_eq!(stators.points.len(), 6);
    let m2 = m
        .markers
        .iter()
        .find(|m| m.ns == "movers" && m.id == 1)
        .expect("m2 marker");
    assert_eq!(m2.r#type, Marker::CUBE);
    assert!((m2.scale.x - 0.21).abs() < 1e-9);

    // Services: enable m1 (Enabling -> Enabled after enable_time), rejections with their ids.
    let enable = c
        .client::<MoverEnableRequest, MoverEnableResponse>(
            "/planar_node/mover_enable",
            MoverEnable::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "enable",
        enable.async_call_service(MoverEnableRequest { mover: "m1".into() }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "enable: {}", r.message);
    assert_ne!(r.command_id, 0);
    let bad = within(
        5.0,
        "enable unknown",
        enable.async_call_service(MoverEnableRequest {
            mover: "nope".into(),
        }),
    )
    .await
    .unwrap();
    assert!(!bad.accepted);
    assert_eq!(bad.error_id, 0x7F01, "{}", bad.message);
    assert!(bad.message.contains("nope"), "{}", bad.message);
    wait_state(&states, 20.0, "m1 Enabled", |s| {
        s.movers[0].state == PlanarMoverState::STATE_ENABLED
    })
    .await;

    let mv = c
        .client::<MoverMoveToPositionRequest, MoverMoveToPositionResponse>(
            "/planar_node/mover_move_to_position",
            srv::MoverMoveToPosition::service_type_name(),
        )
        .await;
    // m2 is still Disabled: E_INVALID_STATE (xplanar.md §2.1, §6.2).
    let r = within(
        5.0,
        "move disabled mover",
        mv.async_call_service(MoverMoveToPositionRequest {
            mover: "m2".into(),
            x: 500.0,
            y: 360.0,
            use_orientation: true,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(!r.accepted);
    assert_eq!(r.error_id, E_INVALID_STATE.0, "{}", r.message);
    let r = within(
        5.0,
        "move NaN",
        mv.async_call_service(MoverMoveToPositionRequest {
            mover: "m1".into(),
            x: f64::NAN,
            y: 100.0,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F02, "{}", r.message);
    let mc = c
        .client::<MoverMoveCRequest, MoverMoveCResponse>(
            "/planar_node/mover_move_c",
            srv::MoverMoveC::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "move_c bad direction",
        mc.async_call_service(MoverMoveCRequest {
            mover: "m1".into(),
            target_position: 5.0,
            direction: 9,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);

    // An action to its result: MoveToPosition of m1 to (300, 200, c 10).
    let ac = c
        .action::<MoverMoveToPositionGoal, MoverMoveToPositionResult, MoverMoveToPositionFeedback>(
            "/planar_node/mover_move_to_position",
            &MoverMoveToPosition::action_type_name(),
        )
        .await;
    let goal = MoverMoveToPositionGoal {
        mover: "m1".into(),
        x: 300.0,
        y: 200.0,
        c: 10.0,
        use_orientation: true,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&ac, "send goal", goal).await;
    assert!(resp.accepted);
    let (status, result) = within(30.0, "move result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && !result.error);
    // Spec tolerance ±0.1 mm, ±0.01° (xplanar.md §7).
    assert!(
        (result.x - 300.0).abs() < 0.1 && (result.y - 200.0).abs() < 0.1,
        "{result:?}"
    );
    assert!((result.c - 10.0).abs() < 0.01, "{result:?}");

    // A goal that fails screening ends Aborted with the error id (unknown mover).
    let goal = MoverMoveToPositionGoal {
        mover: "nope".into(),
        x: 1.0,
        ..Default::default()
    };
    let (gid, _) = send_goal(&ac, "send bad goal", goal).await;
    let (status, result) = within(20.0, "bad goal result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert!(result.error);
    assert_eq!(result.error_id, 0x7F01);

    // Cancel: a slow move across the table; cancel = the mover's Halt, the goal ends Canceled
    // with the mover stopped short of the target.
    let goal = MoverMoveToPositionGoal {
        mover: "m1".into(),
        x: 300.0,
        y: 420.0,
        c: 10.0,
        velocity: 50.0,
        use_orientation: true,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&ac, "send slow goal", goal).await;
    assert!(resp.accepted);
    tokio::time::sleep(std::time::Duration::from_millis(200)).await;
    let cr = within(
        10.0,
        "cancel",
        ac.async_cancel_goal(gid, ros2_client::builtin_interfaces::Time::ZERO),
    )
    .await
    .unwrap();
    assert_eq!(cr.goals_canceling.len(), 1, "cancel accepted");
    let (status, result) = within(20.0, "canceled result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Canceled, "{result:?}");
    assert!(result.command_aborted && !result.done, "{result:?}");
    assert!(
        result.y > 200.0 && result.y < 410.0,
        "stopped on the way: {result:?}"
    );
    // (Older samples are still queued: skip those from before the move.)
    let s = wait_state(&states, 20.0, "m1 at rest", |s| {
        !s.movers[0].busy_mover && s.movers[0].y > 200.0
    })
    .await;
    assert!(
        (s.movers[0].y - result.y).abs() < 5.0,
        "halted near the cancel point: {} vs {}",
        s.movers[0].y,
        result.y
    );

    // Outside a group there are no collision checks (§3.2; issue 15.2): a move onto the
    // standing m2 is accepted and ends in a crash at the contact. The goal aborts with
    // E_COLLISION and objectInfo {Mover (302), m2's OID} (xplanar.md §6.1); both movers are
    // in Error, each naming the other.
    let goal = MoverMoveToPositionGoal {
        mover: "m1".into(),
        x: 600.0,
        y: 360.0,
        use_orientation: true,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&ac, "send colliding goal", goal).await;
    assert!(resp.accepted);
    let (status, result) = within(20.0, "colliding goal result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert_eq!(result.error_id, E_COLLISION.0, "{result:?}");
    assert_eq!(
        (result.object_type, result.object_id),
        (302, s.movers[1].oid)
    );
    let crashed = wait_state(&states, 20.0, "both movers in Error", |s| {
        s.movers
            .iter()
            .all(|m| m.state == PlanarMoverState::STATE_ERROR)
    })
    .await;
    for (k, other) in [(0, 1), (1, 0)] {
        let m = &crashed.movers[k];
        assert_eq!(m.error_id, E_COLLISION.0, "{}", m.name);
        assert_eq!(m.object_id, crashed.movers[other].oid, "{}", m.name);
    }
    let reset = c
        .client::<MoverResetRequest, MoverResetResponse>(
            "/planar_node/mover_reset",
            MoverReset::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "reset m2",
        reset.async_call_service(MoverResetRequest { mover: "m2".into() }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    wait_state(&states, 20.0, "m2 reset to Disabled", |s| {
        s.movers[1].state == PlanarMoverState::STATE_DISABLED
    })
    .await;
    // The crash switched m2 off (reaction Abort): enable it again.
    let r = within(
        5.0,
        "enable m2",
        enable.async_call_service(MoverEnableRequest { mover: "m2".into() }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "enable m2: {}", r.message);
    wait_state(&states, 20.0, "m2 Enabled", |s| {
        s.movers[1].state == PlanarMoverState::STATE_ENABLED
    })
    .await;

    // The fault-injection hook (xplanar.md §6.2): m2 goes to Error with E_OBJECT_ERROR; a
    // wrong object kind is an enum error.
    let inject = c
        .client::<PlanarInjectErrorRequest, PlanarInjectErrorResponse>(
            "/planar_node/sim/inject_error",
            PlanarInjectError::service_type_name(),
        )
        .await;
    let bad = PlanarInjectErrorRequest {
        kind: 7,
        name: "m2".into(),
        reaction: 1,
    };
    let r = within(5.0, "inject bad kind", inject.async_call_service(bad))
        .await
        .unwrap();
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);
    let req = PlanarInjectErrorRequest {
        kind: PlanarInjectErrorRequest::KIND_MOVER,
        name: "m2".into(),
        reaction: 1,
    };
    let r = within(5.0, "inject", inject.async_call_service(req))
        .await
        .unwrap();
    assert!(r.accepted, "{}", r.message);
    let s = wait_state(&states, 20.0, "m2 in Error", |s| {
        s.movers[1].state == PlanarMoverState::STATE_ERROR
    })
    .await;
    assert_eq!(s.movers[1].error_id, E_OBJECT_ERROR.0);

    drop(c);
    node.stop().await;
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn planar_node_over_dds_both_mappings() {
    require_netns();
    scenario(ServiceMapping::Cyclone).await;
    scenario(ServiceMapping::Enhanced).await;
}
