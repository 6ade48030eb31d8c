//! The one place where the FBs of [`super::phasing`], [`super::multi_master`],
//! [`super::ext_setpoint`] and [`super::extensions`] plug into the engine: command dispatch
//! ([`AxisEngine::command_axis3`], called first by `command`), the per-cycle work before and
//! after each axis' step, the Execute-falling hook, the extra instance outputs and the status
//! of these functions ([`ExtStatus`]).

use super::*;

pub use crate::handshake::ExtraOutputs;

/// True for the commands of the added FBs (handled by [`AxisEngine::command_axis3`]).
pub(crate) fn is_axis3(cmd: &AxisCommand) -> bool {
    use AxisCommand as C;
    matches!(
        cmd,
        C::PhasingAbsolute(_)
            | C::PhasingRelative(_)
            | C::HaltPhasing(_)
            | C::PhasingUpdate(_)
            | C::GearInMultiMaster(_)
            | C::ExtSetPointGenEnable(_)
            | C::ExtSetPointGenDisable(_)
            | C::ExtSetPointGenFeed(_)
            | C::ExtSetPointGenFeedWithTorque(_)
            | C::ReadDriveOperationMode(_)
            | C::WriteDriveOperationMode(_)
            | C::BacklashCompensation(_)
            | C::PositionCorrectionLimiter(_)
            | C::ReadDriveAddress(_)
            | C::SelectControlLoop(_)
            | C::SetAcceptBlockedDriveSignal(_)
            | C::SetEncoderScalingFactor(_)
            | C::WriteNcIoOutput(_)
            | C::TableBasedPositionCompensation(_)
            | C::ConvertIncPosToPos(_)
            | C::ConvertPosToIncPos(_)
            | C::ReadParameterSet(_)
            | C::ReadAxisComponents(_)
            | C::WriteParameterPersistent(_)
            | C::WriteBoolParameterPersistent(_)
    )
}

impl AxisEngine {
    /// Dispatch of the added commands (those for which [`is_axis3`] holds).
    pub(super) fn command_axis3(&mut self, cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        use AxisCommand as C;
        if let C::PhasingUpdate(u) = cmd {
            return self.phasing_update(u);
        }
        let ax = self.axis_index(cmd.axis().unwrap_or_default())?;
        match cmd {
            C::PhasingAbsolute(c) => self.phasing_absolute(ax, c),
            C::PhasingRelative(c) => self.phasing_relative(ax, c),
            C::HaltPhasing(c) => self.halt_phasing(ax, c),
            C::GearInMultiMaster(c) => self.gear_in_multi_master(ax, c),
            C::ExtSetPointGenEnable(c) => self.ext_set_point_gen_enable(ax, c),
            C::ExtSetPointGenDisable(_) => self.ext_set_point_gen_disable(ax),
            C::ExtSetPointGenFeed(c) => self.ext_set_point_gen_feed(
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
            C::ExtSetPointGenFeedWithTorque(c) => self.ext_set_point_gen_feed(
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
            C::ReadDriveOperationMode(_) => self.read_drive_operation_mode(ax),
            C::WriteDriveOperationMode(c) => self.write_drive_operation_mode(ax, c),
            C::BacklashCompensation(c) => self.backlash_compensation(ax, c),
            C::PositionCorrectionLimiter(c) => self.position_correction_limiter(ax, c),
            C::ReadDriveAddress(_) => self.read_drive_address(ax),
            C::SelectControlLoop(c) => self.select_control_loop(ax, c),
            C::SetAcceptBlockedDriveSignal(c) => self.set_accept_blocked_drive_signal(ax, c),
            C::SetEncoderScalingFactor(c) => self.set_encoder_scaling_factor(ax, c),
            C::WriteNcIoOutput(c) => self.write_nc_io_output(ax, c),
            C::TableBasedPositionCompensation(c) => self.table_based_position_compensation(ax, c),
            C::ConvertIncPosToPos(c) => self.convert_inc_pos_to_pos(ax, c),
            C::ConvertPosToIncPos(c) => self.convert_pos_to_inc_pos(ax, c),
            C::ReadParameterSet(_) => self.read_parameter_set(ax),
            C::ReadAxisComponents(_) => self.read_axis_components(ax),
            C::WriteParameterPersistent(c) => self.write_param_persistent(ax, c, false),
            C::WriteBoolParameterPersistent(c) => {
                let c = WriteParameter {
                    axis: c.axis,
                    parameter_number: c.parameter_number,
                    value: c.value as u8 as f64,
                };
                self.write_param_persistent(ax, c, true)
            }
            other => unreachable!("not an added command: {other:?}"),
        }
    }

    /// Before axis `i` steps: external set points, multi-master inputs, phasing. No alloc.
    pub(super) fn pre_step_axis3(&mut self, i: usize, dt: f64) {
        self.ext_setpoint_step(i);
        self.multi_master_step(i);
        self.phasing_step(i, dt);
    }

    /// After axis `i` stepped: drive mode and position corrections. No alloc.
    pub(super) fn post_step_axis3(&mut self, i: usize, dt: f64) {
        self.extensions_step(i, dt);
    }

    /// Execute (or Enable) of an instance changed.
    pub(super) fn set_execute_axis3(
        &mut self,
        inst: &crate::handshake::Instance,
        id: CmdId,
        execute: bool,
    ) {
        if !execute && matches!(inst.kind, FbKind::PhasingAbsolute | FbKind::PhasingRelative) {
            self.phasing_execute_fell(id);
        }
    }

    /// A cancelled goal of an added FB: MC_PhasingAbsolute/Relative → MC_HaltPhasing with
    /// the slave's default dynamics (the phasing FB ends with CommandAborted). True when
    /// handled.
    pub(super) fn cancel_axis3(&mut self, inst: &crate::handshake::Instance, id: CmdId) -> bool {
        if !matches!(inst.kind, FbKind::PhasingAbsolute | FbKind::PhasingRelative) {
            return false;
        }
        self.halt_phasing_of(inst.axis, id);
        true
    }

    /// Extra outputs of an instance of the added FBs.
    pub(super) fn extra_outputs(&self, id: CmdId) -> Option<ExtraOutputs> {
        let inst = self.fbs.get(id)?;
        match inst.kind {
            FbKind::ExtSetPointGenEnable | FbKind::ExtSetPointGenDisable => {
                Some(ExtraOutputs::ExtSetPointGen {
                    enabled: self.axes[inst.axis].ext.ext_gen.enabled,
                })
            }
            _ => self.fbs.extra.get(&id).copied(),
        }
    }

    /// The scalar NcToPlc values of [`Self::ext_status`] for the snapshot.
    pub(crate) fn ext_values(&self, i: usize) -> crate::status::ExtValues {
        let a = &self.axes[i];
        let g = &a.ext.ext_gen;
        let corr = a.ext.x.correction();
        let (f, off) = (a.cfg.encoder_scaling_factor, a.cfg.encoder_offset);
        crate::status::ExtValues {
            abs_phasing_pos: a.abs_phasing_pos(),
            act_pos_without_pos_correction: a.act_pos - corr,
            position_correction: corr,
            drive_set_pos: a.set.pos - corr,
            ext_set_pos: g.fed.pos,
            ext_set_velo: g.fed.vel,
            ext_set_acc: g.fed.acc,
            ext_torque: g.torque_offset,
            encoder_increments: ((a.act_pos - off) / f).round().rem_euclid(4_294_967_296.0) as u32,
            control_loop_index: a.ext.x.control_loop_index,
        }
    }

    /// Status of the added functions of one axis.
    pub fn ext_status(&self, axis: &str) -> Option<ExtStatus> {
        let &i = self.index.get(axis)?;
        let v = self.ext_values(i);
        let a = &self.axes[i];
        let g = &a.ext.ext_gen;
        Some(ExtStatus {
            abs_phasing_pos: v.abs_phasing_pos,
            phasing_active: a.phasing_active(),
            ext_set_point_gen_enabled: g.enabled,
            ext_set_pos: v.ext_set_pos,
            ext_set_velo: v.ext_set_velo,
            ext_set_acc: v.ext_set_acc,
            ext_set_direction: g.direction,
            ext_torque: v.ext_torque,
            drive_operation_mode: a.ext.x.drive_mode,
            position_correction: v.position_correction,
            act_pos_without_pos_correction: v.act_pos_without_pos_correction,
            drive_set_pos: v.drive_set_pos,
            encoder_scaling_factor: a.cfg.encoder_scaling_factor,
            encoder_offset: a.cfg.encoder_offset,
            encoder_increments: v.encoder_increments,
            control_loop_index: v.control_loop_index,
            accept_blocked_drive: a.ext.accept_blocked_drive,
            nc_io_outputs: a.ext.x.nc_io,
            masters: a
                .coupling
                .filter(|c| c.ext.multi.is_some())
                .map(|c| c.masters().map(|m| self.axes[m].name.clone()).collect())
                .unwrap_or_default(),
        })
    }
}
