//! MC_TorqueControl (§4.15) and its continuous update.

use super::*;

impl AxisSet {
    // ------------------------------------------------------------------ MC_TorqueControl

    pub(crate) fn torque_inputs(
        name: &str,
        torque: f64,
        ramp: f64,
        hi: f64,
        lo: f64,
    ) -> Result<(), Rejection> {
        let fb = "MC_TorqueControl";
        for (f, v) in [
            ("Torque", torque),
            ("TorqueRamp", ramp),
            ("VelocityLimitHigh", hi),
            ("VelocityLimitLow", lo),
        ] {
            finite(name, fb, f, v)?;
        }
        if ramp <= 0.0 {
            return Err(not_correct(name, fb, "TorqueRamp", ramp, "must be > 0"));
        }
        if lo > hi {
            return Err(not_correct(
                name,
                fb,
                "VelocityLimitLow",
                lo,
                &format!("must not exceed VelocityLimitHigh = {hi}"),
            ));
        }
        Ok(())
    }

    /// MC_TorqueControl (§4.14).
    pub fn torque_control(&mut self, ax: usize, c: TorqueControl) -> Result<FbReply, Rejection> {
        let fb = "MC_TorqueControl";
        let name = self.axes[ax].name.clone();
        Self::torque_inputs(
            &name,
            c.torque,
            c.torque_ramp,
            c.velocity_limit_high,
            c.velocity_limit_low,
        )?;
        if c.options.enable_manual_torque_start_value {
            finite(
                &name,
                fb,
                "Options.ManualTorqueStartValue",
                c.options.manual_torque_start_value,
            )?;
        }
        if c.buffer_mode != BufferMode::Aborting {
            return Err(reject(
                INVALID_MODE,
                format!(
                    "axis '{name}': {fb}: BufferMode {:?} (only MC_Aborting)",
                    c.buffer_mode
                ),
            ));
        }
        let decouple = self.admit_motion(ax, FbClass::TorqueControl, fb, c.buffer_mode)?;
        if decouple {
            self.axes[ax].decouple_keep_velocity();
        }
        let id = self
            .fbs
            .admit(ax, FbKind::TorqueControl, CommandState::Active);
        let a = &mut self.axes[ax];
        let fbs = &mut self.fbs;
        a.cmd_no = a.cmd_no.wrapping_add(1);
        let start = if c.options.enable_manual_torque_start_value {
            c.options.manual_torque_start_value
        } else if a.torque.is_some() {
            a.set_torque
        } else {
            0.0
        };
        a.abort_motion(fbs);
        if let Some(r) = a.reset_waiting.take() {
            fbs.done(r);
        }
        a.job = None;
        a.set_torque = start;
        a.has_been_stopped = false;
        a.last_target = None;
        a.torque = Some(crate::torque::TorqueJob {
            owner: id,
            continuous_update: c.continuous_update,
            torque: if c.relative {
                start + c.torque
            } else {
                c.torque
            },
            ramp: c.torque_ramp,
            v_high: c.velocity_limit_high,
            v_low: c.velocity_limit_low,
            clamped: false,
        });
        Ok(Self::reply(id))
    }

    /// A later call of a running MC_TorqueControl started with ContinuousUpdate.
    pub fn torque_update(
        &mut self,
        id: CmdId,
        torque: f64,
        ramp: f64,
        hi: f64,
        lo: f64,
    ) -> Result<FbReply, Rejection> {
        let inst = self.fbs.get(id).copied().ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        if inst.kind != FbKind::TorqueControl {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("command instance {} is not an MC_TorqueControl", id.0),
            ));
        }
        let a = &mut self.axes[inst.axis];
        Self::torque_inputs(&a.name, torque, ramp, hi, lo)?;
        // Without ContinuousUpdate at the edge, later input changes are ignored (§3.1 rule 1).
        if let Some(t) = a
            .torque
            .as_mut()
            .filter(|t| t.owner == id && t.continuous_update)
        {
            t.torque = torque;
            t.ramp = ramp;
            t.v_high = hi;
            t.v_low = lo;
        }
        Ok(Self::reply(id))
    }
}
