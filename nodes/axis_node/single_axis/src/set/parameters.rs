//! MC_SetPosition (§4.3) and the parameter FBs MC_Read/Write(Bool)Parameter (§4.4).

use super::*;

impl AxisSet {
    /// MC_ReadParameter (§4.4.5).
    pub fn read_parameter(&mut self, ax: usize, c: ReadParameter) -> Result<FbReply, Rejection> {
        let v = self.read_param(ax, "MC_ReadParameter", c.parameter_number, false)?;
        Ok(self.untracked(FbValue::Real(v)))
    }

    /// MC_ReadBoolParameter (§4.4.5).
    pub fn read_bool_parameter(
        &mut self,
        ax: usize,
        c: ReadBoolParameter,
    ) -> Result<FbReply, Rejection> {
        let v = self.read_param(ax, "MC_ReadBoolParameter", c.parameter_number, true)?;
        Ok(self.untracked(FbValue::Bool(v != 0.0)))
    }

    /// MC_WriteParameter (§4.4.8).
    pub fn write_parameter(&mut self, ax: usize, c: WriteParameter) -> Result<FbReply, Rejection> {
        self.write_param(ax, "MC_WriteParameter", c.parameter_number, c.value, false)
    }

    /// MC_WriteBoolParameter (§4.4.8).
    pub fn write_bool_parameter(
        &mut self,
        ax: usize,
        c: WriteBoolParameter,
    ) -> Result<FbReply, Rejection> {
        let v = c.value as u8 as f64;
        self.write_param(ax, "MC_WriteBoolParameter", c.parameter_number, v, true)
    }

    /// MC_ReadActualPosition (§4.4.1).
    pub fn read_actual_position(&mut self, ax: usize) -> FbReply {
        let v = self.axes[ax].act_pos;
        self.untracked(FbValue::Real(v))
    }

    /// MC_ReadActualVelocity (§4.4.2).
    pub fn read_actual_velocity(&mut self, ax: usize) -> FbReply {
        let v = self.axes[ax].act_velo;
        self.untracked(FbValue::Real(v))
    }

    /// MC_ReadAxisError (§4.4.4).
    pub fn read_axis_error(&mut self, ax: usize) -> FbReply {
        let v = self.axes[ax].error_id.0;
        self.untracked(FbValue::DWord(v))
    }

    // ------------------------------------------------------------------ MC_SetPosition

    /// MC_SetPosition (§4.3).
    pub fn set_position(&mut self, ax: usize, c: SetPosition) -> Result<FbReply, Rejection> {
        let a = &self.axes[ax];
        finite(&a.name, "MC_SetPosition", "Position", c.position)?;
        if c.options.select_encoder_index && c.options.encoder_index != 0 {
            return Err(not_correct(
                &a.name,
                "MC_SetPosition",
                "Options.EncoderIndex",
                c.options.encoder_index as f64,
                "must be 0 (one encoder)",
            ));
        }
        self.admit_state(ax, FbClass::SetPosition, "MC_SetPosition")?;
        let id = self.fbs.admit(ax, FbKind::SetPosition, CommandState::Busy);
        let a = &mut self.axes[ax];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        let moving = a.job.is_some() || a.moving();
        if c.options.clear_position_offset {
            let d = -a.set_position_offset;
            shift_coordinates(a, d);
            a.set_position_offset = 0.0;
        } else if c.mode {
            shift_coordinates(a, c.position);
        } else if moving {
            // Absolute while moving = relative with Δ = Position − ActPos (§4.3 proposal).
            shift_coordinates(a, c.position - a.act_pos);
        } else {
            // Absolute at rest: ActPos := Position; the lag is kept unless ClearPositionLag.
            let lag = a.set.pos - a.act_pos;
            shift_coordinates(a, c.position - a.act_pos);
            a.act_pos = c.position;
            if c.options.clear_position_lag {
                a.following_offset = 0.0;
                a.set.pos = c.position;
            } else {
                a.set.pos = c.position + lag;
            }
            a.target_pos = a.set.pos;
        }
        a.last_target = None;
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    // ------------------------------------------------------------------ parameters (§4.4)

    pub(crate) fn param_def(
        &self,
        ax: usize,
        fb: &str,
        number: u32,
    ) -> Result<&'static params::ParamDef, Rejection> {
        params::lookup(number).ok_or_else(|| {
            reject(
                UNKNOWN_PARAMETER,
                format!(
                    "axis '{}': {fb}: unknown ParameterNumber {number}",
                    self.axes[ax].name
                ),
            )
        })
    }

    pub(crate) fn read_param(
        &self,
        ax: usize,
        fb: &str,
        number: u32,
        want_bool: bool,
    ) -> Result<f64, Rejection> {
        let def = self.param_def(ax, fb, number)?;
        let a = &self.axes[ax];
        if want_bool && def.ty != ParamType::Bool {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{}': {fb}: parameter {number} {} is not BOOL",
                    a.name, def.name
                ),
            ));
        }
        Ok(match def.slot {
            Slot::Config(k) => k.get(&a.cfg),
            Slot::Other(off) => a.other_params.get(&off).copied().unwrap_or(0.0),
            // The coupling's (effective) ratio while the axis is a coupled slave (§6).
            Slot::GearRatio => match a.coupling {
                Some(c) => c.ratio,
                None => {
                    return Err(reject(
                        COMMAND_NOT_PERMITTED,
                        format!(
                            "axis '{}': {fb}: AxisGearRatio (3000) only on a coupled slave",
                            a.name
                        ),
                    ))
                }
            },
            Slot::Status(s) => match s {
                StatusValue::CommandedPosition => a.set.pos,
                StatusValue::ActualVelocity => a.act_velo,
                StatusValue::CommandedVelocity => a.set.vel,
                StatusValue::AxisId => a.cfg.axis_id as f64,
                StatusValue::TargetPosition => a.status().target_pos,
                StatusValue::RemainingTimeToGo => {
                    a.job.map_or(0.0, |j| (j.profile.duration() - j.t).max(0.0))
                }
                StatusValue::RemainingDistanceToGo => a
                    .job
                    .filter(|j| j.kind != JobKind::Velocity)
                    .map_or(0.0, |j| (j.target + j.offset - a.set.pos).abs()),
                StatusValue::SetPositionOffset => a.set_position_offset,
                StatusValue::SafCycleTime => a.cfg.cycle_time,
                StatusValue::SvbCycleTime => a.cfg.svb_cycle_time,
            },
        })
    }

    pub(crate) fn write_param(
        &mut self,
        ax: usize,
        fb: &str,
        number: u32,
        value: f64,
        is_bool: bool,
    ) -> Result<FbReply, Rejection> {
        let def = self.param_def(ax, fb, number)?;
        let name = self.axes[ax].name.clone();
        finite(&name, fb, "Value", value)?;
        if def.read_only() {
            return Err(reject(
                READ_ONLY_PARAMETER,
                format!(
                    "axis '{name}': {fb}: parameter {number} {} is read-only",
                    def.name
                ),
            ));
        }
        if is_bool != (def.ty == ParamType::Bool) {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{name}': {fb}: parameter {number} {} has type {:?}",
                    def.name, def.ty
                ),
            ));
        }
        match def.slot {
            Slot::Config(k) => {
                let a = &mut self.axes[ax];
                let mut cfg = a.cfg.clone();
                k.set(&mut cfg, value);
                cfg.validate(&name).map_err(|r| {
                    let id = if r.error_id == ErrorId::NOT_FINITE {
                        r.error_id
                    } else {
                        PARAMETER_NOT_CORRECT
                    };
                    reject(
                        id,
                        format!("{fb}: parameter {number} {}: {}", def.name, r.message),
                    )
                })?;
                a.cfg = cfg;
            }
            Slot::Other(off) => {
                self.axes[ax].other_params.insert(off, value);
            }
            Slot::GearRatio => self.write_gear_ratio(ax, value, fb)?,
            Slot::Status(_) => unreachable!("read-only checked above"),
        }
        let id = self
            .fbs
            .admit(ax, FbKind::WriteParameter, CommandState::Busy);
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    /// AxisGearRatio (3000) written on a coupled slave (§4.4.8): applied at once. A position
    /// coupling is re-anchored at the current master value so the slave does not jump (the
    /// new ratio applies to the master's further travel); MC_GearInDyn takes it as its
    /// effective ratio and target. Not a coupled slave, or several masters → 0x4B05.
    pub(crate) fn write_gear_ratio(
        &mut self,
        ax: usize,
        value: f64,
        fb: &str,
    ) -> Result<(), Rejection> {
        let name = self.axes[ax].name.clone();
        let refuse = |why: &str| {
            Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("axis '{name}': {fb}: AxisGearRatio (3000) {why}"),
            ))
        };
        let Some(mut c) = self.axes[ax].coupling else {
            return refuse("only on a coupled slave");
        };
        if c.ext.multi.is_some() {
            return refuse("of a multi-master coupling: the ratios are MC_GearInMultiMaster's");
        }
        if value == 0.0 {
            return refuse("must not be 0");
        }
        match c.dynamic.as_mut() {
            Some(d) => d.target = value,
            None => {
                let raw = self.master_raw(ax, c.master).pos;
                c.s0 += c.ratio * (raw - c.m0);
                c.m0 = raw;
            }
        }
        c.ratio = value;
        self.axes[ax].coupling = Some(c);
        Ok(())
    }
}
