//! The engine's side of the Part 4 groups (crate `axis_groups`): it lends the groups its
//! axes, handshake and platform profile for each call and cycle ([`GroupCx`]), screens group
//! orders with the ISG profile's start-up, version, enabling-switch and order-slot rules, and
//! composes MC_GrpReset with the members' MC_Reset.

use super::*;
use crate::group::{GroupCallReply, GroupCommand, GroupConfig, GroupCx, GroupStatus};

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
                self.platform_cx().member_reset(ax);
            }
            return Ok(self.group_cx().finish_reset(g).into());
        }
        self.group_cx().group_command(cmd).map(AxisReply::from)
    }

    /// A Part 4 call through the profile's checks and the channel's order slot
    /// (`isg_platform`: start-up, version, enabling switch, R-HS-3/R-HS-4).
    pub(crate) fn group_command_screened(
        &mut self,
        cmd: GroupCommand,
    ) -> Result<AxisReply, Rejection> {
        let (g, order) = self.platform_cx().screen_group(&cmd)?;
        let reply = self.group_command(cmd)?;
        if order {
            self.platform_cx().group_order_placed(g, reply.id);
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
