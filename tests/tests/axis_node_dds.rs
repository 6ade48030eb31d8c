//! axis_node over real DDS, in-process (issue 2 harness (a)): a ros2-client client in its own
//! Context discovers the node, reads a state topic, calls services (accepted and rejected with
//! error ids), runs an action to its result and cancels one; with both request/reply mappings.

use axis_node::AxisNode;
use motion_msgs::action::{MoveAbsolute, MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback};
use motion_msgs::action::{MoveVelocity, MoveVelocityFeedback, MoveVelocityGoal, MoveVelocityResult};
use motion_msgs::msg::AxisStateArray;
use motion_msgs::srv::{self, MoveAbsoluteRequest, MoveAbsoluteResponse, Power, PowerRequest, PowerResponse};
use motion_runtime::shell::{service_qos, topic_qos};
use ros2_client::action::ActionClientQosPolicies;
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{Client, ServiceMapping};
use system_tests::{common, require_netns, unique_domain, within, ClientNode};

const CONFIG: &str = "axes:\n  x:\n    max_velocity: 1000.0\n    acceleration: 10000.0\n    deceleration: 10000.0\n    jerk: 100000.0\n";

fn start_node(domain: u16, mapping: ServiceMapping) -> AxisNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    axis_node::start(&common("axis_node", true, mapping), cfg, "test", domain).expect("axis node")
}

/// Steps the lockstep node `cycles` cycles every millisecond until dropped.
fn drive(node: &AxisNode, cycles: u64) -> system_tests::AbortOnDrop {
    let handle = node.handle();
    system_tests::AbortOnDrop(tokio::spawn(async move {
        while handle.step(cycles).await.is_ok() {
            tokio::time::sleep(std::time::Duration::from_millis(1)).await;
        }
    }))
}

async fn client<Req, Resp>(c: &mut ClientNode, name: &str, ty: ros2_client::ServiceTypeName) -> Client<Req, Resp>
where
    Req: ros2_client::Message + Clone + 'static,
    Resp: ros2_client::Message + 'static,
{
    let cl = c
        .node
        .create_client::<Req, Resp>(c.mapping, &ClientNode::name(name), &ty, service_qos(), service_qos())
        .expect("client");
    within(20.0, &format!("service {name} discovered"), cl.wait_for_service(&c.node)).await;
    cl
}

fn action_qos() -> ActionClientQosPolicies {
    use ros2_client::qos::{Durability, History};
    let status = ros2_client::QosProfile::subscription_default()
        .history(History::KeepLast { depth: 1 })
        .durability(Durability::TransientLocal);
    ActionClientQosPolicies {
        goal_service: service_qos(),
        result_service: service_qos(),
        cancel_service: service_qos(),
        feedback_subscription: topic_qos(),
        status_subscription: status,
    }
}

async fn scenario(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    // Simulated time at 5x real time (a free-running cycle would starve DDS on 2 cores).
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", mapping);

    // A state topic.
    let topic = c
        .node
        .create_topic(&ClientNode::name("/axis_node/axis_states"), AxisStateArray::type_name(), &topic_qos())
        .unwrap();
    let states = c.node.create_subscription::<AxisStateArray>(&topic, None).unwrap();
    let (first, _) = within(20.0, "first axis_states sample", states.async_take()).await.unwrap();
    assert_eq!(first.axes.len(), 1);
    assert_eq!(first.axes[0].name, "x");
    assert_eq!(first.axes[0].motion_state, motion_msgs::msg::AxisState::MC_AXISSTATE_DISABLED);

    // Services: power on, a rejected move (unknown axis, NaN), an accepted one.
    let power = client::<PowerRequest, PowerResponse>(&mut c, "/axis_node/power", Power::service_type_name()).await;
    let r = within(5.0, "power", power.async_call_service(PowerRequest { axis: "x".into(), enable: true, ..Default::default() }))
        .await
        .unwrap();
    assert!(r.accepted, "power: {}", r.message);

    let mv = client::<MoveAbsoluteRequest, MoveAbsoluteResponse>(&mut c, "/axis_node/move_absolute", srv::MoveAbsolute::service_type_name()).await;
    let bad = within(5.0, "move unknown axis", mv.async_call_service(MoveAbsoluteRequest { axis: "nope".into(), position: 1.0, velocity: 10.0, ..Default::default() }))
        .await
        .unwrap();
    assert!(!bad.accepted);
    assert_eq!(bad.error_id, 0x7F01, "{}", bad.message);
    assert!(bad.message.contains("nope"));
    let nan = within(5.0, "move NaN", mv.async_call_service(MoveAbsoluteRequest { axis: "x".into(), position: f64::NAN, velocity: 10.0, ..Default::default() }))
        .await
        .unwrap();
    assert!(!nan.accepted);
    assert_ne!(nan.error_id, 0);
    let bm = within(5.0, "move bad buffer mode", mv.async_call_service(MoveAbsoluteRequest { axis: "x".into(), position: 1.0, velocity: 10.0, buffer_mode: 9, ..Default::default() }))
        .await
        .unwrap();
    assert!(!bm.accepted);
    assert_eq!(bm.error_id, 0x7F03, "{}", bm.message);

    // An action to its result: MC_MoveAbsolute to 50.
    let ac = c
        .node
        .create_action_client::<MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback>(
            mapping,
            &ClientNode::name("/axis_node/move_absolute"),
            &MoveAbsolute::action_type_name(),
            action_qos(),
        )
        .unwrap();
    within(20.0, "action server discovered", ac.goal_client().wait_for_service(&c.node)).await;
    within(20.0, "result service discovered", ac.result_client().wait_for_service(&c.node)).await;
    let goal = MoveAbsoluteGoal { axis: "x".into(), position: 50.0, velocity: 500.0, ..Default::default() };
    let (gid, resp) = within(10.0, "send goal", ac.async_send_goal(goal)).await.unwrap();
    assert!(resp.accepted);
    let (status, result) = within(20.0, "move result", ac.async_request_result(gid)).await.unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && !result.error);
    assert!((result.position - 50.0).abs() < 1e-6, "{} {:?}", result.position, node.handle().snapshot());

    // An action with an error: a goal on an unknown axis ends Aborted with the error id.
    let goal = MoveAbsoluteGoal { axis: "nope".into(), position: 1.0, velocity: 10.0, ..Default::default() };
    let (gid, _) = within(10.0, "send bad goal", ac.async_send_goal(goal)).await.unwrap();
    let (status, result) = within(20.0, "bad goal result", ac.async_request_result(gid)).await.unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert!(result.error);
    assert_eq!(result.error_id, 0x7F01);

    // Cancel: an endless MC_MoveVelocity; cancel = MC_Halt, the goal ends Canceled.
    let vc = c
        .node
        .create_action_client::<MoveVelocityGoal, MoveVelocityResult, MoveVelocityFeedback>(
            mapping,
            &ClientNode::name("/axis_node/move_velocity"),
            &MoveVelocity::action_type_name(),
            action_qos(),
        )
        .unwrap();
    within(20.0, "velocity action discovered", vc.goal_client().wait_for_service(&c.node)).await;
    within(20.0, "velocity cancel discovered", vc.cancel_client().wait_for_service(&c.node)).await;
    within(20.0, "velocity result discovered", vc.result_client().wait_for_service(&c.node)).await;
    let goal = MoveVelocityGoal { axis: "x".into(), velocity: 100.0, direction: 1, ..Default::default() };
    let (gid, resp) = within(10.0, "send velocity goal", vc.async_send_goal(goal)).await.unwrap();
    assert!(resp.accepted);
    tokio::time::sleep(std::time::Duration::from_millis(200)).await;
    let cr = within(10.0, "cancel", vc.async_cancel_goal(gid, ros2_client::builtin_interfaces::Time::ZERO)).await.unwrap();
    assert_eq!(cr.goals_canceling.len(), 1, "cancel accepted");
    let (status, result) = within(20.0, "canceled result", vc.async_request_result(gid)).await.unwrap();
    assert_eq!(status, GoalStatusEnum::Canceled, "{result:?}");
    assert!(result.command_aborted);

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
