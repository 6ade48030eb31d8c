//! `~/jog`: MC_Jog's level-held buttons (single_axis.md §4.11). The node holds one MC_Jog
//! instance per axis, as a PLC program wires one instance to its push-buttons; each call sets
//! the levels of JogForward/JogBackwards:
//! - a rising level starts a motion with a fresh instance, but only while the held instance is
//!   not Busy ("during a motion no other edges are accepted"): otherwise the edge is ignored
//!   (accepted, message says so, command_id = the busy instance);
//! - the level that started the motion going FALSE releases the button (Execute falling of the
//!   instance): continuous modes decelerate and report Done at rest.

use crate::services::respond;
use axis_engine::{AxisCommand, AxisEngine, AxisReply, JogMode, ReplyValue};
use motion_core::{CmdId, Rejection};
use motion_msgs::srv::{Jog, JogRequest, JogResponse};
use motion_runtime::{ControllerHandle, NodeShell, ShellError};
use std::collections::HashMap;
use std::sync::Arc;

/// The button levels and the instance of one axis.
#[derive(Clone, Copy, Debug, Default)]
struct Buttons {
    forward: bool,
    backwards: bool,
    /// The latest admitted instance and whether JogForward started it.
    instance: Option<(CmdId, bool)>,
}

async fn busy(handle: &ControllerHandle<AxisEngine>, id: CmdId) -> bool {
    match handle.call(AxisCommand::ReadFbOutputs { id }).await {
        Ok(AxisReply {
            value: ReplyValue::Outputs(o),
            ..
        }) => o.outputs.standard.busy,
        _ => false,
    }
}

async fn call(
    handle: &ControllerHandle<AxisEngine>,
    held: &mut HashMap<String, Buttons>,
    r: JogRequest,
) -> JogResponse {
    let mode = match JogMode::from_raw(u32::from(r.mode)) {
        Ok(m) => m,
        Err(e) => return respond(Err(e)),
    };
    if handle.snapshot().state.axis(&r.axis).is_none() {
        return respond(Err(Rejection::unknown_object("axis", &r.axis)));
    }
    let prev = held.get(&r.axis).copied().unwrap_or_default();
    let mut next = Buttons {
        forward: r.jog_forward,
        backwards: r.jog_backwards,
        instance: prev.instance,
    };
    // Release: the button that started the held instance went FALSE.
    if let Some((id, fwd)) = prev.instance {
        let released = if fwd {
            prev.forward && !r.jog_forward
        } else {
            prev.backwards && !r.jog_backwards
        };
        if released {
            if let Err(e) = handle
                .call(AxisCommand::SetExecute { id, execute: false })
                .await
            {
                tracing::debug!("jog release of {}: {e}", id.0);
            }
        }
    }
    let rise_fwd = r.jog_forward && !prev.forward;
    let rise_bwd = r.jog_backwards && !prev.backwards;
    let outcome = if !(rise_fwd || rise_bwd) {
        // No edge: only levels changed (or nothing).
        Ok(AxisReply {
            id: prev.instance.map_or(CmdId(0), |(id, _)| id),
            value: ReplyValue::None,
            tracked: false,
        })
    } else {
        if let Some((id, _)) = prev.instance {
            if busy(handle, id).await {
                held.insert(r.axis.clone(), next);
                let mut resp: JogResponse = respond(Ok(AxisReply {
                    id,
                    value: ReplyValue::None,
                    tracked: false,
                }));
                resp.message = format!("MC_Jog of axis '{}' is Busy: edge ignored (§4.11)", r.axis);
                return resp;
            }
        }
        start(handle, &r, mode, rise_fwd, rise_bwd, &mut next).await
    };
    held.insert(r.axis.clone(), next);
    respond(outcome)
}

/// A fresh MC_Jog instance with these button edges (the `~/jog` action's goal converts into
/// the request).
pub(crate) fn jog_fb(r: &JogRequest, mode: JogMode, forward: bool, backwards: bool) -> AxisCommand {
    AxisCommand::Jog(axis_engine::Jog {
        axis: r.axis.clone(),
        jog_forward: forward,
        jog_backwards: backwards,
        mode,
        position: r.position,
        velocity: r.velocity,
        acceleration: r.acceleration,
        deceleration: r.deceleration,
        jerk: r.jerk,
    })
}

async fn start(
    handle: &ControllerHandle<AxisEngine>,
    r: &JogRequest,
    mode: JogMode,
    rise_fwd: bool,
    rise_bwd: bool,
    next: &mut Buttons,
) -> Result<AxisReply, Rejection> {
    let label = crate::services::label(&r.axis, "jog");
    let o = handle
        .call_labeled(jog_fb(r, mode, rise_fwd, rise_bwd), label)
        .await;
    if let Ok(reply) = &o {
        // Forward wins on simultaneous edges (§4.11).
        next.instance = Some((reply.id, rise_fwd));
    }
    o
}

pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    let handle = shell.handle.clone();
    // One call at a time: the levels of a call depend on the previous one.
    let held: Arc<tokio::sync::Mutex<HashMap<String, Buttons>>> = Arc::default();
    shell.service::<JogRequest, JogResponse, _, _>(
        "jog",
        Jog::service_type_name(),
        move |r: JogRequest| {
            let handle = handle.clone();
            let held = held.clone();
            async move {
                let mut held = held.lock().await;
                call(&handle, &mut held, r).await
            }
        },
    )
}
