//! Special extensions (single_axis.md §4.7, §4.4.3, §4.4.6, §4.4.9), each modelled as far as a
//! simulated axis can:
//!
//! * MC_Read/WriteDriveOperationMode (§4.7.1): the mode is stored (default
//!   DriveOperationMode_Pos1 = CSP; Default (0) restores it). MC_TorqueControl switches it to
//!   Torque (1) while running; when torque mode ends without an axis error (MC_Halt, MC_Stop,
//!   another command) it goes back to Pos1, after an error it stays Torque (§4.14).
//!   Admission per §2.4: not in Homing/DiscreteMotion/ContinuousMotion/SynchronizedMotion
//!   (0x4B01). Read replies [`ExtensionValue::DriveOperationMode`].
//! * Position correction (§1.1): MC_BacklashCompensation, MC_PositionCorrectionLimiter and
//!   MC_TableBasedPositionCompensation each produce a correction value; their sum is the
//!   axis' position correction. No physical backlash exists in the simulation, so the
//!   correction is bookkeeping: the closed position loop keeps the corrected actual position
//!   on the set position (ActPos and the state machine are unchanged) and the correction shows
//!   as `ActPosWithoutPosCorrection = ActPos − correction` and as the drive set position
//!   `SetPos − correction` ([`crate::added_inputs::ExtStatus`]). All three need
//!   AxisEnablePosCorrection (1046) = TRUE, else 0x4B04 (TwinCAT doc for the backlash FB;
//!   applied to all three, proposal). They are Enable-type: Enable↑ starts an instance (reply
//!   id), calls with Enable TRUE update its inputs (same id), Enable↓ ends it (Done, outputs
//!   reset) with the DisableMode of that call (Hold keeps the last correction, Reset sets it to 0; the
//!   limiter has no DisableMode and holds). `Ramp` / `Acceleration` = 0 means no rate limit
//!   (proposal); negative → 0x4B06. The travel direction used by the backlash and the table
//!   is the last non-zero set velocity sign.
//! * MC_SetEncoderScalingFactor (§4.7.9) with the encoder model of §1.1
//!   (`inc = round((ActPos − offset)/ScalingFactor)`, AxisEncoderScalingFactor 1040,
//!   AxisEncoderOffset 1041): ABSOLUTE moves the coordinate system so that ActPos =
//!   inc·new factor + offset (the position jumps, set position shifted alike so a following
//!   error is kept); RELATIVE adjusts the offset so ActPos does not jump. Not modelled: the
//!   simulated drive keeps following the NC set points 1:1 afterwards (the real "velocity
//!   jump" of a rescaled encoder does not appear). Factor ≤ 0, EncoderIndex ≠ 0 → 0x4B06.
//! * MC_ConvertIncPosToPos / MC_ConvertPosToIncPos (§4.7.13): with the same model, a 32-bit
//!   counter interpreted nearest to the current actual position; a position farther than half
//!   the counter range from ActPos → 0x4B06. Replies `Real` / `DWord`.
//! * MC_SelectControlLoop (§4.7.7): one control loop: EncoderIndex 0 → Done, others 0x4B06;
//!   SelectType ≠ Standard → 0x4B04.
//! * MC_SetAcceptBlockedDriveSignal (§4.7.8, FUNCTION : BOOL, return value always FALSE):
//!   ControlDWord bit 8; while TRUE the position-lag monitoring raises no error.
//! * MC_WriteNcIoOutput (§4.7.11): a 32-bit image per device and output,
//!   `new = (old AND NOT mask) OR (values AND mask)`, published in [`crate::added_inputs::ExtStatus`].
//! * MC_ReadParameterSet (§4.4.6), MC_ReadAxisComponents (§4.4.3), MC_ReadDriveAddress (§4.7.6):
//!   filled from the configuration (one encoder, controller and drive per axis with the axis
//!   id; NetId 127.0.0.1.1.1, port 0; encoder type Simulation, axis type Continious).
//!   Execute-type: the reply carries the value, the instance is Done in the next cycle.
//! * MC_Write(Bool)ParameterPersistent (§4.4.9): written like MC_Write(Bool)Parameter and kept
//!   in the axis' initialization list ([`AxisSet::persistent_parameters`]). The engine does
//!   no I/O: storing the list in a file keyed by a configuration hash and re-applying it at
//!   start ([`AxisSet::apply_persistent_parameters`]) is the shell's job.

use super::*;
use crate::added::*;

pub use crate::extension_inputs::*;

/// Moves `x` towards `target` by at most `max_step` (∞ = at once).
fn approach(x: f64, target: f64, max_step: f64) -> f64 {
    let d = target - x;
    if d.abs() <= max_step {
        target
    } else {
        x + max_step * d.signum()
    }
}

fn rate_step(rate: f64, dt: f64) -> f64 {
    if rate > 0.0 {
        rate * dt
    } else {
        f64::INFINITY
    }
}

/// Linear interpolation in an equidistant table (end values held outside).
fn interpolate(t: &[PositionCompensationTableElement], p: f64) -> f64 {
    let (first, last) = (t[0], t[t.len() - 1]);
    if p <= first.position {
        return first.compensation;
    }
    if p >= last.position {
        return last.compensation;
    }
    let step = (last.position - first.position) / (t.len() - 1) as f64;
    let k = (((p - first.position) / step).floor() as usize).min(t.len() - 2);
    let (a, b) = (t[k], t[k + 1]);
    a.compensation
        + (b.compensation - a.compensation) * (p - a.position) / (b.position - a.position)
}

const COUNTER: f64 = 4_294_967_296.0;

impl AxisSet {
    fn need_pos_correction(&self, ax: usize, fb: &str) -> Result<(), Rejection> {
        let a = &self.axes[ax];
        if a.cfg.enable_pos_correction {
            Ok(())
        } else {
            Err(reject(
                INVALID_MODE,
                format!(
                    "axis '{}': {fb}: position correction is not enabled \
                     (AxisEnablePosCorrection 1046 = FALSE)",
                    a.name
                ),
            ))
        }
    }

    /// An instantaneous Execute-type command: Busy now, Done in the next cycle.
    fn instant(&mut self, ax: usize, kind: FbKind, value: FbValue) -> FbReply {
        let id = self.fbs.admit(ax, kind, CommandState::Busy);
        self.instant_done.push(id);
        FbReply {
            id,
            value,
            tracked: true,
        }
    }

    /// Ends an Enable-type instance at Enable↓ (Done, outputs reset).
    fn end_enable_instance(&mut self, id: CmdId) -> FbReply {
        self.fbs.done(id);
        self.fbs.set_execute(id, false);
        Self::reply(id)
    }

    /// MC_ReadDriveOperationMode (§4.7.1).
    pub fn read_drive_operation_mode(&mut self, ax: usize) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::DriveOperationMode, "MC_ReadDriveOperationMode")?;
        let m = self.axes[ax].ext.x.drive_mode;
        let v = FbValue::Extension(Box::new(ExtensionValue::DriveOperationMode(m)));
        Ok(self.instant(ax, FbKind::ReadDriveOperationMode, v))
    }

    /// MC_WriteDriveOperationMode (§4.7.1).
    pub fn write_drive_operation_mode(
        &mut self,
        ax: usize,
        c: WriteDriveOperationMode,
    ) -> Result<FbReply, Rejection> {
        self.admit_state(
            ax,
            FbClass::DriveOperationMode,
            "MC_WriteDriveOperationMode",
        )?;
        let x = &mut self.axes[ax].ext.x;
        x.drive_mode = match c.drive_operation_mode {
            DriveOperationMode::Default => DriveOperationMode::Pos1,
            m => m,
        };
        x.torque_seen = false;
        Ok(self.instant(ax, FbKind::WriteDriveOperationMode, FbValue::None))
    }

    /// MC_BacklashCompensation (§4.7.2).
    pub fn backlash_compensation(
        &mut self,
        ax: usize,
        c: BacklashCompensation,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_BacklashCompensation";
        let running = self.axes[ax].ext.x.backlash.map(|b| b.owner);
        if !c.enable {
            let Some(id) = running else {
                return Ok(self.untracked(FbValue::None));
            };
            let x = &mut self.axes[ax].ext.x;
            // DisableMode as given with this call (inputs are read every call, §3.4).
            x.backlash = None;
            if c.disable_mode == DisableMode::Reset {
                x.backlash_corr = 0.0;
            }
            return Ok(self.end_enable_instance(id));
        }
        let name = self.axes[ax].name.clone();
        finite(&name, fb, "Backlash", c.backlash)?;
        finite(&name, fb, "Ramp", c.ramp)?;
        if c.ramp < 0.0 {
            return Err(not_correct(
                &name,
                fb,
                "Ramp",
                c.ramp,
                "must be >= 0 (0 = at once)",
            ));
        }
        let backlash = if c.backlash == 0.0 {
            self.axes[ax].cfg.backlash
        } else {
            c.backlash
        };
        let state = |owner| Backlash {
            owner,
            backlash,
            positive: c.compensation_in_positive_direction,
            ramp: c.ramp,
        };
        if let Some(id) = running {
            self.axes[ax].ext.x.backlash = Some(state(id));
            return Ok(Self::reply(id));
        }
        self.need_pos_correction(ax, fb)?;
        self.admit_state(ax, FbClass::Correction, fb)?;
        let id = self
            .fbs
            .admit(ax, FbKind::BacklashCompensation, CommandState::Active);
        let x = &mut self.axes[ax].ext.x;
        x.backlash = Some(state(id));
        self.fbs.extra.insert(
            id,
            ExtraOutputs::Backlash {
                enabled: true,
                current_backlash: x.backlash_corr,
                limiting: false,
            },
        );
        Ok(Self::reply(id))
    }

    /// MC_PositionCorrectionLimiter (§4.7.5).
    pub fn position_correction_limiter(
        &mut self,
        ax: usize,
        c: PositionCorrectionLimiter,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_PositionCorrectionLimiter";
        let running = self.axes[ax].ext.x.limiter;
        if !c.enable {
            let Some(l) = running else {
                return Ok(self.untracked(FbValue::None));
            };
            self.axes[ax].ext.x.limiter = None;
            return Ok(self.end_enable_instance(l.owner));
        }
        let name = self.axes[ax].name.clone();
        for (f, v) in [
            ("PositionCorrectionValue", c.position_correction_value),
            ("Acceleration", c.acceleration),
            ("CorrectionLength", c.correction_length),
        ] {
            finite(&name, fb, f, v)?;
        }
        if c.acceleration < 0.0 {
            return Err(not_correct(
                &name,
                fb,
                "Acceleration",
                c.acceleration,
                "must be >= 0 (0 = no limit)",
            ));
        }
        if c.correction_mode == PositionCorrectionMode::FullLength && c.correction_length <= 0.0 {
            return Err(not_correct(
                &name,
                fb,
                "CorrectionLength",
                c.correction_length,
                "must be > 0 with POSITIONCORRECTION_MODE_FULLLENGTH",
            ));
        }
        let corr = self.axes[ax].ext.x.limiter_corr;
        if let Some(mut l) = running {
            if l.value != c.position_correction_value {
                l.change = c.position_correction_value - corr;
            }
            l.value = c.position_correction_value;
            l.mode = c.correction_mode;
            l.acceleration = c.acceleration;
            l.length = c.correction_length;
            self.axes[ax].ext.x.limiter = Some(l);
            return Ok(Self::reply(l.owner));
        }
        self.need_pos_correction(ax, fb)?;
        self.admit_state(ax, FbClass::Correction, fb)?;
        let id = self
            .fbs
            .admit(ax, FbKind::PositionCorrectionLimiter, CommandState::Active);
        self.axes[ax].ext.x.limiter = Some(Limiter {
            owner: id,
            value: c.position_correction_value,
            mode: c.correction_mode,
            acceleration: c.acceleration,
            length: c.correction_length,
            change: c.position_correction_value - corr,
        });
        self.fbs
            .extra
            .insert(id, ExtraOutputs::CorrectionLimiter { limiting: false });
        Ok(Self::reply(id))
    }

    /// MC_TableBasedPositionCompensation (§4.7.12).
    pub fn table_based_position_compensation(
        &mut self,
        ax: usize,
        c: TableBasedPositionCompensation,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_TableBasedPositionCompensation";
        let running = self.axes[ax].ext.x.table.as_ref().map(|t| t.owner);
        if !c.enable {
            let Some(id) = running else {
                return Ok(self.untracked(FbValue::None));
            };
            let x = &mut self.axes[ax].ext.x;
            x.table = None;
            if c.disable_mode == DisableMode::Reset {
                x.table_corr = 0.0;
            }
            return Ok(self.end_enable_instance(id));
        }
        let name = self.axes[ax].name.clone();
        let p = c.table_parameter;
        finite(&name, fb, "Ramp", c.ramp)?;
        finite(&name, fb, "TableParameter.MinPosition", p.min_position)?;
        finite(&name, fb, "TableParameter.MaxPosition", p.max_position)?;
        for (k, e) in c.table.iter().enumerate() {
            finite(&name, fb, &format!("Table[{k}].Position"), e.position)?;
            finite(
                &name,
                fb,
                &format!("Table[{k}].Compensation"),
                e.compensation,
            )?;
        }
        if c.ramp < 0.0 {
            return Err(not_correct(
                &name,
                fb,
                "Ramp",
                c.ramp,
                "must be >= 0 (0 = at once)",
            ));
        }
        let n = c.table.len();
        let bad = |what: String| {
            reject(
                PARAMETER_NOT_CORRECT,
                format!("axis '{name}': {fb}: {what}"),
            )
        };
        if n < 2 || n != p.no_of_table_elements as usize {
            return Err(bad(format!(
                "table has {n} elements, TableParameter.NoOfTableElements = {} (need >= 2, equal)",
                p.no_of_table_elements
            )));
        }
        let step = (p.max_position - p.min_position) / (n - 1) as f64;
        let tol = 1e-9 * (p.max_position - p.min_position).abs().max(1.0);
        if step <= 0.0 {
            return Err(bad(format!(
                "MinPosition {} must be below MaxPosition {}",
                p.min_position, p.max_position
            )));
        }
        for (k, e) in c.table.iter().enumerate() {
            let want = p.min_position + k as f64 * step;
            if (e.position - want).abs() > tol {
                return Err(bad(format!(
                    "Table[{k}].Position = {} (the table must be equidistant and strictly \
                     increasing from MinPosition to MaxPosition: expected {want})",
                    e.position
                )));
            }
        }
        let state = |owner| Table {
            owner,
            table: c.table.clone(),
            param: p,
            ramp: c.ramp,
        };
        if let Some(id) = running {
            self.axes[ax].ext.x.table = Some(state(id));
            return Ok(Self::reply(id));
        }
        self.need_pos_correction(ax, fb)?;
        self.admit_state(ax, FbClass::Correction, fb)?;
        let id = self.fbs.admit(
            ax,
            FbKind::TableBasedPositionCompensation,
            CommandState::Active,
        );
        let x = &mut self.axes[ax].ext.x;
        x.table = Some(state(id));
        self.fbs.extra.insert(
            id,
            ExtraOutputs::TableCompensation {
                enabled: true,
                current_correction: x.table_corr,
                limiting: false,
            },
        );
        Ok(Self::reply(id))
    }

    /// MC_ReadDriveAddress (§4.7.6).
    pub fn read_drive_address(&mut self, ax: usize) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::ReadWrite, "MC_ReadDriveAddress")?;
        let id = self.axes[ax].cfg.axis_id;
        let d = DriveAddress {
            net_id: "127.0.0.1.1.1".into(),
            net_id_bytes: [127, 0, 0, 1, 1, 1],
            slave_address: 0,
            channel: 0,
            nc_drive_id: id,
            nc_drive_index: 0,
            nc_drive_type: 0,
            nc_encoder_id: id,
            nc_encoder_index: 0,
            nc_encoder_type: 1,
            nc_axis_id: id,
            nc_axis_type: 1,
            tc_drive_object_id: 0,
            tc_encoder_object_id: 0,
            tc_axis_object_id: 0,
        };
        let v = FbValue::Extension(Box::new(ExtensionValue::DriveAddress(d)));
        Ok(self.instant(ax, FbKind::ReadDriveAddress, v))
    }

    /// MC_SelectControlLoop (§4.7.7).
    pub fn select_control_loop(
        &mut self,
        ax: usize,
        c: SelectControlLoop,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_SelectControlLoop";
        let name = self.axes[ax].name.clone();
        finite(&name, fb, "SyncValue", c.sync_value)?;
        if c.select_type != SelectControlLoopType::Standard {
            return Err(reject(
                INVALID_MODE,
                format!(
                    "axis '{name}': {fb}: SelectType {:?} (only SelectControlLoopType_Standard)",
                    c.select_type
                ),
            ));
        }
        if c.encoder_index != 0 {
            return Err(not_correct(
                &name,
                fb,
                "EncoderIndex",
                c.encoder_index as f64,
                "must be 0 (one control loop)",
            ));
        }
        self.admit_state(ax, FbClass::Correction, fb)?;
        self.axes[ax].ext.x.control_loop_index = 0;
        Ok(self.instant(ax, FbKind::SelectControlLoop, FbValue::None))
    }

    /// MC_SetAcceptBlockedDriveSignal (§4.7.8).
    pub fn set_accept_blocked_drive_signal(
        &mut self,
        ax: usize,
        c: SetAcceptBlockedDriveSignal,
    ) -> Result<FbReply, Rejection> {
        self.axes[ax].ext.accept_blocked_drive = c.enable;
        Ok(self.untracked(FbValue::Bool(false)))
    }

    /// MC_SetEncoderScalingFactor (§4.7.9).
    pub fn set_encoder_scaling_factor(
        &mut self,
        ax: usize,
        c: SetEncoderScalingFactor,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_SetEncoderScalingFactor";
        let name = self.axes[ax].name.clone();
        finite(&name, fb, "ScalingFactor", c.scaling_factor)?;
        if c.scaling_factor <= 0.0 {
            return Err(not_correct(
                &name,
                fb,
                "ScalingFactor",
                c.scaling_factor,
                "must be > 0",
            ));
        }
        if c.options.select_encoder_index && c.options.encoder_index != 0 {
            return Err(not_correct(
                &name,
                fb,
                "Options.EncoderIndex",
                c.options.encoder_index as f64,
                "must be 0 (one encoder)",
            ));
        }
        self.admit_state(ax, FbClass::Correction, fb)?;
        let a = &self.axes[ax];
        let (f, off) = (a.cfg.encoder_scaling_factor, a.cfg.encoder_offset);
        let inc = ((a.act_pos - off) / f).round();
        // ABSOLUTE: the new actual position; RELATIVE: the new offset.
        let new = match c.mode {
            SetScalingFactorMode::Absolute => inc * c.scaling_factor + off,
            SetScalingFactorMode::Relative => a.act_pos - inc * c.scaling_factor,
        };
        if !new.is_finite() || new.abs() > 1e15 {
            return Err(not_correct(
                &name,
                fb,
                "ScalingFactor",
                c.scaling_factor,
                &format!("gives a position or offset out of range ({new})"),
            ));
        }
        let a = &mut self.axes[ax];
        match c.mode {
            SetScalingFactorMode::Absolute => {
                let delta = new - a.act_pos;
                shift_coordinates(a, delta);
            }
            SetScalingFactorMode::Relative => a.cfg.encoder_offset = new,
        }
        a.cfg.encoder_scaling_factor = c.scaling_factor;
        Ok(self.instant(ax, FbKind::SetEncoderScalingFactor, FbValue::None))
    }

    /// MC_WriteNcIoOutput (§4.7.11).
    pub fn write_nc_io_output(
        &mut self,
        ax: usize,
        c: WriteNcIoOutput,
    ) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::ReadWrite, "MC_WriteNcIoOutput")?;
        let img =
            &mut self.axes[ax].ext.x.nc_io[c.device.raw() as usize][c.nc_io_output.raw() as usize];
        *img = (*img & !c.bit_select_mask) | (c.bit_values & c.bit_select_mask);
        Ok(self.instant(ax, FbKind::WriteNcIoOutput, FbValue::None))
    }

    /// MC_ConvertIncPosToPos (§4.7.13).
    pub fn convert_inc_pos_to_pos(
        &mut self,
        ax: usize,
        c: ConvertIncPosToPos,
    ) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::ReadWrite, "MC_ConvertIncPosToPos")?;
        let a = &self.axes[ax];
        let (f, off) = (a.cfg.encoder_scaling_factor, a.cfg.encoder_offset);
        let now = ((a.act_pos - off) / f).round().rem_euclid(COUNTER) as u32;
        let diff = c.inc_pos.wrapping_sub(now) as i32;
        let pos = a.act_pos + diff as f64 * f;
        Ok(self.untracked(FbValue::Real(pos)))
    }

    /// MC_ConvertPosToIncPos (§4.7.13).
    pub fn convert_pos_to_inc_pos(
        &mut self,
        ax: usize,
        c: ConvertPosToIncPos,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_ConvertPosToIncPos";
        let a = &self.axes[ax];
        finite(&a.name, fb, "Position", c.position)?;
        let (f, off) = (a.cfg.encoder_scaling_factor, a.cfg.encoder_offset);
        let half = COUNTER / 2.0 * f;
        if (c.position - a.act_pos).abs() >= half {
            return Err(not_correct(
                &a.name,
                fb,
                "Position",
                c.position,
                &format!(
                    "is ambiguous: farther than half the counter range ({half}) from ActPos {}",
                    a.act_pos
                ),
            ));
        }
        self.admit_state(ax, FbClass::ReadWrite, fb)?;
        let inc = ((c.position - off) / f).round().rem_euclid(COUNTER) as u32;
        Ok(self.untracked(FbValue::DWord(inc)))
    }

    /// MC_ReadParameterSet (§4.4.6).
    pub fn read_parameter_set(&mut self, ax: usize) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::ReadWrite, "MC_ReadParameterSet")?;
        let a = &self.axes[ax];
        let c = &a.cfg;
        let id = c.axis_id;
        let set = AxisParameterSet {
            axis_id: id,
            axis_type: 1,
            axis_name: str::to_owned(&a.name),
            axis_cycle_time: c.cycle_time,
            enable_position_area_control: c.en_position_range_monitoring,
            position_area_control_range: c.position_range_window,
            enable_target_pos_control: c.en_target_position_monitoring,
            target_pos_control_range: c.target_position_window,
            target_pos_control_time: c.target_position_monitoring_time,
            velo_maximum: c.max_velocity,
            ref_velo_search: c.calibration_velocity_forward,
            ref_velo_sync: c.calibration_velocity_backward,
            velo_slow_manual: c.manual_velocity_slow,
            velo_fast_manual: c.manual_velocity_fast,
            enable_peh_time_control: c.en_in_target_timeout,
            peh_control_time: c.in_target_timeout,
            enable_backlash_compensation: a.ext.x.backlash.is_some(),
            backlash: c.backlash,
            ams_net_id: "127.0.0.1.1.1".into(),
            port: 501,
            chn_no: 0,
            acceleration: c.acceleration,
            deceleration: c.deceleration,
            jerk: c.jerk,
            enc_id: id,
            enc_type: 1,
            enc_scale_factor: c.encoder_scaling_factor,
            enc_offset: c.encoder_offset,
            enc_modulo_factor: c.modulo_value,
            enc_enable_soft_end_min_control: c.en_min_soft_pos_limit,
            enc_enable_soft_end_max_control: c.en_max_soft_pos_limit,
            enc_soft_end_min: c.min_soft_pos_limit,
            enc_soft_end_max: c.max_soft_pos_limit,
            enc_max_increment: u32::MAX,
            enc_enable_pos_correction: c.enable_pos_correction,
            enc_ref_search_inverse: c.homing_inv_dir_cam_search,
            enc_ref_sync_inverse: c.homing_inv_dir_sync_search,
            enc_ref_mode: c.encoder_reference_mode,
            enc_ref_position: c.homing_calib_value,
            ctrl_id: id,
            ctrl_enable_pos_diff_control: c.en_position_lag_monitoring,
            ctrl_pos_diff_max: c.max_pos_lag_value,
            ctrl_pos_diff_max_time: c.max_pos_lag_filter_time,
            ctrl_pos_kp: c.position_control_kv,
            drive_id: id,
            drive_type: 0,
            acceleration_max: c.fast_acceleration,
            deceleration_max: c.fast_deceleration,
        };
        let v = FbValue::Extension(Box::new(ExtensionValue::ParameterSet(set)));
        Ok(self.instant(ax, FbKind::ReadParameterSet, v))
    }

    /// MC_ReadAxisComponents (§4.4.3).
    pub fn read_axis_components(&mut self, ax: usize) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::ReadWrite, "MC_ReadAxisComponents")?;
        let id = self.axes[ax].cfg.axis_id;
        let mut ids = [0u32; 9];
        ids[0] = id;
        let v = FbValue::Extension(Box::new(ExtensionValue::AxisComponents(AxisComponents {
            encoder_ids: ids,
            controller_ids: ids,
            drive_ids: ids,
        })));
        Ok(self.instant(ax, FbKind::ReadAxisComponents, v))
    }

    /// MC_Write(Bool)ParameterPersistent: written, then kept in the initialization list.
    pub fn write_param_persistent(
        &mut self,
        ax: usize,
        c: WriteParameter,
        is_bool: bool,
    ) -> Result<FbReply, Rejection> {
        let fb = if is_bool {
            "MC_WriteBoolParameterPersistent"
        } else {
            "MC_WriteParameterPersistent"
        };
        let reply = self.write_param(ax, fb, c.parameter_number, c.value, is_bool)?;
        if let Some(i) = self.fbs.get_mut(reply.id) {
            i.kind = FbKind::WriteParameterPersistent;
        }
        let list = &mut self.axes[ax].ext.x.persistent;
        list.retain(|(n, _)| *n != c.parameter_number);
        list.push((c.parameter_number, c.value));
        Ok(reply)
    }

    /// The initialization list of MC_Write(Bool)ParameterPersistent of an axis
    /// (parameter number, value; BOOL as 0/1), for the shell to store.
    pub fn persistent_parameters(&self, axis: &str) -> Option<Vec<(u32, f64)>> {
        self.index
            .get(axis)
            .map(|&i| self.axes[i].ext.x.persistent.clone())
    }

    /// Re-applies a stored initialization list at start (before the first cycle): each entry
    /// is written as by MC_Write(Bool)ParameterPersistent; the first refused entry stops and
    /// is returned (the entries before it stay applied).
    pub fn apply_persistent_parameters(
        &mut self,
        axis: &str,
        list: &[(u32, f64)],
    ) -> Result<(), Rejection> {
        let ax = self.axis_index(axis)?;
        for &(n, v) in list {
            let is_bool = params::lookup(n).is_some_and(|d| d.ty == ParamType::Bool);
            let c = WriteParameter {
                axis: axis.to_string(),
                parameter_number: n,
                value: v,
            };
            let r = self.write_param_persistent(ax, c, is_bool)?;
            // Applied at start: the instance ends at once, silently (no event, no outputs).
            self.instant_done.retain(|id| *id != r.id);
            self.fbs.done(r.id);
            self.fbs.set_execute(r.id, false);
            self.fbs.events.retain(|e| e.id != r.id);
        }
        Ok(())
    }

    /// After the axis' step: drive mode follow-up and the position corrections. No alloc.
    pub(crate) fn extensions_step(&mut self, i: usize, dt: f64) {
        let a = &mut self.axes[i];
        let v = a.set.vel;
        let x = &mut a.ext.x;
        if v.abs() > 1e-9 {
            x.last_dir = v.signum();
        }
        let travel = (a.set.pos - x.prev_pos).abs();
        x.prev_pos = a.set.pos;
        // Drive operation mode follows MC_TorqueControl (§4.14).
        if a.torque.is_some() {
            x.drive_mode = DriveOperationMode::Torque;
            x.torque_seen = true;
        } else if x.torque_seen {
            x.torque_seen = false;
            if a.error_id.is_none() {
                x.drive_mode = DriveOperationMode::Pos1;
            }
        }
        if let Some(b) = x.backlash {
            let target = if x.last_dir != 0.0 && (x.last_dir > 0.0) == b.positive {
                b.backlash
            } else {
                0.0
            };
            x.backlash_corr = approach(x.backlash_corr, target, rate_step(b.ramp, dt));
            if let Some(o) = self.fbs.extra.get_mut(&b.owner) {
                *o = ExtraOutputs::Backlash {
                    enabled: true,
                    current_backlash: x.backlash_corr,
                    limiting: x.backlash_corr != target,
                };
            }
        }
        if let Some(l) = x.limiter {
            let max = match l.mode {
                PositionCorrectionMode::Unlimited => f64::INFINITY,
                PositionCorrectionMode::Fast => {
                    if l.acceleration > 0.0 {
                        l.acceleration * dt * dt
                    } else {
                        f64::INFINITY
                    }
                }
                PositionCorrectionMode::FullLength => travel * l.change.abs() / l.length,
            };
            x.limiter_corr = approach(x.limiter_corr, l.value, max);
            if let Some(o) = self.fbs.extra.get_mut(&l.owner) {
                *o = ExtraOutputs::CorrectionLimiter {
                    limiting: x.limiter_corr != l.value,
                };
            }
        }
        if let Some(t) = x.table.as_ref() {
            let p = &t.param;
            let mut pos = a.set.pos;
            if p.modulo {
                let period = p.max_position - p.min_position;
                pos = p.min_position + (pos - p.min_position).rem_euclid(period);
            }
            let against = match p.direction {
                WorkDirection::None => true,
                WorkDirection::Both => false,
                WorkDirection::Positive => x.last_dir < 0.0,
                WorkDirection::Negative => x.last_dir > 0.0,
            };
            let target = if against {
                0.0
            } else {
                interpolate(&t.table, pos)
            };
            x.table_corr = approach(x.table_corr, target, rate_step(t.ramp, dt));
            if let Some(o) = self.fbs.extra.get_mut(&t.owner) {
                *o = ExtraOutputs::TableCompensation {
                    enabled: true,
                    current_correction: x.table_corr,
                    limiting: x.table_corr != target,
                };
            }
        }
    }
}
