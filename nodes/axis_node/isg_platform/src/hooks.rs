//! The profile hooks around the Tc2_MC2 axes and the Part 4 groups ([`PlatformCx`]):
//! screening before a single-axis FB call (`screen`), bookkeeping after it (`accepted`,
//! `refused`), the group orders' checks, the platform services, one part of the cycle before
//! and one after the axes (`step_pre`, `step_post`). In `tc2_mc2` without `safety_monitors`
//! every hook returns at once.

use crate::ids::*;
use crate::state::AxisPlatform;
use crate::*;
use axis_groups::{GroupCommand, GroupCx, Groups};
use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, Rejection};
use single_axis::fb_inputs::Power;
use single_axis::inputs::BufferMode;
use single_axis::AxisSet;

/// The platform with what it works on, lent for one call or cycle.
pub struct PlatformCx<'a> {
    /// The platform state.
    pub platform: &'a mut Platform,
    /// The single axes.
    pub set: &'a mut AxisSet,
    /// The Part 4 groups.
    pub groups: &'a mut Groups,
}

fn reject(id: ErrorId, msg: String) -> Rejection {
    Rejection::new(id, msg)
}

/// `isg_mcp` FB-level ids (§7.3): state rejections → 4901, parameter errors → 4902.
fn isg_id(id: ErrorId) -> ErrorId {
    use single_axis::error_ids::*;
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

impl PlatformCx<'_> {
    /// The groups with what they work on (this platform as their profile).
    fn group_cx(&mut self) -> GroupCx<'_> {
        GroupCx {
            groups: self.groups,
            axes: &mut self.set.axes,
            index: &self.set.index,
            fbs: &mut self.set.fbs,
            profile: self.platform,
        }
    }
}

impl PlatformCx<'_> {
    /// Builds the platform state from the profile and the configuration (per-axis keys must
    /// name axes; values finite and > 0).
    pub fn build(
        &mut self,
        profile: PlatformProfile,
        cfg: &PlatformConfig,
    ) -> Result<(), Rejection> {
        for (name, a) in &cfg.axes {
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
        p.profile = profile;
        p.cfg = cfg.clone();
        p.g_order_id = cfg.g_order_id;
        p.axes = self
            .set
            .axes
            .iter()
            .map(|a| {
                let c = cfg.axes.get(&*a.name).cloned().unwrap_or_default();
                AxisPlatform {
                    referenced: c.referenced,
                    cfg: c,
                    ..AxisPlatform::default()
                }
            })
            .collect();
        for ax in 0..self.set.axes.len() {
            self.sync_soft_limits(ax);
            use single_axis::axis::TravelLimits;
            self.set.axes[ax].travel_limits =
                match (self.platform.isg(), self.platform.axes[ax].cfg.modulo) {
                    (false, _) => TravelLimits::Planned,
                    (true, false) => TravelLimits::Monitored,
                    (true, true) => TravelLimits::Off,
                };
        }
        if self.platform.isg() {
            let modulo = self.platform.axes.iter().map(|p| p.cfg.modulo).collect();
            let rules = crate::axis_rules::IsgAxisRules { modulo };
            self.set.set_profile(Box::new(rules));
        }
        Ok(())
    }

    /// R-SAF-6: software limits are not monitored on a non-referenced axis; the configured
    /// enables come back when it is referenced again.
    pub fn sync_soft_limits(&mut self, ax: usize) {
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
    pub fn screen(&mut self, ax: usize, call: &mut AxisCall<'_>) -> Result<(), Rejection> {
        let name = self.set.axes[ax].name.clone();
        let isg = self.platform.isg();
        let order = call.places_order();
        if isg {
            if let Some(fb) = call.not_in_catalogue() {
                return Err(reject(
                    ERR_SIM_NOT_IMPLEMENTED,
                    format!("axis '{name}': {fb} is not implemented by the ISG platform (§3.1)"),
                ));
            }
            let read = !order && !matches!(call.fb, "MC_Power" | "MC_SetOverride");
            if self.platform.version_mismatch && call.fb != SIM {
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
            if call.fb == "MC_ReadActualPosition" && !self.set.axes[ax].error_id.is_none() {
                return Err(reject(
                    ERR_PLC_AX_MC,
                    format!(
                        "axis '{name}': in ERROR_STOP (MC error {})",
                        self.set.axes[ax].error_id.0
                    ),
                ));
            }
            // ISG has no BufferMode: every new command aborts (§14).
            if let Some(m) = call.buffer_mode.as_deref_mut() {
                *m = BufferMode::Aborting;
            }
        }
        if self.platform.safety() {
            // Motion FBs (R-SAF-6: only MoveRelative, MoveVelocity, Home, Stop, Halt on a
            // non-referenced axis).
            let fb = call.motion.then_some(call.fb);
            let p = &self.platform.axes[ax];
            // R-SAF-5: in T1/T2 orders need the enabling switch.
            let stopping = matches!(call.fb, "MC_Stop" | "MC_Halt");
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
                        fb,
                        "MC_MoveRelative"
                            | "MC_MoveVelocity"
                            | "MC_Home"
                            | "MC_Stop"
                            | "MC_Halt"
                            | "MC_SetPosition"
                    );
                    if !allowed {
                        return Err(reject(
                            ERR_SIM_AXIS_NOT_REFERENCED,
                            format!("axis '{name}': {fb} needs a referenced axis (R-SAF-6)"),
                        ));
                    }
                }
                let vb = p.cfg.vb_not_referenced;
                if let Some(v) = call.velocity.as_deref_mut() {
                    *v = v.min(vb);
                }
            }
            // R-SAF-5: T1 clamps the commanded velocity.
            if self.platform.mode == OperatingMode::T1 {
                let lim = p.t1_limit();
                if let Some(v) = call.velocity.as_deref_mut() {
                    *v = v.min(lim);
                }
            }
            // R-SAF-1a: the SAI refuses a programmed velocity above the monitoring limit.
            let limit = p.velocity_limit();
            let active = p.velocity_lease == 0;
            if let Some(v) = call.velocity.as_deref().copied() {
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
                if call.fb != "MC_Stop" {
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

    /// A single-axis FB call was refused: `isg_mcp` shows the FB-level ids (§7.3).
    pub fn refused(&self, mut r: Rejection) -> Rejection {
        if self.platform.isg() {
            r.error_id = isg_id(r.error_id);
        }
        r
    }

    /// Bookkeeping after an accepted single-axis FB call (instance `id`): order slot and
    /// number, MC_Home tracking, MC_Reset clearing the message buffer, overrides during a
    /// feed hold.
    pub fn accepted(&mut self, ax: usize, order: bool, kind: PostKind, id: CmdId) {
        let isg = self.platform.isg();
        if isg && order {
            if self.platform.order_ids.len() > 4096 {
                let (fbs, groups) = (&self.set.fbs, &*self.groups);
                self.platform
                    .order_ids
                    .retain(|id, _| fbs.get(*id).is_some() || groups.instances.contains_key(id));
            }
            self.platform.axes[ax].slot = Some((id, kind == PostKind::Stop));
            self.platform.draw_order_id(id);
        }
        if kind == PostKind::Home && self.platform.safety() {
            self.platform.homes.push((id, ax));
        }
        if kind == PostKind::Reset && isg {
            self.platform.axes[ax].messages.clear();
        }
        if kind == PostKind::Override && self.platform.axes[ax].feed_hold {
            // An override written during a feed hold must not release it.
            self.apply_feed_hold(ax);
        }
    }

    /// Records an MC message (§7.2): class > 0 raises the axis error with the reaction.
    pub fn mc_message(&mut self, ax: usize, error_id: u32, remedy: u16, reaction: u16) {
        self.platform.mc_message(
            &mut self.set.axes,
            &mut self.set.fbs,
            ax,
            error_id,
            remedy,
            reaction,
        );
    }

    /// Safety and simulation services (§8, §12.1); the value of read services.
    pub fn command(&mut self, c: PlatformCommand) -> Result<Option<PlatformReply>, Rejection> {
        let ax_of = |e: &Self, n: &str| {
            e.set
                .index
                .get(n)
                .copied()
                .ok_or_else(|| Rejection::unknown_object("axis", n))
        };
        let mut value = None;
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
                        self.group_cx().group_abort_motion(g, true);
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
                value = Some(PlatformReply::Versions(Versions {
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
                value = Some(PlatformReply::Messages(m));
            }
            PlatformCommand::ReadOrderId { id } => {
                let o = self.platform.order_ids.get(&id).copied().unwrap_or(0);
                value = Some(PlatformReply::OrderId(o));
            }
        }
        Ok(value)
    }

    /// Before the groups and axes step: order slots free again, feed hold (R-SAF-5), end of
    /// start-up (R-INIT-1).
    pub fn step_pre(&mut self) {
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
            .filter(|j| j.kind == single_axis::axis::JobKind::Velocity)
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
    pub fn step_post(&mut self) {
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
                        axis: str::to_owned(&name),
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
    pub fn map_events(&mut self, events: &mut [CommandEvent]) {
        if !self.platform.isg() {
            return;
        }
        for e in events {
            if let CommandState::Error(id) = e.state {
                let mapped = self.set.shown_error_id(e.id, id);
                if mapped != id {
                    e.state = CommandState::Error(mapped);
                    if let Some(i) = self.set.fbs.get_mut(e.id) {
                        i.state = CommandState::Error(mapped);
                    }
                }
            }
        }
    }
}

/// What `accepted` must know about the call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PostKind {
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

/// The FB name of the §1.5 simulation inputs in an [`AxisCall`].
pub const SIM: &str = "sim";

/// What the profile must know of one single-axis FB call: the manual's FB name (the rules of
/// plcopen_platform.md name FBs) and the inputs it may change.
#[derive(Debug)]
pub struct AxisCall<'a> {
    /// The manual's name ("MC_MoveAbsolute"), [`SIM`] for the simulation inputs.
    pub fb: &'static str,
    /// A Tc2_MC2 extension FB (phasing, multi-master gearing, external set points, §4.7).
    pub extension: bool,
    /// A single-axis motion FB (MC_MoveAbsolute ... MC_SetPosition, MC_Home, MC_Jog, gearing,
    /// torque, superposition): screened by the safety rules.
    pub motion: bool,
    /// The commanded Velocity of a move FB.
    pub velocity: Option<&'a mut f64>,
    /// The BufferMode input.
    pub buffer_mode: Option<&'a mut BufferMode>,
}

impl AxisCall<'_> {
    /// Does the FB place an order in the axis' order slot (§6.2)? Reads, MC_Power,
    /// MC_SetOverride and the simulation inputs do not.
    pub fn places_order(&self) -> bool {
        !matches!(
            self.fb,
            "MC_Power"
                | "MC_SetOverride"
                | "MC_ReadParameter"
                | "MC_ReadBoolParameter"
                | "MC_ReadStatus"
                | "MC_ReadActualPosition"
                | "MC_ReadActualVelocity"
                | "MC_ReadAxisError"
                | SIM
        )
    }

    /// FBs of §3.1 marked * or not in the ISG catalogue (→ 4905 in `isg_mcp`).
    pub fn not_in_catalogue(&self) -> Option<&'static str> {
        match self.fb {
            "MC_ReadBoolParameter"
            | "MC_WriteBoolParameter"
            | "MC_TorqueControl"
            | "MC_MoveContinuousAbsolute"
            | "MC_MoveContinuousRelative"
            | "MC_ReadActualVelocity"
            | "MC_Jog"
            | "MC_MoveModulo"
            | "MC_GearInDyn"
            | "MC_AbortSuperposition" => Some(self.fb),
            // Phasing, multi-master gearing, external set points, §4.7 extensions: Tc2_MC2 only.
            _ if self.extension => Some("this Tc2_MC2 extension FB"),
            _ => None,
        }
    }

    /// Classifies the call for [`PlatformCx::accepted`] and whether it places an order.
    pub fn classify(&self) -> (bool, PostKind) {
        let kind = match self.fb {
            "MC_Home" => PostKind::Home,
            "MC_Reset" => PostKind::Reset,
            "MC_Stop" => PostKind::Stop,
            "MC_Power" | "MC_SetOverride" => PostKind::Override,
            _ => PostKind::Other,
        };
        (self.places_order(), kind)
    }
}

impl PlatformCx<'_> {
    /// A Part 4 call through the profile's start-up, version and enabling-switch checks (§9,
    /// R-SAF-2, R-SAF-5) and the channel's order slot (R-HS-3/R-HS-4: one order per cycle,
    /// MC_GroupStop overwrites; reads and MC_GroupSetOverride use no slot). Ok((g, order)):
    /// the group's index and whether the call places an order on it (then
    /// [`Self::group_order_placed`]); an unknown group → UNKNOWN_OBJECT after the checks.
    pub fn screen_group(&self, cmd: &GroupCommand) -> Result<(usize, bool), Rejection> {
        let read = matches!(
            cmd,
            GroupCommand::GroupReadStatus { .. }
                | GroupCommand::GroupReadError { .. }
                | GroupCommand::GroupReadActualPosition { .. }
                | GroupCommand::GroupReadActualVelocity { .. }
                | GroupCommand::GroupReadConfiguration { .. }
        );
        if self.platform.isg() && !read {
            if self.platform.version_mismatch {
                return Err(Rejection::new(
                    ERR_SIM_VERSION_MISMATCH,
                    format!(
                        "group '{}': HLI version/size mismatch (R-SAF-2)",
                        cmd.group()
                    ),
                ));
            }
            if self.platform.starting() {
                return Err(Rejection::new(
                    ERR_PO_AX_TNA_INIT_STATE,
                    format!("group '{}': order during start-up (§9)", cmd.group()),
                ));
            }
        }
        // R-SAF-5: in T1/T2 group motions need the enabling switch.
        let motion = matches!(
            cmd,
            GroupCommand::MoveLinearAbsolute(_)
                | GroupCommand::MoveLinearRelative(_)
                | GroupCommand::MovePath(_)
        );
        if motion
            && self.platform.safety()
            && self.platform.mode != OperatingMode::Auto
            && !self.platform.enabling_switch
        {
            return Err(Rejection::new(
                ERR_SIM_TRANSITION_NOT_ALLOWED,
                format!(
                    "group '{}': motion in {:?} needs the enabling switch (R-SAF-5)",
                    cmd.group(),
                    self.platform.mode
                ),
            ));
        }
        let order =
            self.platform.isg() && !read && !matches!(cmd, GroupCommand::GroupSetOverride(_));
        let g = self.groups.index_of(cmd.group())?;
        if order && self.groups.list[g].slot && !matches!(cmd, GroupCommand::GroupStop(_)) {
            return Err(Rejection::new(
                FB_ERR_MC_DID_NOT_TAKE_ORDER,
                format!(
                    "group '{}': the channel's order slot is already used in this cycle (R-HS-3)",
                    cmd.group()
                ),
            ));
        }
        Ok((g, order))
    }

    /// Group `g`'s order (instance `id`) was taken: its slot is used, it gets its order number.
    pub fn group_order_placed(&mut self, g: usize, id: CmdId) {
        self.groups.list[g].slot = true;
        self.platform.draw_order_id(id);
    }

    /// A member of a group reset by MC_GrpReset was reset: in `isg_mcp` its MC message buffer
    /// is cleared too (R-ERR-3).
    pub fn member_reset(&mut self, ax: usize) {
        if self.platform.isg() {
            self.platform.axes[ax].messages.clear();
        }
    }
}
