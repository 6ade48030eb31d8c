//! [`AxisEngine`]: the composition of the axis node's layers, implementing
//! [`motion_core::Engine`]: the single axes ([`AxisSet`], crate `single_axis`), PLCopen Part 4
//! groups, collision-avoidance groups and the platform profile with its raw FB layer.
//!
//! `command` routes one FB call: group, platform and CA calls to their layer; a single-axis
//! call through the profile's screening, the groups' and CA's claims on the axis, the FB
//! itself, and the profile's bookkeeping of the result. `step` runs one cycle in the order of
//! §1.1: profile, groups, CA, the axes (masters before slaves), profile, events.

use crate::command::*;
use crate::config::AxisConfig;
use crate::snapshot::{AxisSnapshot, AxisStatus};
use motion_core::{CmdId, CommandEvent, Engine, ErrorId, ExecuteOutputs, Rejection, State1, Tick};
use single_axis::{AxisSet, FbKind, FbOutputs, FbReply, FbValue, PowerOutputs};

/// The axis node's engine: the axes with their FB instances and the layers built on them.
#[derive(Debug)]
pub struct AxisEngine {
    /// The single axes and their FB instances (crate `single_axis`).
    pub(crate) set: AxisSet,
    /// Part 4 axis groups (plcopen_platform.md §3.2, §5).
    pub(crate) groups: crate::group::Groups,
    /// Platform profile, safety functions, start-up (plcopen_platform.md §6–§10).
    pub(crate) platform: crate::platform::Platform,
    /// The raw FB layer (plcopen_platform.md §12.2).
    pub(crate) raw: isg_platform::raw::RawLayer<AxisCommand>,
    tick: u64,
    /// Collision-avoidance groups (collision_avoidance.md).
    ca: crate::ca::CaGroups,
}

impl From<FbReply> for AxisReply {
    fn from(r: FbReply) -> Self {
        AxisReply {
            id: r.id,
            value: r.value.into(),
            tracked: r.tracked,
        }
    }
}

impl AxisEngine {
    /// Builds the engine from `(name, config)` pairs; names must be unique and non-empty,
    /// every config valid (message names axis, key and value).
    pub fn new(axes: Vec<(String, AxisConfig)>) -> Result<Self, Rejection> {
        Self::with_config(axes, &crate::platform::EngineConfig::default())
    }

    /// Builds the engine with an engine-level configuration: `platform_profile`, Part 4
    /// groups and platform settings (plcopen_platform.md). Unknown axis names in it are
    /// refused with `UNKNOWN_OBJECT`.
    pub fn with_config(
        axes: Vec<(String, AxisConfig)>,
        config: &crate::platform::EngineConfig,
    ) -> Result<Self, Rejection> {
        let mut e = AxisEngine {
            set: AxisSet::new(axes)?,
            groups: Default::default(),
            platform: Default::default(),
            raw: Default::default(),
            tick: 0,
            ca: crate::ca::CaGroups::default(),
        };
        e.build_groups(&config.groups)?;
        e.platform_cx()
            .build(config.platform_profile, &config.platform)?;
        Ok(e)
    }

    /// The collision-avoidance groups (outputs of CA instances, e.g. MC_GearInPosCA's InSync).
    pub fn ca_groups(&self) -> &crate::ca::CaGroups {
        &self.ca
    }

    /// Adds a collision-avoidance group (startup configuration, collision_avoidance.md §3.1).
    pub fn add_ca_group(
        &mut self,
        name: impl Into<String>,
        cfg: crate::ca::CaGroupConfig,
    ) -> Result<(), Rejection> {
        self.ca.add_group(name.into(), cfg)
    }

    /// NcToPlc status of axis `i` with the CA fields of its group.
    fn axis_status(&self, i: usize, master: bool) -> AxisStatus {
        let mut s = AxisStatus::default();
        self.axis_status_into(i, master, &mut s);
        s
    }

    /// [`Self::axis_status`] written into `s` in place (a snapshot's refill).
    fn axis_status_into(&self, i: usize, master: bool, s: &mut AxisStatus) {
        self.set.axis_status_into(i, master, s);
        self.ca.patch_status(i, s);
    }

    /// Axis names in configuration order.
    pub fn axis_names(&self) -> impl Iterator<Item = &str> {
        self.set.axes.iter().map(|a| a.name.as_ref())
    }

    /// The status of one axis.
    pub fn status(&self, axis: &str) -> Option<AxisStatus> {
        self.set
            .index
            .get(axis)
            .map(|&i| self.axis_status(i, self.set.is_master(i)))
    }

    /// Standard outputs of an admitted Execute-type instance (§3.1–§3.3).
    pub fn outputs(&self, id: CmdId) -> Option<ExecuteOutputs> {
        self.fb_outputs(id)
            .map(|o| o.standard)
            .or_else(|| self.group_outputs(id))
            .or_else(|| self.ca.outputs(id))
    }

    /// All outputs of an instance (incl. InVelocity).
    pub fn fb_outputs(&self, id: CmdId) -> Option<FbOutputs> {
        self.set.fb_outputs(id)
    }

    /// Outputs of the axis' MC_Power (Enable-type, §4.1).
    pub fn power_outputs(&self, axis: &str) -> Option<PowerOutputs> {
        self.set.power_outputs(axis)
    }

    /// The axis an instance belongs to and its FB.
    pub fn instance(&self, id: CmdId) -> Option<(&str, FbKind)> {
        self.set.instance(id)
    }

    /// Superposition outputs of an MC_MoveSuperImposed instance (§4.9).
    pub fn superimposed_outputs(
        &self,
        id: CmdId,
    ) -> Option<crate::superposition::SuperImposedOutputs> {
        self.set.superimposed_outputs(id)
    }

    /// Recorded data of an MC_TouchProbe instance (after its first accepted edge).
    pub fn probe_outputs(&self, id: CmdId) -> Option<crate::probe::ProbeOutputs> {
        self.set.probe_outputs(id)
    }

    /// MC_SetOverride.Enabled of the axis.
    pub fn set_override_enabled(&self, axis: &str) -> Option<bool> {
        self.set.set_override_enabled(axis)
    }

    /// Status of the added functions of one axis.
    pub fn ext_status(&self, axis: &str) -> Option<ExtStatus> {
        self.set.ext_status(axis)
    }

    /// The axis' initialization list of persistent parameters (§4.4.9), for the shell to
    /// store.
    pub fn persistent_parameters(&self, axis: &str) -> Option<Vec<(u32, f64)>> {
        self.set.persistent_parameters(axis)
    }

    /// Re-applies a stored initialization list at start (§4.4.9).
    pub fn apply_persistent_parameters(
        &mut self,
        axis: &str,
        list: &[(u32, f64)],
    ) -> Result<(), Rejection> {
        self.set.apply_persistent_parameters(axis, list)
    }
}

impl AxisEngine {
    /// One FB call: group and platform calls, instance updates, then single-axis FBs through
    /// the profile hooks.
    pub(crate) fn dispatch(&mut self, mut cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        match cmd {
            AxisCommand::Group(g) => return self.group_command_screened(g),
            AxisCommand::Platform(p) => return self.platform_command(p),
            AxisCommand::SetExecute { id, execute } => {
                if let Some(r) = self.group_set_execute(id, execute) {
                    return Ok(r);
                }
                return self.set.set_execute(id, execute).map(Into::into);
            }
            AxisCommand::ReadFbOutputs { id } => {
                if let Some(o) = self.group_outputs(id) {
                    return Ok(AxisReply {
                        id,
                        value: ReplyValue::Group(crate::group::GroupReply::Outputs(o)),
                        tracked: false,
                    });
                }
                if self.set.fbs.get(id).is_none() {
                    if let Some(outputs) = self.ca.outputs(id) {
                        let gear = self.ca.gear_outputs(id);
                        let v = crate::ca::CaValue::Outputs { outputs, gear };
                        return Ok(AxisReply {
                            id,
                            value: ReplyValue::Ca(Box::new(v)),
                            tracked: false,
                        });
                    }
                }
                return self.set.read_fb_outputs(id).map(Into::into);
            }
            AxisCommand::Ca(c) => {
                return self
                    .ca
                    .command(c, &mut self.set.axes, &self.set.index, &mut self.set.fbs)
                    .map(AxisReply::from)
            }
            AxisCommand::HomeCalibrationCam {
                id,
                calibration_cam,
            } => return self.set.home_cam(id, calibration_cam).map(Into::into),
            AxisCommand::TouchProbePlcEvent { id, plc_event } => {
                return self.set.probe_plc_event(id, plc_event).map(Into::into)
            }
            AxisCommand::TorqueControlUpdate {
                id,
                torque,
                torque_ramp,
                velocity_limit_high,
                velocity_limit_low,
            } => {
                return self
                    .set
                    .torque_update(
                        id,
                        torque,
                        torque_ramp,
                        velocity_limit_high,
                        velocity_limit_low,
                    )
                    .map(Into::into)
            }
            // A later call of a running phasing instance (by id, like the updates above).
            AxisCommand::PhasingUpdate(u) => return self.set.phasing_update(u).map(Into::into),
            _ => {}
        }
        let ax = self.set.axis_index(cmd.axis().unwrap_or_default())?;
        // Profile hooks (plcopen_platform.md): screening, then bookkeeping of the result.
        let (order, kind) = {
            let mut call = cmd.platform_call();
            self.platform_cx().screen(ax, &mut call)?;
            call.classify()
        };
        self.group_screen_axis_command(ax, &cmd)?;
        if cmd.is_plain_motion() {
            self.ca.screen_single_axis_motion(ax)?;
        }
        match self.axis_command(ax, cmd) {
            Ok(reply) => {
                self.platform_cx().accepted(ax, order, kind, reply.id);
                Ok(reply)
            }
            Err(r) => Err(self.platform_cx().refused(r)),
        }
    }
}

impl AxisEngine {
    /// One single-axis call (after the profile hooks), routed to its FB in [`AxisSet`].
    fn axis_command(&mut self, ax: usize, cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        let s = &mut self.set;
        let reply = match cmd {
            AxisCommand::Power(c) => s.power(ax, c),
            AxisCommand::Reset(_) => s.reset(ax),
            AxisCommand::MoveAbsolute(c) => s.move_absolute(ax, c),
            AxisCommand::MoveRelative(c) => s.move_relative(ax, c),
            AxisCommand::MoveAdditive(c) => s.move_additive(ax, c),
            AxisCommand::MoveModulo(c) => s.move_modulo(ax, c),
            AxisCommand::MoveVelocity(c) => s.move_velocity(ax, c),
            AxisCommand::MoveContinuousAbsolute(c) => s.move_continuous_absolute(ax, c),
            AxisCommand::MoveContinuousRelative(c) => s.move_continuous_relative(ax, c),
            AxisCommand::Halt(c) => s.halt(ax, c),
            AxisCommand::Stop(c) => s.stop(ax, c),
            AxisCommand::SetPosition(c) => s.set_position(ax, c),
            AxisCommand::ReadParameter(c) => s.read_parameter(ax, c),
            AxisCommand::ReadBoolParameter(c) => s.read_bool_parameter(ax, c),
            AxisCommand::WriteParameter(c) => s.write_parameter(ax, c),
            AxisCommand::WriteBoolParameter(c) => s.write_bool_parameter(ax, c),
            AxisCommand::ReadStatus(_) => {
                // The same source as the snapshot (CoupleState 1/2 of a master, CA fields).
                let st = self.axis_status(ax, self.set.is_master(ax));
                Ok(self.set.untracked(FbValue::Status(Box::new(st))))
            }
            AxisCommand::ReadActualPosition(_) => Ok(s.read_actual_position(ax)),
            AxisCommand::ReadActualVelocity(_) => Ok(s.read_actual_velocity(ax)),
            AxisCommand::ReadAxisError(_) => Ok(s.read_axis_error(ax)),
            AxisCommand::Sim(c) => s.sim(ax, c),
            AxisCommand::Home(c) => s.home(ax, c),
            AxisCommand::Jog(c) => s.jog(ax, c),
            AxisCommand::SetOverride(c) => s.set_override(ax, c),
            AxisCommand::GearIn(c) => s.gear_in(ax, c),
            AxisCommand::GearOut(_) => s.gear_out(ax),
            AxisCommand::GearInDyn(c) => s.gear_in_dyn(ax, c),
            AxisCommand::TorqueControl(c) => s.torque_control(ax, c),
            AxisCommand::MoveSuperImposed(c) => s.move_superimposed(ax, c),
            AxisCommand::TouchProbe(c) => s.touch_probe(ax, c),
            AxisCommand::AbortTrigger(c) => s.abort_trigger(ax, c),
            AxisCommand::AbortSuperposition(_) => s.abort_superposition(ax),
            AxisCommand::SetExecute { .. }
            | AxisCommand::HomeCalibrationCam { .. }
            | AxisCommand::TorqueControlUpdate { .. }
            | AxisCommand::TouchProbePlcEvent { .. }
            | AxisCommand::PhasingUpdate(_)
            | AxisCommand::ReadFbOutputs { .. }
            | AxisCommand::Group(_)
            | AxisCommand::Platform(_)
            | AxisCommand::Ca(_) => {
                unreachable!("handled above")
            }
            // The FBs added after the first release (phasing, multi-master gearing,
            // external set-point generator, §4.7 extensions).
            AxisCommand::PhasingAbsolute(c) => s.phasing_absolute(ax, c),
            AxisCommand::PhasingRelative(c) => s.phasing_relative(ax, c),
            AxisCommand::HaltPhasing(c) => s.halt_phasing(ax, c),
            AxisCommand::GearInMultiMaster(c) => s.gear_in_multi_master(ax, c),
            AxisCommand::ExtSetPointGenEnable(c) => s.ext_set_point_gen_enable(ax, c),
            AxisCommand::ExtSetPointGenDisable(_) => s.ext_set_point_gen_disable(ax),
            AxisCommand::ExtSetPointGenFeed(c) => s.ext_set_point_gen_feed(
                ax,
                "MC_ExtSetPointGenFeed",
                State1 {
                    pos: c.position,
                    vel: c.velocity,
                    acc: c.acceleration,
                },
                c.direction,
                0.0,
            ),
            AxisCommand::ExtSetPointGenFeedWithTorque(c) => s.ext_set_point_gen_feed(
                ax,
                "MC_ExtSetPointGenFeedWithTorque",
                State1 {
                    pos: c.position,
                    vel: c.velocity,
                    acc: c.acceleration,
                },
                c.direction,
                c.torque_offset,
            ),
            AxisCommand::ReadDriveOperationMode(_) => s.read_drive_operation_mode(ax),
            AxisCommand::WriteDriveOperationMode(c) => s.write_drive_operation_mode(ax, c),
            AxisCommand::BacklashCompensation(c) => s.backlash_compensation(ax, c),
            AxisCommand::PositionCorrectionLimiter(c) => s.position_correction_limiter(ax, c),
            AxisCommand::ReadDriveAddress(_) => s.read_drive_address(ax),
            AxisCommand::SelectControlLoop(c) => s.select_control_loop(ax, c),
            AxisCommand::SetAcceptBlockedDriveSignal(c) => s.set_accept_blocked_drive_signal(ax, c),
            AxisCommand::SetEncoderScalingFactor(c) => s.set_encoder_scaling_factor(ax, c),
            AxisCommand::WriteNcIoOutput(c) => s.write_nc_io_output(ax, c),
            AxisCommand::TableBasedPositionCompensation(c) => {
                s.table_based_position_compensation(ax, c)
            }
            AxisCommand::ConvertIncPosToPos(c) => s.convert_inc_pos_to_pos(ax, c),
            AxisCommand::ConvertPosToIncPos(c) => s.convert_pos_to_inc_pos(ax, c),
            AxisCommand::ReadParameterSet(_) => s.read_parameter_set(ax),
            AxisCommand::ReadAxisComponents(_) => s.read_axis_components(ax),
            AxisCommand::WriteParameterPersistent(c) => s.write_param_persistent(ax, c, false),
            AxisCommand::WriteBoolParameterPersistent(c) => {
                let c = WriteParameter {
                    axis: c.axis,
                    parameter_number: c.parameter_number,
                    value: c.value as u8 as f64,
                };
                s.write_param_persistent(ax, c, true)
            }
        };
        reply.map(Into::into)
    }
}

impl Engine for AxisEngine {
    type Command = AxisCommand;
    type Reply = AxisReply;
    type Snapshot = AxisSnapshot;

    fn command(&mut self, cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        self.dispatch(cmd)
    }

    /// MC_Stop on every axis with its AxisFastDec/AxisFastJerk (the error reaction's
    /// dynamics); an axis that cannot take it (disabled, already stopping) is left as it is.
    fn fail_safe_stop(&mut self) {
        for i in 0..self.set.axes.len() {
            let a = &self.set.axes[i];
            let stop = Stop {
                axis: str::to_owned(&a.name),
                deceleration: a.cfg.fast_deceleration,
                jerk: a.cfg.fast_jerk,
                options: MoveOptions::default(),
            };
            let _ = self.dispatch(AxisCommand::Stop(stop));
        }
    }

    fn at_rest(&self) -> bool {
        (0..self.set.axes.len()).all(|i| self.axis_status(i, false).set_velo == 0.0)
    }

    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        // A non-positive or non-finite cycle time cannot advance anything (defensive: the
        // runtime always passes the configured period).
        if !(tick.dt > 0.0 && tick.dt.is_finite()) {
            events.append(&mut self.set.fbs.events);
            return;
        }
        self.tick = tick.index;
        self.set.begin_cycle();
        self.platform_cx().step_pre();
        self.groups_step(tick.dt);
        self.ca.step(tick.dt, &mut self.set.axes, &mut self.set.fbs);
        self.set.step_axes(tick.dt);
        self.platform_cx().step_post();
        self.set.end_cycle();
        let from = events.len();
        events.append(&mut self.set.fbs.events);
        self.platform_cx().map_events(&mut events[from..]);
        // Events of orders the raw FB layer placed become its acknowledgements.
        let set = &self.set;
        self.raw
            .route(events, from, &|id, e| set.shown_error_id(id, e));
    }

    fn snapshot(&self) -> AxisSnapshot {
        let mut s = AxisSnapshot::default();
        self.snapshot_into(&mut s);
        s
    }

    fn snapshot_into(&self, out: &mut AxisSnapshot) {
        let master = self.set.masters();
        let starting = self.platform.starting();
        out.tick = self.tick;
        // Refilled in place: an old snapshot's statuses are overwritten, not rebuilt.
        out.axes
            .resize_with(self.set.axes.len(), AxisStatus::default);
        for (i, s) in out.axes.iter_mut().enumerate() {
            self.axis_status_into(i, master.get(i).copied().unwrap_or(false), s);
            s.ext = self.set.ext_values(i);
            if starting {
                // INIT_STATE during start-up (§9).
                s.motion_state = crate::state::MotionState::Undefined;
            }
        }
        out.groups.clear();
        out.groups
            .extend((0..self.groups.list.len()).map(|g| self.group_status(g)));
        out.platform = self.platform_status();
        out.ca_groups = self.ca.snapshot(&self.set.axes);
    }

    fn reply_id(reply: &AxisReply) -> Option<CmdId> {
        // Read-type calls and MC_Power have no lifetime of their own: nothing to watch.
        reply.tracked.then_some(reply.id)
    }

    fn error_text(id: ErrorId) -> String {
        if let Some(t) = crate::platform::ids::text(id) {
            return format!("{}: {t}", id.0);
        }
        crate::error_ids::text(id)
    }

    fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
        if let Some(r) = self.group_cancel(id) {
            return r;
        }
        // A cancelled goal halts the axis with the command's own dynamics (MC_Halt semantics).
        if self.set.fbs.get(id).is_none() && self.ca.owns(id) {
            return self.ca.cancel(id, &self.set.axes, &mut self.set.fbs);
        }
        self.set.cancel(id)
    }
}

// ---- The composition's glue to the Part 4 groups.
mod groups;
mod platform;
