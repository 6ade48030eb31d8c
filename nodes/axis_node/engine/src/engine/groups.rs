//! The engine's side of the Part 4 groups (crate `axis_groups`): it lends the groups its
//! axes, handshake and platform profile for each call and cycle ([`GroupCx`]), screens group
//! orders with the ISG profile's start-up, version, enabling-switch and order-slot rules, and
//! composes MC_GrpReset with the members' MC_Reset.

use super::*;
use crate::group::{GroupCallReply, GroupCommand, GroupConfig, GroupCx, GroupStatus};
use crate::platform::ids::*;

impl From<GroupCallReply> for AxisReply {
    fn from(r: GroupCallReply) -> Self {
        AxisReply {
            id: r.id,
            value: r.value.map_or(ReplyValue::None, ReplyValue::Group),
            tracked: r.tracked,
        }
    }
}

impl AxisEngine {
    /// The groups with what they work on, for one call or cycle.
    fn group_cx(&mut self) -> GroupCx<'_> {
        GroupCx {
            groups: &mut self.groups,
            axes: &mut self.set.axes,
            index: &self.set.index,
            fbs: &mut self.set.fbs,
            profile: &mut self.platform,
        }
    }

    /// One Part 4 FB call. MC_GrpReset: the group admits it, the members in ErrorStop get
    /// MC_Reset (in isg_mcp their MC message buffers are cleared too, R-ERR-3), then the
    /// group error is cleared.
    fn group_command(&mut self, cmd: GroupCommand) -> Result<AxisReply, Rejection> {
        if let GroupCommand::GroupReset { group } = &cmd {
            let g = self.groups.index_of(group)?;
            for ax in self.group_cx().admit_reset(g)? {
                self.set.reset(ax)?;
                if self.platform.isg() {
                    self.platform.axes[ax].messages.clear();
                }
            }
            return Ok(self.group_cx().finish_reset(g).into());
        }
        self.group_cx().group_command(cmd).map(AxisReply::from)
    }

    /// A Part 4 call through the profile's start-up and version checks (§9, R-SAF-2).
    pub(crate) fn group_command_screened(
        &mut self,
        cmd: GroupCommand,
    ) -> Result<AxisReply, Rejection> {
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
            && self.platform.mode != crate::platform::OperatingMode::Auto
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
        // R-HS-3/R-HS-4 on the group's channel slot: one order per cycle, MC_GroupStop
        // overwrites; reads and MC_GroupSetOverride use no slot.
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
        let reply = self.group_command(cmd)?;
        if order {
            self.groups.list[g].slot = true;
            self.platform
                .order_ids
                .insert(reply.id, self.platform.g_order_id);
            self.platform.g_order_id = self.platform.g_order_id.wrapping_add(1);
        }
        Ok(reply)
    }

    /// Single-axis motion FBs on a member of a moving or stopping group are refused.
    pub(crate) fn group_screen_axis_command(
        &self,
        ax: usize,
        cmd: &crate::command::AxisCommand,
    ) -> Result<(), Rejection> {
        let fb = match cmd.motion_fb_name() {
            Some(fb) => fb,
            None if matches!(cmd, crate::command::AxisCommand::Reset(_))
                && self.set.axes[ax].error_id.is_none() =>
            {
                "MC_Reset"
            }
            None => return Ok(()),
        };
        self.group_blocks_axis(ax, fb)
    }

    /// Hook for single-axis commands: a member of a moving/stopping group refuses motion.
    pub(crate) fn group_blocks_axis(&self, ax: usize, fb: &str) -> Result<(), Rejection> {
        self.groups
            .blocks_axis(ax, fb, &self.set.axes, self.platform.isg())
    }

    /// The group of a command instance's Execute falling edge (MC_GroupStop unlock).
    pub(crate) fn group_set_execute(&mut self, id: CmdId, execute: bool) -> Option<AxisReply> {
        self.group_cx()
            .group_set_execute(id, execute)
            .map(AxisReply::from)
    }

    /// Cancel of a group motion goal = MC_GroupHalt with the command's own deceleration.
    pub(crate) fn group_cancel(&mut self, id: CmdId) -> Option<Result<(), Rejection>> {
        self.group_cx().group_cancel(id)
    }

    /// Outputs of a group instance (the active profile's Execute rules).
    pub fn group_outputs(&self, id: CmdId) -> Option<ExecuteOutputs> {
        self.groups
            .outputs(id, self.set.fbs.cycle, self.platform.isg())
    }

    /// The status of one group (MC_GroupReadStatus and the snapshot).
    pub(crate) fn group_status(&self, g: usize) -> GroupStatus {
        self.groups.status(g, &self.set.axes)
    }

    /// The status of a group by name.
    pub fn group(&self, name: &str) -> Option<GroupStatus> {
        self.groups.by_name(name, &self.set.axes)
    }

    /// Group names in configuration order.
    pub fn group_names(&self) -> impl Iterator<Item = &str> {
        self.groups.names()
    }

    /// Ends a group's motion and hands the members back (disable, ungroup).
    pub(crate) fn group_abort_motion(&mut self, g: usize, abort_lock: bool) {
        self.group_cx().group_abort_motion(g, abort_lock);
    }

    /// One cycle of every group, before the axes step. Without groups there is nothing to do
    /// (and no instance to report), so the cycle of a plain single-axis engine skips it.
    pub(crate) fn groups_step(&mut self, dt: f64) {
        if self.groups.list.is_empty() && self.groups.instant_done.is_empty() {
            return;
        }
        self.group_cx().groups_step(dt);
    }

    /// Builds the groups of the configuration (R-ARCH-4).
    pub(crate) fn build_groups(&mut self, cfg: &[GroupConfig]) -> Result<(), Rejection> {
        self.groups.build(cfg, &self.set.index, self.set.axes.len())
    }
}
