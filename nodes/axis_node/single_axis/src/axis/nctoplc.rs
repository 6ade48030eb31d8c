//! NcToPlc values and status bits of the axis (single_axis.md §5.1): what a PLC reads in
//! NCTOPLC_AXIS_REF and MC_ReadStatus.

use super::*;
use crate::status::{axis_state, bits, AxisStatus};

impl Axis {
    /// NcToPlc values and status bits of this axis (§5.1).
    pub fn status(&self) -> AxisStatus {
        let mut s = AxisStatus::default();
        self.status_into(&mut s);
        s
    }

    /// [`Self::status`] written into `s` field by field (`ext` reset): a snapshot of every
    /// cycle refills its statuses in place instead of moving a fresh one per axis.
    pub fn status_into(&self, s: &mut AxisStatus) {
        let state = self.state();
        // Borrowed: a job holds its whole profile, too large to copy for each look.
        let job = self.job.as_ref();
        let has_job = self.job.is_some() || self.torque.is_some();
        let mut w = 0u32;
        let mut set = |cond: bool, bit: u32| {
            if cond {
                w |= bit
            }
        };
        let moving = self.set.vel.abs() > V_REST;
        set(
            self.controller_on && self.status && self.error_id.is_none(),
            bits::OPERATIONAL,
        );
        set(self.homed, bits::HOMED);
        set(!moving && !has_job, bits::NOT_MOVING);
        set(
            !has_job && (self.act_pos - self.target_pos).abs() <= self.cfg.position_range_window,
            bits::IN_POSITION_AREA,
        );
        set(!has_job && self.in_target, bits::IN_TARGET_POSITION);
        set(self.has_been_stopped, bits::HAS_BEEN_STOPPED);
        set(self.coupling.is_some(), bits::PROTECTED);
        set(self.homing.is_some(), bits::HOMING_BUSY);
        set(self.overlay.is_some(), bits::COMPENSATING);
        set(has_job, bits::HAS_JOB);
        set(self.set.vel > V_REST, bits::POSITIVE_DIRECTION);
        set(self.set.vel < -V_REST, bits::NEGATIVE_DIRECTION);
        let const_vel = moving && self.set.acc.abs() <= 1e-9;
        set(const_vel, bits::CONSTANT_VELOCITY);
        set(
            job.is_some_and(|j| j.kind == JobKind::Velocity || j.continuous),
            bits::CONTINUOUS_MOTION,
        );
        set(self.controller_on && self.status, bits::CONTROL_LOOP_CLOSED);
        set(self.pending.is_some(), bits::CMD_BUFFERED);
        set(true, bits::PTP_MODE);
        set(
            self.cfg.en_min_soft_pos_limit && self.set.pos < self.cfg.min_soft_pos_limit,
            bits::SOFT_LIMIT_MIN_EXCEEDED,
        );
        set(
            self.cfg.en_max_soft_pos_limit && self.set.pos > self.cfg.max_soft_pos_limit,
            bits::SOFT_LIMIT_MAX_EXCEEDED,
        );
        set(self.drive_fault, bits::DRIVE_DEVICE_ERROR);
        set(
            self.torque.is_some_and(|t| t.clamped),
            bits::DRIVE_LIMIT_ACTIVE,
        );
        set(self.lock.is_some(), bits::MOTION_COMMANDS_LOCKED);
        set(!self.error_id.is_none(), bits::ERROR);
        w |= self.ext_state_bits();
        let ax_state = match job {
            None if self.coupling.is_some() => axis_state::SYNCHRON,
            None => axis_state::INACTIVE,
            Some(j) if j.paused && !moving => axis_state::OVERRIDE_ZERO,
            Some(_) if self.set.acc * self.set.vel > 1e-9 => axis_state::PHASE_ACCPOS,
            Some(_) if self.set.acc * self.set.vel < -1e-9 => axis_state::PHASE_ACCNEG,
            Some(_) if moving => axis_state::PHASE_VELOCONST,
            Some(_) => axis_state::RUNNING,
        };
        let jerk = job.map_or(0.0, |j| j.profile.jerk_at(j.t));
        let p = self.cfg.modulo_value;
        // Every field is written (the pattern names them all); the name only when it differs,
        // so a refill does not touch the shared name's count.
        let AxisStatus {
            name,
            motion_state,
            state_dword,
            error_code,
            axis_state,
            couple_state,
            set_pos,
            set_velo,
            set_acc,
            set_jerk,
            act_pos,
            act_velo,
            act_acc,
            pos_diff,
            target_pos,
            modulo_act_pos,
            modulo_act_turns,
            modulo_set_pos,
            modulo_set_turns,
            override_percent,
            power_status,
            homed,
            has_job: has_job_out,
            cmd_buffered,
            cmd_no,
            homing_state,
            raw_pos,
            raw_act_pos,
            home_cam,
            set_position_offset,
            set_torque,
            ext,
        } = s;
        if !std::sync::Arc::ptr_eq(name, &self.name) {
            *name = self.name.clone();
        }
        *motion_state = state;
        *state_dword = w;
        *error_code = self.error_id.0;
        *axis_state = ax_state;
        *couple_state = if self.coupling.is_some() { 3 } else { 0 };
        *set_pos = self.set.pos;
        *set_velo = self.set.vel;
        *set_acc = self.set.acc;
        *set_jerk = jerk;
        *act_pos = self.act_pos;
        *act_velo = self.act_velo;
        *act_acc = self.act_acc;
        *pos_diff = self.set.pos - self.act_pos;
        *target_pos = if job.is_some_and(|j| j.kind == JobKind::Velocity) {
            self.set.pos
        } else {
            self.target_pos
        };
        *modulo_set_pos = modulo::modulo(self.set.pos, p);
        *modulo_set_turns = modulo::turns(self.set.pos, p);
        // Without a following error both are the same: one `fmod` less per axis and cycle.
        (*modulo_act_pos, *modulo_act_turns) = if self.act_pos == self.set.pos {
            (*modulo_set_pos, *modulo_set_turns)
        } else {
            (
                modulo::modulo(self.act_pos, p),
                modulo::turns(self.act_pos, p),
            )
        };
        *override_percent = self.override_pct;
        *power_status = self.status;
        *homed = self.homed;
        *has_job_out = has_job;
        *cmd_buffered = self.pending.is_some();
        *cmd_no = self.cmd_no;
        *homing_state = self.homing.map_or(0, |h| h.phase);
        *raw_pos = self.set.pos - self.coord_offset;
        *raw_act_pos = self.raw_act();
        *home_cam = self.virtual_cam(self.raw_act());
        *set_position_offset = self.set_position_offset;
        *set_torque = self.set_torque;
        *ext = Default::default();
    }
}
