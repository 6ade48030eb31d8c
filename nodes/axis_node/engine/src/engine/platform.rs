//! The engine's side of the platform profile (crate `isg_platform`): it lends the profile the
//! axes and groups for each call and cycle ([`PlatformCx`]) and tells it what a single-axis
//! call is ([`AxisCall`], from the command).

use super::AxisEngine;
use crate::command::*;
use crate::platform::*;
use motion_core::{CmdId, CommandEvent, ErrorId, Rejection, Tick};

impl AxisEngine {
    /// The platform with what it works on, for one call or cycle.
    pub(crate) fn platform_cx(&mut self) -> PlatformCx<'_> {
        PlatformCx {
            platform: &mut self.platform,
            set: &mut self.set,
            groups: &mut self.groups,
        }
    }

    /// Safety, simulation and session services (§8, §12.1), answered at once.
    pub(crate) fn platform_command(&mut self, c: PlatformCommand) -> Result<AxisReply, Rejection> {
        let value = self.platform_cx().command(c)?;
        Ok(AxisReply {
            id: self.set.fbs.untracked_id(),
            value: value.map_or(ReplyValue::None, ReplyValue::Platform),
            tracked: false,
        })
    }

    /// The snapshot's platform part (with the raw layer's clog warnings).
    pub(crate) fn platform_status(&self) -> PlatformStatus {
        self.platform
            .status(&self.set, &self.groups, self.raw.warnings())
    }

    /// One PLC cycle of the raw FB layer (§12.2): the calls in order, then one MC cycle.
    /// Events of commands not owned by raw instances are appended to `events`.
    pub fn fb_cycle(
        &mut self,
        tick: Tick,
        calls: &[raw::FbCall],
        events: &mut Vec<CommandEvent>,
    ) -> Vec<raw::FbOut> {
        // The layer drives this engine; it is lent out for the cycle (the engine's own step
        // then finds no raw-owned command: the layer routes the cycle's events itself).
        let mut layer = std::mem::take(&mut self.raw);
        let outs = layer.fb_cycle(self, tick, calls, events);
        self.raw = layer;
        outs
    }

    /// Warnings of the raw layer so far (4906).
    pub fn raw_warnings(&self) -> &[raw::RawWarning] {
        self.raw.warnings()
    }
}

impl isg_platform::raw::RawHost for AxisEngine {
    type Call = AxisCommand;

    fn place(&mut self, call: AxisCommand) -> Result<(CmdId, bool), Rejection> {
        self.dispatch(call).map(|r| (r.id, r.tracked))
    }

    fn release(&mut self, id: CmdId) {
        let _ = self.dispatch(AxisCommand::SetExecute { id, execute: false });
    }

    fn mc_cycle(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        motion_core::Engine::step(self, tick, events);
    }

    fn take_events(&mut self, events: &mut Vec<CommandEvent>) {
        events.append(&mut self.set.fbs.events);
    }

    fn channel(&self, call: &AxisCommand) -> Option<usize> {
        match call {
            AxisCommand::Group(g) => self
                .groups
                .index
                .get(g.group())
                .map(|&i| self.set.axes.len() + i),
            _ => call.axis().and_then(|n| self.set.index.get(n).copied()),
        }
    }

    fn channels(&self) -> usize {
        self.set.axes.len() + self.groups.list.len()
    }

    fn channel_name(&self, channel: usize) -> String {
        match self.set.axes.get(channel) {
            Some(a) => str::to_owned(&a.name),
            None => self.groups.list[channel - self.set.axes.len()].name.clone(),
        }
    }

    fn cyclic_inputs(call: &AxisCommand) -> bool {
        matches!(
            call,
            AxisCommand::Power(_)
                | AxisCommand::SetOverride(_)
                | AxisCommand::Group(crate::group::GroupCommand::GroupSetOverride(_))
        )
    }

    fn in_velocity(&self, id: CmdId) -> bool {
        self.set
            .fbs
            .outputs_with(id, false)
            .is_some_and(|o| o.in_velocity)
    }

    fn shown_error(&self, id: CmdId, e: ErrorId) -> ErrorId {
        self.set.shown_error_id(id, e)
    }

    fn platform(&mut self) -> &mut Platform {
        &mut self.platform
    }
}

impl AxisCommand {
    /// What the platform profile must know of this single-axis call: its FB name and the
    /// inputs the profile may change (Velocity of the move FBs; BufferMode of the FBs that
    /// `isg_mcp` forces to MC_Aborting).
    pub fn platform_call(&mut self) -> AxisCall<'_> {
        use AxisCommand::*;
        let fb = self.fb_name();
        let extension = self.is_extension();
        let motion = self.motion_fb_name().is_some();
        let (velocity, buffer_mode) = match self {
            MoveAbsolute(c) => (Some(&mut c.velocity), Some(&mut c.buffer_mode)),
            MoveRelative(c) => (Some(&mut c.velocity), Some(&mut c.buffer_mode)),
            MoveAdditive(c) => (Some(&mut c.velocity), Some(&mut c.buffer_mode)),
            MoveModulo(c) => (Some(&mut c.velocity), Some(&mut c.buffer_mode)),
            MoveVelocity(c) => (Some(&mut c.velocity), Some(&mut c.buffer_mode)),
            MoveContinuousAbsolute(c) => (Some(&mut c.velocity), None),
            MoveContinuousRelative(c) => (Some(&mut c.velocity), None),
            Halt(c) => (None, Some(&mut c.buffer_mode)),
            Home(c) => (None, Some(&mut c.buffer_mode)),
            GearIn(c) => (None, Some(&mut c.buffer_mode)),
            _ => (None, None),
        };
        AxisCall {
            fb,
            extension,
            motion,
            velocity,
            buffer_mode,
        }
    }
}
