//! `~/fb/cycle` (plcopen_platform.md §12.2) and `~/submit_batch` (§12.1), both one cycle run
//! by the runtime's custom cycle. `~/fb/cycle` is the raw FB layer over ROS. One request = one PLC
//! cycle: the listed FB instances are called in order with their inputs, then the MC runs the
//! cycle (the runtime's custom cycle, so it replaces exactly one plain cycle; in lockstep mode
//! the request runs it). The request carries `msgs_interface_hash` (R-VER-1): another value
//! than this node's is refused with 4904. Each call's FB is the engine's FB call as JSON, in
//! its serde form (e.g. `{"MoveRelative": {"axis": "x", ...}}`).

use crate::convert::axis_state;
use axis_engine::platform::ids::ERR_SIM_VERSION_MISMATCH;
use axis_engine::platform::raw::{FbCall as RawCall, FbOut as RawOut, FbState};
use axis_engine::{AxisCommand, AxisEngine};
use motion_core::{ErrorId, Rejection};
use motion_msgs::msg::FbOut;
use motion_msgs::srv::{
    FbCycle, FbCycleRequest, FbCycleResponse, SubmitBatch, SubmitBatchRequest, SubmitBatchResponse,
};
use motion_runtime::shell::stamp_ns;
use motion_runtime::{CommandLabel, ControllerHandle, NodeShell, ShellError};
use std::sync::Arc;

/// An FB call from its JSON text (the engine's serde form `{"<Fb>": {...}}`) and the FB's
/// name (`<Fb>`); `what` names it in errors.
fn fb_from_json(text: &str, what: &str) -> Result<(AxisCommand, String), Rejection> {
    let bad = |e: serde_json::Error| {
        Rejection::new(
            ErrorId::VALUE_OUT_OF_RANGE,
            format!("{what}: not an FB call: {e}"),
        )
    };
    let v: serde_json::Value = serde_json::from_str(text).map_err(bad)?;
    let name = v
        .as_object()
        .and_then(|o| o.keys().next().cloned())
        .unwrap_or_default();
    Ok((serde_json::from_value(v).map_err(bad)?, name))
}

/// `~/command_status` label of a batch order: its axis or group and the FB (`name`, as in
/// the JSON) in snake_case.
fn batch_label(name: &str, cmd: &AxisCommand) -> CommandLabel {
    let command = motion_runtime::shell::snake_case(name);
    let object = match cmd {
        AxisCommand::Group(g) => g.group().to_string(),
        c => c.axis().unwrap_or_default().to_string(),
    };
    CommandLabel { object, command }
}

/// The raw calls of a request, or the first bad one.
fn decode(req: &FbCycleRequest) -> Result<Vec<RawCall>, Rejection> {
    if req.interface_hash != motion_msgs::INTERFACE_HASH {
        return Err(Rejection::new(
            ERR_SIM_VERSION_MISMATCH,
            format!(
                "interface_hash 0x{:08X} is not this node's msgs_interface_hash 0x{:08X} (R-VER-1)",
                req.interface_hash,
                motion_msgs::INTERFACE_HASH
            ),
        ));
    }
    req.calls
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let (fb, _) = fb_from_json(&c.fb, &format!("calls[{k}] ({}): fb", c.instance))?;
            if c.instance.is_empty() {
                return Err(Rejection::new(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("calls[{k}]: instance is empty"),
                ));
            }
            Ok(RawCall {
                instance: c.instance.clone(),
                execute: c.execute,
                fb,
            })
        })
        .collect()
}

fn out_msg(o: RawOut) -> FbOut {
    FbOut {
        instance: o.instance,
        done: o.done,
        busy: o.busy,
        active: o.active,
        command_aborted: o.command_aborted,
        error: o.error,
        error_id: o.error_id.0,
        in_velocity: o.in_velocity,
        order_id: o.order_id,
        in_flight: o.in_flight,
        fb_state: match o.fb_state {
            FbState::Idle => FbOut::FB_IDLE,
            FbState::Active => FbOut::FB_ACTIVE,
            FbState::Error => FbOut::FB_ERROR,
        },
    }
}

async fn answer(handle: &ControllerHandle<AxisEngine>, req: FbCycleRequest) -> FbCycleResponse {
    let refused = |r: Rejection| FbCycleResponse {
        accepted: false,
        error_id: r.error_id.0,
        message: r.message,
        ..FbCycleResponse::default()
    };
    let calls = match decode(&req) {
        Ok(c) => c,
        Err(r) => return refused(r),
    };
    let clock = handle.clock().clone();
    let done = handle
        .cycle_with(move |e: &mut AxisEngine, tick, events| {
            let outs = e.fb_cycle(tick, &calls, events);
            let t = stamp_ns(clock.at((tick.index + 1) as f64 * tick.dt));
            let axes = motion_core::Engine::snapshot(e)
                .axes
                .iter()
                .map(|a| axis_state(a, t.clone()))
                .collect();
            (outs, tick.index + 1, axes)
        })
        .await;
    match done {
        Ok((outs, cycle, axes)) => FbCycleResponse {
            accepted: true,
            outputs: outs.into_iter().map(out_msg).collect(),
            cycle,
            axes,
            ..FbCycleResponse::default()
        },
        Err(r) => refused(r),
    }
}

async fn batch(
    handle: &ControllerHandle<AxisEngine>,
    labels: Arc<motion_runtime::shell::CommandRegistry>,
    req: SubmitBatchRequest,
) -> SubmitBatchResponse {
    let refused = |r: Rejection| SubmitBatchResponse {
        accepted: false,
        error_id: r.error_id.0,
        message: r.message,
        ..SubmitBatchResponse::default()
    };
    let decoded: Result<Vec<(AxisCommand, CommandLabel)>, Rejection> = req
        .orders
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let (c, name) = fb_from_json(t, &format!("orders[{k}]"))?;
            let l = batch_label(&name, &c);
            Ok((c, l))
        })
        .collect();
    let orders = match decoded {
        Ok(o) => o,
        Err(r) => return refused(r),
    };
    let ran = handle
        .cycle_with(move |e: &mut AxisEngine, tick, events| {
            use motion_core::Engine;
            let results: Vec<Result<Option<motion_core::CmdId>, Rejection>> = orders
                .into_iter()
                .map(|(cmd, label)| {
                    let r = e.command(cmd)?;
                    let id = AxisEngine::reply_id(&r);
                    if let Some(id) = id {
                        labels.insert(id, label);
                    }
                    Ok(id)
                })
                .collect();
            e.step(tick, events);
            results
        })
        .await;
    match ran {
        Ok(results) => {
            let mut r = SubmitBatchResponse {
                accepted: true,
                ..SubmitBatchResponse::default()
            };
            for x in results {
                r.order_accepted.push(x.is_ok());
                match x {
                    Ok(id) => {
                        r.command_ids.push(id.map_or(0, |i| i.0));
                        r.error_ids.push(0);
                        r.messages.push(String::new());
                    }
                    Err(e) => {
                        r.command_ids.push(0);
                        r.error_ids.push(e.error_id.0);
                        r.messages.push(e.message);
                    }
                }
            }
            r
        }
        Err(r) => refused(r),
    }
}

/// Registers `~/fb/cycle` and `~/submit_batch`.
pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    let handle = shell.handle.clone();
    shell.service::<FbCycleRequest, FbCycleResponse, _, _>(
        "fb/cycle",
        FbCycle::service_type_name(),
        move |req| {
            let handle = handle.clone();
            async move { answer(&handle, req).await }
        },
    )?;
    let handle = shell.handle.clone();
    let labels = shell.registry.clone();
    shell.service::<SubmitBatchRequest, SubmitBatchResponse, _, _>(
        "submit_batch",
        SubmitBatch::service_type_name(),
        move |req| {
            let (handle, labels) = (handle.clone(), labels.clone());
            async move { batch(&handle, labels, req).await }
        },
    )
}
