//! `~/fb/cycle` (plcopen_platform.md §12.2): the raw FB layer over ROS. One request = one PLC
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
use motion_msgs::srv::{FbCycle, FbCycleRequest, FbCycleResponse};
use motion_runtime::{ControllerHandle, NodeShell, ShellError};

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
            let fb: AxisCommand = serde_json::from_str(&c.fb).map_err(|e| {
                Rejection::new(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("calls[{k}] ({}): fb is not an FB call: {e}", c.instance),
                )
            })?;
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
    let done = handle
        .cycle_with(move |e: &mut AxisEngine, tick, events| {
            let outs = e.fb_cycle(tick, &calls, events);
            let t = (tick.index + 1) as f64 * tick.dt;
            let axes = motion_core::Engine::snapshot(e)
                .axes
                .iter()
                .map(|a| axis_state(a, t))
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

/// Registers `~/fb/cycle`.
pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    let handle = shell.handle.clone();
    shell.service::<FbCycleRequest, FbCycleResponse, _, _>(
        "fb/cycle",
        FbCycle::service_type_name(),
        move |req| {
            let handle = handle.clone();
            async move { answer(&handle, req).await }
        },
    )
}
