//! The rcl_interfaces parameter services as `ros2 param` uses them (issue 13 §3), under both
//! request/reply mappings: list, get, describe (read-only, with a description), and a set
//! refused with its reason. Before the vendored ros2-client patch the services spoke the
//! Enhanced mapping only, so an rmw_cyclonedds client got no answer.

use ros2_client::rcl_interfaces::{
    DescribeParametersRequest, DescribeParametersResponse, GetParametersRequest,
    GetParametersResponse, ListParametersRequest, ListParametersResponse, SetParametersRequest,
    SetParametersResponse,
};
use ros2_client::{ServiceMapping, ServiceTypeName};
use system_tests::{require_netns, unique_domain, within, ClientNode};

async fn parameters_over(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = system_tests::flood::axis_node_with(domain, mapping);
    let mut c = ClientNode::new(domain, "param_client", mapping);
    let ty = |n: &str| ServiceTypeName::new("rcl_interfaces", n);

    let list = c
        .client::<ListParametersRequest, ListParametersResponse>(
            "/axis_node/list_parameters",
            ty("ListParameters"),
        )
        .await;
    let r = within(
        10.0,
        "list_parameters",
        list.async_call_service(ListParametersRequest {
            prefixes: vec![],
            depth: 0,
        }),
    )
    .await
    .unwrap();
    for name in [
        "cycle_period",
        "state_rate",
        "lockstep",
        "service_mapping",
        "queue_capacity",
        "result_timeout",
        "axes",
        "use_sim_time",
    ] {
        assert!(
            r.result.names.iter().any(|n| n == name),
            "{name} not listed: {:?}",
            r.result.names
        );
    }

    let get = c
        .client::<GetParametersRequest, GetParametersResponse>(
            "/axis_node/get_parameters",
            ty("GetParameters"),
        )
        .await;
    let r = within(
        10.0,
        "get_parameters",
        get.async_call_service(GetParametersRequest {
            names: vec!["cycle_period".into(), "axes".into()],
        }),
    )
    .await
    .unwrap();
    assert_eq!(r.values.len(), 2);
    assert_eq!(r.values[0].double_value, 0.001, "{:?}", r.values[0]);
    assert_eq!(r.values[1].string_array, vec!["x".to_string()]);

    let describe = c
        .client::<DescribeParametersRequest, DescribeParametersResponse>(
            "/axis_node/describe_parameters",
            ty("DescribeParameters"),
        )
        .await;
    let r = within(
        10.0,
        "describe_parameters",
        describe.async_call_service(DescribeParametersRequest {
            names: vec!["cycle_period".into(), "queue_capacity".into()],
        }),
    )
    .await
    .unwrap();
    assert_eq!(r.values.len(), 2);
    for d in &r.values {
        assert!(d.read_only, "{} not read-only", d.name);
        assert!(
            !d.description.is_empty() && !d.description.contains("not implemented"),
            "{}: '{}'",
            d.name,
            d.description
        );
    }
    assert!(r.values[0].description.contains("cycle period"));

    let set = c
        .client::<SetParametersRequest, SetParametersResponse>(
            "/axis_node/set_parameters",
            ty("SetParameters"),
        )
        .await;
    let r = within(
        10.0,
        "set_parameters",
        set.async_call_service(SetParametersRequest {
            parameter: vec![ros2_client::parameters::raw::Parameter {
                name: "state_rate".into(),
                value: ros2_client::parameters::ParameterValue::Double(10.0).into(),
            }],
        }),
    )
    .await
    .unwrap();
    assert_eq!(r.results.len(), 1);
    assert!(!r.results[0].successful);
    assert!(
        r.results[0].reason.contains("read-only"),
        "{}",
        r.results[0].reason
    );
    drop(node);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn parameter_services_with_the_cyclone_mapping() {
    require_netns();
    parameters_over(ServiceMapping::Cyclone).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn parameter_services_with_the_enhanced_mapping() {
    require_netns();
    parameters_over(ServiceMapping::Enhanced).await;
}

/// A node announces its declared parameters on `/parameter_events` as new parameters, as
/// rclcpp and rclpy announce each declaration (vendored ros2-client patch 9). The writer is
/// transient-local (depth 1), so a reader that joins after the node started, as here, still
/// gets the declaration: the node's full name and the launch config's values.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn declared_parameters_are_announced_on_parameter_events() {
    use futures::StreamExt;
    use motion_msgs::deps::rcl_interfaces::msg::ParameterEvent;
    use ros2_client::qos::{Durability, History, QosProfile};
    use ros2_client::MessageTypeName;
    require_netns();
    let domain = unique_domain();
    let node = system_tests::flood::axis_node_with(domain, ServiceMapping::Enhanced);
    let mut c = ClientNode::new(domain, "param_events_client", ServiceMapping::Enhanced);
    // rcl's parameter-events profile asks volatile; transient-local is what a late reader needs.
    let qos = QosProfile::publisher_default()
        .durability(Durability::TransientLocal)
        .history(History::KeepLast { depth: 100 });
    let topic = c
        .node
        .create_topic(
            &ClientNode::name("/parameter_events"),
            MessageTypeName::new("rcl_interfaces", "ParameterEvent"),
            &qos,
        )
        .expect("topic");
    let sub = c
        .node
        .create_subscription::<ParameterEvent>(&topic, None)
        .expect("subscription");
    let event = within(10.0, "the axis node's parameter event", async {
        let mut events = Box::pin(sub.async_stream());
        loop {
            let (e, _) = events.next().await.unwrap().expect("read");
            if e.node == "/axis_node" {
                return e;
            }
        }
    })
    .await;
    assert!(event.changed_parameters.is_empty() && event.deleted_parameters.is_empty());
    let value = |name: &str| {
        let p = event.new_parameters.iter().find(|p| p.name == name);
        p.unwrap_or_else(|| panic!("{name} not announced: {event:?}"))
            .value
            .clone()
    };
    // ParameterType: DOUBLE 3, BOOL 1, STRING_ARRAY 9.
    let cycle_period = value("cycle_period");
    assert_eq!((cycle_period.r#type, cycle_period.double_value), (3, 0.001));
    let lockstep = value("lockstep");
    assert_eq!((lockstep.r#type, lockstep.bool_value), (1, true));
    let axes = value("axes");
    assert_eq!(
        (axes.r#type, axes.string_array_value),
        (9, vec!["x".into()])
    );
    assert!(
        event.stamp.sec > 0,
        "stamped with the system time: {event:?}"
    );
    drop(node);
}
