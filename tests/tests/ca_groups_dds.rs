//! axis_node's collision-avoidance groups over real DDS, in-process (lockstep): a ring group of
//! three movers is built and enabled through `~/ca/ring/` services, a follower's
//! MC_MoveAbsoluteCA into its leader's gap waits behind the leader (the state topic shows the
//! gap kept) and finishes once the leader has moved on; read_status, refused requests with
//! their error ids, a cancelled MC_MoveRelativeCA (= MC_HaltCA), MC_GearInPosCA to InSync with
//! an ungrouped master, and MC_GroupStop; with both request/reply mappings.

use axis_node::AxisNode;
use motion_msgs::action::{
    GearInPosCa, GearInPosCaFeedback, GearInPosCaGoal, GearInPosCaResult, MoveAbsoluteCa,
    MoveAbsoluteCaFeedback, MoveAbsoluteCaGoal, MoveAbsoluteCaResult, MoveRelativeCa,
    MoveRelativeCaFeedback, MoveRelativeCaGoal, MoveRelativeCaResult,
};
use motion_msgs::msg::{CaAxisState, CaGroupState, CommandStatus, McLreal};
use motion_msgs::srv::*;
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{Client, Message, ServiceMapping};
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

const CONFIG: &str = "
axes:
  a: {initial_position: 1000.0, max_velocity: 2000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0, fast_acceleration: 20000.0, fast_deceleration: 20000.0, fast_jerk: 200000.0}
  b: {initial_position: 500.0, max_velocity: 2000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0, fast_acceleration: 20000.0, fast_deceleration: 20000.0, fast_jerk: 200000.0}
  c: {initial_position: 0.0, max_velocity: 2000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0, fast_acceleration: 20000.0, fast_deceleration: 20000.0, fast_jerk: 200000.0}
  m: {initial_position: 0.0, max_velocity: 2000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}
ca_groups:
  ring: {rail_length: 3000.0, default_gap: 100.0}
";

const NS: &str = "/axis_node/ca/ring";

fn start_node(domain: u16, mapping: ServiceMapping) -> AxisNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    axis_node::start(&common("axis_node", true, mapping), cfg, "test", domain).expect("axis node")
}

fn value(v: f64) -> McLreal {
    McLreal {
        kind: McLreal::VALUE,
        value: v,
    }
}

async fn call<Req, Resp>(c: &Client<Req, Resp>, what: &str, r: Req) -> Resp
where
    Req: Message + Clone + 'static,
    Resp: Message + 'static,
{
    within(10.0, what, c.async_call_service(r))
        .await
        .unwrap_or_else(|e| panic!("{what}: {e:?}"))
}

/// The next state sample for which `f` holds.
async fn state_until(
    states: &ros2_client::Subscription<CaGroupState>,
    what: &str,
    mut f: impl FnMut(&CaGroupState) -> bool,
) -> CaGroupState {
    within(30.0, what, async {
        loop {
            let (s, _) = states.async_take().await.unwrap();
            if f(&s) {
                return s;
            }
        }
    })
    .await
}

fn goal(axis: &str, position: f64, velocity: f64) -> MoveAbsoluteCaGoal {
    MoveAbsoluteCaGoal {
        axis: axis.into(),
        position: value(position),
        velocity: value(velocity),
        ..Default::default()
    }
}

async fn scenario(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "ca_client", mapping);

    let states = c.subscribe::<CaGroupState>(&format!("{NS}/state"), CaGroupState::type_name());
    let statuses =
        c.subscribe::<CommandStatus>("/axis_node/command_status", CommandStatus::type_name());
    let first = state_until(&states, "first ca state", |_| true).await;
    assert_eq!(first.name, "ring");
    assert_eq!(first.state, CaGroupState::STATE_GROUP_DISABLED);
    assert!(first.axes.is_empty());

    // Power the movers, add them (idents 1..3), enable the group.
    let power = c
        .client::<PowerRequest, PowerResponse>("/axis_node/power", Power::service_type_name())
        .await;
    for axis in ["a", "b", "c", "m"] {
        let r = call(
            &power,
            "power",
            PowerRequest {
                axis: axis.into(),
                enable: true,
                ..Default::default()
            },
        )
        .await;
        assert!(r.accepted, "power {axis}: {}", r.message);
    }
    let add = c
        .client::<CaAddAxisRequest, CaAddAxisResponse>(
            &format!("{NS}/add_axis"),
            CaAddAxis::service_type_name(),
        )
        .await;
    for (i, axis) in ["a", "b", "c"].into_iter().enumerate() {
        let r = call(
            &add,
            "add_axis",
            CaAddAxisRequest {
                axis: axis.into(),
                ident_in_group: i as u32 + 1,
            },
        )
        .await;
        assert!(r.accepted, "add_axis {axis}: {}", r.message);
        assert_ne!(r.command_id, 0);
    }
    // Unknown axis: the shell's 0x7F01.
    let r = call(
        &add,
        "add_axis unknown",
        CaAddAxisRequest {
            axis: "nope".into(),
            ident_in_group: 9,
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F01, "{}", r.message);
    assert!(r.message.contains("nope"), "{}", r.message);
    let enable = c
        .client::<CaGroupCommandRequest, CaGroupCommandResponse>(
            &format!("{NS}/group_enable"),
            CaGroupCommand::service_type_name(),
        )
        .await;
    let r = call(&enable, "group_enable", CaGroupCommandRequest::default()).await;
    assert!(r.accepted, "group_enable: {}", r.message);
    within(10.0, "group_enable Done on command_status", async {
        loop {
            let (s, _) = statuses.async_take().await.unwrap();
            if s.command_id == r.command_id && s.done {
                assert_eq!(
                    (s.object.as_str(), s.command.as_str()),
                    ("ring", "group_enable")
                );
                break;
            }
        }
    })
    .await;
    let s = state_until(&states, "standby with 3 axes", |s| {
        s.state == CaGroupState::STATE_GROUP_STANDBY && s.axes.len() == 3
    })
    .await;
    let order: Vec<&str> = s.axes.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(order, ["a", "b", "c"], "front first");
    assert_eq!(s.axes[1].predecessor, "a");
    assert!((s.axes[1].gap_actual - 500.0).abs() < 1e-9);
    assert!(
        (s.axes[0].gap_actual - 2000.0).abs() < 1e-9,
        "across the seam"
    );
    assert_eq!(s.group_axes_count, 3);

    // Refused goals end ABORTED with the id: NaN (shell 0x7F02), bad enum (engine 0x4B04).
    let mv = c
        .action::<MoveAbsoluteCaGoal, MoveAbsoluteCaResult, MoveAbsoluteCaFeedback>(
            &format!("{NS}/move_absolute"),
            &MoveAbsoluteCa::action_type_name(),
        )
        .await;
    for (g, id) in [
        (goal("b", f64::NAN, 500.0), 0x7F02),
        (
            MoveAbsoluteCaGoal {
                gap_control_mode: 9,
                ..goal("b", 600.0, 500.0)
            },
            0x4B04,
        ),
        (goal("zz", 600.0, 500.0), 0x7F01),
    ] {
        let (gid, _) = send_goal(&mv, "bad goal", g).await;
        let (status, result) = within(20.0, "bad goal result", mv.async_request_result(gid))
            .await
            .unwrap();
        assert_eq!(status, GoalStatusEnum::Aborted);
        assert!(result.error && !result.done);
        assert_eq!(result.error_id, id, "{}", result.message);
    }
    // A NaN on a service: 0x7F02.
    let ovr = c
        .client::<CaSetOverrideRequest, CaSetOverrideResponse>(
            &format!("{NS}/set_override"),
            CaSetOverride::service_type_name(),
        )
        .await;
    let r = call(
        &ovr,
        "set_override NaN",
        CaSetOverrideRequest {
            enable: true,
            vel_factor: f64::NAN,
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F02, "{}", r.message);

    // The follower b into a's gap (target 950, gap 100 behind a at 1000): it waits at 900.
    let (follower, resp) = send_goal(&mv, "follower goal", goal("b", 950.0, 500.0)).await;
    assert!(resp.accepted);
    let mut fb = Box::pin(mv.feedback_stream(follower));
    let mut worst = f64::INFINITY;
    let s = state_until(&states, "follower waits behind the leader", |s| {
        let b = &s.axes[1];
        worst = worst.min(b.gap_actual - b.gap_target);
        b.active_command_id != 0 && b.velocity.abs() < 1e-9 && b.position > 800.0
    })
    .await;
    let b = &s.axes[1];
    assert!(
        (b.position - 900.0).abs() < 1e-6,
        "waits at 900: {}",
        b.position
    );
    assert!(b.gap_actual >= b.gap_target - 1e-6, "gap kept: {b:?}");
    assert!((b.gap_target - 100.0).abs() < 1e-9);
    {
        // Feedback shows the command Busy and Active (the first ones may predate the state
        // that shows the follower's command in control).
        use futures::StreamExt;
        within(10.0, "follower feedback Active", async {
            loop {
                let f = fb.next().await.expect("feedback").expect("feedback ok");
                assert!(f.busy);
                assert_eq!(f.command_id, b.active_command_id);
                if f.active {
                    break;
                }
            }
        })
        .await;
    }

    // The leader moves on to 1500 (its action to its result); then the follower arrives.
    let (leader, _) = send_goal(&mv, "leader goal", goal("a", 1500.0, 1000.0)).await;
    // The follower ends first (at 950 while the leader still runs to 1500): the node answers
    // result requests one goal at a time, in the order the goals end.
    let (status, result) = within(30.0, "follower result", mv.async_request_result(follower))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!((result.final_position - 950.0).abs() < 1e-6);
    let (status, result) = within(30.0, "leader result", mv.async_request_result(leader))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && !result.error);
    assert!((result.final_position - 1500.0).abs() < 1e-6);
    assert_ne!(result.command_id, 0);
    let s = state_until(&states, "all standing", |s| {
        worst = worst.min(s.axes[1].gap_actual - s.axes[1].gap_target);
        s.all_axes_standing && s.state == CaGroupState::STATE_GROUP_STANDBY
    })
    .await;
    assert!(worst >= -1e-6, "b's gap never below its target: {worst}");
    assert!(s.axes[1].min_gap_margin >= -1e-6, "{:?}", s.axes[1]);
    assert!((s.axes[0].position - 1500.0).abs() < 1e-6);

    // read_status, read_error.
    let rs = c
        .client::<CaReadStatusRequest, CaReadStatusResponse>(
            &format!("{NS}/read_status"),
            CaReadStatus::service_type_name(),
        )
        .await;
    let r = call(&rs, "read_status", CaReadStatusRequest::default()).await;
    assert!(r.accepted, "{}", r.message);
    assert!(r.group_standby && r.all_axes_standing && !r.group_moving && !r.in_position);
    let re = c
        .client::<CaReadErrorRequest, CaReadErrorResponse>(
            &format!("{NS}/read_error"),
            CaReadError::service_type_name(),
        )
        .await;
    let r = call(&re, "read_error", CaReadErrorRequest::default()).await;
    assert!(r.accepted && r.group_error_id == 0, "{r:?}");

    // Track positions without an active track: the absolute set position, ids 0.
    let rtp = c
        .client::<CaReadTrackPositionsRequest, CaReadTrackPositionsResponse>(
            &format!("{NS}/read_track_positions"),
            CaReadTrackPositions::service_type_name(),
        )
        .await;
    let r = call(
        &rtp,
        "read_track_positions",
        CaReadTrackPositionsRequest { axis: "b".into() },
    )
    .await;
    assert!(r.accepted && r.valid, "{r:?}");
    assert!(
        (r.track_position - 950.0).abs() < 1e-6 && r.track_id == 0,
        "{r:?}"
    );
    // update_gap without ContinuousUpdate: the engine's CONTINUOUS_UPDATE_NOT_ENABLED.
    let ug = c
        .client::<CaUpdateGapRequest, CaUpdateGapResponse>(
            &format!("{NS}/update_gap"),
            CaUpdateGap::service_type_name(),
        )
        .await;
    let r = call(
        &ug,
        "update_gap",
        CaUpdateGapRequest {
            axis: "b".into(),
            gap: value(50.0),
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x8F0F, "{}", r.message);

    // Cancel = MC_HaltCA: c's long relative move ends CANCELED with command_aborted.
    let rel = c
        .action::<MoveRelativeCaGoal, MoveRelativeCaResult, MoveRelativeCaFeedback>(
            &format!("{NS}/move_relative"),
            &MoveRelativeCa::action_type_name(),
        )
        .await;
    let (gid, _) = send_goal(
        &rel,
        "relative goal",
        MoveRelativeCaGoal {
            axis: "c".into(),
            distance: value(300.0),
            velocity: value(100.0),
            ..Default::default()
        },
    )
    .await;
    let s = state_until(&states, "c moving", |s| s.axes[2].velocity > 10.0).await;
    assert_eq!(
        s.axes[2].command_kind,
        CaAxisState::COMMAND_KIND_MOVE_RELATIVE
    );
    let cr = within(
        10.0,
        "cancel",
        rel.async_cancel_goal(gid, ros2_client::builtin_interfaces::Time::ZERO),
    )
    .await
    .unwrap();
    assert_eq!(cr.goals_canceling.len(), 1, "cancel accepted");
    let (status, result) = within(20.0, "canceled result", rel.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Canceled, "{result:?}");
    assert!(result.command_aborted && !result.done);
    let s = state_until(&states, "c halted", |s| s.all_axes_standing).await;
    assert!(s.axes[2].position > 0.0 && s.axes[2].position < 300.0);
    assert_eq!(s.axes[2].command_kind, CaAxisState::COMMAND_KIND_NONE);

    // MC_GearInPosCA: c follows the ungrouped master m (s* = 300 + m - 100), Early; the goal
    // succeeds at InSync and the coupling runs on (the state shows InSync).
    let mvel = c
        .client::<MoveVelocityRequest, MoveVelocityResponse>(
            "/axis_node/move_velocity",
            MoveVelocity::service_type_name(),
        )
        .await;
    let r = call(
        &mvel,
        "master move_velocity",
        MoveVelocityRequest {
            axis: "m".into(),
            velocity: 100.0,
            direction: 1,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    let gear = c
        .action::<GearInPosCaGoal, GearInPosCaResult, GearInPosCaFeedback>(
            &format!("{NS}/gear_in_pos"),
            &GearInPosCa::action_type_name(),
        )
        .await;
    let gear_goal = GearInPosCaGoal {
        master: "m".into(),
        slave: "c".into(),
        master_sync_position: value(100.0),
        slave_sync_position: value(300.0),
        sync_strategy: GearInPosCaGoal::SYNC_STRATEGY_EARLY,
        velocity: value(1000.0),
        ..Default::default()
    };
    let (gid, _) = send_goal(&gear, "gear goal", gear_goal.clone()).await;
    let (status, result) = within(30.0, "gear result", gear.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(result.done && !result.error, "{result:?}");
    assert_ne!(result.command_id, 0);
    let s = state_until(&states, "c in sync", |s| s.axes[2].in_sync).await;
    assert_eq!(s.axes[2].active_command_id, result.command_id);
    assert_eq!(
        s.axes[2].command_kind,
        CaAxisState::COMMAND_KIND_GEAR_IN_POS
    );
    assert!(!s.axes[2].start_sync);

    // ST_GearInPosCAOptions (§5.5.2) reach the engine: its ids for bad values, and a
    // re-coupling with restrictions, MinimalSlavePosition and MasterSignalCorrection None.
    let refused = [
        (
            GearInPosCaGoal {
                minimal_slave_position: McLreal {
                    kind: McLreal::DEFAULT,
                    value: 0.0,
                },
                ..gear_goal.clone()
            },
            0x8F0A, // INVALID_SYNC_OPTIONS
        ),
        (
            GearInPosCaGoal {
                dynamics_reference_system: 0x0101_0010,
                ..gear_goal.clone()
            },
            0x8F0C, // COMPENSATION_ERROR: no template registered
        ),
        (
            GearInPosCaGoal {
                slave_sync_position_reference_system: 0x0101_0010,
                ..gear_goal.clone()
            },
            0x8F0C,
        ),
    ];
    for (g, id) in refused {
        let (gid, _) = send_goal(&gear, "refused gear goal", g).await;
        let (status, result) = within(20.0, "refused gear result", gear.async_request_result(gid))
            .await
            .unwrap();
        assert_eq!(status, GoalStatusEnum::Aborted);
        assert_eq!(result.error_id, id, "{}", result.message);
    }
    let c_pos = s.axes[2].position;
    let (gid, _) = send_goal(
        &gear,
        "gear goal with options",
        GearInPosCaGoal {
            forbid_direction_reversal: true,
            forbid_master_velocity_undershoot: true,
            minimal_slave_position: value(c_pos - 1000.0),
            master_signal_correction: 1,
            ..gear_goal.clone()
        },
    )
    .await;
    let (status, result) = within(30.0, "options gear result", gear.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    state_until(&states, "c in sync again", |s| {
        s.axes[2].in_sync && s.axes[2].active_command_id == result.command_id
    })
    .await;

    // MC_GroupStop: Stopping while Execute is held, Standby after the falling edge.
    let stop = c
        .client::<CaGroupStopRequest, CaGroupStopResponse>(
            &format!("{NS}/group_stop"),
            CaGroupStop::service_type_name(),
        )
        .await;
    let r = call(
        &stop,
        "group_stop",
        CaGroupStopRequest {
            execute: true,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    assert_ne!(r.command_id, 0);
    state_until(&states, "stopping", |s| {
        s.state == CaGroupState::STATE_GROUP_STOPPING
    })
    .await;
    let r2 = call(&rs, "read_status stopping", CaReadStatusRequest::default()).await;
    assert!(r2.group_stopping, "{r2:?}");
    // No motion while Stopping: the engine's NOT_ALLOWED_IN_GROUP_STATE.
    let (gid, _) = send_goal(&mv, "goal while stopping", goal("c", 100.0, 100.0)).await;
    let (status, result) = within(20.0, "stopping goal result", mv.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted);
    assert_eq!(result.error_id, 0x813E, "{}", result.message);
    state_until(&states, "stopped: all standing", |s| {
        s.state == CaGroupState::STATE_GROUP_STOPPING && s.all_axes_standing
    })
    .await;
    let r = call(
        &stop,
        "group_stop release",
        CaGroupStopRequest {
            execute: false,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    assert!(r.stop_done, "released after standstill");
    state_until(&states, "standby after the release", |s| {
        s.state == CaGroupState::STATE_GROUP_STANDBY
    })
    .await;

    // The §9.4 simulation helpers under ~/sim/.
    let sim_pos = c
        .client::<SetPositionRequest, SetPositionResponse>(
            "/axis_node/sim/set_position",
            SetPosition::service_type_name(),
        )
        .await;
    let set_c = |position: f64| SetPositionRequest {
        axis: "c".into(),
        position,
        ..Default::default()
    };
    let r = call(
        &sim_pos,
        "sim/set_position in the enabled group",
        set_c(50.0),
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x813E, "{}", r.message);
    let inject = c
        .client::<InjectErrorRequest, InjectErrorResponse>(
            "/axis_node/sim/inject_axis_error",
            InjectError::service_type_name(),
        )
        .await;
    let r = call(
        &inject,
        "sim/inject_axis_error",
        InjectErrorRequest {
            axis: "b".into(),
            error_id: 0,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    let s = state_until(&states, "error stop", |s| {
        s.state == CaGroupState::STATE_GROUP_ERROR_STOP
    })
    .await;
    assert_eq!(s.group_error_id, 0x4550, "error_id 0 = 0x4550");
    for (name, to) in [
        ("group_disable", CaGroupState::STATE_GROUP_ERROR_DISABLED),
        ("group_reset", CaGroupState::STATE_GROUP_DISABLED),
    ] {
        let cl = c
            .client::<CaGroupCommandRequest, CaGroupCommandResponse>(
                &format!("{NS}/{name}"),
                CaGroupCommand::service_type_name(),
            )
            .await;
        let r = call(&cl, name, CaGroupCommandRequest::default()).await;
        assert!(r.accepted, "{name}: {}", r.message);
        state_until(&states, name, |s| s.state == to).await;
    }
    // Disabled group: set_position and set_axis_power act on the axis.
    let r = call(
        &sim_pos,
        "sim/set_position in a disabled group",
        set_c(50.0),
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    state_until(&states, "c at 50", |s| {
        s.axes
            .iter()
            .any(|a| a.name == "c" && (a.position - 50.0).abs() < 1e-9)
    })
    .await;
    let sim_power = c
        .client::<PowerRequest, PowerResponse>(
            "/axis_node/sim/set_axis_power",
            Power::service_type_name(),
        )
        .await;
    let r = call(
        &sim_power,
        "sim/set_axis_power",
        PowerRequest {
            axis: "c".into(),
            enable: false,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted && !r.status, "{r:?}");
    let r = call(
        &enable,
        "group_enable with c unpowered",
        CaGroupCommandRequest::default(),
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    state_until(&states, "not ready", |s| {
        s.state == CaGroupState::STATE_GROUP_NOT_READY
    })
    .await;
    let step = c
        .client::<StepCyclesRequest, StepCyclesResponse>(
            "/axis_node/sim/step",
            StepCycles::service_type_name(),
        )
        .await;
    let r = call(&step, "sim/step", StepCyclesRequest { cycles: 3 }).await;
    assert!(r.accepted && r.cycle_index > 0, "{r:?}");

    drop(c);
    node.stop().await;
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn ca_groups_over_dds_both_mappings() {
    require_netns();
    scenario(ServiceMapping::Cyclone).await;
    scenario(ServiceMapping::Enhanced).await;
}
