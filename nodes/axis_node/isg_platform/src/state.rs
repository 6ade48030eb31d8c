//! The platform's runtime state: per-axis safety state, start-up, order numbers, MC
//! messages.

use crate::ids::*;
use crate::*;
use axis_groups::Groups;
use motion_core::{CmdId, ErrorId, Rejection};
use single_axis::axis::Axis;
use single_axis::handshake::Handshake;
use single_axis::AxisSet;
use std::collections::{HashMap, VecDeque};

/// Runtime safety state of one axis.
#[derive(Clone, Debug, Default)]
pub(crate) struct AxisPlatform {
    pub cfg: AxisPlatformConfig,
    pub referenced: bool,
    /// Cycles left with velocity monitoring off (0 = active).
    pub velocity_lease: u32,
    pub torque_lease: u32,
    pub torque_limiting: bool,
    /// Injected actual velocity and cycles left.
    pub injected: Option<(f64, u32)>,
    pub messages: VecDeque<McMessage>,
    pub feed_hold: bool,
    /// Order slot of this cycle: the instance that placed its order.
    pub slot: Option<(CmdId, bool)>,
    /// The configured software-limit enables (min, max), suspended while not referenced
    /// (R-SAF-6: no machine-fixed reference, no software limit monitoring).
    pub soft_limits: Option<(bool, bool)>,
}

impl AxisPlatform {
    /// The R-SYS-1 braking deceleration: `a_limit`, or `fast_deceleration` when 0.
    pub fn a_limit(&self, fast_deceleration: f64) -> f64 {
        if self.cfg.a_limit > 0.0 {
            self.cfg.a_limit
        } else {
            fast_deceleration
        }
    }

    /// Velocity monitoring limit \[u/s\] (R-SAF-1).
    pub fn velocity_limit(&self) -> f64 {
        match self.cfg.kind {
            AxisKind::Linear => LINEAR_LIMIT_MM_S * self.cfg.units_per_mm,
            AxisKind::Rotary => {
                if self.cfg.vb_monitor > 0.0 {
                    self.cfg.vb_monitor
                } else {
                    self.cfg.vb_not_referenced
                }
            }
        }
    }

    /// T1 velocity clamp \[u/s\].
    pub fn t1_limit(&self) -> f64 {
        match self.cfg.kind {
            AxisKind::Linear => T1_LIMIT_MM_S * self.cfg.units_per_mm,
            AxisKind::Rotary => self.velocity_limit(),
        }
    }
}

/// Runtime platform state.
#[derive(Clone, Debug, Default)]
pub struct Platform {
    pub(crate) profile: PlatformProfile,
    pub(crate) cfg: PlatformConfig,
    pub(crate) axes: Vec<AxisPlatform>,
    /// Steps run so far.
    pub(crate) cycles: u64,
    pub(crate) version_mismatch: bool,
    pub(crate) g_order_id: u32,
    pub(crate) order_ids: HashMap<CmdId, u32>,
    pub(crate) mode: OperatingMode,
    pub(crate) enabling_switch: bool,
    pub(crate) start_button: bool,
    /// MC_Home instances whose Done marks the axis referenced (R-SAF-6).
    pub(crate) homes: Vec<(CmdId, usize)>,
}

impl Platform {
    /// `MAX_RETRIALS`: cycles a raw-layer instance retries an order that found the slot
    /// occupied.
    pub fn max_retrials(&self) -> u32 {
        self.cfg.max_retrials
    }

    /// The order number of an instance (R-FB-3), if it placed one.
    pub fn order_id(&self, id: CmdId) -> Option<u32> {
        self.order_ids.get(&id).copied()
    }

    /// Instance `id` placed an order: it gets the next global order number (§4.3).
    pub(crate) fn draw_order_id(&mut self, id: CmdId) {
        self.order_ids.insert(id, self.g_order_id);
        self.g_order_id = self.g_order_id.wrapping_add(1);
    }

    /// A raw-layer re-trigger (§4.3): the new command keeps the instance's order number, and
    /// the number it drew is given back.
    pub fn keep_order_id(&mut self, id: CmdId, order_id: u32) {
        self.g_order_id = self.g_order_id.wrapping_sub(1);
        self.order_ids.insert(id, order_id);
    }

    /// The `isg_mcp` profile is active.
    pub fn isg(&self) -> bool {
        self.profile == PlatformProfile::IsgMcp
    }

    /// Safety monitors of §8 active (always in `isg_mcp`).
    pub fn safety(&self) -> bool {
        self.isg() || self.cfg.safety_monitors
    }

    /// Start-up running (R-INIT-1): `isg_mcp` only.
    pub fn starting(&self) -> bool {
        self.isg() && self.cycles < u64::from(self.cfg.nr_cycles_chk_mc_runs)
    }

    /// Motion in T1/T2 needs the enabling switch and START (R-SAF-5).
    pub fn feed_hold(&self) -> bool {
        self.safety()
            && self.mode != OperatingMode::Auto
            && !(self.enabling_switch && self.start_button)
    }
}

/// The groups' view of the platform profile (crate `axis_groups`): ISG ids and outputs,
/// feed hold, safety caps and the safety checks of group orders.
impl axis_groups::GroupProfile for Platform {
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
                a.start_job(single_axis::axis::Job::internal(
                    single_axis::axis::JobKind::FastStop,
                    profile,
                    stop,
                    l,
                ));
            }
        }
    }

    /// Velocity cap of an axis from the safety functions \[u/s\]: T1 (R-SAF-5) and
    /// non-referenced (R-SAF-6); infinite when none applies.
    pub fn velocity_cap(&self, ax: usize) -> f64 {
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

impl Platform {
    /// Snapshot part; `warnings` = the raw FB layer's clog warnings so far.
    pub fn status(
        &self,
        set: &AxisSet,
        groups: &Groups,
        warnings: &[RawWarning],
    ) -> PlatformStatus {
        let p = self;
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
                let axes = set.axes.iter().flat_map(|a| {
                    let job = a.job.and_then(|j| j.owner);
                    let pending = a.pending.as_ref().map(|q| q.owner);
                    job.into_iter().chain(pending)
                });
                let groups = groups.list.iter().flat_map(|g| {
                    let job = g.job.as_ref().and_then(|j| j.owner);
                    job.into_iter().chain(g.lock.map(|l| l.owner))
                });
                axes.chain(groups)
                    .filter_map(|id| p.order_ids.get(&id).map(|&o| (id.0, o)))
                    .collect()
            } else {
                Vec::new()
            },
            clog_warnings: warnings.len(),
            recent_clog_warnings: warnings[warnings.len().saturating_sub(RECENT_CLOG_WARNINGS)..]
                .to_vec(),
            g_order_id: p.g_order_id,
            operating_mode: p.mode,
            enabling_switch: p.enabling_switch,
            start_button: p.start_button,
            axes: if p.safety() {
                p.axes
                    .iter()
                    .zip(&set.axes)
                    .map(|(s, a)| AxisSafetyStatus {
                        name: str::to_owned(&a.name),
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
