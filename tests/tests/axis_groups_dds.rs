//! axis_node's PLCopen Part 4 axis groups and ISG platform safety services over real DDS,
//! in-process (lockstep), with both request/reply mappings: a group of two axes is powered,
//! enabled, moved by `move_linear_absolute` to its exact end positions, refused with error ids,
//! moved again by the `move_linear_relative` service, stopped by `group_stop` (and released),
//! read back by `read_status`; then an `isg_mcp` node
//! refuses a group move in T1 without the enabling switch (4901, R-SAF-5), and `~/events`
//! (reliable, keep-all) carries the safety events, the acknowledgements and injected MC
//! messages, without gaps and in order.

use axis_node::AxisNode;
use motion_msgs::action::{
    AxesGroupHalt, AxesGroupHaltFeedback, AxesGroupHaltGoal, AxesGroupHaltResult,
    MoveLinearAbsolute, MoveLinearAbsoluteFeedback, MoveLinearAbsoluteGoal,
    MoveLinearAbsoluteResult, MoveRelative, MoveRelativeFeedback, MoveRelativeGoal,
    MoveRelativeResult,
};
use motion_msgs::msg::{
    AxesGroupState, AxisEvent, AxisState, CommandStatus, FbCall, FbOut, PlatformStatus,
};
use motion_msgs::srv::{
    AxesGroupAddAxis, AxesGroupAddAxisRequest, AxesGroupAddAxisResponse, AxesGroupCommand,
    AxesGroupCommandRequest, AxesGroupCommandResponse, AxesGroupReadActual,
    AxesGroupReadActualRequest, AxesGroupReadActualResponse, AxesGroupReadStatus,
    AxesGroupReadStatusRequest, AxesGroupReadStatusResponse, AxesGroupStop, AxesGroupStopRequest,
    AxesGroupStopResponse, FbCycle, FbCycleRequest, FbCycleResponse, GetOutputs, GetOutputsRequest,
    GetOutputsResponse, MoveLinearRelativeRequest, MoveLinearRelativeResponse,
    PlatformInjectMcMessage, PlatformInjectMcMessageRequest, PlatformInjectMcMessageResponse,
    PlatformVersions, PlatformVersionsRequest, PlatformVersionsResponse, SafetyButton,
    SafetyButtonRequest, SafetyButtonResponse, SafetyOperatingMode, SafetyOperatingModeRequest,
    SafetyOperatingModeResponse, SubmitBatch, SubmitBatchRequest, SubmitBatchResponse,
};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{Client, ServiceMapping};
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

const AXIS: &str =
    "{ max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0, fast_deceleration: 50000.0, fast_jerk: 1000000.0 }";

fn start_node(domain: u16, mapping: ServiceMapping, profile: &str) -> AxisNode {
    let text = format!(
        "axes:\n  x: {AXIS}\n  y: {AXIS}\nplatform_profile: {profile}\ngroups:\n  - name: g\n    axes: [x, y]\n"
    );
    let cfg: serde_yaml::Value = serde_yaml::from_str(&text).unwrap();
    axis_node::start(&common("axis_node", true, mapping), cfg, "test", domain).expect("axis node")
}

async fn power(c: &mut ClientNode) {
    for axis in ["x", "y"] {
        c.power_on(axis).await;
    }
}

async fn read_status(
    rs: &Client<AxesGroupReadStatusRequest, AxesGroupReadStatusResponse>,
) -> AxesGroupReadStatusResponse {
    let r = within(
        5.0,
        "read_status",
        rs.async_call_service(Default::default()),
    )
    .await
    .unwrap();
    assert!(r.accepted, "read_status: {}", r.message);
    r
}

/// The tc2_mc2 group scenario.
async fn groups(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping, "tc2_mc2");
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", mapping);

    let states =
        c.subscribe::<AxesGroupState>("/axis_node/groups/g/state", AxesGroupState::type_name());
    let statuses =
        c.subscribe::<CommandStatus>("/axis_node/command_status", CommandStatus::type_name());
    let (first, _) = within(20.0, "first group state", states.async_take())
        .await
        .unwrap();
    assert_eq!(first.name, "g");
    assert_eq!(first.axes, ["x", "y"]);
    assert_eq!(first.idents, [1, 2]);
    assert_eq!(first.state, AxesGroupState::STATE_GROUP_DISABLED);

    // Power both members, then MCV_GroupEnable: GroupStandby.
    power(&mut c).await;
    let enable = c
        .client::<AxesGroupCommandRequest, AxesGroupCommandResponse>(
            "/axis_node/groups/g/group_enable",
            AxesGroupCommand::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "group_enable",
        enable.async_call_service(Default::default()),
    )
    .await
    .unwrap();
    assert!(r.accepted, "group_enable: {}", r.message);
    assert_ne!(r.command_id, 0);
    // The instance's outputs by command id (~/get_outputs): Done the cycle after the edge.
    let outputs = c
        .client::<GetOutputsRequest, GetOutputsResponse>(
            "/axis_node/get_outputs",
            GetOutputs::service_type_name(),
        )
        .await;
    within(10.0, "group_enable Done on ~/get_outputs", async {
        loop {
            let o = outputs
                .async_call_service(GetOutputsRequest {
                    command_id: r.command_id,
                })
                .await
                .unwrap();
            assert!(o.accepted && !o.error, "{o:?}");
            if o.done {
                break;
            }
            tokio::time::sleep(std::time::Duration::from_millis(20)).await;
        }
    })
    .await;
    let rs = c
        .client::<AxesGroupReadStatusRequest, AxesGroupReadStatusResponse>(
            "/axis_node/groups/g/read_status",
            AxesGroupReadStatus::service_type_name(),
        )
        .await;
    let s = read_status(&rs).await;
    assert!(s.group_standby && !s.group_disabled, "{s:?}");
    assert_eq!(s.status.state, AxesGroupState::STATE_GROUP_STANDBY);

    // MC_MoveLinearAbsolute to (30, 40): Done, members exactly at the targets.
    let ac = c
        .action::<MoveLinearAbsoluteGoal, MoveLinearAbsoluteResult, MoveLinearAbsoluteFeedback>(
            "/axis_node/groups/g/move_linear_absolute",
            &MoveLinearAbsolute::action_type_name(),
        )
        .await;
    let goal = MoveLinearAbsoluteGoal {
        position: vec![30.0, 40.0],
        velocity: 500.0,
        coord_system: 1,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&ac, "move_linear_absolute", goal).await;
    assert!(resp.accepted);
    let (status, result) = within(20.0, "move result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && !result.error && !result.command_aborted);
    assert_eq!(result.positions.len(), 2);
    assert!((result.positions[0] - 30.0).abs() < 1e-9, "{result:?}");
    assert!((result.positions[1] - 40.0).abs() < 1e-9, "{result:?}");
    within(10.0, "command_status Done of the group move", async {
        loop {
            let (s, _) = statuses.async_take().await.unwrap();
            if s.done && s.command == "move_linear_absolute" {
                assert_eq!(s.object, "g");
                break;
            }
        }
    })
    .await;
    let rp = c
        .client::<AxesGroupReadActualRequest, AxesGroupReadActualResponse>(
            "/axis_node/groups/g/read_actual_position",
            AxesGroupReadActual::service_type_name(),
        )
        .await;
    let p = within(
        5.0,
        "read_actual_position",
        rp.async_call_service(AxesGroupReadActualRequest { coord_system: 1 }),
    )
    .await
    .unwrap();
    assert!(p.accepted, "{}", p.message);
    assert_eq!(p.values.len(), 2);
    assert!((p.values[0] - 30.0).abs() < 1e-9 && (p.values[1] - 40.0).abs() < 1e-9);

    // The same kind of motion as a service: accepted at once with its command id, Done on
    // ~/command_status; a bad request is refused at once with its id.
    let mr = c
        .client::<MoveLinearRelativeRequest, MoveLinearRelativeResponse>(
            "/axis_node/groups/g/move_linear_relative",
            motion_msgs::srv::MoveLinearRelative::service_type_name(),
        )
        .await;
    let req = |distance: Vec<f64>| MoveLinearRelativeRequest {
        distance,
        velocity: 500.0,
        coord_system: 1,
        ..Default::default()
    };
    let r = within(
        5.0,
        "move_linear_relative service",
        mr.async_call_service(req(vec![-10.0, 5.0])),
    )
    .await
    .unwrap();
    assert!(r.accepted && r.command_id > 0, "{}", r.message);
    within(10.0, "command_status Done of the service move", async {
        loop {
            let (s, _) = statuses.async_take().await.unwrap();
            if s.command_id == r.command_id && s.done {
                assert_eq!(
                    (s.object.as_str(), s.command.as_str()),
                    ("g", "move_linear_relative")
                );
                break;
            }
        }
    })
    .await;
    let bad = within(
        5.0,
        "move_linear_relative NaN",
        mr.async_call_service(req(vec![f64::NAN, 0.0])),
    )
    .await
    .unwrap();
    assert!(!bad.accepted);
    assert_eq!(bad.error_id, 0x7F02, "{}", bad.message);
    let p = within(
        5.0,
        "read_actual_position after the service move",
        rp.async_call_service(AxesGroupReadActualRequest { coord_system: 1 }),
    )
    .await
    .unwrap();
    assert!((p.values[0] - 20.0).abs() < 1e-9 && (p.values[1] - 45.0).abs() < 1e-9);
    // And back to (30, 40).
    let r = within(
        5.0,
        "move_linear_relative back",
        mr.async_call_service(req(vec![10.0, -5.0])),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    within(10.0, "command_status Done of the way back", async {
        loop {
            let (s, _) = statuses.async_take().await.unwrap();
            if s.command_id == r.command_id && s.done {
                break;
            }
        }
    })
    .await;

    // Bad requests with their error ids: coord_system out of range (0x7F03), unknown axis
    // (0x7F01), NaN target (0x7F02, in the goal's result), wrong number of values (4902).
    let bad = within(
        5.0,
        "read_actual_position coord 9",
        rp.async_call_service(AxesGroupReadActualRequest { coord_system: 9 }),
    )
    .await
    .unwrap();
    assert!(!bad.accepted);
    assert_eq!(bad.error_id, 0x7F03, "{}", bad.message);
    let add = c
        .client::<AxesGroupAddAxisRequest, AxesGroupAddAxisResponse>(
            "/axis_node/groups/g/add_axis",
            AxesGroupAddAxis::service_type_name(),
        )
        .await;
    let bad = within(
        5.0,
        "add_axis nope",
        add.async_call_service(AxesGroupAddAxisRequest {
            axis: "nope".into(),
            ident_in_group: 0,
        }),
    )
    .await
    .unwrap();
    assert!(!bad.accepted);
    assert_eq!(bad.error_id, 0x7F01, "{}", bad.message);
    assert!(bad.message.contains("nope"));
    for (position, id) in [(vec![f64::NAN, 1.0], 0x7F02), (vec![1.0], 4902)] {
        let goal = MoveLinearAbsoluteGoal {
            position,
            velocity: 500.0,
            coord_system: 1,
            ..Default::default()
        };
        let (gid, _) = send_goal(&ac, "bad move", goal).await;
        let (status, result) = within(20.0, "bad move result", ac.async_request_result(gid))
            .await
            .unwrap();
        assert_eq!(status, GoalStatusEnum::Aborted, "{result:?}");
        assert!(result.error);
        assert_eq!(result.error_id, id, "{}", result.message);
    }

    // MC_GroupStop: GroupStopping while Execute is held, GroupStandby after the falling edge.
    let stop = c
        .client::<AxesGroupStopRequest, AxesGroupStopResponse>(
            "/axis_node/groups/g/group_stop",
            AxesGroupStop::service_type_name(),
        )
        .await;
    let r = within(
        5.0,
        "group_stop",
        stop.async_call_service(AxesGroupStopRequest {
            execute: true,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "group_stop: {}", r.message);
    let s = read_status(&rs).await;
    assert!(s.group_stopping, "{s:?}");
    let r = within(
        5.0,
        "group_stop release",
        stop.async_call_service(AxesGroupStopRequest {
            execute: false,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "group_stop release: {}", r.message);
    // The state topic's history may still hold samples from before the stop: ask the group.
    let s = within(10.0, "standby after the release", async {
        loop {
            let s = read_status(&rs).await;
            if s.group_standby {
                break s;
            }
            tokio::time::sleep(std::time::Duration::from_millis(10)).await;
        }
    })
    .await;
    assert!(s.group_standby && s.in_position, "{s:?}");
    let act = &s.status.act_position;
    assert!(
        (act[0] - 30.0).abs() < 1e-9 && (act[1] - 40.0).abs() < 1e-9,
        "{act:?}"
    );

    // Cancel of a group move = MC_GroupHalt: the goal ends Canceled, the group stands still.
    let slow = MoveLinearAbsoluteGoal {
        position: vec![130.0, 140.0],
        velocity: 10.0,
        coord_system: 1,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&ac, "slow move", slow.clone()).await;
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
    assert!(result.command_aborted, "{result:?}");
    within(10.0, "standby after the cancel", async {
        loop {
            let (s, _) = states.async_take().await.unwrap();
            // (Older samples from before the move may still be queued.)
            let moved = s.act_position[0] > 30.0 + 1e-6;
            if moved && s.state == AxesGroupState::STATE_GROUP_STANDBY && s.path_velocity == 0.0 {
                assert!(s.act_position[0] < 130.0, "{s:?}");
                break;
            }
        }
    })
    .await;

    // MC_GroupHalt as an action: it takes over a running move (CommandAborted) and is Done at
    // standstill.
    let halt = c
        .action::<AxesGroupHaltGoal, AxesGroupHaltResult, AxesGroupHaltFeedback>(
            "/axis_node/groups/g/group_halt",
            &AxesGroupHalt::action_type_name(),
        )
        .await;
    let (move_gid, _) = send_goal(&ac, "slow move 2", slow).await;
    tokio::time::sleep(std::time::Duration::from_millis(200)).await;
    let (hgid, resp) = send_goal(&halt, "group_halt", AxesGroupHaltGoal::default()).await;
    assert!(resp.accepted);
    let (status, result) = within(20.0, "halt result", halt.async_request_result(hgid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && result.positions.len() == 2, "{result:?}");
    let (status, result) = within(
        20.0,
        "halted move result",
        ac.async_request_result(move_gid),
    )
    .await
    .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted, "{result:?}");
    assert!(result.command_aborted && !result.error, "{result:?}");

    drop(c);
    node.stop().await;
}

/// The isg_mcp safety case: T1 without the enabling switch refuses group motion (4901).
async fn safety(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping, "isg_mcp");
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "test_client", mapping);
    let platform =
        c.subscribe::<PlatformStatus>("/axis_node/platform/status", PlatformStatus::type_name());
    // ~/events with a keep-all reader, collected in the background.
    let events: std::sync::Arc<std::sync::Mutex<Vec<AxisEvent>>> = Default::default();
    {
        use ros2_client::qos::{History, QosProfile};
        let qos = QosProfile::publisher_default().history(History::KeepAll);
        let topic = c
            .node
            .create_topic(
                &ClientNode::name("/axis_node/events"),
                AxisEvent::type_name(),
                &qos,
            )
            .unwrap();
        let sub = c
            .node
            .create_subscription::<AxisEvent>(&topic, Some(qos))
            .unwrap();
        let sink = events.clone();
        tokio::spawn(async move {
            while let Ok((e, _)) = sub.async_take().await {
                sink.lock().unwrap().push(e);
            }
        });
    }
    // Start-up over (R-INIT-1), then power.
    within(20.0, "platform started", async {
        loop {
            let (p, _) = platform.async_take().await.unwrap();
            if p.hli_initialized {
                assert_eq!(p.profile, PlatformStatus::PROFILE_ISG_MCP);
                break;
            }
        }
    })
    .await;
    power(&mut c).await;

    let mode = c
        .client::<SafetyOperatingModeRequest, SafetyOperatingModeResponse>(
            "/axis_node/safety/operating_mode",
            SafetyOperatingMode::service_type_name(),
        )
        .await;
    let bad = within(
        5.0,
        "operating_mode 7",
        mode.async_call_service(SafetyOperatingModeRequest { mode: 7 }),
    )
    .await
    .unwrap();
    assert!(!bad.accepted);
    assert_eq!(bad.error_id, 0x7F03, "{}", bad.message);
    let r = within(
        5.0,
        "operating_mode T1",
        mode.async_call_service(SafetyOperatingModeRequest { mode: 1 }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    within(10.0, "T1 on ~/platform/status", async {
        loop {
            let (p, _) = platform.async_take().await.unwrap();
            if p.operating_mode == PlatformStatus::MODE_T1 {
                assert!(!p.enabling_switch);
                break;
            }
        }
    })
    .await;

    let ac = c
        .action::<MoveLinearAbsoluteGoal, MoveLinearAbsoluteResult, MoveLinearAbsoluteFeedback>(
            "/axis_node/groups/g/move_linear_absolute",
            &MoveLinearAbsolute::action_type_name(),
        )
        .await;
    let goal = MoveLinearAbsoluteGoal {
        position: vec![10.0, 10.0],
        velocity: 500.0,
        coord_system: 1,
        ..Default::default()
    };
    let (gid, _) = send_goal(&ac, "move in T1", goal).await;
    let (status, result) = within(20.0, "T1 move result", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted, "{result:?}");
    assert!(result.error);
    assert_eq!(result.error_id, 4901, "{}", result.message);
    assert!(
        result.message.contains("enabling switch"),
        "{}",
        result.message
    );

    // Enabling switch and START held: the move runs in T1 (R-SAF-5) to its end.
    power(&mut c).await;
    for (name, pressed) in [
        ("/axis_node/safety/enabling_switch", true),
        ("/axis_node/safety/start_button", true),
    ] {
        let b = c
            .client::<SafetyButtonRequest, SafetyButtonResponse>(
                name,
                SafetyButton::service_type_name(),
            )
            .await;
        let r = within(
            5.0,
            name,
            b.async_call_service(SafetyButtonRequest { pressed }),
        )
        .await
        .unwrap();
        assert!(r.accepted, "{name}: {}", r.message);
    }
    let goal = MoveLinearAbsoluteGoal {
        position: vec![10.0, 60.0],
        velocity: 500.0,
        coord_system: 1,
        ..Default::default()
    };
    let (gid, _) = send_goal(&ac, "move in T1 with START", goal).await;
    {
        // Feedback (§12.1): the ISG order number and the group state while it moves.
        use futures::StreamExt;
        let mut fb = Box::pin(ac.feedback_stream(gid));
        within(10.0, "group feedback with order number", async {
            loop {
                let f = fb.next().await.expect("feedback").expect("feedback ok");
                if f.active && f.order_id > 0 {
                    assert_eq!(f.group_state, AxesGroupState::STATE_GROUP_MOVING, "{f:?}");
                    break;
                }
            }
        })
        .await;
    }
    let (status, result) = within(20.0, "T1 move with START", ac.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!((result.positions[0] - 10.0).abs() < 1e-9, "{result:?}");
    assert!((result.positions[1] - 60.0).abs() < 1e-9, "{result:?}");

    // The raw FB layer over ROS (~/fb/cycle, §12.2): a wrong interface hash is refused with
    // 4904; with the node's hash (from ~/platform/versions) an MC_MoveRelative instance on x
    // is Busy at its edge, Active after ACCEPTED, Done at the target, Done held while Execute
    // stays TRUE; each request runs a cycle.
    let versions = c
        .client::<PlatformVersionsRequest, PlatformVersionsResponse>(
            "/axis_node/platform/versions",
            PlatformVersions::service_type_name(),
        )
        .await;
    let v = within(
        5.0,
        "versions",
        versions.async_call_service(PlatformVersionsRequest::default()),
    )
    .await
    .unwrap();
    assert_eq!(v.msgs_interface_hash, motion_msgs::INTERFACE_HASH);
    let fbc = c
        .client::<FbCycleRequest, FbCycleResponse>(
            "/axis_node/fb/cycle",
            FbCycle::service_type_name(),
        )
        .await;
    let mv = axis_engine::AxisCommand::MoveRelative(axis_engine::MoveRelative {
        axis: "x".into(),
        distance: 5.0,
        velocity: 100.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: axis_engine::BufferMode::Aborting,
        options: Default::default(),
    });
    let req = |hash: u32, execute: bool| FbCycleRequest {
        interface_hash: hash,
        calls: vec![FbCall {
            instance: "raw_mv".into(),
            execute,
            fb: serde_json::to_string(&mv).unwrap(),
        }],
    };
    let r = within(
        5.0,
        "fb/cycle bad hash",
        fbc.async_call_service(req(1, true)),
    )
    .await
    .unwrap();
    assert!(!r.accepted);
    assert_eq!(r.error_id, 4904, "{}", r.message);
    {
        let r = within(
            5.0,
            "fb/cycle 1",
            fbc.async_call_service(req(v.msgs_interface_hash, true)),
        )
        .await
        .unwrap();
        assert!(r.accepted, "{}", r.message);
        let o = &r.outputs[0];
        assert!(o.busy && !o.active && o.order_id > 0, "{o:?}");
        assert_eq!(o.fb_state, FbOut::FB_ACTIVE);
    }
    let mut last_cycle = 0;
    let mut n = 0;
    loop {
        let r = within(
            5.0,
            "fb/cycle",
            fbc.async_call_service(req(v.msgs_interface_hash, true)),
        )
        .await
        .unwrap();
        assert!(r.accepted, "{}", r.message);
        if last_cycle > 0 {
            // (The test's driver steps the lockstep node too.)
            assert!(r.cycle > last_cycle, "each request runs a cycle");
        }
        last_cycle = r.cycle;
        if n == 0 {
            assert!(r.outputs[0].active, "{:?}", r.outputs[0]);
        }
        if r.outputs[0].done {
            // x stood at 10 after the group move in T1.
            assert_eq!(r.axes[0].name, "x");
            assert!((r.axes[0].set_pos - 15.0).abs() < 1e-9, "{:?}", r.axes[0]);
            break;
        }
        n += 1;
        assert!(n < 3000, "raw move not done");
    }
    let r = within(
        5.0,
        "fb/cycle held",
        fbc.async_call_service(req(v.msgs_interface_hash, true)),
    )
    .await
    .unwrap();
    assert!(r.outputs[0].done, "Done held while Execute is TRUE");
    let r = within(
        5.0,
        "fb/cycle falling",
        fbc.async_call_service(req(v.msgs_interface_hash, false)),
    )
    .await
    .unwrap();
    assert!(!r.outputs[0].done && !r.outputs[0].busy);

    // Action feedback (§12.1): the ISG order number and the axis state of a running move.
    let mr = c
        .action::<MoveRelativeGoal, MoveRelativeResult, MoveRelativeFeedback>(
            "/axis_node/move_relative",
            &MoveRelative::action_type_name(),
        )
        .await;
    let (gid, resp) = send_goal(
        &mr,
        "move_relative y",
        MoveRelativeGoal {
            axis: "y".into(),
            distance: 3.0,
            velocity: 10.0,
            ..Default::default()
        },
    )
    .await;
    assert!(resp.accepted);
    {
        use futures::StreamExt;
        let mut fb = Box::pin(mr.feedback_stream(gid));
        within(10.0, "feedback with order number", async {
            loop {
                let f = fb.next().await.expect("feedback").expect("feedback ok");
                if f.active && f.order_id > 0 {
                    assert_eq!(
                        f.axis_state,
                        AxisState::MC_AXISSTATE_DISCRETEMOTION,
                        "{f:?}"
                    );
                    break;
                }
            }
        })
        .await;
    }
    let (status, _) = within(20.0, "move_relative y result", mr.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded);

    // ~/submit_batch (§12.1): two orders on y in one cycle: the second finds the order slot
    // used (4, R-HS-3); a bad order text refuses the whole batch.
    let sb = c
        .client::<SubmitBatchRequest, SubmitBatchResponse>(
            "/axis_node/submit_batch",
            SubmitBatch::service_type_name(),
        )
        .await;
    let on_y = |distance: f64| {
        serde_json::to_string(&axis_engine::AxisCommand::MoveRelative(
            axis_engine::MoveRelative {
                axis: "y".into(),
                distance,
                ..match &mv {
                    axis_engine::AxisCommand::MoveRelative(m) => m.clone(),
                    _ => unreachable!(),
                }
            },
        ))
        .unwrap()
    };
    let r = within(
        5.0,
        "submit_batch",
        sb.async_call_service(SubmitBatchRequest {
            orders: vec![on_y(1.0), on_y(2.0)],
        }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);
    assert_eq!(r.order_accepted, vec![true, false]);
    assert!(r.command_ids[0] > 0);
    assert_eq!(r.error_ids[1], 4, "{:?}", r.messages);
    let r = within(
        5.0,
        "submit_batch bad",
        sb.async_call_service(SubmitBatchRequest {
            orders: vec![on_y(1.0), "{\"Fly\": {}}".into()],
        }),
    )
    .await
    .unwrap();
    assert!(!r.accepted && r.order_accepted.is_empty());
    assert_eq!(r.error_id, 0x7F06, "{}", r.message);
    assert!(r.message.contains("orders[1]"), "{}", r.message);

    // An MC warning and an MC error injected on x arrive on ~/events, after the safety event
    // of T1 and the acknowledgements of the move.
    let inject = c
        .client::<PlatformInjectMcMessageRequest, PlatformInjectMcMessageResponse>(
            "/axis_node/sim/inject_mc_message",
            PlatformInjectMcMessage::service_type_name(),
        )
        .await;
    for (error_id, remedy, reaction) in [(12345, 0, 0), (91001, 1, 2)] {
        let r = within(
            5.0,
            "inject_mc_message",
            inject.async_call_service(PlatformInjectMcMessageRequest {
                axis: "x".into(),
                error_id,
                behebungs_klasse: remedy,
                reaktions_klasse: reaction,
            }),
        )
        .await
        .unwrap();
        assert!(r.accepted, "{}", r.message);
    }
    let log = within(10.0, "the MC error on ~/events", async {
        loop {
            {
                let log = events.lock().unwrap();
                if log
                    .iter()
                    .any(|e| e.kind == AxisEvent::KIND_ERROR && e.error_id == 91001)
                {
                    return log.clone();
                }
            }
            tokio::time::sleep(std::time::Duration::from_millis(20)).await;
        }
    })
    .await;
    // Reliable keep-all: no sequence gaps.
    for (k, e) in log.iter().enumerate() {
        assert_eq!(e.seq, log[0].seq + k as u64, "gap before {e:?}");
    }
    let pos = |f: &dyn Fn(&AxisEvent) -> bool, what: &str| {
        log.iter()
            .position(f)
            .unwrap_or_else(|| panic!("{what} missing in {log:#?}"))
    };
    let t1 = pos(
        &|e| {
            e.kind == AxisEvent::KIND_SAFETY && e.state == "operating_mode" && e.text.contains("T1")
        },
        "safety event T1",
    );
    // The move with START: accepted, then done (the refused one has no command: rejected at
    // its Execute edge, its error is in the goal's result).
    let accepted = pos(
        &|e| {
            e.kind == AxisEvent::KIND_ACKNOWLEDGEMENT
                && e.object == "g"
                && e.state == "ACCEPTED"
                && e.text.contains("move_linear_absolute")
        },
        "acknowledgement ACCEPTED",
    );
    let done = pos(
        &|e| {
            e.kind == AxisEvent::KIND_ACKNOWLEDGEMENT
                && e.object == "g"
                && e.state == "DONE"
                && e.command_id == log[accepted].command_id
        },
        "acknowledgement DONE",
    );
    pos(
        &|e| e.kind == AxisEvent::KIND_SAFETY && e.state == "enabling_switch",
        "safety event enabling switch",
    );
    let warning = pos(
        &|e| e.kind == AxisEvent::KIND_WARNING && e.error_id == 12345 && e.object == "x",
        "MC warning",
    );
    let error = pos(
        &|e| e.kind == AxisEvent::KIND_ERROR && e.error_id == 91001,
        "MC error",
    );
    let e = &log[error];
    assert_eq!(
        (e.object.as_str(), e.remedy_class, e.reaction_class),
        ("x", 1, 2)
    );
    assert!(
        t1 < accepted && accepted < done && done < warning && warning < error,
        "{log:#?}"
    );

    drop(c);
    node.stop().await;
}

async fn scenario(mapping: ServiceMapping) {
    groups(mapping).await;
    safety(mapping).await;
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn axis_groups_over_dds_both_mappings() {
    require_netns();
    scenario(ServiceMapping::Cyclone).await;
    scenario(ServiceMapping::Enhanced).await;
}
