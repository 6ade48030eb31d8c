//! The platform profile's safety and simulation services (plcopen_platform.md §8, §12.1):
//! `~/safety/deactivate`, `~/safety/operating_mode`, `~/safety/enabling_switch`,
//! `~/safety/start_button`, `~/sim/inject_mc_message`, `~/sim/inject_actual_velocity`,
//! `~/sim/torque_limit`, `~/sim/set_referenced`, `~/platform/versions`, and the topic
//! `~/platform/status` (`motion_msgs/PlatformStatus`).

use crate::services::{label, respond};
use axis_engine::platform::{OperatingMode, PlatformReply, PlatformStatus, SafetyFunction};
use axis_engine::{AxisCommand, AxisEngine, PlatformCommand, PlatformProfile, ReplyValue};
use motion_core::Rejection;
use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::msg::{PlatformAxisStatus, PlatformMcMessage};
use motion_msgs::srv::*;
use motion_runtime::shell::{header, stamp};
use motion_runtime::{CommandLabel, NodeShell, ShellError};

type Decoded = Result<(AxisCommand, CommandLabel), Rejection>;

fn platform(object: &str, command: &str, c: PlatformCommand) -> Decoded {
    Ok((AxisCommand::Platform(c), label(object, command)))
}

/// The platform state as `motion_msgs/PlatformStatus`.
pub fn platform_status(p: &PlatformStatus, stamp: Time) -> motion_msgs::msg::PlatformStatus {
    motion_msgs::msg::PlatformStatus {
        header: header(stamp),
        profile: match p.profile {
            PlatformProfile::Tc2Mc2 => motion_msgs::msg::PlatformStatus::PROFILE_TC2_MC2,
            PlatformProfile::IsgMcp => motion_msgs::msg::PlatformStatus::PROFILE_ISG_MCP,
        },
        hli_initialized: p.hli_initialized,
        platform_base_done: p.platform_base_done,
        init_cycles: p.init_cycles,
        version_mismatch: p.version_mismatch,
        errors: p.errors.iter().map(|e| e.0).collect(),
        clog_warnings: p.clog_warnings as u64,
        g_order_id: p.g_order_id,
        operating_mode: p.operating_mode as u8,
        enabling_switch: p.enabling_switch,
        start_button: p.start_button,
        axes: p
            .axes
            .iter()
            .map(|a| PlatformAxisStatus {
                name: a.name.clone(),
                referenced: a.referenced,
                velocity_monitoring: a.velocity_monitoring,
                torque_limit_monitoring: a.torque_limit_monitoring,
                torque_limiting: a.torque_limiting,
                velocity_limit: a.velocity_limit,
                drive_enabled: a.drive_enabled,
                feed_hold: a.feed_hold,
                messages: a
                    .messages
                    .iter()
                    .map(|m| PlatformMcMessage {
                        error_id: m.error_id,
                        cycle: m.cycle,
                        behebungs_klasse: m.behebungs_klasse,
                        reaktions_klasse: m.reaktions_klasse,
                    })
                    .collect(),
            })
            .collect(),
    }
}

fn decode_deactivate(r: SafetyDeactivateRequest) -> Decoded {
    let function = SafetyFunction::from_raw(u32::from(r.function))?;
    platform(
        &r.axis.clone(),
        "safety/deactivate",
        PlatformCommand::SafetyDeactivate {
            axis: r.axis,
            function,
            lease_cycles: r.lease_cycles,
        },
    )
}

fn decode_operating_mode(r: SafetyOperatingModeRequest) -> Decoded {
    let mode = OperatingMode::from_raw(u32::from(r.mode))?;
    platform(
        "",
        "safety/operating_mode",
        PlatformCommand::OperatingMode { mode },
    )
}

fn decode_enabling_switch(r: SafetyButtonRequest) -> Decoded {
    platform(
        "",
        "safety/enabling_switch",
        PlatformCommand::EnablingSwitch { pressed: r.pressed },
    )
}

fn decode_start_button(r: SafetyButtonRequest) -> Decoded {
    platform(
        "",
        "safety/start_button",
        PlatformCommand::StartButton { pressed: r.pressed },
    )
}

fn decode_inject_mc_message(r: PlatformInjectMcMessageRequest) -> Decoded {
    platform(
        &r.axis.clone(),
        "sim/inject_mc_message",
        PlatformCommand::InjectMcMessage {
            axis: r.axis,
            error_id: r.error_id,
            behebungs_klasse: r.behebungs_klasse,
            reaktions_klasse: r.reaktions_klasse,
        },
    )
}

fn decode_inject_actual_velocity(r: PlatformInjectActualVelocityRequest) -> Decoded {
    if !r.velocity.is_finite() {
        return Err(Rejection::not_finite(
            &format!("axis '{}': inject_actual_velocity", r.axis),
            "velocity",
            r.velocity,
        ));
    }
    platform(
        &r.axis.clone(),
        "sim/inject_actual_velocity",
        PlatformCommand::InjectActualVelocity {
            axis: r.axis,
            velocity: r.velocity,
            duration_cycles: r.duration_cycles,
        },
    )
}

fn decode_torque_limit(r: PlatformTorqueLimitRequest) -> Decoded {
    platform(
        &r.axis.clone(),
        "sim/torque_limit",
        PlatformCommand::TorqueLimit {
            axis: r.axis,
            active: r.active,
        },
    )
}

fn decode_set_referenced(r: PlatformSetReferencedRequest) -> Decoded {
    platform(
        &r.axis.clone(),
        "sim/set_referenced",
        PlatformCommand::SetReferenced {
            axis: r.axis,
            referenced: r.referenced,
        },
    )
}

fn decode_versions(_r: PlatformVersionsRequest) -> Decoded {
    platform("", "platform/versions", PlatformCommand::ReadVersions)
}

fn respond_versions(o: crate::services::Outcome) -> PlatformVersionsResponse {
    let v = match &o {
        Ok(r) => match &r.value {
            ReplyValue::Platform(PlatformReply::Versions(v)) => Some(v.clone()),
            _ => None,
        },
        Err(_) => None,
    };
    let base: PlatformVersionsResponse = respond(o);
    match v {
        Some(v) => PlatformVersionsResponse {
            hli_version: v.hli_version,
            hli_size: v.hli_size,
            mcp_base: v.mcp_base,
            mcp_plcopen_p1: v.mcp_plcopen_p1,
            mcp_plcopen_p4: v.mcp_plcopen_p4,
            node_version: v.node_version,
            msgs_interface_hash: motion_msgs::INTERFACE_HASH,
            ..base
        },
        None => base,
    }
}

pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    shell.command_service(
        "safety/deactivate",
        SafetyDeactivate::service_type_name(),
        decode_deactivate,
        respond::<SafetyDeactivateResponse>,
    )?;
    shell.command_service(
        "safety/operating_mode",
        SafetyOperatingMode::service_type_name(),
        decode_operating_mode,
        respond::<SafetyOperatingModeResponse>,
    )?;
    shell.command_service(
        "safety/enabling_switch",
        SafetyButton::service_type_name(),
        decode_enabling_switch,
        respond::<SafetyButtonResponse>,
    )?;
    shell.command_service(
        "safety/start_button",
        SafetyButton::service_type_name(),
        decode_start_button,
        respond::<SafetyButtonResponse>,
    )?;
    shell.command_service(
        "sim/inject_mc_message",
        PlatformInjectMcMessage::service_type_name(),
        decode_inject_mc_message,
        respond::<PlatformInjectMcMessageResponse>,
    )?;
    shell.command_service(
        "sim/inject_actual_velocity",
        PlatformInjectActualVelocity::service_type_name(),
        decode_inject_actual_velocity,
        respond::<PlatformInjectActualVelocityResponse>,
    )?;
    shell.command_service(
        "sim/torque_limit",
        PlatformTorqueLimit::service_type_name(),
        decode_torque_limit,
        respond::<PlatformTorqueLimitResponse>,
    )?;
    shell.command_service(
        "sim/set_referenced",
        PlatformSetReferenced::service_type_name(),
        decode_set_referenced,
        respond::<PlatformSetReferencedResponse>,
    )?;
    shell.command_service(
        "platform/versions",
        PlatformVersions::service_type_name(),
        decode_versions,
        respond_versions,
    )?;
    shell.state_publisher(
        "~/platform/status",
        motion_msgs::msg::PlatformStatus::type_name(),
        |s| platform_status(&s.state.platform, stamp(s)),
    )
}
