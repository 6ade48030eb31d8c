//! pickplace_node over real DDS, in-process: a ros2-client client in its own Context discovers
//! the node, reads `~/state`, `~/events` and `~/command_status`, sets the enable levels, gets
//! rejections with their error ids, runs a `~/pick_and_place` goal to its result and cancels
//! one (halt, then abort), runs `~/home`, reads the parameters back; with both request/reply
//! mappings.

use motion_msgs::action::{
    PickPlaceExecute, PickPlaceExecuteFeedback, PickPlaceExecuteGoal, PickPlaceExecuteResult,
};
use motion_msgs::action::{
    PickPlaceHome, PickPlaceHomeFeedback, PickPlaceHomeGoal, PickPlaceHomeResult,
};
use motion_msgs::msg::{CommandStatus, PickPlaceEvent, PickPlaceState};
use motion_msgs::srv::*;
use pickplace_node::PickPlaceNode;
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::ServiceMapping;
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

const CONFIG: &str = r#"
initial_tcp: [0, 0, 200, 180, 0, 0, 0]
belts:
  "1":
    initial_velocity: 100.0
    params: {conveyor_belt_origin: [400, 500, 100, 0, 0, 180], lower_sync_limit: 200, upper_sync_limit: 800, z_dist_belt: 50}
params:
  path_vel: 500
  path_acc: 5000
  path_dec: 5000
  path_jerk: 1000000
  max_vel: [0, 0, 0, 0, 0, 0, 0]
  max_acc_dec: [0, 0, 0, 0, 0, 0, 0]
  max_jerk: [0, 0, 0, 0, 0, 0, 0]
"#;

const UNKNOWN_OBJECT: u32 = 0x7F01;
const ENUM_OUT_OF_RANGE: u32 = 0x7F03;
const INVALID_PARAMETER: u32 = 90001;

fn start_node(domain: u16, mapping: ServiceMapping) -> PickPlaceNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    pickplace_node::start(
        &common("pickplace_node", true, mapping),
        cfg,
        "test",
        domain,
    )
    .expect("pickplace node")
}

fn goal(target: [f64; 7], params: &str) -> PickPlaceExecuteGoal {
    PickPlaceExecuteGoal {
        set_target: 0,
        use_target_pose: true,
        target_pose: target,
        params: params.into(),
    }
}

async fn scenario(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", mapping);

    // ~/state: DISABLED, the TCP where configured, belt 1 running.
    let states =
        c.subscribe::<PickPlaceState>("/pickplace_node/state", PickPlaceState::type_name());
    let statuses =
        c.subscribe::<CommandStatus>("/pickplace_node/command_status", CommandStatus::type_name());
    let events = {
        use ros2_client::qos::{Durability, History};
        let qos = ros2_client::QosProfile::subscription_default()
            .durability(Durability::Volatile)
            .history(History::KeepLast { depth: 1000 });
        let name = ClientNode::name("/pickplace_node/events");
        let topic = c
            .node
            .create_topic(&name, PickPlaceEvent::type_name(), &qos)
            .unwrap();
        c.node
            .create_subscription::<PickPlaceEvent>(&topic, None)
            .unwrap()
    };
    let (first, _) = within(20.0, "first state sample", states.async_take())
        .await
        .unwrap();
    assert_eq!(first.state, PickPlaceState::STATE_DISABLED);
    assert_eq!((first.tcp_x, first.tcp_y, first.tcp_z), (0.0, 0.0, 200.0));
    assert_eq!(first.belts.len(), 1);
    assert_eq!(first.belts[0].belt, 1);
    assert!(first.belts[0].configured && first.belts[0].velocity == 100.0);

    // Levels: xEnable, xRegulatorOnALL (the service discovery also gives ~/events time to match).
    let enable = c
        .client::<PickPlaceSetEnableRequest, PickPlaceSetEnableResponse>(
            "/pickplace_node/set_enable",
            PickPlaceSetEnable::service_type_name(),
        )
        .await;
    let reg = c
        .client::<PickPlaceSetRegulatorOnRequest, PickPlaceSetRegulatorOnResponse>(
            "/pickplace_node/set_regulator_on",
            PickPlaceSetRegulatorOn::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "enable",
        enable.async_call_service(PickPlaceSetEnableRequest { enable: true }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    let r = within(
        5.0,
        "regulator",
        reg.async_call_service(PickPlaceSetRegulatorOnRequest { regulator_on: true }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);

    // The state change DISABLED -> READY arrives on ~/events.
    let ready = within(20.0, "READY event", async {
        loop {
            let (e, _) = events.async_take().await.unwrap();
            if e.kind == PickPlaceEvent::KIND_STATE_CHANGED
                && e.to_state == PickPlaceState::STATE_READY
            {
                break e;
            }
        }
    })
    .await;
    assert_eq!(ready.from_state, PickPlaceState::STATE_DISABLED);

    // Rejections with their ids: unknown belt, bad parameter value, enum out of range.
    let belt_input = c
        .client::<PickPlaceBeltInputRequest, PickPlaceBeltInputResponse>(
            "/pickplace_node/belt_input",
            PickPlaceBeltInput::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "belt 17",
        belt_input.async_call_service(PickPlaceBeltInputRequest {
            belt: 17,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(!r.accepted);
    assert_eq!(r.error_id, UNKNOWN_OBJECT, "{}", r.message);
    assert!(r.message.contains("17"), "{}", r.message);
    let set_params = c
        .client::<PickPlaceSetParamsRequest, PickPlaceSetParamsResponse>(
            "/pickplace_node/set_params",
            PickPlaceSetParams::service_type_name(),
        )
        .await;
    let write = |params: &str| {
        set_params.async_call_service(PickPlaceSetParamsRequest {
            params: params.into(),
        })
    };
    let r = within(5.0, "path_vel -5", write("{path_vel: -5}"))
        .await
        .unwrap();
    assert!(!r.accepted);
    assert_eq!(r.error_id, INVALID_PARAMETER, "{}", r.message);
    let jog = c
        .client::<PickPlaceJogRequest, PickPlaceJogResponse>(
            "/pickplace_node/jog",
            PickPlaceJog::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "jog axis 14",
        jog.async_call_service(PickPlaceJogRequest {
            select_axis: 14,
            jog_pos: true,
            jog_neg: false,
        }),
    )
    .await
    .unwrap();
    assert!(!r.accepted);
    assert_eq!(r.error_id, ENUM_OUT_OF_RANGE, "{}", r.message);
    // A partial write that is accepted, read back with the other fields kept.
    let r = within(5.0, "z_start_dist", write("{z_start_dist: 20}"))
        .await
        .unwrap();
    assert!(r.accepted, "{}", r.message);
    let get = c
        .client::<PickPlaceGetParamsRequest, PickPlaceGetParamsResponse>(
            "/pickplace_node/get_params",
            PickPlaceGetParams::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "get_params",
        get.async_call_service(PickPlaceGetParamsRequest { belt: 0 }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    let p: serde_yaml::Value = serde_yaml::from_str(&r.params).unwrap();
    assert_eq!(p["z_start_dist"].as_f64(), Some(20.0));
    assert_eq!(p["path_vel"].as_f64(), Some(500.0));

    // ~/pick_and_place to a static target: result Done with the TCP at the target, and the
    // execute edge's outputs on ~/command_status.
    let ac = c
        .action::<PickPlaceExecuteGoal, PickPlaceExecuteResult, PickPlaceExecuteFeedback>(
            "/pickplace_node/pick_and_place",
            &PickPlaceExecute::action_type_name(),
        )
        .await;
    let target = [150.0, -50.0, 120.0, 180.0, 0.0, 0.0, 0.0];
    let (gid, resp) = send_goal(&ac, "send goal", goal(target, "")).await;
    assert!(resp.accepted);
    let (status, result) = within(30.0, "pick_and_place result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && !result.error, "{result:?}");
    for (got, want) in result.tcp.iter().zip(target) {
        assert!((got - want).abs() < 1e-6, "{:?}", result.tcp);
    }
    let done = within(10.0, "command_status done", async {
        loop {
            let (s, _) = statuses.async_take().await.unwrap();
            if s.done {
                break s;
            }
        }
    })
    .await;
    assert_eq!(
        (done.object.as_str(), done.command.as_str()),
        ("cell", "pick_and_place")
    );

    // A goal that fails screening: accepted, then ABORTED with the id.
    let bad = PickPlaceExecuteGoal {
        set_target: 9,
        ..Default::default()
    };
    let (gid, _) = send_goal(&ac, "send bad goal", bad).await;
    let (status, result) = within(20.0, "bad goal result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert!(result.error);
    assert_eq!(result.error_id, ENUM_OUT_OF_RANGE, "{}", result.message);

    // ~/home: A1 and A2 in the first stage (direct set, §6) -> Done, group homed.
    let r = within(
        5.0,
        "homing order",
        write("{homing_order: [1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]}"),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    let home = c
        .action::<PickPlaceHomeGoal, PickPlaceHomeResult, PickPlaceHomeFeedback>(
            "/pickplace_node/home",
            &PickPlaceHome::action_type_name(),
        )
        .await;
    let (gid, resp) = send_goal(&home, "send home goal", PickPlaceHomeGoal::default()).await;
    assert!(resp.accepted);
    let (status, result) = within(20.0, "home result", home.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && result.axes_group_homed, "{result:?}");

    // Cancel: a long move (2 m at 100 mm/s); cancel = halt, abort at standstill -> CANCELED,
    // the cell READY again without a held path.
    let far = [2150.0, -50.0, 120.0, 180.0, 0.0, 0.0, 0.0];
    let (gid, resp) = send_goal(&ac, "send long goal", goal(far, "{path_vel: 100}")).await;
    assert!(resp.accepted);
    tokio::time::sleep(std::time::Duration::from_millis(300)).await;
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
    assert!(result.command_aborted);
    // (homing set X and Y to their home position 0: the move started at X = 0)
    assert!(
        result.tcp[0] > 1.0 && result.tcp[0] < 2150.0,
        "stopped on the way: {:?}",
        result.tcp
    );
    within(
        10.0,
        "READY without held path, at rest where the goal ended",
        async {
            loop {
                let (s, _) = states.async_take().await.unwrap();
                // (older samples may still be queued: wait for one at the end position)
                if s.state == PickPlaceState::STATE_READY
                    && !s.path_hold
                    && !s.busy
                    && (s.tcp_x - result.tcp[0]).abs() < 1e-6
                {
                    break;
                }
            }
        },
    )
    .await;

    drop(c);
    node.stop().await;
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pickplace_node_over_dds_both_mappings() {
    require_netns();
    scenario(ServiceMapping::Cyclone).await;
    scenario(ServiceMapping::Enhanced).await;
}
