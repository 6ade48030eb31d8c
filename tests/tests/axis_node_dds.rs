//! axis_node over real DDS, in-process (issue 2 harness (a)): a ros2-client client in its own
//! Context discovers the node, reads a state topic, calls services (accepted and rejected with
//! error ids), runs an action to its result and cancels one; with both request/reply mappings.

use axis_node::AxisNode;
use motion_msgs::action::{Jog, JogFeedback, JogGoal, JogResult};
use motion_msgs::action::{
    MoveAbsolute, MoveAbsoluteFeedback, MoveAbsoluteGoal, MoveAbsoluteResult,
};
use motion_msgs::action::{
    MoveVelocity, MoveVelocityFeedback, MoveVelocityGoal, MoveVelocityResult,
};
use motion_msgs::msg::{AxisState, AxisStateArray, CommandStatus};
use motion_msgs::srv::{
    self, MoveAbsoluteRequest, MoveAbsoluteResponse, Power, PowerRequest, PowerResponse,
};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::ServiceMapping;
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

const CONFIG: &str = "axes:\n  x:\n    max_velocity: 1000.0\n    acceleration: 10000.0\n    deceleration: 10000.0\n    jerk: 100000.0\n";

fn start_node(domain: u16, mapping: ServiceMapping) -> AxisNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    axis_node::start(&common("axis_node", true, mapping), cfg, "test", domain).expect("axis node")
}

async fn scenario(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", mapping);

    // A state topic.
    let states =
        c.subscribe::<AxisStateArray>("/axis_node/axis_states", AxisStateArray::type_name());
    let statuses =
        c.subscribe::<CommandStatus>("/axis_node/command_status", CommandStatus::type_name());
    let (first, _) = within(20.0, "first axis_states sample", states.async_take())
        .await
        .unwrap();
    assert_eq!(first.axes.len(), 1);
    assert_eq!(first.axes[0].name, "x");
    assert_eq!(first.axes[0].motion_state, AxisState::MC_AXISSTATE_DISABLED);

    // Services: power on, rejected moves (unknown axis, NaN, bad enum), then the action.
    let power = c
        .client::<PowerRequest, PowerResponse>("/axis_node/power", Power::service_type_name())
        .await;
    let r = within(
        5.0,
        "power",
        power.async_call_service(PowerRequest {
            axis: "x".into(),
            enable: true,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "power: {}", r.message);

    let mv = c
        .client::<MoveAbsoluteRequest, MoveAbsoluteResponse>(
            "/axis_node/move_absolute",
            srv::MoveAbsolute::service_type_name(),
        )
        .await;
    let call = |axis: &str, position: f64, buffer_mode: u8| {
        mv.async_call_service(MoveAbsoluteRequest {
            axis: axis.into(),
            position,
            velocity: 10.0,
            buffer_mode,
            ..Default::default()
        })
    };
    let bad = within(5.0, "move unknown axis", call("nope", 1.0, 0))
        .await
        .unwrap();
    assert!(!bad.accepted);
    assert_eq!(bad.error_id, 0x7F01, "{}", bad.message);
    assert!(bad.message.contains("nope"));
    let nan = within(5.0, "move NaN", call("x", f64::NAN, 0))
        .await
        .unwrap();
    assert!(!nan.accepted);
    assert_ne!(nan.error_id, 0, "{}", nan.message);
    let bm = within(5.0, "move bad buffer mode", call("x", 1.0, 9))
        .await
        .unwrap();
    assert!(!bm.accepted);
    assert_eq!(bm.error_id, 0x7F03, "{}", bm.message);

    // An action to its result: MC_MoveAbsolute to 50.
    let ac = c
        .action::<MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback>(
            "/axis_node/move_absolute",
            &MoveAbsolute::action_type_name(),
        )
        .await;
    let goal = MoveAbsoluteGoal {
        axis: "x".into(),
        position: 50.0,
        velocity: 500.0,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&ac, "send goal", goal).await;
    assert!(resp.accepted);
    let (status, result) = within(20.0, "move result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && !result.error);
    assert!((result.position - 50.0).abs() < 1e-6, "{}", result.position);
    // The same command's Done on ~/command_status, labelled.
    within(10.0, "command_status Done", async {
        loop {
            let (s, _) = statuses.async_take().await.unwrap();
            if s.done && s.command == "move_absolute" {
                assert_eq!(s.object, "x");
                break;
            }
        }
    })
    .await;

    // An action with an error: a goal on an unknown axis ends Aborted with the error id.
    let goal = MoveAbsoluteGoal {
        axis: "nope".into(),
        position: 1.0,
        velocity: 10.0,
        ..Default::default()
    };
    let (gid, _) = send_goal(&ac, "send bad goal", goal).await;
    let (status, result) = within(20.0, "bad goal result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert!(result.error);
    assert_eq!(result.error_id, 0x7F01);

    // fb_instance (§12.1): a goal of another instance takes over in the engine (the first
    // ends ABORTED, no reason); a goal of the same instance re-triggers it (ABORTED,
    // command_aborted, "retriggered"); the last runs to Done.
    let slow = |position: f64, fb_instance: &str| MoveAbsoluteGoal {
        axis: "x".into(),
        position,
        velocity: 20.0,
        fb_instance: fb_instance.into(),
        ..Default::default()
    };
    let (g1, _) = send_goal(&ac, "instance a", slow(0.0, "a")).await;
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    let (g2, _) = send_goal(&ac, "instance b", slow(10.0, "b")).await;
    let (status, r1) = within(20.0, "a result", ac.async_request_result(g1))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted, "{r1:?}");
    assert!(
        r1.command_aborted && !r1.error && r1.message.is_empty(),
        "{r1:?}"
    );
    tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    let (g3, _) = send_goal(&ac, "instance b again", slow(5.0, "b")).await;
    let (status, r2) = within(20.0, "b result", ac.async_request_result(g2))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted, "{r2:?}");
    assert!(r2.command_aborted && !r2.error, "{r2:?}");
    assert_eq!(r2.message, "retriggered");
    let (status, r3) = within(20.0, "re-triggered result", ac.async_request_result(g3))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{r3:?}");
    assert!((r3.position - 5.0).abs() < 1e-6, "{r3:?}");

    // Cancel: an endless MC_MoveVelocity; cancel = MC_Halt, the goal ends Canceled.
    let vc = c
        .action::<MoveVelocityGoal, MoveVelocityResult, MoveVelocityFeedback>(
            "/axis_node/move_velocity",
            &MoveVelocity::action_type_name(),
        )
        .await;
    // A slow ramp (100 s to InVelocity, where the goal would succeed): canceled while ramping.
    let goal = MoveVelocityGoal {
        axis: "x".into(),
        velocity: 100.0,
        acceleration: 1.0,
        direction: 1,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&vc, "send velocity goal", goal).await;
    assert!(resp.accepted);
    tokio::time::sleep(std::time::Duration::from_millis(200)).await;
    let cr = within(
        10.0,
        "cancel",
        vc.async_cancel_goal(gid, ros2_client::builtin_interfaces::Time::ZERO),
    )
    .await
    .unwrap();
    assert_eq!(cr.goals_canceling.len(), 1, "cancel accepted");
    let (status, result) = within(20.0, "canceled result", vc.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Canceled, "{result:?}");
    assert!(result.command_aborted);
    // MC_Halt brings the axis to standstill (it does not stay in ContinuousMotion).
    within(10.0, "standstill after the cancel", async {
        loop {
            let (s, _) = states.async_take().await.unwrap();
            if s.axes[0].motion_state == AxisState::MC_AXISSTATE_STANDSTILL {
                assert!(s.axes[0].act_velo.abs() < 1e-9);
                break;
            }
        }
    })
    .await;

    // MC_Jog as an action: the goal holds the button, cancel releases it; the axis brakes with
    // the jog's deceleration (20 u/s^2: 1 s), the instance ends Done and the goal CANCELED
    // (done = true).
    let jc = c
        .action::<JogGoal, JogResult, JogFeedback>("/axis_node/jog", &Jog::action_type_name())
        .await;
    let goal = JogGoal {
        axis: "x".into(),
        jog_forward: true,
        mode: JogGoal::MC_JOGMODE_CONTINOUS,
        velocity: 20.0,
        deceleration: 20.0,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&jc, "send jog goal", goal).await;
    assert!(resp.accepted);
    within(10.0, "jogging at 20", async {
        loop {
            let (s, _) = states.async_take().await.unwrap();
            if (s.axes[0].act_velo - 20.0).abs() < 1e-6 {
                break;
            }
        }
    })
    .await;
    let cr = within(
        10.0,
        "cancel jog",
        jc.async_cancel_goal(gid, ros2_client::builtin_interfaces::Time::ZERO),
    )
    .await
    .unwrap();
    assert_eq!(cr.goals_canceling.len(), 1, "cancel accepted");
    // While it brakes the goal is CANCELING, still active: it reports its progress, as
    // rclcpp's and rclpy's action servers do (ros2-client patch 10); below 10 u/s the axis
    // has braked for half a second, long after the cancel was answered.
    let braking = within(10.0, "feedback while canceling", async {
        use futures::StreamExt;
        let mut fb = Box::pin(jc.feedback_stream(gid));
        loop {
            let f = fb.next().await.expect("feedback stream").expect("feedback");
            if f.velocity > 0.0 && f.velocity < 10.0 {
                break f;
            }
        }
    })
    .await;
    assert!(braking.busy, "{braking:?}");
    let (status, result) = within(20.0, "jog result", jc.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Canceled, "{result:?}");
    assert!(result.done && !result.command_aborted, "{result:?}");
    // A jog goal without a button is refused with its id.
    let (gid, _) = send_goal(
        &jc,
        "send buttonless jog",
        JogGoal {
            axis: "x".into(),
            jog_forward: false,
            ..Default::default()
        },
    )
    .await;
    let (status, result) = within(20.0, "buttonless jog result", jc.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert_eq!(result.error_id, 0x7F06, "{result:?}");

    drop(c);
    node.stop().await;
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn axis_node_over_dds_both_mappings() {
    require_netns();
    scenario(ServiceMapping::Cyclone).await;
    scenario(ServiceMapping::Enhanced).await;
}
