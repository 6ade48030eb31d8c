//! The ROS side never goes deaf, never stalls, never drops a request (issue 12), over real
//! DDS, in-process:
//! - replies never carry unbounded echoed input, and large legitimate replies work (§1);
//! - a client that never asks for its result does not delay another client's result; ended
//!   results are kept for `result_timeout`, then dropped (§2);
//! - bursts of service requests and action goals all get an answer (§3).

use axis_engine::{AxisCommand, BufferMode, MoveAbsolute, MoveOptions};
use motion_msgs::srv::{
    PickPlaceSetParams, PickPlaceSetParamsRequest, PickPlaceSetParamsResponse, Power, PowerRequest,
    PowerResponse, SubmitBatch, SubmitBatchRequest, SubmitBatchResponse,
};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::ServiceMapping;
use std::time::{Duration, Instant};
use system_tests::flood::{
    axis_node, goal_burst, move_absolute_client, move_goal, pipelined, service_flood, QUEUE_FULL,
};
use system_tests::{common, drive, require_netns, unique_domain, within, ClientNode};

/// §1: a refusal never echoes a 66 kB input whole, and the node keeps answering; a long
/// legitimate reply (2000 refused batch orders) arrives whole.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn replies_stay_bounded_and_large_replies_arrive() {
    require_netns();
    let domain = unique_domain();
    let node = axis_node(domain, 900.0);
    let _driver = drive(&node, 5);
    let pp_cfg: serde_yaml::Value = serde_yaml::from_str(
        "belts:\n  \"1\":\n    params: {conveyor_belt_origin: [400, 500, 100, 0, 0, 180]}\n",
    )
    .unwrap();
    let pp = pickplace_node::start(
        &common("pickplace_node", true, ServiceMapping::Cyclone),
        pp_cfg,
        "test",
        domain,
    )
    .expect("pickplace node");
    let _pp_driver = drive(&pp, 5);
    let mut c = ClientNode::new(domain, "test_client", ServiceMapping::Cyclone);

    let sp = c
        .client::<PickPlaceSetParamsRequest, PickPlaceSetParamsResponse>(
            "/pickplace_node/set_params",
            PickPlaceSetParams::service_type_name(),
        )
        .await;
    let huge = format!("{{path_vel: {}}}", "9".repeat(66_000));
    let r = within(
        10.0,
        "set_params 66 kB",
        sp.async_call_service(PickPlaceSetParamsRequest { params: huge }),
    )
    .await
    .unwrap();
    assert!(!r.accepted);
    assert_ne!(r.error_id, 0);
    assert!(
        r.message.len() <= motion_core::fb::MAX_MESSAGE_LEN,
        "reply message of {} bytes",
        r.message.len()
    );
    // Still serving: a good request is accepted.
    let r = within(
        5.0,
        "set_params after",
        sp.async_call_service(PickPlaceSetParamsRequest {
            params: "{path_vel: 200}".into(),
        }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);

    // 2000 orders on an unpowered axis: each refused with its message; the reply (~100 kB)
    // arrives whole.
    let sb = c
        .client::<SubmitBatchRequest, SubmitBatchResponse>(
            "/axis_node/submit_batch",
            SubmitBatch::service_type_name(),
        )
        .await;
    let order = serde_json::to_string(&AxisCommand::MoveAbsolute(MoveAbsolute {
        axis: "x".into(),
        position: 1.0,
        velocity: 10.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }))
    .unwrap();
    let r = within(
        20.0,
        "submit_batch of 2000",
        sb.async_call_service(SubmitBatchRequest {
            orders: vec![order; 2000],
        }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    assert_eq!(r.order_accepted.len(), 2000);
    assert!(r.order_accepted.iter().all(|a| !a));
    assert!(r.error_ids.iter().all(|&e| e != 0));
    let bytes: usize = r.messages.iter().map(|m| m.len() + 5).sum();
    assert!(
        bytes > 65_536,
        "reply only {bytes} bytes: not a large reply"
    );
}

/// §2: client A never asks for its result; client B's result comes within one state period
/// of its goal ending. A's result is still there when A asks later.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_that_never_asks_for_its_result_stalls_nobody() {
    require_netns();
    let domain = unique_domain();
    let node = axis_node(domain, 900.0);
    let _driver = drive(&node, 5);
    let mut a = ClientNode::new(domain, "client_a", ServiceMapping::Cyclone);
    let mut b = ClientNode::new(domain, "client_b", ServiceMapping::Cyclone);
    let ac_a = move_absolute_client(&mut a).await;
    let ac_b = move_absolute_client(&mut b).await;
    // Both goals fail screening (unpowered axis: accepted, then ABORTED with the id at once).
    let (gid_a, acc) = within(10.0, "goal A", ac_a.async_send_goal(move_goal(5.0)))
        .await
        .unwrap();
    assert!(acc.accepted);
    tokio::time::sleep(Duration::from_millis(500)).await; // A's goal has ended, unasked
    for k in 0..3 {
        let (gid_b, acc) = within(10.0, "goal B", ac_b.async_send_goal(move_goal(5.0)))
            .await
            .unwrap();
        assert!(acc.accepted);
        let t0 = Instant::now();
        let (status, result) = within(10.0, "result B", ac_b.async_request_result(gid_b))
            .await
            .unwrap();
        let took = t0.elapsed();
        assert_eq!(status, GoalStatusEnum::Aborted);
        assert!(result.error && result.error_id != 0, "{result:?}");
        // One state period (10 ms) plus DDS round trips on a loaded 2-core machine.
        assert!(
            took < Duration::from_millis(500),
            "B's result #{k} took {took:?}"
        );
    }
    let (status, result) = within(5.0, "result A", ac_a.async_request_result(gid_a))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert!(result.error);
}

/// §2: an ended goal's result is dropped after `result_timeout`; asked later, the answer is
/// STATUS_UNKNOWN at once (as rclcpp), never silence.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn results_expire_after_result_timeout() {
    require_netns();
    let domain = unique_domain();
    let node = axis_node(domain, 1.0);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", ServiceMapping::Cyclone);
    let ac = move_absolute_client(&mut c).await;
    let (early, _) = within(10.0, "goal", ac.async_send_goal(move_goal(5.0)))
        .await
        .unwrap();
    let (late, _) = within(10.0, "goal", ac.async_send_goal(move_goal(5.0)))
        .await
        .unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let (status, _) = within(5.0, "result in time", ac.async_request_result(early))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let (status, _) = within(5.0, "result after timeout", ac.async_request_result(late))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Unknown);
}

/// §3: back-to-back requests with no wait in between are all answered (the first used to be
/// lost beyond 10 in flight).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn back_to_back_requests_are_all_answered() {
    require_netns();
    let domain = unique_domain();
    let node = axis_node(domain, 900.0);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", ServiceMapping::Cyclone);
    let power = c
        .client::<PowerRequest, PowerResponse>("/axis_node/power", Power::service_type_name())
        .await;
    let reqs = (0..200).map(|k| PowerRequest {
        axis: "x".into(),
        enable: k % 2 == 0,
        ..Default::default()
    });
    let n = pipelined(
        &power,
        reqs,
        200,
        Duration::from_secs(5),
        |r: &PowerResponse| assert!(r.accepted || r.error_id == QUEUE_FULL, "{}", r.message),
    )
    .await;
    assert_eq!((n.sent, n.lost()), (200, 0), "{}", n.summary());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn four_clients_flooding_services_lose_nothing() {
    require_netns();
    let (read, motion) = service_flood(5000, 64).await;
    println!(
        "read_status: {}\nmove_absolute: {}",
        read.summary(),
        motion.summary()
    );
    assert_eq!((read.sent, read.lost()), (20_000, 0), "{}", read.summary());
    assert_eq!(
        (motion.sent, motion.lost()),
        (20_000, 0),
        "{}",
        motion.summary()
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_burst_of_2000_goals_gets_every_result() {
    require_netns();
    let (goals, results) = goal_burst(2000).await;
    println!("goals: {}\nresults: {}", goals.summary(), results.summary());
    assert_eq!((goals.sent, goals.lost()), (2000, 0), "{}", goals.summary());
    assert_eq!(
        (results.sent, results.lost()),
        (2000, 0),
        "{}",
        results.summary()
    );
}
