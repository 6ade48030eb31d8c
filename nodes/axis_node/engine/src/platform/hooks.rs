//! The engine's side of the platform profile (crate `isg_platform`): it lends the profile the
//! axes and groups for each call and cycle ([`PlatformCx`]) and tells it what a single-axis
//! call is ([`AxisCall`], from the command).

use super::*;
use crate::command::*;
use crate::engine::AxisEngine;
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
            Some(a) => a.name.clone(),
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
        self.platform.error_id(&self.set, id, e)
    }

    fn platform(&mut self) -> &mut Platform {
        &mut self.platform
    }
}

impl AxisCommand {
    /// The manual's FB name of a single-axis call ([`SIM`] for the simulation inputs; empty
    /// for calls that are not single-axis FBs).
    pub fn fb_name(&self) -> &'static str {
        use AxisCommand::*;
        match self {
            Power(_) => "MC_Power",
            Reset(_) => "MC_Reset",
            MoveAbsolute(_) => "MC_MoveAbsolute",
            MoveRelative(_) => "MC_MoveRelative",
            MoveAdditive(_) => "MC_MoveAdditive",
            MoveModulo(_) => "MC_MoveModulo",
            MoveVelocity(_) => "MC_MoveVelocity",
            MoveContinuousAbsolute(_) => "MC_MoveContinuousAbsolute",
            MoveContinuousRelative(_) => "MC_MoveContinuousRelative",
            Halt(_) => "MC_Halt",
            Stop(_) => "MC_Stop",
            SetPosition(_) => "MC_SetPosition",
            ReadParameter(_) => "MC_ReadParameter",
            ReadBoolParameter(_) => "MC_ReadBoolParameter",
            WriteParameter(_) => "MC_WriteParameter",
            WriteBoolParameter(_) => "MC_WriteBoolParameter",
            ReadStatus(_) => "MC_ReadStatus",
            ReadActualPosition(_) => "MC_ReadActualPosition",
            ReadActualVelocity(_) => "MC_ReadActualVelocity",
            ReadAxisError(_) => "MC_ReadAxisError",
            Sim(_) => SIM,
            Home(_) => "MC_Home",
            Jog(_) => "MC_Jog",
            SetOverride(_) => "MC_SetOverride",
            GearIn(_) => "MC_GearIn",
            GearOut(_) => "MC_GearOut",
            GearInDyn(_) => "MC_GearInDyn",
            TorqueControl(_) => "MC_TorqueControl",
            MoveSuperImposed(_) => "MC_MoveSuperImposed",
            AbortSuperposition(_) => "MC_AbortSuperposition",
            TouchProbe(_) => "MC_TouchProbe",
            AbortTrigger(_) => "MC_AbortTrigger",
            PhasingAbsolute(_) | PhasingUpdate(_) => "MC_PhasingAbsolute",
            PhasingRelative(_) => "MC_PhasingRelative",
            HaltPhasing(_) => "MC_HaltPhasing",
            GearInMultiMaster(_) => "MC_GearInMultiMaster",
            ExtSetPointGenEnable(_) => "MC_ExtSetPointGenEnable",
            ExtSetPointGenDisable(_) => "MC_ExtSetPointGenDisable",
            ExtSetPointGenFeed(_) => "MC_ExtSetPointGenFeed",
            ExtSetPointGenFeedWithTorque(_) => "MC_ExtSetPointGenFeedWithTorque",
            ReadDriveOperationMode(_) => "MC_ReadDriveOperationMode",
            WriteDriveOperationMode(_) => "MC_WriteDriveOperationMode",
            BacklashCompensation(_) => "MC_BacklashCompensation",
            PositionCorrectionLimiter(_) => "MC_PositionCorrectionLimiter",
            ReadDriveAddress(_) => "MC_ReadDriveAddress",
            SelectControlLoop(_) => "MC_SelectControlLoop",
            SetAcceptBlockedDriveSignal(_) => "MC_SetAcceptBlockedDriveSignal",
            SetEncoderScalingFactor(_) => "MC_SetEncoderScalingFactor",
            WriteNcIoOutput(_) => "MC_WriteNcIoOutput",
            TableBasedPositionCompensation(_) => "MC_TableBasedPositionCompensation",
            ConvertIncPosToPos(_) => "MC_ConvertIncPosToPos",
            ConvertPosToIncPos(_) => "MC_ConvertPosToIncPos",
            ReadParameterSet(_) => "MC_ReadParameterSet",
            ReadAxisComponents(_) => "MC_ReadAxisComponents",
            WriteParameterPersistent(_) => "MC_WriteParameterPersistent",
            WriteBoolParameterPersistent(_) => "MC_WriteBoolParameterPersistent",
            SetExecute { .. }
            | HomeCalibrationCam { .. }
            | TorqueControlUpdate { .. }
            | TouchProbePlcEvent { .. }
            | ReadFbOutputs { .. }
            | Group(_)
            | Platform(_)
            | Ca(_) => "",
        }
    }

    /// What the platform profile must know of this single-axis call: its FB name and the
    /// inputs the profile may change (Velocity of the move FBs; BufferMode of the FBs that
    /// `isg_mcp` forces to MC_Aborting).
    pub fn platform_call(&mut self) -> AxisCall<'_> {
        use AxisCommand::*;
        let fb = self.fb_name();
        let extension = crate::engine::is_axis3(self);
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
