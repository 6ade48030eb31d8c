//! axis_node's phasing, multi-master gearing, external setpoint generator and §4.7 extension
//! services over real DDS (a ros2-client client in its own Context, the node in lockstep driven
//! by `drive`), both service mappings: single_axis.md §4.4.3, §4.4.6, §4.4.9, §4.6, §4.7,
//! §4.12.4, §4.13, and the shell ids 0x7F01/0x7F02/0x7F03.

use axis_node::AxisNode;
use motion_msgs::action;
use motion_msgs::msg::AxisState;
use motion_msgs::srv::{self, *};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{Client, Message, ServiceMapping};
use std::path::{Path, PathBuf};
use std::time::Duration;
use system_tests::{common, drive, require_netns, send_goal, unique_domain, within, ClientNode};

const AXIS: &str =
    "{max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}";

fn config(file: &Path) -> serde_yaml::Value {
    let text = format!(
        "axes:
  m: {AXIS}
  s: {AXIS}
  m2: {AXIS}
  e: {{max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0,
       enable_pos_correction: true, backlash: 0.5}}
persistent_parameter_file: {}
",
        file.display()
    );
    serde_yaml::from_str(&text).unwrap()
}

fn start_node(domain: u16, mapping: ServiceMapping, file: &Path) -> AxisNode {
    axis_node::start(
        &common("axis_node", true, mapping),
        config(file),
        "test",
        domain,
    )
    .expect("axis node")
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

/// Creates a service client of `/axis_node/<name>` (types inferred at the use site).
async fn client<Req, Resp>(
    c: &mut ClientNode,
    name: &str,
    ty: ros2_client::ServiceTypeName,
) -> Client<Req, Resp>
where
    Req: Message + Clone + 'static,
    Resp: Message + 'static,
{
    c.client(&format!("/axis_node/{name}"), ty).await
}

struct Base {
    power: Client<PowerRequest, PowerResponse>,
    status: Client<ReadStatusRequest, ReadStatusResponse>,
    act_pos: Client<ReadActualPositionRequest, ReadActualPositionResponse>,
    outputs: Client<GetOutputsRequest, GetOutputsResponse>,
}

impl Base {
    async fn new(c: &mut ClientNode) -> Base {
        Base {
            power: client(c, "power", srv::Power::service_type_name()).await,
            status: client(c, "read_status", srv::ReadStatus::service_type_name()).await,
            act_pos: client(
                c,
                "read_actual_position",
                srv::ReadActualPosition::service_type_name(),
            )
            .await,
            outputs: client(c, "get_outputs", srv::GetOutputs::service_type_name()).await,
        }
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

    /// Waits until `axis` is at `p` (±1e-6).
    async fn until_pos(&self, axis: &str, p: f64, what: &str) {
        within(20.0, what, async {
            loop {
                let now = self.pos(axis).await;
                if (now - p).abs() < 1e-6 {
                    return;
                }
                tokio::time::sleep(Duration::from_millis(5)).await;
            }
        })
        .await
    }

    /// MC_Power with Enable; waits for Standstill and returns the MC_Power instance's id.
    async fn power_on(&self, axis: &str) -> u64 {
        let r = call(
            &self.power,
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
        within(20.0, "Standstill after MC_Power", async {
            loop {
                let s = call(
                    &self.status,
                    "read_status",
                    ReadStatusRequest { axis: axis.into() },
                )
                .await;
                if s.status.motion_state == AxisState::MC_AXISSTATE_STANDSTILL {
                    return;
                }
                tokio::time::sleep(Duration::from_millis(5)).await;
            }
        })
        .await;
        r.command_id
    }
}

fn accepted<T: std::fmt::Debug>(what: &str, ok: bool, msg: &str, r: &T) {
    assert!(ok, "{what}: {msg} {r:?}");
}

async fn scenario(mapping: ServiceMapping, file: PathBuf) {
    let _ = std::fs::remove_file(&file);
    let domain = unique_domain();
    let node = start_node(domain, mapping, &file);
    let driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "ext_client", mapping);
    let s_state = c.subscribe::<AxisState>("/axis_node/axes/s/state", AxisState::type_name());
    let b = Base::new(&mut c).await;
    for ax in ["m", "s", "m2", "e"] {
        let id = b.power_on(ax).await;
        // MC_Power's outputs by its command id (§4.1; issue 15.12).
        let o = b.out(id).await;
        assert_eq!((o.axis.as_str(), o.fb.as_str()), (ax, "MC_Power"), "{o:?}");
        assert!(
            o.status && o.valid && o.busy && o.active && !o.error,
            "{o:?}"
        );
    }

    // --- MC_GearIn s to m, then MC_PhasingRelative (action) to Done: SlavePos = s0 + ratio·Δm
    // + φ, master at rest -> s = 5 (§4.13.2).
    let gear_in: Client<GearInRequest, GearInResponse> =
        client(&mut c, "gear_in", srv::GearIn::service_type_name()).await;
    let r = call(
        &gear_in,
        "gear_in",
        GearInRequest {
            master: "m".into(),
            slave: "s".into(),
            ..Default::default()
        },
    )
    .await;
    accepted("gear_in", r.accepted, &r.message, &r);
    b.until(r.command_id, "InGear", |o| o.in_gear || o.done)
        .await;
    let rel = c
        .action::<action::PhasingRelativeGoal, action::PhasingRelativeResult, action::PhasingRelativeFeedback>(
            "/axis_node/phasing_relative",
            &action::PhasingRelative::action_type_name(),
        )
        .await;
    let goal = action::PhasingRelativeGoal {
        master: "m".into(),
        slave: "s".into(),
        phase_shift: 5.0,
        velocity: 50.0,
        ..Default::default()
    };
    let (gid, resp) = send_goal(&rel, "phasing_relative goal", goal).await;
    assert!(resp.accepted);
    let (st, res) = within(
        30.0,
        "phasing_relative result",
        rel.async_request_result(gid),
    )
    .await
    .unwrap();
    assert_eq!(st, GoalStatusEnum::Succeeded, "{res:?}");
    assert!(res.done && !res.error, "{res:?}");
    let (pm, ps) = (b.pos("m").await, b.pos("s").await);
    assert!(
        (ps - pm - 5.0).abs() < 1e-6,
        "phase offset 5: m {pm}, s {ps}"
    );

    // MC_PhasingAbsolute as a service: AbsolutePhaseShift on ~/get_outputs, s = m + 8.
    let abs: Client<PhasingAbsoluteRequest, PhasingAbsoluteResponse> = client(
        &mut c,
        "phasing_absolute",
        srv::PhasingAbsolute::service_type_name(),
    )
    .await;
    let r = call(
        &abs,
        "phasing_absolute",
        PhasingAbsoluteRequest {
            master: "m".into(),
            slave: "s".into(),
            phase_shift: 8.0,
            velocity: 50.0,
            ..Default::default()
        },
    )
    .await;
    accepted("phasing_absolute", r.accepted, &r.message, &r);
    let o = b
        .until(r.command_id, "phasing_absolute Done", |o| o.done)
        .await;
    assert_eq!(o.fb, "MC_PhasingAbsolute");
    assert_eq!(o.axis, "s");
    assert!((o.absolute_phase_shift - 8.0).abs() < 1e-9, "{o:?}");
    assert!((b.pos("s").await - b.pos("m").await - 8.0).abs() < 1e-6);
    // AbsPhasingPos in the axis state (NcToPlc of the added functions).
    within(10.0, "AbsPhasingPos 8 on ~/axes/s/state", async {
        loop {
            let (st, _) = s_state.async_take().await.unwrap();
            if (st.abs_phasing_pos - 8.0).abs() < 1e-9 {
                assert!(
                    (st.drive_set_pos - st.set_pos).abs() < 1e-9,
                    "no correction: {st:?}"
                );
                break;
            }
        }
    })
    .await;
    // Unknown slave: 0x7F01; NaN phase shift: 0x7F02; BufferMode 9: 0x7F03.
    let r = call(
        &abs,
        "phasing_absolute nope",
        PhasingAbsoluteRequest {
            master: "m".into(),
            slave: "nope".into(),
            velocity: 50.0,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F01, "{}", r.message);
    let r = call(
        &abs,
        "phasing_absolute bad buffer mode",
        PhasingAbsoluteRequest {
            master: "m".into(),
            slave: "s".into(),
            velocity: 50.0,
            buffer_mode: 9,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);

    // --- MC_PhasingUpdate on a running slow MC_PhasingAbsolute (ContinuousUpdate, to 20 at
    // 1 u/s): the new
    // shift 12 at 50 u/s ends the phasing at 12 (AbsPhasingPos on ~/axes/s/state); then
    // MC_HaltPhasing stops a phasing toward 100 short of it (CommandAborted, φ stays).
    let update: Client<PhasingUpdateRequest, PhasingUpdateResponse> = client(
        &mut c,
        "phasing_update",
        srv::PhasingUpdate::service_type_name(),
    )
    .await;
    let slow = call(
        &abs,
        "phasing_absolute slow",
        PhasingAbsoluteRequest {
            master: "m".into(),
            slave: "s".into(),
            phase_shift: 20.0,
            velocity: 1.0,
            continuous_update: true,
            ..Default::default()
        },
    )
    .await;
    accepted("phasing_absolute slow", slow.accepted, &slow.message, &slow);
    let r = call(
        &update,
        "phasing_update",
        PhasingUpdateRequest {
            command_id: slow.command_id,
            phase_shift: 12.0,
            velocity: 50.0,
            ..Default::default()
        },
    )
    .await;
    accepted("phasing_update", r.accepted, &r.message, &r);
    let o = b
        .until(slow.command_id, "updated phasing Done", |o| o.done)
        .await;
    assert!((o.absolute_phase_shift - 12.0).abs() < 1e-9, "{o:?}");
    within(10.0, "AbsPhasingPos 12", async {
        loop {
            let (st, _) = s_state.async_take().await.unwrap();
            if (st.abs_phasing_pos - 12.0).abs() < 1e-9 {
                break;
            }
        }
    })
    .await;
    let r = call(
        &update,
        "phasing_update unknown command",
        PhasingUpdateRequest {
            command_id: 999_999,
            phase_shift: 1.0,
            velocity: 50.0,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted, "{r:?}");
    let halt: Client<HaltPhasingRequest, HaltPhasingResponse> = client(
        &mut c,
        "halt_phasing",
        srv::HaltPhasing::service_type_name(),
    )
    .await;
    let far = call(
        &abs,
        "phasing_absolute far",
        PhasingAbsoluteRequest {
            master: "m".into(),
            slave: "s".into(),
            phase_shift: 100.0,
            velocity: 5.0,
            ..Default::default()
        },
    )
    .await;
    accepted("phasing_absolute far", far.accepted, &far.message, &far);
    tokio::time::sleep(Duration::from_millis(100)).await;
    let r = call(
        &halt,
        "halt_phasing",
        HaltPhasingRequest {
            master: "m".into(),
            slave: "s".into(),
            ..Default::default()
        },
    )
    .await;
    accepted("halt_phasing", r.accepted, &r.message, &r);
    b.until(far.command_id, "far phasing aborted", |o| o.command_aborted)
        .await;
    b.until(r.command_id, "halt_phasing Done", |o| o.done).await;
    let phi = within(10.0, "phasing halted", async {
        loop {
            let (st, _) = s_state.async_take().await.unwrap();
            if st.abs_phasing_pos > 12.0 && st.abs_phasing_pos < 100.0 {
                return st.abs_phasing_pos;
            }
        }
    })
    .await;
    tokio::time::sleep(Duration::from_millis(100)).await;
    let (st, _) = within(5.0, "state", s_state.async_take()).await.unwrap();
    assert!(
        st.abs_phasing_pos < 100.0 && st.abs_phasing_pos >= phi - 1e-9,
        "{st:?}"
    );

    // --- MC_SelectControlLoop, MC_SetEncoderScalingFactor, MC_WriteNcIoOutput and
    // MC_TableBasedPositionCompensation on e, with their bad inputs.
    let scl: Client<SelectControlLoopRequest, SelectControlLoopResponse> = client(
        &mut c,
        "select_control_loop",
        srv::SelectControlLoop::service_type_name(),
    )
    .await;
    let r = call(
        &scl,
        "select_control_loop",
        SelectControlLoopRequest {
            axis: "e".into(),
            select_type: 1,
            ..Default::default()
        },
    )
    .await;
    accepted("select_control_loop", r.accepted, &r.message, &r);
    b.until(r.command_id, "select_control_loop Done", |o| o.done)
        .await;
    let r = call(
        &scl,
        "select_control_loop type 9",
        SelectControlLoopRequest {
            axis: "e".into(),
            select_type: 9,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);
    let esf: Client<SetEncoderScalingFactorRequest, SetEncoderScalingFactorResponse> = client(
        &mut c,
        "set_encoder_scaling_factor",
        srv::SetEncoderScalingFactor::service_type_name(),
    )
    .await;
    let e_state = c.subscribe::<AxisState>("/axis_node/axes/e/state", AxisState::type_name());
    let r = call(
        &esf,
        "set_encoder_scaling_factor",
        SetEncoderScalingFactorRequest {
            axis: "e".into(),
            scaling_factor: 0.5,
            ..Default::default()
        },
    )
    .await;
    accepted("set_encoder_scaling_factor", r.accepted, &r.message, &r);
    b.until(r.command_id, "scaling factor Done", |o| o.done)
        .await;
    within(10.0, "encoder increments at 0.5 u/inc", async {
        loop {
            let (st, _) = e_state.async_take().await.unwrap();
            let expected = (st.act_pos / 0.5).round().rem_euclid(4_294_967_296.0) as u32;
            if st.encoder_increments == expected && st.act_pos != 0.0 {
                break;
            }
            if st.act_pos == 0.0 && st.encoder_increments == 0 {
                break;
            }
        }
    })
    .await;
    for (f, id) in [(0.0, 0x7F06u32), (f64::NAN, 0x7F02)] {
        let r = call(
            &esf,
            "set_encoder_scaling_factor bad",
            SetEncoderScalingFactorRequest {
                axis: "e".into(),
                scaling_factor: f,
                ..Default::default()
            },
        )
        .await;
        assert!(!r.accepted, "{f}");
        if id == 0x7F02 {
            assert_eq!(r.error_id, id, "{}", r.message);
        }
    }
    let io: Client<WriteNcIoOutputRequest, WriteNcIoOutputResponse> = client(
        &mut c,
        "write_nc_io_output",
        srv::WriteNcIoOutput::service_type_name(),
    )
    .await;
    let r = call(
        &io,
        "write_nc_io_output",
        WriteNcIoOutputRequest {
            axis: "e".into(),
            device: 0,
            nc_io_output: 2,
            bit_select_mask: 0xFF,
            bit_values: 0x5A,
        },
    )
    .await;
    accepted("write_nc_io_output", r.accepted, &r.message, &r);
    b.until(r.command_id, "write_nc_io_output Done", |o| o.done)
        .await;
    for (device, out) in [(5u8, 0u8), (0, 14)] {
        let r = call(
            &io,
            "write_nc_io_output bad",
            WriteNcIoOutputRequest {
                axis: "e".into(),
                device,
                nc_io_output: out,
                bit_select_mask: 1,
                bit_values: 1,
            },
        )
        .await;
        assert!(!r.accepted, "device {device} output {out}");
        assert_eq!(r.error_id, 0x7F03, "{}", r.message);
    }

    let gear_out: Client<GearOutRequest, GearOutResponse> =
        client(&mut c, "gear_out", srv::GearOut::service_type_name()).await;
    let r = call(&gear_out, "gear_out", GearOutRequest { slave: "s".into() }).await;
    accepted("gear_out", r.accepted, &r.message, &r);

    // --- MC_GearInMultiMaster (Enable-type): s follows m (ratio 1) + m2 (ratio 0.5); moving
    // m2 by 10 moves s by 5. Same command_id while enabled; Enable FALSE ends it.
    let gimm: Client<GearInMultiMasterRequest, GearInMultiMasterResponse> = client(
        &mut c,
        "gear_in_multi_master",
        srv::GearInMultiMaster::service_type_name(),
    )
    .await;
    let req = GearInMultiMasterRequest {
        slave: "s".into(),
        master1: "m".into(),
        master2: "m2".into(),
        enable: true,
        gear_ratio1: 1.0,
        gear_ratio2: 0.5,
        ..Default::default()
    };
    let r = call(&gimm, "gear_in_multi_master", req.clone()).await;
    accepted("gear_in_multi_master", r.accepted, &r.message, &r);
    let id = r.command_id;
    let o = b.until(id, "multi-master InGear", |o| o.in_gear).await;
    assert_eq!(o.fb, "MC_GearInMultiMaster");
    assert!(o.busy && !o.error, "{o:?}");
    let r = call(&gimm, "gear_in_multi_master again", req.clone()).await;
    assert!(r.accepted && r.command_id == id, "same instance {r:?}");
    let s0 = b.pos("s").await;
    let mv_rel: Client<MoveRelativeRequest, MoveRelativeResponse> = client(
        &mut c,
        "move_relative",
        srv::MoveRelative::service_type_name(),
    )
    .await;
    let r = call(
        &mv_rel,
        "move_relative m2",
        MoveRelativeRequest {
            axis: "m2".into(),
            distance: 10.0,
            velocity: 100.0,
            ..Default::default()
        },
    )
    .await;
    accepted("move_relative", r.accepted, &r.message, &r);
    b.until(r.command_id, "m2 moved", |o| o.done).await;
    b.until_pos("s", s0 + 5.0, "s follows 0.5 · m2").await;
    let r = call(
        &gimm,
        "gear_in_multi_master sync mode 3",
        GearInMultiMasterRequest {
            sync_mode: 3,
            ..req.clone()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);
    let r = call(
        &gimm,
        "gear_in_multi_master off",
        GearInMultiMasterRequest {
            enable: false,
            ..req
        },
    )
    .await;
    accepted("gear_in_multi_master off", r.accepted, &r.message, &r);
    b.until(id, "multi-master ended", |o| !o.busy).await;

    // --- External setpoint generator (§4.6) on e: enable, feed 2.0 -> e at 2.0, disable.
    let ext_en: Client<ExtSetPointGenEnableRequest, ExtSetPointGenEnableResponse> = client(
        &mut c,
        "ext_set_point_gen_enable",
        srv::ExtSetPointGenEnable::service_type_name(),
    )
    .await;
    let ext_dis: Client<ExtSetPointGenDisableRequest, ExtSetPointGenDisableResponse> = client(
        &mut c,
        "ext_set_point_gen_disable",
        srv::ExtSetPointGenDisable::service_type_name(),
    )
    .await;
    let feed: Client<ExtSetPointGenFeedRequest, ExtSetPointGenFeedResponse> = client(
        &mut c,
        "ext_set_point_gen_feed",
        srv::ExtSetPointGenFeed::service_type_name(),
    )
    .await;
    let r = call(
        &ext_en,
        "ext_set_point_gen_enable",
        ExtSetPointGenEnableRequest {
            axis: "e".into(),
            position: 2.0,
            position_type: 1,
            use_torque_offset: false,
        },
    )
    .await;
    accepted("ext_set_point_gen_enable", r.accepted, &r.message, &r);
    assert!(r.enabled);
    let o = b.until(r.command_id, "enable Done", |o| o.done).await;
    assert!(o.enabled, "{o:?}");
    let r = call(
        &feed,
        "feed",
        ExtSetPointGenFeedRequest {
            axis: "e".into(),
            position: 2.0,
            ..Default::default()
        },
    )
    .await;
    accepted("feed", r.accepted, &r.message, &r);
    b.until_pos("e", 2.0, "e at the fed position").await;
    let r = call(
        &feed,
        "feed with torque",
        ExtSetPointGenFeedRequest {
            axis: "e".into(),
            position: 2.0,
            with_torque: true,
            torque_offset: 5.0,
            ..Default::default()
        },
    )
    .await;
    accepted("feed with torque", r.accepted, &r.message, &r);
    let r = call(
        &feed,
        "feed direction 5",
        ExtSetPointGenFeedRequest {
            axis: "e".into(),
            direction: 5,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);
    let r = call(
        &ext_en,
        "ext_set_point_gen_enable nope",
        ExtSetPointGenEnableRequest {
            axis: "nope".into(),
            position_type: 1,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted && !r.enabled);
    assert_eq!(r.error_id, 0x7F01, "{}", r.message);
    let r = call(
        &ext_dis,
        "ext_set_point_gen_disable",
        ExtSetPointGenDisableRequest { axis: "e".into() },
    )
    .await;
    accepted("ext_set_point_gen_disable", r.accepted, &r.message, &r);
    assert!(!r.enabled);
    assert!((b.pos("e").await - 2.0).abs() < 1e-6);

    // --- MC_BacklashCompensation (Enable-type) on e (AxisEnablePosCorrection TRUE).
    let bl: Client<BacklashCompensationRequest, BacklashCompensationResponse> = client(
        &mut c,
        "backlash_compensation",
        srv::BacklashCompensation::service_type_name(),
    )
    .await;
    let r = call(
        &bl,
        "backlash_compensation",
        BacklashCompensationRequest {
            axis: "e".into(),
            enable: true,
            ..Default::default()
        },
    )
    .await;
    accepted("backlash_compensation", r.accepted, &r.message, &r);
    assert!(r.enabled);
    let o = b.out(r.command_id).await;
    assert_eq!(o.fb, "MC_BacklashCompensation");
    assert!(
        o.enabled && o.busy && o.current_backlash.is_finite(),
        "{o:?}"
    );
    let id = r.command_id;
    let r = call(
        &bl,
        "backlash_compensation off",
        BacklashCompensationRequest {
            axis: "e".into(),
            enable: false,
            disable_mode: 1,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted && !r.enabled, "{r:?}");
    b.until(id, "backlash ended", |o| !o.busy).await;
    // Position correction not enabled on m: 0x4B04 (MC_BacklashCompensation).
    let r = call(
        &bl,
        "backlash_compensation on m",
        BacklashCompensationRequest {
            axis: "m".into(),
            enable: true,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted && !r.enabled);
    assert_eq!(r.error_id, 0x4B04, "{}", r.message);
    let r = call(
        &bl,
        "backlash_compensation disable mode 7",
        BacklashCompensationRequest {
            axis: "e".into(),
            enable: true,
            disable_mode: 7,
            ..Default::default()
        },
    )
    .await;
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);

    // --- MC_TableBasedPositionCompensation (Enable-type) on e at 2: the table 0 → 0, 10 → 1,
    // 20 → 2 gives a correction of 0.2 (in ~/axes/e/state); a table whose length differs from
    // NoOfTableElements is refused.
    let tc: Client<TableBasedPositionCompensationRequest, TableBasedPositionCompensationResponse> =
        client(
            &mut c,
            "table_based_position_compensation",
            srv::TableBasedPositionCompensation::service_type_name(),
        )
        .await;
    let table = |n: u32| TableBasedPositionCompensationRequest {
        axis: "e".into(),
        enable: true,
        table: [0.0, 10.0, 20.0]
            .iter()
            .map(|&p| motion_msgs::msg::PositionCompensationTableElement {
                position: p,
                compensation: p / 10.0,
            })
            .collect(),
        min_position: 0.0,
        max_position: 20.0,
        no_of_table_elements: n,
        direction: 1,
        ..Default::default()
    };
    let r = call(&tc, "table compensation", table(3)).await;
    accepted("table compensation", r.accepted, &r.message, &r);
    assert!(r.enabled, "{r:?}");
    within(10.0, "correction 0.2 on e", async {
        loop {
            let (st, _) = e_state.async_take().await.unwrap();
            if (st.position_correction - 0.2).abs() < 1e-9 {
                assert!(
                    (st.drive_set_pos - (st.set_pos - 0.2)).abs() < 1e-9,
                    "{st:?}"
                );
                break;
            }
        }
    })
    .await;
    let r = call(&tc, "table compensation, wrong element count", table(4)).await;
    assert!(!r.accepted, "{r:?}");
    let r = call(
        &tc,
        "table compensation off",
        TableBasedPositionCompensationRequest {
            axis: "e".into(),
            enable: false,
            disable_mode: 1,
            ..Default::default()
        },
    )
    .await;
    assert!(r.accepted && !r.enabled, "{r:?}");

    // --- MC_ConvertPosToIncPos / IncPosToPos on m (AxisEncoderScalingFactor 0.0001, offset 0).
    let p2i: Client<ConvertPosToIncPosRequest, ConvertPosToIncPosResponse> = client(
        &mut c,
        "convert_pos_to_inc_pos",
        srv::ConvertPosToIncPos::service_type_name(),
    )
    .await;
    let i2p: Client<ConvertIncPosToPosRequest, ConvertIncPosToPosResponse> = client(
        &mut c,
        "convert_inc_pos_to_pos",
        srv::ConvertIncPosToPos::service_type_name(),
    )
    .await;
    let r = call(
        &p2i,
        "convert_pos_to_inc_pos",
        ConvertPosToIncPosRequest {
            axis: "m".into(),
            position: 1.0,
            ..Default::default()
        },
    )
    .await;
    accepted("convert_pos_to_inc_pos", r.accepted, &r.message, &r);
    assert_eq!(r.inc_pos, 10_000);
    let r = call(
        &i2p,
        "convert_inc_pos_to_pos",
        ConvertIncPosToPosRequest {
            axis: "m".into(),
            inc_pos: 10_000,
            ..Default::default()
        },
    )
    .await;
    accepted("convert_inc_pos_to_pos", r.accepted, &r.message, &r);
    assert!((r.position - 1.0).abs() < 1e-9, "{r:?}");
    let r = call(
        &p2i,
        "convert_pos_to_inc_pos NaN",
        ConvertPosToIncPosRequest {
            axis: "m".into(),
            position: f64::NAN,
            ..Default::default()
        },
    )
    .await;
    assert!(!r.accepted);
    assert_eq!(r.error_id, 0x7F02, "{}", r.message);

    // --- Reads: MC_ReadParameterSet, MC_ReadAxisComponents, MC_ReadDriveAddress, drive mode.
    let rps: Client<ReadParameterSetRequest, ReadParameterSetResponse> = client(
        &mut c,
        "read_parameter_set",
        srv::ReadParameterSet::service_type_name(),
    )
    .await;
    let r = call(
        &rps,
        "read_parameter_set",
        ReadParameterSetRequest { axis: "m".into() },
    )
    .await;
    accepted("read_parameter_set", r.accepted, &r.message, &r);
    assert_eq!(r.parameter.axis_name, "m");
    assert_eq!(r.parameter.velo_maximum, 1000.0);
    assert_eq!(r.parameter.acceleration, 10000.0);
    assert!((r.parameter.axis_cycle_time - 0.001).abs() < 1e-12);
    let r = call(
        &rps,
        "read_parameter_set nope",
        ReadParameterSetRequest {
            axis: "nope".into(),
        },
    )
    .await;
    assert_eq!(r.error_id, 0x7F01, "{}", r.message);
    let rac: Client<ReadAxisComponentsRequest, ReadAxisComponentsResponse> = client(
        &mut c,
        "read_axis_components",
        srv::ReadAxisComponents::service_type_name(),
    )
    .await;
    let r = call(
        &rac,
        "read_axis_components",
        ReadAxisComponentsRequest { axis: "m".into() },
    )
    .await;
    accepted("read_axis_components", r.accepted, &r.message, &r);
    assert!(r.encoder_ids[0] != 0, "{r:?}");
    let rda: Client<ReadDriveAddressRequest, ReadDriveAddressResponse> = client(
        &mut c,
        "read_drive_address",
        srv::ReadDriveAddress::service_type_name(),
    )
    .await;
    let r = call(
        &rda,
        "read_drive_address",
        ReadDriveAddressRequest { axis: "m".into() },
    )
    .await;
    accepted("read_drive_address", r.accepted, &r.message, &r);
    assert_eq!(r.net_id, "127.0.0.1.1.1");
    let wdm: Client<WriteDriveOperationModeRequest, WriteDriveOperationModeResponse> = client(
        &mut c,
        "write_drive_operation_mode",
        srv::WriteDriveOperationMode::service_type_name(),
    )
    .await;
    let rdm: Client<ReadDriveOperationModeRequest, ReadDriveOperationModeResponse> = client(
        &mut c,
        "read_drive_operation_mode",
        srv::ReadDriveOperationMode::service_type_name(),
    )
    .await;
    let r = call(
        &wdm,
        "write_drive_operation_mode 2",
        WriteDriveOperationModeRequest {
            axis: "m".into(),
            drive_operation_mode: 2,
        },
    )
    .await;
    accepted("write_drive_operation_mode", r.accepted, &r.message, &r);
    let r = call(
        &rdm,
        "read_drive_operation_mode",
        ReadDriveOperationModeRequest { axis: "m".into() },
    )
    .await;
    assert!(r.accepted && r.drive_operation_mode == 2, "{r:?}");
    let r = call(
        &wdm,
        "write_drive_operation_mode 7",
        WriteDriveOperationModeRequest {
            axis: "m".into(),
            drive_operation_mode: 7,
        },
    )
    .await;
    assert_eq!(r.error_id, 0x7F03, "{}", r.message);

    // --- MC_WriteParameterPersistent / MC_WriteBoolParameterPersistent: stored in the file.
    let wpp: Client<WriteParameterPersistentRequest, WriteParameterPersistentResponse> = client(
        &mut c,
        "write_parameter_persistent",
        srv::WriteParameterPersistent::service_type_name(),
    )
    .await;
    let wbpp: Client<WriteBoolParameterPersistentRequest, WriteBoolParameterPersistentResponse> =
        client(
            &mut c,
            "write_bool_parameter_persistent",
            srv::WriteBoolParameterPersistent::service_type_name(),
        )
        .await;
    let r = call(
        &wpp,
        "write_parameter_persistent",
        WriteParameterPersistentRequest {
            axis: "m".into(),
            parameter_number: 1002,
            value: 123.0,
        },
    )
    .await;
    accepted("write_parameter_persistent", r.accepted, &r.message, &r);
    let r = call(
        &wbpp,
        "write_bool_parameter_persistent",
        WriteBoolParameterPersistentRequest {
            axis: "m".into(),
            parameter_number: 1020,
            value: false,
        },
    )
    .await;
    accepted(
        "write_bool_parameter_persistent",
        r.accepted,
        &r.message,
        &r,
    );
    let lists = axis_node_persistent(&file);
    assert_eq!(lists, vec![(1002, 123.0), (1020, 0.0)], "file {file:?}");
    let r = call(
        &wpp,
        "write_parameter_persistent NaN",
        WriteParameterPersistentRequest {
            axis: "m".into(),
            parameter_number: 1002,
            value: f64::NAN,
        },
    )
    .await;
    assert_eq!(r.error_id, 0x7F02, "{}", r.message);

    drop(driver);
    drop(b);
    drop(c);
    node.stop().await;

    // A new node with the same file starts with the stored values.
    let domain = unique_domain();
    let node = start_node(domain, mapping, &file);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "ext_client2", mapping);
    let read_par: Client<ReadParameterRequest, ReadParameterResponse> = client(
        &mut c,
        "read_parameter",
        srv::ReadParameter::service_type_name(),
    )
    .await;
    let r = call(
        &read_par,
        "read_parameter 1002",
        ReadParameterRequest {
            axis: "m".into(),
            parameter_number: 1002,
        },
    )
    .await;
    assert!(r.accepted && r.value == 123.0, "{r:?}");
    let r = call(
        &read_par,
        "read_parameter 1020",
        ReadParameterRequest {
            axis: "m".into(),
            parameter_number: 1020,
        },
    )
    .await;
    assert!(r.accepted && r.is_bool && !r.bool_value, "{r:?}");
    drop(c);
    node.stop().await;
    let _ = std::fs::remove_file(&file);
}

/// The stored list of axis `m` in a persistent-parameter file.
fn axis_node_persistent(file: &Path) -> Vec<(u32, f64)> {
    let text = std::fs::read_to_string(file).expect("persistent parameter file");
    let lists: std::collections::BTreeMap<String, Vec<(u32, f64)>> =
        serde_yaml::from_str(&text).expect("yaml");
    lists.get("m").cloned().unwrap_or_default()
}

/// Both mappings in one test: DDS tests in parallel threads of one process slow discovery down.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn axis_node_extensions_over_dds_both_mappings() {
    require_netns();
    let dir = std::env::temp_dir().join(format!("axis_node_ext_dds_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    scenario(ServiceMapping::Cyclone, dir.join("cyclone.yaml")).await;
    scenario(ServiceMapping::Enhanced, dir.join("enhanced.yaml")).await;
    let _ = std::fs::remove_dir_all(&dir);
}
