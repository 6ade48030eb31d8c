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
