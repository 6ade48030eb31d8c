//! MC_Home (§4.10): the homing FB's calls (the homing run itself is `crate::homing`).

use super::*;

impl AxisSet {
    // ------------------------------------------------------------------ MC_Home (§4.10)

    /// MC_Home (§4.10).
    pub fn home(&mut self, ax: usize, c: Home) -> Result<FbReply, Rejection> {
        let fb = "MC_Home";
        let a = &self.axes[ax];
        let name = a.name.clone();
        if !c.use_default_position {
            finite(&name, fb, "Position", c.position)?;
        }
        finite(
            &name,
            fb,
            "Options.SearchVelocity",
            c.options.search_velocity,
        )?;
        finite(&name, fb, "Options.SyncVelocity", c.options.sync_velocity)?;
        let position = if c.use_default_position {
            a.cfg.homing_calib_value
        } else {
            c.position
        };
        let class = match c.homing_mode {
            HomingMode::DefaultHoming => FbClass::HomeDefault,
            _ => FbClass::HomeNoMotion,
        };
        if c.homing_mode != HomingMode::DefaultHoming {
            self.admit_state(ax, class, fb)?;
            let id = self.fbs.admit(ax, FbKind::Home, CommandState::Busy);
            let a = &mut self.axes[ax];
            a.cmd_no = a.cmd_no.wrapping_add(1);
            match c.homing_mode {
                HomingMode::Direct => {
                    // ActPos := Position; SetPos keeps the lag unless ClearPositionLag.
                    let lag = a.set.pos - a.act_pos;
                    shift_coordinates(a, position - a.act_pos);
                    a.act_pos = position;
                    if c.options.clear_position_lag {
                        a.following_offset = 0.0;
                        a.set.pos = position;
                    } else {
                        a.set.pos = position + lag;
                    }
                    a.target_pos = a.set.pos;
                    a.set_position_offset = 0.0;
                    a.last_target = None;
                    a.homed = true;
                }
                HomingMode::ForceCalibration => a.homed = true,
                HomingMode::ResetCalibration => a.homed = false,
                HomingMode::DefaultHoming => unreachable!(),
            }
            self.instant_done.push(id);
            return Ok(Self::reply(id));
        }
        let dir = |d: Direction, inv: bool, field: &str| -> Result<f64, Rejection> {
            match d {
                Direction::Positive => Ok(1.0),
                Direction::Negative => Ok(-1.0),
                Direction::Undefined => Ok(if inv { -1.0 } else { 1.0 }),
                other => Err(reject(
                    INVALID_MODE,
                    format!("axis '{name}': {fb}: {field} = {other:?} is not a homing direction"),
                )),
            }
        };
        let search_dir = dir(
            c.options.search_direction,
            a.cfg.homing_inv_dir_cam_search,
            "Options.SearchDirection",
        )?;
        let sync_dir = dir(
            c.options.sync_direction,
            a.cfg.homing_inv_dir_sync_search,
            "Options.SyncDirection",
        )?;
        let speed = |v: f64, default: f64, field: &str| -> Result<f64, Rejection> {
            if v < 0.0 || v > a.cfg.max_velocity {
                Err(not_correct(
                    &name,
                    fb,
                    field,
                    v,
                    &format!("must be in [0, {}] (0 = default)", a.cfg.max_velocity),
                ))
            } else if v == 0.0 {
                Ok(default)
            } else {
                Ok(v)
            }
        };
        let search_velocity = speed(
            c.options.search_velocity,
            a.cfg.calibration_velocity_forward,
            "Options.SearchVelocity",
        )?;
        let sync_velocity = speed(
            c.options.sync_velocity,
            a.cfg.calibration_velocity_backward,
            "Options.SyncVelocity",
        )?;
        let mode = if c.options.reference_mode == 0 {
            a.cfg.encoder_reference_mode
        } else {
            c.options.reference_mode
        };
        if !matches!(mode, 0..=7) {
            return Err(reject(
                INVALID_MODE,
                format!("axis '{name}': {fb}: reference mode {mode} is not an E_EncoderReferenceMode (0..7)"),
            ));
        }
        self.admit_state(ax, class, fb)?;
        let id = self.fbs.admit(ax, FbKind::Home, CommandState::Active);
        let a = &mut self.axes[ax];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        a.start_homing(crate::homing::Homing {
            owner: id,
            phase: 1,
            position,
            search_dir,
            search_velocity,
            sync_dir,
            sync_velocity,
            mode: if mode == 0 { 1 } else { mode },
            cam_input: c.calibration_cam,
            prev_cam: false,
            prev_raw: 0.0,
            pulse: 0.0,
            ref_raw: 0.0,
            start_raw: 0.0,
            homed_before: false,
        });
        Ok(Self::reply(id))
    }

    /// A later call of a running MC_Home with a new bCalibrationCam level.
    pub fn home_cam(&mut self, id: CmdId, cam: bool) -> Result<FbReply, Rejection> {
        let inst = self.fbs.get(id).copied().ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        if inst.kind != FbKind::Home {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("command instance {} is not an MC_Home", id.0),
            ));
        }
        if let Some(h) = self.axes[inst.axis]
            .homing
            .as_mut()
            .filter(|h| h.owner == id)
        {
            h.cam_input = cam;
        }
        Ok(Self::reply(id))
    }
}
