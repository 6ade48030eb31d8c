//! The routing of the FBs added after the first release (phasing, multi-master gearing,
//! external set-point generator, §4.7 extensions; their semantics live in
//! `single_axis::set`): [`AxisEngine::command_axis3`], called by `dispatch` after the profile
//! hooks.

use super::*;

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
            return self.set.phasing_update(u).map(Into::into);
        }
        let s = &mut self.set;
        let ax = s.axis_index(cmd.axis().unwrap_or_default())?;
        let reply = match cmd {
            C::PhasingAbsolute(c) => s.phasing_absolute(ax, c),
            C::PhasingRelative(c) => s.phasing_relative(ax, c),
            C::HaltPhasing(c) => s.halt_phasing(ax, c),
            C::GearInMultiMaster(c) => s.gear_in_multi_master(ax, c),
            C::ExtSetPointGenEnable(c) => s.ext_set_point_gen_enable(ax, c),
            C::ExtSetPointGenDisable(_) => s.ext_set_point_gen_disable(ax),
            C::ExtSetPointGenFeed(c) => s.ext_set_point_gen_feed(
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
            C::ExtSetPointGenFeedWithTorque(c) => s.ext_set_point_gen_feed(
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
            C::ReadDriveOperationMode(_) => s.read_drive_operation_mode(ax),
            C::WriteDriveOperationMode(c) => s.write_drive_operation_mode(ax, c),
            C::BacklashCompensation(c) => s.backlash_compensation(ax, c),
            C::PositionCorrectionLimiter(c) => s.position_correction_limiter(ax, c),
            C::ReadDriveAddress(_) => s.read_drive_address(ax),
            C::SelectControlLoop(c) => s.select_control_loop(ax, c),
            C::SetAcceptBlockedDriveSignal(c) => s.set_accept_blocked_drive_signal(ax, c),
            C::SetEncoderScalingFactor(c) => s.set_encoder_scaling_factor(ax, c),
            C::WriteNcIoOutput(c) => s.write_nc_io_output(ax, c),
            C::TableBasedPositionCompensation(c) => s.table_based_position_compensation(ax, c),
            C::ConvertIncPosToPos(c) => s.convert_inc_pos_to_pos(ax, c),
            C::ConvertPosToIncPos(c) => s.convert_pos_to_inc_pos(ax, c),
            C::ReadParameterSet(_) => s.read_parameter_set(ax),
            C::ReadAxisComponents(_) => s.read_axis_components(ax),
            C::WriteParameterPersistent(c) => s.write_param_persistent(ax, c, false),
            C::WriteBoolParameterPersistent(c) => {
                let c = WriteParameter {
                    axis: c.axis,
                    parameter_number: c.parameter_number,
                    value: c.value as u8 as f64,
                };
                s.write_param_persistent(ax, c, true)
            }
            other => unreachable!("not an added command: {other:?}"),
        };
        reply.map(Into::into)
    }
}
