//! MC_Power (§4.1), MC_Reset (§4.2) and MC_SetOverride: the axis' enable, error reset and
//! velocity override.

use super::*;

impl AxisSet {
    // ------------------------------------------------------------------ MC_Power

    /// MC_Power (§4.1).
    pub fn power(&mut self, ax: usize, c: Power) -> Result<FbReply, Rejection> {
        // The axis' one MC_Power instance: the same id on every call (read with ReadFbOutputs).
        let id = match self.axes[ax].power_id {
            Some(id) => id,
            None => {
                let id = self.fbs.untracked_id();
                self.axes[ax].power_id = Some(id);
                id
            }
        };
        let a = &mut self.axes[ax];
        let checked = finite(&a.name, "MC_Power", "Override", c.override_percent).and_then(|_| {
            if (0.0..=100.0).contains(&c.override_percent) {
                Ok(())
            } else {
                Err(not_correct(
                    &a.name,
                    "MC_Power",
                    "Override",
                    c.override_percent,
                    "must be in [0, 100]",
                ))
            }
        });
        if let Err(e) = checked {
            // Error/ErrorID of the instance; the previous override stays in force (§4.1).
            a.power_error = e.error_id;
            return Err(e);
        }
        a.power_error = ErrorId::NONE;
        let fbs = &mut self.fbs;
        // Enable edges (§4.1).
        if c.enable && !a.enable {
            a.controller_on = true;
            a.power_off_pending = false;
            // The axis takes its actual position as set position (like a reset).
            if !a.moving() && a.job.is_none() {
                a.set = State1::at_rest(a.act_pos);
                a.following_offset = 0.0;
                a.target_pos = a.set.pos;
            }
            a.status_pending = !a.drive_fault;
        } else if !c.enable && a.enable {
            let busy = a.job.is_some_and(|j| j.owner.is_some());
            if c.buffer_mode != BufferMode::Aborting && busy {
                a.power_off_pending = true;
            } else {
                a.switch_off(fbs);
            }
        }
        a.enable = c.enable;
        a.enable_positive = c.enable_positive;
        a.enable_negative = c.enable_negative;
        if c.override_percent != a.power_override {
            a.power_override = c.override_percent;
            if a.set_override.is_none() {
                apply_override(a, c.override_percent, fbs);
            }
        }
        // A feed enable of the current travel direction dropped: stop with AxisDec (§2.4).
        if a.controller_on && a.error_id.is_none() {
            let v = a.set.vel;
            let blocked = (v > 1e-9 && !a.enable_positive) || (v < -1e-9 && !a.enable_negative);
            let stopping = a.job.is_some_and(|j| {
                matches!(j.kind, JobKind::Stop | JobKind::FastStop)
                    || (j.kind == JobKind::Halt && j.owner.is_none())
            });
            if blocked && !stopping {
                a.abort_motion(fbs);
                let l = a.default_limits();
                let profile = a.plan_stop(&l);
                let stop = profile.end().pos;
                a.start_job(Job::internal(JobKind::Halt, profile, stop, l));
            }
        }
        // The reply carries MC_Power.Status at this call (TRUE one cycle after Enable↑).
        let status = self.axes[ax].status;
        Ok(FbReply {
            id,
            value: FbValue::Bool(status),
            tracked: false,
        })
    }

    // ------------------------------------------------------------------ MC_Reset

    /// MC_Reset (§4.2).
    pub fn reset(&mut self, ax: usize) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::Reset, "MC_Reset")?;
        let id = self.fbs.admit(ax, FbKind::Reset, CommandState::Busy);
        let a = &mut self.axes[ax];
        let fbs = &mut self.fbs;
        a.cmd_no = a.cmd_no.wrapping_add(1);
        let had_drive_fault = a.drive_fault;
        a.error_id = ErrorId::NONE;
        a.drive_fault = false;
        if had_drive_fault && a.controller_on {
            a.status_pending = true;
        }
        // Release the MC_Stop lock (§4.8.10).
        if let Some(lock) = a.lock.take() {
            if let Some(i) = fbs.get_mut(lock.owner) {
                if i.locked {
                    i.locked = false;
                    i.cleared = !i.execute;
                } else {
                    fbs.aborted(lock.owner);
                }
            }
        }
        // A slave is decoupled (§4.2 proposal), keeping its velocity for the fast stop.
        a.decouple_keep_velocity();
        // Copy the actual position into the set position (§4.2).
        a.set.pos = a.act_pos;
        a.following_offset = 0.0;
        a.abort_motion(fbs);
        if a.moving() {
            let l = a.fast_limits();
            let profile = a.plan_stop(&l);
            let stop = profile.end().pos;
            a.start_job(Job::internal(JobKind::FastStop, profile, stop, l));
            a.reset_waiting = Some(id);
            a.last_target = Some(stop);
        } else {
            a.job = None;
            a.target_pos = a.set.pos;
            a.last_target = Some(a.set.pos);
            self.instant_done.push(id);
        }
        Ok(Self::reply(id))
    }

    // ------------------------------------------------------------------ MC_SetOverride

    /// MC_SetOverride (§4.7.10).
    pub fn set_override(&mut self, ax: usize, c: SetOverride) -> Result<FbReply, Rejection> {
        let fb = "MC_SetOverride";
        let a = &mut self.axes[ax];
        for (f, v) in [
            ("VelFactor", c.vel_factor),
            ("AccFactor", c.acc_factor),
            ("JerkFactor", c.jerk_factor),
        ] {
            finite(&a.name, fb, f, v)?;
        }
        if c.enable {
            if !(0.0..=1.0).contains(&c.vel_factor) {
                return Err(not_correct(
                    &a.name,
                    fb,
                    "VelFactor",
                    c.vel_factor,
                    "must be in [0, 1]",
                ));
            }
            a.set_override = Some(c.vel_factor * 100.0);
            apply_override(a, c.vel_factor * 100.0, &mut self.fbs);
        } else if a.set_override.take().is_some() {
            // The last MC_SetOverride disabled: MC_Power's value applies again.
            let p = a.power_override;
            apply_override(a, p, &mut self.fbs);
        }
        Ok(self.untracked(FbValue::None))
    }

    /// MC_SetOverride.Enabled of the axis.
    pub fn set_override_enabled(&self, axis: &str) -> Option<bool> {
        self.index
            .get(axis)
            .map(|&i| self.axes[i].set_override.is_some())
    }
}
