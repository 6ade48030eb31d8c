//! The profile hooks around the Tc2_MC2 engine: screening before a single-axis FB call
//! (`platform_pre`), bookkeeping after it (`platform_post`), one part of the cycle before and
//! one after the axes (`platform_step_pre`, `platform_step_post`). In `tc2_mc2` without
//! `safety_monitors` every hook returns at once.

use super::ids::*;
use super::*;
use crate::axis::Axis;
use crate::command::*;
use crate::engine::AxisEngine;
use crate::handshake::Handshake;
use motion_core::{CommandEvent, CommandState, Rejection};

fn reject(id: ErrorId, msg: String) -> Rejection {
    Rejection::new(id, msg)
}

/// Does the FB place an order in the axis' order slot (§6.2)? Reads, MC_Power, MC_SetOverride,
/// simulation hooks and instance updates do not.
fn places_order(cmd: &AxisCommand) -> bool {
    use AxisCommand::*;
    !matches!(
        cmd,
        Power(_)
            | SetOverride(_)
            | ReadParameter(_)
            | ReadBoolParameter(_)
            | ReadStatus(_)
            | ReadActualPosition(_)
            | ReadActualVelocity(_)
            | ReadAxisError(_)
            | Sim(_)
            | SetExecute { .. }
            | ReadFbOutputs { .. }
            | HomeCalibrationCam { .. }
            | TouchProbePlcEvent { .. }
            | TorqueControlUpdate { .. }
    )
}

/// FBs of §3.1 marked * or not in the ISG catalogue (→ 4905 in `isg_mcp`).
fn not_in_catalogue(cmd: &AxisCommand) -> Option<&'static str> {
    use AxisCommand::*;
    Some(match cmd {
        ReadBoolParameter(_) => "MC_ReadBoolParameter",
        WriteBoolParameter(_) => "MC_WriteBoolParameter",
        TorqueControl(_) | TorqueControlUpdate { .. } => "MC_TorqueControl",
        MoveContinuousAbsolute(_) => "MC_MoveContinuousAbsolute",
        MoveContinuousRelative(_) => "MC_MoveContinuousRelative",
        ReadActualVelocity(_) => "MC_ReadActualVelocity",
        Jog(_) => "MC_Jog",
        MoveModulo(_) => "MC_MoveModulo",
        GearInDyn(_) => "MC_GearInDyn",
        AbortSuperposition(_) => "MC_AbortSuperposition",
        // Phasing, multi-master gearing, external set points, §4.7 extensions: Tc2_MC2 only.
        c if crate::engine::is_axis3(c) => "this Tc2_MC2 extension FB",
        _ => return None,
    })
}

/// The commanded velocity of a move FB.
fn velocity_of(cmd: &mut AxisCommand) -> Option<&mut f64> {
    use AxisCommand::*;
    Some(match cmd {
        MoveAbsolute(c) => &mut c.velocity,
        MoveRelative(c) => &mut c.velocity,
        MoveAdditive(c) => &mut c.velocity,
        MoveModulo(c) => &mut c.velocity,
        MoveVelocity(c) => &mut c.velocity,
        MoveContinuousAbsolute(c) => &mut c.velocity,
        MoveContinuousRelative(c) => &mut c.velocity,
        _ => return None,
    })
}

/// ISG has no BufferMode: every new command aborts (§14).
fn force_aborting(cmd: &mut AxisCommand) {
    use AxisCommand::*;
    let m = match cmd {
        MoveAbsolute(c) => &mut c.buffer_mode,
        MoveRelative(c) => &mut c.buffer_mode,
        MoveAdditive(c) => &mut c.buffer_mode,
        MoveModulo(c) => &mut c.buffer_mode,
        MoveVelocity(c) => &mut c.buffer_mode,
        Halt(c) => &mut c.buffer_mode,
        Home(c) => &mut c.buffer_mode,
        GearIn(c) => &mut c.buffer_mode,
        _ => return,
    };
    *m = BufferMode::Aborting;
}

/// `isg_mcp` FB-level ids (§7.3): state rejections → 4901, parameter errors → 4902.
fn isg_id(id: ErrorId) -> ErrorId {
    use crate::error_ids::*;
    match id {
        AXIS_CANNOT_BE_STARTED | AXIS_NOT_MOVING | COMMAND_NOT_PERMITTED => {
            ERR_SIM_TRANSITION_NOT_ALLOWED
        }
        INVALID_MODE | PARAMETER_NOT_CORRECT | BUFFER_FULL | BLENDING_POSITION_INVALID => {
            ERR_SIM_INVALID_PARAMETER
        }
        other => other,
    }
}

impl AxisEngine {
    /// Builds the platform state from the engine config (per-axis keys must name axes).
    pub(crate) fn build_platform(&mut self, cfg: &EngineConfig) -> Result<(), Rejection> {
        for (name, a) in &cfg.platform.axes {
            if !self.set.index.contains_key(name) {
                return Err(Rejection::unknown_object("axis", name));
            }
            for (key, v) in [
                ("units_per_mm", a.units_per_mm),
                ("units_per_deg", a.units_per_deg),
                ("vb_not_referenced", a.vb_not_referenced),
                ("vb_torq_limit_max", a.vb_torq_limit_max),
                ("vb_monitor", a.vb_monitor),
                ("a_limit", a.a_limit),
            ] {
                if !v.is_finite() {
                    return Err(Rejection::not_finite(
                        &format!("axis '{name}': platform config"),
                        key,
                        v,
                    ));
                }
                if v < 0.0 || (v == 0.0 && key != "vb_monitor" && key != "a_limit") {
                    return Err(reject(
                        ErrorId::VALUE_OUT_OF_RANGE,
                        format!("axis '{name}': platform config key {key} = {v} must be > 0"),
                    ));
                }
            }
        }
        let p = &mut self.platform;
        p.profile = cfg.platform_profile;
        p.cfg = cfg.platform.clone();
        p.g_order_id = cfg.platform.g_order_id;
        p.axes = self
            .set
            .axes
            .iter()
            .map(|a| {
                let c = cfg.platform.axes.get(&a.name).cloned().unwrap_or_default();
                AxisPlatform {
                    referenced: c.referenced,
                    cfg: c,
                    ..AxisPlatform::default()
                }
            })
            .collect();
        for ax in 0..self.set.axes.len() {
            self.sync_soft_limits(ax);
            use crate::axis::TravelLimits;
            self.set.axes[ax].travel_limits =
                match (self.platform.isg(), self.platform.axes[ax].cfg.modulo) {
                    (false, _) => TravelLimits::Planned,
                    (true, false) => TravelLimits::Monitored,
                    (true, true) => TravelLimits::Off,
                };
        }
        if self.platform.isg() {
            let modulo = self.platform.axes.iter().map(|p| p.cfg.modulo).collect();
            let rules = super::axis_rules::IsgAxisRules { modulo };
            self.set.set_profile(Box::new(rules));
        }
        Ok(())
    }

    /// R-SAF-6: software limits are not monitored on a non-referenced axis; the configured
    /// enables come back when it is referenced again.
    pub(crate) fn sync_soft_limits(&mut self, ax: usize) {
        if !self.platform.safety() {
            return;
        }
        let p = &mut self.platform.axes[ax];
        let c = &mut self.set.axes[ax].cfg;
        match (p.referenced, p.soft_limits) {
            (false, None) => {
                p.soft_limits = Some((c.en_min_soft_pos_limit, c.en_max_soft_pos_limit));
                c.en_min_soft_pos_limit = false;
                c.en_max_soft_pos_limit = false;
            }
            (true, Some((lo, hi))) => {
                p.soft_limits = None;
                c.en_min_soft_pos_limit = lo;
                c.en_max_soft_pos_limit = hi;
            }
            _ => {}
        }
    }

    /// Screening of a single-axis FB call before the Tc2_MC2 logic (may change the call:
    /// BufferMode, velocity clamps).
    pub(crate) fn platform_pre(
        &mut self,
        ax: usize,
        cmd: &mut AxisCommand,
    ) -> Result<(), Rejection> {
        let name = self.set.axes[ax].name.clone();
        let isg = self.platform.isg();
        let order = places_order(cmd);
        if isg {
            if let Some(fb) = not_in_catalogue(cmd) {
                return Err(reject(
                    ERR_SIM_NOT_IMPLEMENTED,
                    format!("axis '{name}': {fb} is not implemented by the ISG platform (§3.1)"),
                ));
            }
            let read =
                !order && !matches!(cmd, AxisCommand::Power(_) | AxisCommand::SetOverride(_));
            if self.platform.version_mismatch && !matches!(cmd, AxisCommand::Sim(_)) {
                return Err(reject(
                    ERR_SIM_VERSION_MISMATCH,
                    format!("axis '{name}': HLI version/size of the client and the node differ (R-SAF-2)"),
                ));
            }
            if self.platform.starting() && !read {
                return Err(reject(
                    ERR_PO_AX_TNA_INIT_STATE,
                    format!(
                        "axis '{name}': order during start-up (cycle {} of {}, §9)",
                        self.platform.cycles, self.platform.cfg.nr_cycles_chk_mc_runs
                    ),
                ));
            }
            // §7.2: instances of an axis in ERROR_STOP show ErrorID 1 (E6: also an enabled
            // MC_ReadActualPosition).
            if matches!(cmd, AxisCommand::ReadActualPosition(_))
                && !self.set.axes[ax].error_id.is_none()
            {
                return Err(reject(
                    ERR_PLC_AX_MC,
                    format!(
                        "axis '{name}': in ERROR_STOP (MC error {})",
                        self.set.axes[ax].error_id.0
                    ),
                ));
            }
            force_aborting(cmd);
        }
        if self.platform.safety() {
            // Motion FBs (R-SAF-6: only MoveRelative, MoveVelocity, Home, Stop, Halt on a
            // non-referenced axis).
            let fb = cmd.motion_fb_name();
            let p = &self.platform.axes[ax];
            // R-SAF-5: in T1/T2 orders need the enabling switch.
            let stopping = matches!(cmd, AxisCommand::Stop(_) | AxisCommand::Halt(_));
            if fb.is_some()
                && !stopping
                && self.platform.mode != OperatingMode::Auto
                && !self.platform.enabling_switch
            {
                return Err(reject(
                    ERR_SIM_TRANSITION_NOT_ALLOWED,
                    format!(
                        "axis '{name}': {} in {:?} needs the enabling switch (R-SAF-5)",
                        fb.unwrap_or(""),
                        self.platform.mode
                    ),
                ));
            }
            // R-SAF-6: non-referenced axes.
            if !p.referenced {
                if let Some(fb) = fb {
                    let allowed = matches!(
                        cmd,
                        AxisCommand::MoveRelative(_)
                            | AxisCommand::MoveVelocity(_)
                            | AxisCommand::Home(_)
                            | AxisCommand::Stop(_)
                            | AxisCommand::Halt(_)
                            | AxisCommand::SetPosition(_)
                    );
                    if !allowed {
                        return Err(reject(
                            ERR_SIM_AXIS_NOT_REFERENCED,
                            format!("axis '{name}': {fb} needs a referenced axis (R-SAF-6)"),
                        ));
                    }
                }
                let vb = p.cfg.vb_not_referenced;
                if let Some(v) = velocity_of(cmd) {
                    *v = v.min(vb);
                }
            }
            // R-SAF-5: T1 clamps the commanded velocity.
            if self.platform.mode == OperatingMode::T1 {
                let lim = p.t1_limit();
                if let Some(v) = velocity_of(cmd) {
                    *v = v.min(lim);
                }
            }
            // R-SAF-1a: the SAI refuses a programmed velocity above the monitoring limit.
            let limit = p.velocity_limit();
            let active = p.velocity_lease == 0;
            if let Some(v) = velocity_of(cmd).map(|v| *v) {
                if active && v.is_finite() && v > limit {
                    self.mc_message(ax, MC_PROGRAMMED_VELOCITY_EXCEEDS_LIMIT.0, 1, 1);
                    return Err(reject(
                        ERR_PLC_AX_MC,
                        format!("axis '{name}': MC error 60241: programmed velocity {v} exceeds the monitoring limit {limit} (R-SAF-1)"),
                    ));
                }
            }
        }
        if isg && order {
            // R-HS-3/R-HS-4: one order per axis and cycle; MC_Stop overwrites.
            if let Some((prev, _)) = self.platform.axes[ax].slot {
                if !matches!(cmd, AxisCommand::Stop(_)) {
                    return Err(reject(
                        FB_ERR_MC_DID_NOT_TAKE_ORDER,
                        format!(
                            "axis '{name}': the order slot is already used in this cycle (R-HS-3)"
                        ),
                    ));
                }
                // The overwritten order is aborted (the stop ends it with CommandAborted).
                let _ = prev;
            }
        }
        Ok(())
    }

    /// Bookkeeping after a single-axis FB call: `isg_mcp` error ids, order slot and number,
    /// MC_Home tracking, MC_Reset clearing the message buffer.
    pub(crate) fn platform_post(
        &mut self,
        ax: usize,
        order: bool,
        kind: PostKind,
        res: Result<AxisReply, Rejection>,
    ) -> Result<AxisReply, Rejection> {
        let isg = self.platform.isg();
        match res {
            Err(mut r) => {
                if isg {
                    r.error_id = isg_id(r.error_id);
                }
                Err(r)
            }
            Ok(reply) => {
                if isg && order {
                    if self.platform.order_ids.len() > 4096 {
                        let (fbs, groups) = (&self.set.fbs, &self.groups);
                        self.platform.order_ids.retain(|id, _| {
                            fbs.get(*id).is_some() || groups.instances.contains_key(id)
                        });
                    }
                    self.platform.axes[ax].slot = Some((reply.id, kind == PostKind::Stop));
                    self.platform
                        .order_ids
                        .insert(reply.id, self.platform.g_order_id);
                    self.platform.g_order_id = self.platform.g_order_id.wrapping_add(1);
                }
                if kind == PostKind::Home && self.platform.safety() {
                    self.platform.homes.push((reply.id, ax));
                }
                if kind == PostKind::Reset && isg {
                    self.platform.axes[ax].messages.clear();
                }
                if kind == PostKind::Override && self.platform.axes[ax].feed_hold {
                    // An override written during a feed hold must not release it.
                    self.apply_feed_hold(ax);
                }
                Ok(reply)
            }
        }
    }

    /// Records an MC message (§7.2): class > 0 raises the axis error with the reaction.
    pub(crate) fn mc_message(&mut self, ax: usize, error_id: u32, remedy: u16, reaction: u16) {
        self.platform.mc_message(
            &mut self.set.axes,
            &mut self.set.fbs,
            ax,
            error_id,
            remedy,
            reaction,
        );
    }

    /// Safety and simulation services (§8, §12.1).
    pub(crate) fn platform_command(&mut self, c: PlatformCommand) -> Result<AxisReply, Rejection> {
        let ax_of = |e: &Self, n: &str| {
            e.set
                .index
                .get(n)
                .copied()
                .ok_or_else(|| Rejection::unknown_object("axis", n))
        };
        let mut value = ReplyValue::None;
        match c {
            PlatformCommand::SafetyDeactivate {
                axis,
                function,
                lease_cycles,
            } => {
                let ax = ax_of(self, &axis)?;
                let lease = if lease_cycles == 0 {
                    self.platform.cfg.lease_cycles
                } else {
                    lease_cycles
                };
                let p = &mut self.platform.axes[ax];
                match function {
                    SafetyFunction::VelocityMonitoring => p.velocity_lease = lease,
                    SafetyFunction::TorqueLimitMonitoring => p.torque_lease = lease,
                }
            }
            PlatformCommand::OperatingMode { mode } => {
                let was = self.platform.mode;
                self.platform.mode = mode;
                if was == OperatingMode::Auto
                    && mode != OperatingMode::Auto
                    && self.platform.safety()
                {
                    // Drive enables removed: every axis powers off, orders end CommandAborted.
                    for a in &mut self.set.axes {
                        a.switch_off(&mut self.set.fbs);
                        a.enable = false;
                    }
                    let groups: Vec<usize> = (0..self.groups.list.len()).collect();
                    for g in groups {
                        self.group_abort_motion(g, true);
                    }
                }
            }
            PlatformCommand::EnablingSwitch { pressed } => self.platform.enabling_switch = pressed,
            PlatformCommand::StartButton { pressed } => self.platform.start_button = pressed,
            PlatformCommand::InjectMcMessage {
                axis,
                error_id,
                behebungs_klasse,
                reaktions_klasse,
            } => {
                let ax = ax_of(self, &axis)?;
                if error_id == 0 {
                    return Err(reject(
                        ErrorId::VALUE_OUT_OF_RANGE,
                        format!("axis '{axis}': inject_mc_message: error_id must be > 0"),
                    ));
                }
                if reaktions_klasse > 3 {
                    return Err(reject(
                        ErrorId::ENUM_OUT_OF_RANGE,
                        format!("axis '{axis}': inject_mc_message: reaktions_klasse = {reaktions_klasse} must be 0..3"),
                    ));
                }
                self.mc_message(ax, error_id, behebungs_klasse, reaktions_klasse);
            }
            PlatformCommand::InjectActualVelocity {
                axis,
                velocity,
                duration_cycles,
            } => {
                let ax = ax_of(self, &axis)?;
                if !velocity.is_finite() {
                    return Err(Rejection::not_finite(
                        &format!("axis '{axis}': inject_actual_velocity"),
                        "velocity",
                        velocity,
                    ));
                }
                self.platform.axes[ax].injected = Some((velocity, duration_cycles));
            }
            PlatformCommand::TorqueLimit { axis, active } => {
                let ax = ax_of(self, &axis)?;
                self.platform.axes[ax].torque_limiting = active;
            }
            PlatformCommand::SetReferenced { axis, referenced } => {
                let ax = ax_of(self, &axis)?;
                self.platform.axes[ax].referenced = referenced;
                self.sync_soft_limits(ax);
            }
            PlatformCommand::SessionStart {
                hli_version,
                hli_size,
            } => {
                self.platform.version_mismatch = hli_version != self.platform.cfg.hli_version
                    || hli_size != self.platform.cfg.hli_size;
                if self.platform.version_mismatch {
                    return Err(reject(
                        ERR_SIM_VERSION_MISMATCH,
                        format!(
                            "HLI mismatch: client {hli_version}/{hli_size}, node {}/{} (R-SAF-2)",
                            self.platform.cfg.hli_version, self.platform.cfg.hli_size
                        ),
                    ));
                }
            }
            PlatformCommand::ReadVersions => {
                let v = env!("CARGO_PKG_VERSION").to_string();
                value = ReplyValue::Platform(PlatformReply::Versions(Versions {
                    hli_version: self.platform.cfg.hli_version,
                    hli_size: self.platform.cfg.hli_size,
                    mcp_base: v.clone(),
                    mcp_plcopen_p1: v.clone(),
                    mcp_plcopen_p4: v.clone(),
                    node_version: v,
                }));
            }
            PlatformCommand::ReadMessages { axis } => {
                let ax = ax_of(self, &axis)?;
                let m = self.platform.axes[ax].messages.iter().copied().collect();
                value = ReplyValue::Platform(PlatformReply::Messages(m));
            }
            PlatformCommand::ReadOrderId { id } => {
                let o = self.platform.order_ids.get(&id).copied().unwrap_or(0);
                value = ReplyValue::Platform(PlatformReply::OrderId(o));
            }
        }
        Ok(AxisReply {
            id: self.set.fbs.untracked_id(),
            value,
            tracked: false,
        })
    }

    /// Before the groups and axes step: order slots free again, feed hold (R-SAF-5), end of
    /// start-up (R-INIT-1).
    pub(crate) fn platform_step_pre(&mut self) {
        if !self.platform.safety() {
            return;
        }
        for p in &mut self.platform.axes {
            p.slot = None;
        }
        let hold = self.platform.feed_hold();
        for ax in 0..self.set.axes.len() {
            if self.platform.axes[ax].feed_hold != hold {
                self.platform.axes[ax].feed_hold = hold;
                self.apply_feed_hold(ax);
            }
        }
    }

    /// Applies the axis' feed-hold level as its effective override (0 while held).
    fn apply_feed_hold(&mut self, ax: usize) {
        let hold = self.platform.axes[ax].feed_hold;
        let a = &mut self.set.axes[ax];
        let pct = if hold {
            0.0
        } else {
            a.set_override.unwrap_or(a.power_override)
        };
        // A feed hold is not an override change of Tc2_MC2: MC_MoveVelocity is not aborted
        // by it (the owner is kept out of the replanning).
        let owner = a
            .job
            .as_mut()
            .filter(|j| j.kind == crate::axis::JobKind::Velocity)
            .and_then(|j| j.owner.take());
        single_axis::set::apply_override(a, pct, &mut self.set.fbs);
        if let (Some(id), Some(j)) = (owner, a.job.as_mut()) {
            j.owner = Some(id);
            if let Some(i) = self.set.fbs.get_mut(id) {
                // InVelocity again once the velocity is reached after the hold.
                i.in_velocity = false;
            }
        }
    }

    /// After the axes step: cyclic actual-velocity monitors (R-SAF-1b, R-SAF-4), leases,
    /// MC_Home → referenced, `isg_mcp` ErrorID 1 for instances of an axis in ERROR_STOP.
    pub(crate) fn platform_step_post(&mut self) {
        self.platform.cycles += 1;
        if !self.platform.safety() {
            return;
        }
        // R-INIT-1: start-up is cycles 0..9; with `auto_power` the axes are powered at its
        // end, STANDSTILL for the orders of cycle 10 (not one cycle later).
        if self.platform.isg()
            && self.platform.cycles == u64::from(self.platform.cfg.nr_cycles_chk_mc_runs)
            && self.platform.cfg.auto_power
        {
            for ax in 0..self.set.axes.len() {
                let name = self.set.axes[ax].name.clone();
                let _ = self.set.power(
                    ax,
                    Power {
                        axis: name,
                        enable: true,
                        enable_positive: true,
                        enable_negative: true,
                        override_percent: 100.0,
                        buffer_mode: BufferMode::Aborting,
                    },
                );
                let a = &mut self.set.axes[ax];
                if a.status_pending {
                    a.status_pending = false;
                    a.status = a.controller_on && !a.drive_fault;
                }
            }
        }
        for ax in 0..self.set.axes.len() {
            let p = &mut self.platform.axes[ax];
            let v = match p.injected.as_mut() {
                Some((v, n)) if *n > 0 => {
                    *n -= 1;
                    *v
                }
                _ => {
                    p.injected = None;
                    self.set.axes[ax].act_velo
                }
            };
            let vel_active = p.velocity_lease == 0;
            let torque_active = p.torque_lease == 0;
            p.velocity_lease = p.velocity_lease.saturating_sub(1);
            p.torque_lease = p.torque_lease.saturating_sub(1);
            let limit = p.velocity_limit();
            let tlimit = p.cfg.vb_torq_limit_max;
            let torque = p.torque_limiting;
            if !self.set.axes[ax].error_id.is_none() {
                continue;
            }
            if self.set.axes[ax].beyond_travel_limit() {
                self.mc_message(ax, MC_LIMIT_REACHED.0, 1, 2);
            } else if vel_active && v.abs() > limit {
                self.mc_message(ax, MC_ACTUAL_VELOCITY_EXCEEDED.0, 1, 3);
            } else if torque && torque_active && v.abs() > tlimit {
                self.mc_message(ax, MC_ACTUAL_VELOCITY_TORQUE_LIMIT.0, 1, 3);
            }
        }
        let fbs = &self.set.fbs;
        let axes = &mut self.platform.axes;
        self.platform
            .homes
            .retain(|&(id, ax)| match fbs.get(id).map(|i| i.state) {
                Some(CommandState::Done) => {
                    axes[ax].referenced = true;
                    false
                }
                Some(s) => !s.is_final(),
                None => false,
            });
        for ax in 0..self.set.axes.len() {
            if self.platform.axes[ax].referenced && self.platform.axes[ax].soft_limits.is_some() {
                self.sync_soft_limits(ax);
            }
        }
    }

    /// `isg_mcp`: an error event of an instance whose axis is in ERROR_STOP with that id
    /// shows ErrorID 1 (§7.2).
    /// The instance keeps that id (also after MC_Reset cleared the axis error).
    pub(crate) fn platform_map_events(&mut self, events: &mut [CommandEvent]) {
        if !self.platform.isg() {
            return;
        }
        for e in events {
            if let CommandState::Error(id) = e.state {
                let mapped = self.platform_error_id(e.id, id);
                if mapped != id {
                    e.state = CommandState::Error(mapped);
                    if let Some(i) = self.set.fbs.get_mut(e.id) {
                        i.state = CommandState::Error(mapped);
                    }
                }
            }
        }
    }

    /// The ErrorID an instance shows for `id` under the active profile.
    pub(crate) fn platform_error_id(&self, inst: CmdId, id: ErrorId) -> ErrorId {
        if !self.platform.isg() {
            return id;
        }
        match self.set.fbs.get(inst) {
            Some(i) => super::axis_rules::isg_error_id(&self.set.axes[i.axis], id),
            None => id,
        }
    }

    /// Snapshot part.
    pub(crate) fn platform_status(&self) -> PlatformStatus {
        let p = &self.platform;
        let n = u64::from(p.cfg.nr_cycles_chk_mc_runs);
        PlatformStatus {
            profile: p.profile,
            hli_initialized: !p.starting(),
            platform_base_done: !p.starting() && !p.version_mismatch,
            init_cycles: if p.isg() { p.cycles.min(n) } else { 0 },
            version_mismatch: p.version_mismatch,
            errors: if p.version_mismatch {
                vec![ERR_SIM_VERSION_MISMATCH]
            } else {
                Vec::new()
            },
            orders: if p.isg() {
                let axes = self.set.axes.iter().flat_map(|a| {
                    let job = a.job.and_then(|j| j.owner);
                    let pending = a.pending.as_ref().map(|q| q.owner);
                    job.into_iter().chain(pending)
                });
                let groups = self.groups.list.iter().flat_map(|g| {
                    let job = g.job.as_ref().and_then(|j| j.owner);
                    job.into_iter().chain(g.lock.map(|l| l.owner))
                });
                axes.chain(groups)
                    .filter_map(|id| p.order_ids.get(&id).map(|&o| (id.0, o)))
                    .collect()
            } else {
                Vec::new()
            },
            clog_warnings: self.raw.warnings.len(),
            recent_clog_warnings: self.raw.warnings
                [self.raw.warnings.len().saturating_sub(RECENT_CLOG_WARNINGS)..]
                .to_vec(),
            g_order_id: p.g_order_id,
            operating_mode: p.mode,
            enabling_switch: p.enabling_switch,
            start_button: p.start_button,
            axes: if p.safety() {
                p.axes
                    .iter()
                    .zip(&self.set.axes)
                    .map(|(s, a)| AxisSafetyStatus {
                        name: a.name.clone(),
                        referenced: s.referenced,
                        velocity_monitoring: s.velocity_lease == 0,
                        torque_limit_monitoring: s.torque_lease == 0,
                        torque_limiting: s.torque_limiting,
                        velocity_limit: s.velocity_limit(),
                        drive_enabled: a.controller_on && a.status,
                        feed_hold: s.feed_hold,
                        messages: s.messages.iter().copied().collect(),
                    })
                    .collect()
            } else {
                Vec::new()
            },
        }
    }
}

/// What `platform_post` must know about the call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PostKind {
    /// MC_Home.
    Home,
    /// MC_Reset.
    Reset,
    /// MC_Stop.
    Stop,
    /// MC_Power / MC_SetOverride (write the override).
    Override,
    /// Anything else.
    Other,
}

/// Classifies a call for `platform_post` and whether it places an order.
pub(crate) fn classify(cmd: &AxisCommand) -> (bool, PostKind) {
    let kind = match cmd {
        AxisCommand::Home(_) => PostKind::Home,
        AxisCommand::Reset(_) => PostKind::Reset,
        AxisCommand::Stop(_) => PostKind::Stop,
        AxisCommand::Power(_) | AxisCommand::SetOverride(_) => PostKind::Override,
        _ => PostKind::Other,
    };
    (places_order(cmd), kind)
}

/// The groups' view of the platform profile (crate `axis_groups`): ISG ids and outputs,
/// feed hold, safety caps and the safety checks of group orders.
impl crate::group::GroupProfile for Platform {
    fn isg(&self) -> bool {
        Platform::isg(self)
    }

    fn feed_hold(&self) -> bool {
        Platform::feed_hold(self)
    }

    fn velocity_cap(&self, ax: usize) -> f64 {
        Platform::velocity_cap(self, ax)
    }

    /// R-SAF-1a/R-SAF-6 for a group order: absolute group moves need referenced members
    /// (4903); a member's programmed velocity `v · |u_i|` above its monitoring limit raises
    /// MC error 60241 on that axis (the FB shows ErrorID 1, the group goes to
    /// GROUP_ERROR_STOP).
    fn check_group_motion(
        &mut self,
        axes: &mut [Axis],
        fbs: &mut Handshake,
        group: &str,
        fb: &str,
        members: &[usize],
        absolute: bool,
        dir: &[f64],
        velocity: f64,
    ) -> Result<(), Rejection> {
        if !self.safety() {
            return Ok(());
        }
        for &ax in members {
            if absolute && !self.axes[ax].referenced {
                return Err(Rejection::new(
                    ERR_SIM_AXIS_NOT_REFERENCED,
                    format!(
                        "group '{group}': {fb} needs referenced members; axis '{}' is not (R-SAF-6)",
                        axes[ax].name
                    ),
                ));
            }
        }
        for (k, &ax) in members.iter().enumerate() {
            let cap = self.velocity_cap(ax);
            let v = velocity.min(if dir[k].abs() > 1e-12 {
                cap / dir[k].abs()
            } else {
                f64::INFINITY
            }) * dir[k].abs();
            let p = &self.axes[ax];
            if p.velocity_lease == 0 && v > p.velocity_limit() {
                let limit = p.velocity_limit();
                self.mc_message(axes, fbs, ax, MC_PROGRAMMED_VELOCITY_EXCEEDS_LIMIT.0, 1, 1);
                return Err(Rejection::new(
                    ERR_PLC_AX_MC,
                    format!(
                        "group '{group}': {fb}: MC error 60241 on axis '{}': programmed velocity {v} exceeds the monitoring limit {limit} (R-SAF-1)",
                        axes[ax].name
                    ),
                ));
            }
        }
        Ok(())
    }
}

impl Platform {
    /// Records an MC message (§7.2): class > 0 raises the axis error with the reaction.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn mc_message(
        &mut self,
        axes: &mut [Axis],
        fbs: &mut Handshake,
        ax: usize,
        error_id: u32,
        remedy: u16,
        reaction: u16,
    ) {
        let m = McMessage {
            error_id,
            cycle: self.cycles,
            behebungs_klasse: remedy,
            reaktions_klasse: reaction,
        };
        let buf = &mut self.axes[ax].messages;
        buf.push_front(m);
        buf.truncate(ERROR_BUFFER_LEN);
        if remedy > 0 {
            let a = &mut axes[ax];
            let first = a.error_id.is_none();
            a.raise_error(ErrorId(error_id), reaction >= 3, fbs);
            if first {
                a.error_reaction = reaction;
            }
            // Reaction class 1: decelerate with the programmed deceleration; class 2: quick
            // stop with the limit deceleration `a_limit` (R-SYS-1) and the fast jerk; class 3:
            // brake at once.
            if (reaction == 1 || reaction == 2) && a.moving() {
                let (d, jerk) = match reaction {
                    1 => (a.last_dec, a.last_jerk),
                    _ => (
                        self.axes[ax].a_limit(a.cfg.fast_deceleration),
                        a.cfg.fast_jerk,
                    ),
                };
                let l = motion_core::Limits {
                    velocity: a.cfg.max_velocity,
                    acceleration: d,
                    deceleration: d,
                    jerk,
                };
                let profile = a.plan_stop(&l);
                let stop = profile.end().pos;
                a.start_job(crate::axis::Job::internal(
                    crate::axis::JobKind::FastStop,
                    profile,
                    stop,
                    l,
                ));
            }
        }
    }

    /// Velocity cap of an axis from the safety functions \[u/s\]: T1 (R-SAF-5) and
    /// non-referenced (R-SAF-6); infinite when none applies.
    pub(crate) fn velocity_cap(&self, ax: usize) -> f64 {
        if !self.safety() {
            return f64::INFINITY;
        }
        let p = &self.axes[ax];
        let mut cap = f64::INFINITY;
        if self.mode == OperatingMode::T1 {
            cap = cap.min(p.t1_limit());
        }
        if !p.referenced {
            cap = cap.min(p.cfg.vb_not_referenced);
        }
        cap
    }
}
