//! axis_node's function blocks over real DDS (a ros2-client client in its own Context, the node
//! in lockstep driven by `drive`): each FB at least once, asserting the behaviour, states and
//! error ids of single_axis.md (§2 states and admission, §3.6 Buffered, §4.x per FB, §7 ids).

use axis_node::AxisNode;
use motion_msgs::action;
use motion_msgs::msg::{AxisState, CommandStatus};
use motion_msgs::srv::{self, *};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{Client, Message, ServiceMapping};
use std::time::Duration;
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

const CONFIG: &str = "axes:
  x:
    max_velocity: 1000.0
    acceleration: 10000.0
    deceleration: 10000.0
    jerk: 100000.0
    home_cam: [10.0, 20.0]
  y:
    max_velocity: 1000.0
    acceleration: 10000.0
    deceleration: 10000.0
    jerk: 100000.0
";

const STANDSTILL: u8 = AxisState::MC_AXISSTATE_STANDSTILL;
/// 0x4B01 "axis cannot be started" (§2.4, §4.8.10 while locked, §7).
const AXIS_CANNOT_BE_STARTED: u32 = 0x4B01;

fn start_node(domain: u16, mapping: ServiceMapping) -> AxisNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    axis_node::start(&common("axis_node", true, mapping), cfg, "test", domain).expect("axis node")
}

async fn call<Req: Message + Clone + 'static, Resp: Message + 'static>(
    cl: &Client<Req, Resp>,
    what: &str,
    req: Req,
) -> Resp {
    within(10.0, what, cl.async_call_service(req))
        .await
        .unwrap_or_else(|e| panic!("{what}: {e:?}"))
}

/// The service clients of the scenario.
struct Axis {
    power: Client<PowerRequest, PowerResponse>,
    reset: Client<ResetRequest, ResetResponse>,
    mv_abs: Client<MoveAbsoluteRequest, MoveAbsoluteResponse>,
    mv_rel: Client<MoveRelativeRequest, MoveRelativeResponse>,
    mv_vel: Client<MoveVelocityRequest, MoveVelocityResponse>,
    mv_mod: Client<MoveModuloRequest, MoveModuloResponse>,
    stop: Client<StopRequest, StopResponse>,
    gear_out: Client<GearOutRequest, GearOutResponse>,
    jog: Client<JogRequest, JogResponse>,
    read_par: Client<ReadParameterRequest, ReadParameterResponse>,
    write_par: Client<WriteParameterRequest, WriteParameterResponse>,
    status: Client<ReadStatusRequest, ReadStatusResponse>,
    axis_error: Client<ReadAxisErrorRequest, ReadAxisErrorResponse>,
    act_pos: Client<ReadActualPositionRequest, ReadActualPositionResponse>,
    act_vel: Client<ReadActualVelocityRequest, ReadActualVelocityResponse>,
    outputs: Client<GetOutputsRequest, GetOutputsResponse>,
    inject: Client<InjectErrorRequest, InjectErrorResponse>,
}

impl Axis {
    async fn new(c: &mut ClientNode) -> Axis {
        macro_rules! cl {
            ($name:literal, $srv:ident) => {
                c.client(
                    concat!("/axis_node/", $name),
                    srv::$srv::service_type_name(),
                )
                .await
            };
        }
        Axis {
            power: cl!("power", Power),
            reset: cl!("reset", Reset),
            mv_abs: cl!("move_absolute", MoveAbsolute),
            mv_rel: cl!("move_relative", MoveRelative),
            mv_vel: cl!("move_velocity", MoveVelocity),
            mv_mod: cl!("move_modulo", MoveModulo),
            stop: cl!("stop", Stop),
            gear_out: cl!("gear_out", GearOut),
            jog: cl!("jog", Jog),
            read_par: cl!("read_parameter", ReadParameter),
            write_par: cl!("write_parameter", WriteParameter),
            status: cl!("read_status", ReadStatus),
            axis_error: cl!("read_axis_error", ReadAxisError),
            act_pos: cl!("read_actual_position", ReadActualPosition),
            act_vel: cl!("read_actual_velocity", ReadActualVelocity),
            outputs: cl!("get_outputs", GetOutputs),
            inject: cl!("sim/inject_error", InjectError),
        }
    }

    async fn status(&self, axis: &str) -> ReadStatusResponse {
        let r = call(
            &self.status,
            "read_status",
            ReadStatusRequest { axis: axis.into() },
        )
        .await;
        assert!(r.accepted, "read_status: {}", r.message);
        r
    }

    async fn pos(&self, axis: &str) -> f64 {
        let r = call(
            &self.act_pos,
            "read_actual_position",
            ReadActualPositionRequest { axis: axis.into() },
        )
        .await;
        assert!(r.accepted, "{}", r.message);
        r.position
    }

    async fn out(&self, id: u64) -> GetOutputsResponse {
        let r = call(
            &self.outputs,
            "get_outputs",
            GetOutputsRequest { command_id: id },
        )
        .await;
        assert!(r.accepted, "get_outputs {id}: {}", r.message);
        r
    }

    /// Polls the outputs of instance `id` until `f` holds (as a PLC polls its FB instance).
    async fn until(
        &self,
        id: u64,
        what: &str,
        f: impl Fn(&GetOutputsResponse) -> bool,
    ) -> GetOutputsResponse {
        within(20.0, what, async {
            loop {
                let o = self.out(id).await;
                if f(&o) {
                    return o;
                }
                tokio::time::sleep(Duration::from_millis(5)).await;
            }
        })
        .await
    }

    async fn until_state(&self, axis: &str, state: u8, what: &str) -> ReadStatusResponse {
        within(20.0, what, async {
            loop {
                let s = self.status(axis).await;
                if s.status.motion_state == state {
                    return s;
                }
                tokio::time::sleep(Duration::from_millis(5)).await;
            }
        })
        .await
    }

    async fn move_abs(
        &self,
        axis: &str,
        position: f64,
        velocity: f64,
        buffer_mode: u8,
    ) -> MoveAbsoluteResponse {
        let req = MoveAbsoluteRequest {
            axis: axis.into(),
            position,
            velocity,
            buffer_mode,
            ..Default::default()
        };
        call(&self.mv_abs, "move_absolute", req).await
    }

    async fn move_velocity(&self, axis: &str, velocity: f64) -> u64 {
        let req = MoveVelocityRequest {
            axis: axis.into(),
            velocity,
            direction: 1,
            ..Default::default()
        };
        let r = call(&self.mv_vel, "move_velocity", req).await;
        assert!(r.accepted, "move_velocity: {}", r.message);
        r.command_id
    }
}

async fn power_on(a: &Axis, axis: &str) {
    let r = call(
        &a.power,
        "power",
        PowerRequest {
            axis: axis.into(),
            enable: true,
            r#override: 100.0,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "power {axis}: {}", r.message);
    // T3: Disabled -> Standstill once Enable and Status are TRUE (§2.2).
    let s = a
        .until_state(axis, STANDSTILL, "Standstill after MC_Power")
        .await;
    assert!(s.standstill && !s.disabled && !s.error_stop);
    assert!(s.status.power_status);
}

async fn scenario(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "fb_client", mapping);
    let statuses =
        c.subscribe::<CommandStatus>("/axis_node/command_status", CommandStatus::type_name());
    let a = Axis::new(&mut c).await;

    // --- MC_Power (§4.1): Disabled before, Standstill after; unknown axis 0x7F01.
    let s = a.status("x").await;
    assert!(s.disabled && s.status.motion_state == AxisState::MC_AXISSTATE_DISABLED);
    // §2.4: a move on a Disabled axis is rejected with 0x4B01.
    let r = a.move_abs("x", 1.0, 10.0, 0).await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, AXIS_CANNOT_BE_STARTED, "{}", r.message);
    let r = call(
        &a.power,
        "power nope",
        PowerRequest {
            axis: "nope".into(),
            enable: true,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F01);
    power_on(&a, "x").await;
    power_on(&a, "y").await;

    // --- MC_Home (§4.10) as an action: PLCCAM homing onto the virtual cam [10, 20]; the
    // reference (falling cam edge) gets Position 100, the axis stops one braking distance later.
    assert!(!a.status("x").await.status.homed);
    let home = c
        .action::<action::HomeGoal, action::HomeResult, action::HomeFeedback>(
            "/axis_node/home",
            &action::Home::action_type_name(),
        )
        .await;
    let goal = action::HomeGoal {
        axis: "x".into(),
        position: 100.0,
        use_default_position: false,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&home, "home goal", goal).await;
    assert!(resp.accepted);
    // State Homing while the run is on (T12; the goal is accepted before the engine takes the
    // edge, so wait for it).
    let s = a
        .until_state("x", AxisState::MC_AXISSTATE_HOMING, "homing run")
        .await;
    assert!(s.homing && !s.standstill);
    // NcToPlc.HomingState shows the phase (§4.10; issue 15.11).
    assert!((1..=6).contains(&s.status.homing_state), "{s:?}");
    let (st, res) = within(30.0, "home result", home.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded, "{res:?}");
    assert!(res.done && !res.error);
    let s = a.status("x").await;
    assert!(s.status.homed && s.standstill, "{s:?}");
    // Braking distance of the jerk-limited stop from the calibration velocity 30 u/s (a_max not
    // reached): v·√(v/j); the stop starts at most one 1 ms cycle (0.03 u) after the edge.
    let braking = 30.0 * (30.0f64 / 100_000.0).sqrt();
    let past = s.status.act_pos - (100.0 + braking);
    assert!(
        (-1e-6..0.03 + 1e-6).contains(&past),
        "reference 100 + braking distance {braking}: {}",
        s.status.act_pos
    );
    // The §1.5 simulation values: the raw machine position is unchanged by the calibration
    // (reference = the falling cam edge at raw 20 in the positive sync direction, so ActPos =
    // raw + 80), and the virtual cam is low one braking distance past its edge.
    assert_eq!(s.status.homing_state, 0, "ready");
    assert!(
        (s.status.act_pos - s.status.raw_act_pos - 80.0).abs() < 1e-6,
        "raw {} act {}",
        s.status.raw_act_pos,
        s.status.act_pos
    );
    assert!(!s.status.home_cam && s.status.raw_act_pos > 20.0);
    assert!((s.status.set_pos - s.status.raw_set_pos - 80.0).abs() < 1e-6);
    // MC_Home with HomingMode 9 is not an MC_HomingMode: 0x7F03.
    let goal = action::HomeGoal {
        axis: "x".into(),
        homing_mode: 9,
        ..Default::default()
    };
    let (gid, _) = send_goal(&home, "bad home goal", goal).await;
    let (st, res) = within(20.0, "bad home result", home.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Aborted);
    assert_eq!(res.error_id, 0x7F03, "{}", res.message);

    // --- Move + buffered move (§3.6 Buffered): the second waits (Busy, not Active) while the
    // first runs, starts when it is Done, the first ends Done (not aborted).
    let p0 = a.pos("x").await;
    let first = a.move_abs("x", p0 + 100.0, 100.0, 0).await;
    assert!(first.accepted, "{}", first.message);
    let second = a.move_abs("x", p0 + 150.0, 100.0, 1).await;
    assert!(second.accepted, "{}", second.message);
    let o2 = a.out(second.command_id).await;
    assert_eq!(o2.fb, "MC_MoveAbsolute");
    assert_eq!(o2.axis, "x");
    assert!(
        o2.busy && !o2.active && !o2.done,
        "buffered: waiting {o2:?}"
    );
    let o1 = a.out(first.command_id).await;
    assert!(o1.busy && o1.active, "first running {o1:?}");
    let o2 = a
        .until(second.command_id, "buffered move active", |o| {
            o.active || o.done
        })
        .await;
    assert!(!o2.error);
    let o1 = a.out(first.command_id).await;
    assert!(
        o1.done && !o1.command_aborted && !o1.busy,
        "first Done when the buffered one takes over {o1:?}"
    );
    a.until(second.command_id, "buffered move Done", |o| o.done)
        .await;
    assert!((a.pos("x").await - (p0 + 150.0)).abs() < 1e-6);
    assert!(a.status("x").await.standstill);
    // A bad enum (Direction 9) on MC_MoveModulo: 0x7F03; NaN: rejected with an id.
    let r = call(
        &a.mv_mod,
        "move_modulo",
        MoveModuloRequest {
            axis: "x".into(),
            position: 10.0,
            velocity: 10.0,
            direction: 9,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);
    let r = a.move_abs("x", f64::NAN, 10.0, 0).await;
    assert!(!r.accepted && r.error_id != 0, "{}", r.message);

    // --- MC_MoveVelocity (§4.8.6) as an action: succeeds at InVelocity, the axis runs on.
    let mvel = c
        .action::<action::MoveVelocityGoal, action::MoveVelocityResult, action::MoveVelocityFeedback>(
            "/axis_node/move_velocity",
            &action::MoveVelocity::action_type_name(),
        )
        .await;
    let goal = action::MoveVelocityGoal {
        axis: "x".into(),
        velocity: 80.0,
        direction: 1,
        ..Default::default()
    };
    let (gid, _) = send_goal(&mvel, "velocity goal", goal).await;
    let (st, res) = within(20.0, "velocity result", mvel.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded, "{res:?}");
    assert!(res.done && !res.error);
    let s = a.status("x").await;
    assert!(
        s.continuous_motion && (s.status.set_velo - 80.0).abs() < 1e-9,
        "{s:?}"
    );

    // --- MC_Halt (§4.8.9) as an action on an endless MC_MoveVelocity: the halt succeeds at
    // rest, the velocity command ends CommandAborted, the axis is in Standstill.
    let vel = a.move_velocity("x", 100.0).await;
    a.until(vel, "InVelocity", |o| o.in_velocity).await;
    let v = call(
        &a.act_vel,
        "read_actual_velocity",
        ReadActualVelocityRequest { axis: "x".into() },
    )
    .await;
    assert!(
        (v.actual_velocity - 100.0).abs() < 1e-6,
        "{}",
        v.actual_velocity
    );
    let halt = c
        .action::<action::HaltGoal, action::HaltResult, action::HaltFeedback>(
            "/axis_node/halt",
            &action::Halt::action_type_name(),
        )
        .await;
    let (gid, _) = send_goal(
        &halt,
        "halt goal",
        action::HaltGoal {
            axis: "x".into(),
            ..Default::default()
        },
    )
    .await;
    let (st, res) = within(20.0, "halt result", halt.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded, "{res:?}");
    assert!(res.done);
    assert!(a.out(vel).await.command_aborted);
    let s = a.status("x").await;
    assert!(s.standstill && s.status.act_velo.abs() < 1e-9);

    // --- MC_MoveContinuousAbsolute (§4.8.7) as an action: succeeds at InEndVelocity, the axis
    // then runs on at EndVelocity in ContinuousMotion; MC_TorqueControl (§4.14) succeeds at
    // InTorque and keeps torque mode (ContinuousMotion). MC_Halt ends both.
    let cont = c
        .action::<action::MoveContinuousAbsoluteGoal, action::MoveContinuousAbsoluteResult, action::MoveContinuousAbsoluteFeedback>(
            "/axis_node/move_continuous_absolute",
            &action::MoveContinuousAbsolute::action_type_name(),
        )
        .await;
    let p = a.pos("x").await;
    let goal = action::MoveContinuousAbsoluteGoal {
        axis: "x".into(),
        position: p + 20.0,
        velocity: 100.0,
        end_velocity: 50.0,
        ..Default::default()
    };
    let (gid, _) = send_goal(&cont, "continuous goal", goal).await;
    let (st, res) = within(20.0, "continuous result", cont.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded, "{res:?}");
    assert!(res.done && !res.error);
    assert!(
        res.position >= p + 20.0 - 1e-6,
        "InEndVelocity at the target: {}",
        res.position
    );
    let s = a.status("x").await;
    assert!(s.continuous_motion, "runs on after InEndVelocity: {s:?}");
    assert!(
        (s.status.set_velo - 50.0).abs() < 1e-6,
        "EndVelocity: {}",
        s.status.set_velo
    );
    let (gid, _) = send_goal(
        &halt,
        "halt goal",
        action::HaltGoal {
            axis: "x".into(),
            ..Default::default()
        },
    )
    .await;
    let (st, _) = within(20.0, "halt result", halt.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded);
    let torque = c
        .action::<action::TorqueControlGoal, action::TorqueControlResult, action::TorqueControlFeedback>(
            "/axis_node/torque_control",
            &action::TorqueControl::action_type_name(),
        )
        .await;
    let goal = action::TorqueControlGoal {
        axis: "x".into(),
        torque: 10.0,
        torque_ramp: 100.0,
        velocity_limit_high: 400.0,
        velocity_limit_low: -500.0,
        ..Default::default()
    };
    let (gid, _) = send_goal(&torque, "torque goal", goal).await;
    let (st, res) = within(20.0, "torque result", torque.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded, "{res:?}");
    assert!(res.done && !res.error);
    assert!(
        a.status("x").await.continuous_motion,
        "torque mode runs on after InTorque"
    );
    // TorqueRamp 0 is not a valid ramp (> 0): rejected with 0x4B06 in the result.
    let goal = action::TorqueControlGoal {
        axis: "x".into(),
        torque: 10.0,
        velocity_limit_high: 400.0,
        velocity_limit_low: -500.0,
        ..Default::default()
    };
    let (gid, _) = send_goal(&torque, "bad torque goal", goal).await;
    let (st, res) = within(20.0, "bad torque result", torque.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Aborted);
    assert!(res.error && res.error_id == 0x4B06, "{res:?}");
    let (gid, _) = send_goal(
        &halt,
        "halt goal",
        action::HaltGoal {
            axis: "x".into(),
            ..Default::default()
        },
    )
    .await;
    let (st, _) = within(20.0, "halt result", halt.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded);
    a.until_state("x", STANDSTILL, "Standstill after MC_Halt")
        .await;

    // --- MC_Stop (§4.8.10): stops and locks; moves are rejected with 0x4B01 until Execute
    // falls; then Standstill and moves are accepted again.
    let vel = a.move_velocity("x", 100.0).await;
    a.until(vel, "moving", |o| o.in_velocity).await;
    let stop = call(
        &a.stop,
        "stop",
        StopRequest {
            axis: "x".into(),
            execute: true,
            ..Default::default()
        },
    )
    .await;
    assert!(stop.accepted, "{}", stop.message);
    let o = a.until(stop.command_id, "stop Done", |o| o.done).await;
    assert!(
        o.busy && o.active,
        "Busy and Active stay TRUE while locked {o:?}"
    );
    let s = a.status("x").await;
    assert!(s.stopping && s.status.motion_state == AxisState::MC_AXISSTATE_STOPPING);
    assert!(s.status.act_velo.abs() < 1e-9);
    assert!(a.out(vel).await.command_aborted);
    let r = a.move_abs("x", 0.0, 10.0, 0).await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, AXIS_CANNOT_BE_STARTED, "locked: {}", r.message);
    let r = call(
        &a.stop,
        "stop release",
        StopRequest {
            axis: "x".into(),
            execute: false,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until_state("x", STANDSTILL, "Standstill after the unlock (N6)")
        .await;
    let p = a.pos("x").await;
    let r = a.move_abs("x", p + 1.0, 10.0, 0).await;
    assert!(r.accepted, "unlocked: {}", r.message);
    a.until(r.command_id, "move after unlock Done", |o| o.done)
        .await;

    // --- MC_GearIn (§4.12.1) as an action: succeeds at InGear; the slave follows the master
    // with ratio 3/2; MC_GearOut decouples (slave at rest -> Standstill, T10b).
    let gear = c
        .action::<action::GearInGoal, action::GearInResult, action::GearInFeedback>(
            "/axis_node/gear_in",
            &action::GearIn::action_type_name(),
        )
        .await;
    let goal = action::GearInGoal {
        master: "x".into(),
        slave: "y".into(),
        ratio_numerator: 3.0,
        ratio_denominator: 2,
        ..Default::default()
    };
    let (gid, _) = send_goal(&gear, "gear_in goal", goal).await;
    let (st, res) = within(20.0, "gear_in result", gear.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded, "{res:?}");
    assert!(res.done && !res.error);
    let s = a.status("y").await;
    assert!(s.synchronized_motion, "slave coupled: {s:?}");
    assert!(
        a.status("x").await.standstill,
        "coupling never changes the master's state"
    );
    let (m0, s0) = (a.pos("x").await, a.pos("y").await);
    let r = call(
        &a.mv_rel,
        "master move",
        MoveRelativeRequest {
            axis: "x".into(),
            distance: 20.0,
            velocity: 200.0,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until(r.command_id, "master move Done", |o| o.done).await;
    let (m1, s1) = (a.pos("x").await, a.pos("y").await);
    assert!((m1 - m0 - 20.0).abs() < 1e-6);
    assert!(
        (s1 - s0 - 30.0).abs() < 1e-6,
        "slave moved {} for 20 of the master",
        s1 - s0
    );
    // Denominator 0: 0x4B06 (§4.12.1).
    let goal = action::GearInGoal {
        master: "x".into(),
        slave: "y".into(),
        ratio_numerator: 1.0,
        ratio_denominator: 0,
        ..Default::default()
    };
    let (gid, _) = send_goal(&gear, "bad gear_in goal", goal).await;
    let (st, res) = within(20.0, "bad gear_in result", gear.async_request_result(gid))
        .await
        .unwrap();
    assert_eq!(st, GoalStatusEnum::Aborted);
    assert_eq!(res.error_id, 0x4B06, "{}", res.message);
    let r = call(
        &a.gear_out,
        "gear_out",
        GearOutRequest { slave: "y".into() },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until_state("y", STANDSTILL, "slave Standstill after MC_GearOut")
        .await;
    // Not coupled any more: MC_GearOut -> 0x4B05 (§4.12.3).
    let r = call(
        &a.gear_out,
        "gear_out again",
        GearOutRequest { slave: "y".into() },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x4B05, "{}", r.message);

    // --- MC_Jog (§4.11), level-held buttons: CONTINOUS moves while JogForward is TRUE
    // (ContinuousMotion), releasing it decelerates to Done at rest; INCHING moves one step.
    let jog = |forward: bool, mode: u8, position: f64| JogRequest {
        axis: "y".into(),
        jog_forward: forward,
        mode,
        position,
        velocity: 50.0,
        ..Default::default()
    };
    let r = call(&a.jog, "jog press", jog(true, 2, 0.0)).await;
    assert!(r.accepted, "{}", r.message);
    let id = r.command_id;
    let s = a
        .until_state("y", AxisState::MC_AXISSTATE_CONTINUOUSMOTION, "jogging")
        .await;
    // The jerk-limited ramp may still be at 0 in the first ContinuousMotion sample.
    assert!(s.status.act_velo >= 0.0, "jogging forward");
    let r = call(&a.jog, "jog held", jog(true, 2, 0.0)).await;
    assert!(r.accepted && r.command_id == id, "no new edge while held");
    within(20.0, "jog at velocity", async {
        while (a.status("y").await.status.act_velo - 50.0).abs() > 1e-6 {
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    })
    .await;
    let r = call(&a.jog, "jog release", jog(false, 2, 0.0)).await;
    assert!(r.accepted, "{}", r.message);
    // Execute (the button) is already FALSE: Done shows for one cycle only (§3.1 rule 6), so
    // it is observed as the instance's event on ~/command_status rather than by polling.
    within(20.0, "jog Done at rest", async {
        loop {
            let (st, _) = statuses.async_take().await.unwrap();
            if st.command_id == id && st.done {
                assert_eq!((st.object.as_str(), st.command.as_str()), ("y", "jog"));
                break;
            }
        }
    })
    .await;
    let s = a.status("y").await;
    assert!(s.standstill && s.status.act_velo.abs() < 1e-9, "{s:?}");
    let p = a.pos("y").await;
    let r = call(&a.jog, "inch", jog(true, 3, 5.0)).await;
    assert!(r.accepted, "{}", r.message);
    a.until(r.command_id, "inching step Done", |o| o.done).await;
    assert!(
        (a.pos("y").await - (p + 5.0)).abs() < 1e-6,
        "one step of Position"
    );
    call(&a.jog, "inch release", jog(false, 3, 5.0)).await;
    let r = call(&a.jog, "bad jog mode", jog(true, 7, 0.0)).await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);

    // --- MC_Read/WriteParameter (§4.4.5, §4.4.8): round trip of SWLimitPos (2) and its alias
    // AxisMaxSoftPosLimit (1019), a BOOL one, read-only 0x4D04, unknown 0x4D03.
    let w = |n: u32, value: f64, is_bool: bool, bool_value: bool| WriteParameterRequest {
        axis: "x".into(),
        parameter_number: n,
        value,
        is_bool,
        bool_value,
        ..Default::default()
    };
    let r = call(&a.write_par, "write 2", w(2, 2000.0, false, false)).await;
    assert!(r.accepted, "{}", r.message);
    for n in [2, 1019] {
        let r = call(
            &a.read_par,
            "read",
            ReadParameterRequest {
                axis: "x".into(),
                parameter_number: n,
            },
        )
        .await;
        assert!(r.accepted && !r.is_bool, "{}", r.message);
        assert_eq!(r.value, 2000.0, "parameter {n}");
    }
    let r = call(&a.write_par, "write 4", w(4, 0.0, true, true)).await;
    assert!(r.accepted, "{}", r.message);
    let r = call(
        &a.read_par,
        "read 4",
        ReadParameterRequest {
            axis: "x".into(),
            parameter_number: 4,
        },
    )
    .await;
    assert!(r.accepted && r.is_bool && r.bool_value, "{r:?}");
    let r = call(&a.write_par, "write read-only 1", w(1, 5.0, false, false)).await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x4D04, "{}", r.message);
    let r = call(
        &a.read_par,
        "read unknown",
        ReadParameterRequest {
            axis: "x".into(),
            parameter_number: 999,
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x4D03, "{}", r.message);

    // --- An injected axis error (§1.5) -> ErrorStop (T1); commands rejected with 0x4B01;
    // MC_ReadAxisError shows it; MC_Reset -> Standstill (T4), error cleared.
    let r = call(
        &a.inject,
        "inject",
        InjectErrorRequest {
            axis: "x".into(),
            error_id: 0x4550,
            drive_fault: false,
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    let s = a
        .until_state("x", AxisState::MC_AXISSTATE_ERRORSTOP, "ErrorStop")
        .await;
    assert!(s.error_stop && s.status.error_code == 0x4550);
    let e = call(
        &a.axis_error,
        "read_axis_error",
        ReadAxisErrorRequest { axis: "x".into() },
    )
    .await;
    assert!(e.accepted);
    assert_eq!(e.axis_error_id, 0x4550);
    let r = a.move_abs("x", 0.0, 10.0, 0).await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, AXIS_CANNOT_BE_STARTED, "{}", r.message);
    let r = call(&a.reset, "reset", ResetRequest { axis: "x".into() }).await;
    assert!(r.accepted, "{}", r.message);
    let s = a
        .until_state("x", STANDSTILL, "Standstill after MC_Reset")
        .await;
    assert_eq!(s.status.error_code, 0);
    let e = call(
        &a.axis_error,
        "read_axis_error",
        ReadAxisErrorRequest { axis: "x".into() },
    )
    .await;
    assert_eq!(e.axis_error_id, 0);

    // ~/get_outputs of an unknown instance: 0x7F01.
    let r = call(
        &a.outputs,
        "get_outputs unknown",
        GetOutputsRequest {
            command_id: 987_654_321,
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F01);

    drop(c);
    node.stop().await;
}

/// The remaining FBs and hooks, one call each with the behaviour the spec fixes.
async fn more_fbs(mapping: ServiceMapping) {
    let domain = unique_domain();
    let node = start_node(domain, mapping);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "fb_client2", mapping);
    let statuses =
        c.subscribe::<CommandStatus>("/axis_node/command_status", CommandStatus::type_name());
    let a = Axis::new(&mut c).await;
    macro_rules! cl {
        ($name:literal, $srv:ident) => {
            c.client(
                concat!("/axis_node/", $name),
                srv::$srv::service_type_name(),
            )
            .await
        };
    }
    let set_override: Client<SetOverrideRequest, SetOverrideResponse> =
        cl!("set_override", SetOverride);
    let superimposed: Client<MoveSuperImposedRequest, MoveSuperImposedResponse> =
        cl!("move_superimposed", MoveSuperImposed);
    let abort_sup: Client<AbortSuperpositionRequest, AbortSuperpositionResponse> =
        cl!("abort_superposition", AbortSuperposition);
    let probe: Client<TouchProbeRequest, TouchProbeResponse> = cl!("touch_probe", TouchProbe);
    let plc_event: Client<TouchProbePlcEventRequest, TouchProbePlcEventResponse> =
        cl!("touch_probe_plc_event", TouchProbePlcEvent);
    let abort_trigger: Client<AbortTriggerRequest, AbortTriggerResponse> =
        cl!("abort_trigger", AbortTrigger);
    let probe_input: Client<SetProbeInputRequest, SetProbeInputResponse> =
        cl!("sim/probe_input", SetProbeInput);
    let offset: Client<SetFollowingOffsetRequest, SetFollowingOffsetResponse> =
        cl!("sim/set_following_offset", SetFollowingOffset);
    let set_position: Client<SetPositionRequest, SetPositionResponse> =
        cl!("set_position", SetPosition);
    let home: Client<HomeRequest, HomeResponse> = cl!("home", Home);
    let home_cam: Client<HomeCalibrationCamRequest, HomeCalibrationCamResponse> =
        cl!("home_calibration_cam", HomeCalibrationCam);
    let gear_dyn: Client<GearInDynRequest, GearInDynResponse> = cl!("gear_in_dyn", GearInDyn);
    let set_execute: Client<SetExecuteRequest, SetExecuteResponse> = cl!("set_execute", SetExecute);
    let torque_update: Client<TorqueControlUpdateRequest, TorqueControlUpdateResponse> =
        cl!("torque_control_update", TorqueControlUpdate);
    power_on(&a, "x").await;
    power_on(&a, "y").await;

    // MC_SetPosition (§4.3) absolute at standstill: ActPos becomes Position.
    let r = call(
        &set_position,
        "set_position",
        SetPositionRequest {
            axis: "x".into(),
            position: 500.0,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    within(10.0, "SetPosition applied", async {
        while (a.pos("x").await - 500.0).abs() > 1e-9 {
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    })
    .await;

    // MC_Home with MC_Direct (§4.10): ActPos := Position, Homed, no motion, Done.
    let r = call(
        &home,
        "home direct",
        HomeRequest {
            axis: "x".into(),
            position: 42.0,
            use_default_position: false,
            homing_mode: 1,
            search_direction: 128,
            sync_direction: 128,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until(r.command_id, "MC_Direct Done", |o| o.done).await;
    let s = a.status("x").await;
    assert!(s.status.homed && s.standstill);
    assert!((s.status.act_pos - 42.0).abs() < 1e-9);
    let r = call(
        &home_cam,
        "cam of an unknown instance",
        HomeCalibrationCamRequest {
            command_id: 424_242,
            calibration_cam: true,
        },
    )
    .await;
    assert_eq!((r.accepted, r.error_id), (false, 0x7F01), "{}", r.message);

    // MC_MoveModulo (§4.8.4) positive to 90 of the period 360 from 42: ends at 90.
    let r = call(
        &a.mv_mod,
        "move_modulo",
        MoveModuloRequest {
            axis: "x".into(),
            position: 90.0,
            velocity: 200.0,
            direction: 1,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until(r.command_id, "modulo Done", |o| o.done).await;
    let s = a.status("x").await;
    assert!(
        (s.status.act_pos - 90.0).abs() < 1e-6 && (s.status.modulo_act_pos - 90.0).abs() < 1e-6,
        "{s:?}"
    );
    // ModuloSetPos/ModuloSetTurns (NcToPlc, §4.8.5; issue 15.11): 400 = 1 turn + 40.
    let r = a.move_abs("x", 400.0, 500.0, 0).await;
    a.until(r.command_id, "move to 400 Done", |o| o.done).await;
    let s = a.status("x").await;
    assert!(
        (s.status.modulo_set_pos - 40.0).abs() < 1e-6 && s.status.modulo_set_turns == 1,
        "{s:?}"
    );
    // MC_Direction 2 (shortest way) with a target beyond the period: 0x4B06.
    let r = call(
        &a.mv_mod,
        "move_modulo 400 shortest",
        MoveModuloRequest {
            axis: "x".into(),
            position: 400.0,
            velocity: 200.0,
            direction: 2,
            ..Default::default()
        },
    )
    .await;
    assert_eq!((r.accepted, r.error_id), (false, 0x4B06), "{}", r.message);

    // MC_SetExecute falling edge on a finished instance resets its outputs (§3.1 rule 5).
    let r2 = a.move_abs("x", 100.0, 200.0, 0).await;
    a.until(r2.command_id, "move Done", |o| o.done).await;
    let r = call(
        &set_execute,
        "set_execute",
        SetExecuteRequest {
            command_id: r2.command_id,
            execute: false,
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    let o = a.out(r2.command_id).await;
    assert!(!o.done && !o.busy && !o.error, "outputs reset: {o:?}");

    // MC_SetOverride (§4.7.10): VelFactor 0.5 halves the velocity of a running MC_MoveVelocity;
    // VelFactor 1.5 is outside [0, 1]: 0x4B06.
    let r = call(
        &set_override,
        "set_override",
        SetOverrideRequest {
            axis: "x".into(),
            enable: true,
            vel_factor: 0.5,
            acc_factor: 1.0,
            jerk_factor: 1.0,
        },
    )
    .await;
    assert!(r.accepted && r.enabled, "{}", r.message);
    let vel = a.move_velocity("x", 100.0).await;
    a.until(vel, "InVelocity at 50 %", |o| o.in_velocity).await;
    let s = a.status("x").await;
    assert!(
        (s.status.act_velo - 50.0).abs() < 1e-6 && (s.status.r#override - 50.0).abs() < 1e-9,
        "{s:?}"
    );
    let r = call(
        &set_override,
        "bad override",
        SetOverrideRequest {
            axis: "x".into(),
            enable: true,
            vel_factor: 1.5,
            acc_factor: 1.0,
            jerk_factor: 1.0,
        },
    )
    .await;
    assert_eq!(
        (r.accepted, r.enabled, r.error_id),
        (false, false, 0x4B06),
        "{}",
        r.message
    );
    let r = call(
        &set_override,
        "override off",
        SetOverrideRequest {
            axis: "x".into(),
            enable: false,
            vel_factor: 1.0,
            acc_factor: 1.0,
            jerk_factor: 1.0,
        },
    )
    .await;
    assert!(r.accepted && !r.enabled, "{}", r.message);
    // An override change aborts MC_MoveVelocity (CommandAborted, Busy FALSE) while the axis
    // keeps moving with the new override-scaled velocity in ContinuousMotion (§4.8.6).
    let o = a
        .until(
            vel,
            "MoveVelocity CommandAborted by the override change",
            |o| o.command_aborted,
        )
        .await;
    assert!(!o.busy && !o.in_velocity, "{o:?}");
    within(10.0, "velocity 100 % again", async {
        loop {
            let s = a.status("x").await;
            assert!(s.continuous_motion, "keeps moving: {s:?}");
            if (s.status.act_velo - 100.0).abs() < 1e-6 {
                break;
            }
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    })
    .await;
    let vel = a.move_velocity("x", 100.0).await;
    a.until(vel, "InVelocity", |o| o.in_velocity).await;

    // MC_MoveSuperImposed (§4.9.1) on the moving axis: Done with ActualDistance = Distance;
    // the base motion goes on. MC_AbortSuperposition with no overlay: Done at once (p).
    let sup = |axis: &str| MoveSuperImposedRequest {
        axis: axis.into(),
        mode: 1,
        distance: 10.0,
        velocity_diff: 50.0,
        velocity_process: 100.0,
        length: 1000.0,
        ..Default::default()
    };
    let r = call(&superimposed, "move_superimposed", sup("x")).await;
    assert!(r.accepted, "{}", r.message);
    let o = a.until(r.command_id, "overlay Done", |o| o.done).await;
    assert!((o.actual_distance - 10.0).abs() < 1e-6, "{o:?}");
    assert!(a.out(vel).await.active, "the base motion runs on");
    let r = call(
        &abort_sup,
        "abort_superposition",
        AbortSuperpositionRequest { axis: "x".into() },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until(r.command_id, "abort Done", |o| o.done).await;
    // On an axis at standstill: 0x4B03 (§2.4).
    let r = call(&superimposed, "superimposed at standstill", sup("y")).await;
    assert_eq!((r.accepted, r.error_id), (false, 0x4B03), "{}", r.message);
    let h = call(
        &a.stop,
        "stop x",
        StopRequest {
            axis: "x".into(),
            execute: true,
            ..Default::default()
        },
    )
    .await;
    a.until(h.command_id, "stopped", |o| o.done).await;
    call(
        &a.stop,
        "unlock x",
        StopRequest {
            axis: "x".into(),
            execute: false,
            ..Default::default()
        },
    )
    .await;
    a.until_state("x", STANDSTILL, "x Standstill").await;

    // MC_TouchProbe (§4.5.1) on probe unit 1: a rising edge of the virtual input records the
    // position (the axis is at rest: RecordedPosition = ActPos); PlcEvent source via
    // ~/touch_probe_plc_event; MC_AbortTrigger aborts an armed probe (CommandAborted).
    let px = a.pos("x").await;
    let tp = |touch_probe: u8| TouchProbeRequest {
        axis: "x".into(),
        touch_probe,
        mode: 1,
        ..Default::default()
    };
    let r = call(&probe, "touch_probe", tp(1)).await;
    assert!(r.accepted, "{}", r.message);
    let id = r.command_id;
    assert!(a.out(id).await.busy);
    let r = call(
        &probe_input,
        "probe input",
        SetProbeInputRequest {
            axis: "x".into(),
            unit: 1,
            level: true,
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    let o = a.until(id, "probe Done", |o| o.done).await;
    assert!(
        o.recorded && (o.recorded_position - px).abs() < 1e-9,
        "{o:?}"
    );
    call(
        &probe_input,
        "probe input low",
        SetProbeInputRequest {
            axis: "x".into(),
            unit: 1,
            level: false,
        },
    )
    .await;
    let r = call(
        &probe_input,
        "probe unit 3",
        SetProbeInputRequest {
            axis: "x".into(),
            unit: 3,
            level: true,
        },
    )
    .await;
    assert_eq!((r.accepted, r.error_id), (false, 0x7F06), "{}", r.message);
    let r = call(&probe, "touch_probe plc", tp(10)).await;
    assert!(r.accepted, "{}", r.message);
    let id = r.command_id;
    let r = call(
        &plc_event,
        "plc event",
        TouchProbePlcEventRequest {
            command_id: id,
            plc_event: true,
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    let o = a.until(id, "PlcEvent probe Done", |o| o.done).await;
    assert!((o.recorded_position - px).abs() < 1e-9, "{o:?}");
    // A later input keeps the instance's label on ~/command_status.
    within(10.0, "PlcEvent probe Done on command_status", async {
        loop {
            let (st, _) = statuses.async_take().await.unwrap();
            if st.command_id == id && st.done {
                assert_eq!(
                    (st.object.as_str(), st.command.as_str()),
                    ("x", "touch_probe")
                );
                break;
            }
        }
    })
    .await;
    let r = call(&probe, "touch_probe armed", tp(2)).await;
    let id = r.command_id;
    let r = call(
        &abort_trigger,
        "abort_trigger",
        AbortTriggerRequest {
            axis: "x".into(),
            touch_probe: 2,
            mode: 1,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until(id, "probe CommandAborted", |o| o.command_aborted)
        .await;
    let r = call(
        &probe,
        "touch_probe bad edge",
        TouchProbeRequest { edge: 5, ..tp(1) },
    )
    .await;
    assert_eq!((r.accepted, r.error_id), (false, 0x7F03), "{}", r.message);

    // MC_GearInDyn (§4.12.2): Enable couples, InGear once r_eff = GearRatio; the slave follows
    // with the ratio; Enable FALSE ends the instance, the coupling stays (then MC_GearOut).
    let gd = |enable: bool| GearInDynRequest {
        master: "x".into(),
        slave: "y".into(),
        enable,
        gear_ratio: 0.5,
        ..Default::default()
    };
    let r = call(&gear_dyn, "gear_in_dyn", gd(true)).await;
    assert!(r.accepted, "{}", r.message);
    let gid = r.command_id;
    a.until(gid, "InGear", |o| o.in_gear).await;
    assert!(a.status("y").await.synchronized_motion);
    let (m0, s0) = (a.pos("x").await, a.pos("y").await);
    let r = call(
        &a.mv_rel,
        "master",
        MoveRelativeRequest {
            axis: "x".into(),
            distance: 10.0,
            velocity: 100.0,
            ..Default::default()
        },
    )
    .await;
    a.until(r.command_id, "master Done", |o| o.done).await;
    assert!((a.pos("x").await - m0 - 10.0).abs() < 1e-6);
    assert!((a.pos("y").await - s0 - 5.0).abs() < 1e-6, "ratio 0.5");
    let r = call(&gear_dyn, "gear_in_dyn off", gd(false)).await;
    assert!(r.accepted, "{}", r.message);
    let o = a.out(gid).await;
    assert!(!o.busy && !o.in_gear, "{o:?}");
    assert!(
        a.status("y").await.synchronized_motion,
        "coupling kept with the frozen ratio"
    );
    let r = call(
        &a.gear_out,
        "gear_out",
        GearOutRequest { slave: "y".into() },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    a.until_state("y", STANDSTILL, "y decoupled").await;

    // ~/torque_control_update of an unknown instance: 0x7F01.
    let r = call(
        &torque_update,
        "torque update",
        TorqueControlUpdateRequest {
            command_id: 77_777,
            torque: 1.0,
            torque_ramp: 1.0,
            velocity_limit_high: 1.0,
            velocity_limit_low: -1.0,
        },
    )
    .await;
    assert_eq!((r.accepted, r.error_id), (false, 0x7F01), "{}", r.message);

    // sim/set_following_offset (§1.5, ideal model): ActPos = SetPos + offset.
    let r = call(
        &offset,
        "offset",
        SetFollowingOffsetRequest {
            axis: "y".into(),
            offset: 0.25,
        },
    )
    .await;
    assert!(r.accepted, "{}", r.message);
    within(10.0, "offset applied", async {
        loop {
            let s = a.status("y").await.status;
            if (s.act_pos - s.set_pos - 0.25).abs() < 1e-9 {
                assert!(
                    (s.pos_diff + 0.25).abs() < 1e-9,
                    "PosDiff = SetPos - ActPos"
                );
                break;
            }
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    })
    .await;
    let r = call(
        &offset,
        "offset NaN",
        SetFollowingOffsetRequest {
            axis: "y".into(),
            offset: f64::NAN,
        },
    )
    .await;
    assert!(!r.accepted && r.error_id != 0, "{}", r.message);

    drop(c);
    node.stop().await;
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn axis_node_function_blocks_over_dds_both_mappings() {
    require_netns();
    scenario(ServiceMapping::Cyclone).await;
    scenario(ServiceMapping::Enhanced).await;
    more_fbs(ServiceMapping::Enhanced).await;
}
