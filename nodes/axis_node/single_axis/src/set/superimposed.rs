//! MC_MoveSuperImposed and MC_AbortSuperposition (§4.9) (the overlay's cycle is
//! `crate::superposition`).

use super::*;

impl AxisSet {
    // ------------------------------------------------------------------ superposition (§4.9)

    /// MC_MoveSuperImposed (§4.9).
    pub fn move_superimposed(
        &mut self,
        ax: usize,
        c: MoveSuperImposed,
    ) -> Result<FbReply, Rejection> {
        let fb = "MC_MoveSuperImposed";
        let name = self.axes[ax].name.clone();
        for (f, v) in [
            ("Distance", c.distance),
            ("VelocityDiff", c.velocity_diff),
            ("Acceleration", c.acceleration),
            ("Deceleration", c.deceleration),
            ("Jerk", c.jerk),
            ("VelocityProcess", c.velocity_process),
            ("Length", c.length),
        ] {
            finite(&name, fb, f, v)?;
        }
        for (f, v) in [
            ("VelocityDiff", c.velocity_diff),
            ("VelocityProcess", c.velocity_process),
        ] {
            if v <= 0.0 {
                return Err(not_correct(&name, fb, f, v, "must be > 0"));
            }
        }
        for (f, v) in [
            ("Acceleration", c.acceleration),
            ("Deceleration", c.deceleration),
            ("Jerk", c.jerk),
            ("Length", c.length),
        ] {
            if v < 0.0 {
                return Err(not_correct(&name, fb, f, v, "must be >= 0"));
            }
        }
        self.admit_state(ax, FbClass::MoveSuperImposed, fb)?;
        let a = &self.axes[ax];
        if a.set.vel.abs() <= 1e-9 && !a.job.is_some_and(|j| j.paused) {
            return Err(reject(
                AXIS_NOT_MOVING,
                format!("axis '{name}': {fb}: the axis is not moving"),
            ));
        }
        let acc = if c.acceleration > 0.0 {
            c.acceleration
        } else {
            a.cfg.acceleration
        };
        let dec = if c.deceleration > 0.0 {
            c.deceleration
        } else {
            a.cfg.deceleration
        };
        let p = crate::superposition::plan(
            c.mode.raw(),
            c.distance,
            c.velocity_diff,
            acc,
            dec,
            c.velocity_process,
            c.length,
        );
        let dir = if a.set.vel.abs() > 1e-9 {
            a.set.vel.signum()
        } else {
            a.job.map_or(1.0, |j| travel_dir(a, &j))
        };
        let additive = matches!(c.mode.raw(), 1 | 3 | 5);
        let t_used = p.t;
        let out = crate::superposition::SuperImposedOutputs {
            warning: p.warning,
            warning_id: crate::superposition::warning_id(&p),
            actual_velocity_diff: p.dv,
            actual_distance: c.distance.signum() * p.area,
            actual_length: if additive {
                c.velocity_process * t_used
            } else {
                c.velocity_process * t_used + c.distance
            },
            actual_acceleration: p.a,
            actual_deceleration: p.d,
        };
        let id = self
            .fbs
            .admit(ax, FbKind::MoveSuperImposed, CommandState::Active);
        self.fbs.superimposed.insert(id, out);
        let a = &mut self.axes[ax];
        a.abort_overlay(&mut self.fbs);
        if p.t <= 0.0 || p.area <= 0.0 {
            // D = 0 or no time available: Done at once (with Warning in the latter case).
            self.instant_done.push(id);
        } else {
            a.overlay = Some(crate::superposition::Overlay {
                owner: id,
                plan: p,
                tau: 0.0,
                sign: c.distance.signum() * dir,
                dir,
                vp: c.velocity_process,
                abort_option: c.abort_option.raw(),
                abort: None,
                covered: 0.0,
            });
        }
        Ok(Self::reply(id))
    }

    /// MC_AbortSuperposition (§4.9).
    pub fn abort_superposition(&mut self, ax: usize) -> Result<FbReply, Rejection> {
        self.admit_state(ax, FbClass::AbortSuperposition, "MC_AbortSuperposition")?;
        let id = self
            .fbs
            .admit(ax, FbKind::AbortSuperposition, CommandState::Busy);
        let a = &mut self.axes[ax];
        match a.overlay.as_mut() {
            Some(o) if o.abort.is_none() => {
                let v = o.plan.vel(o.tau);
                o.abort = Some((id, o.tau, v));
                let owner = o.owner;
                self.fbs.aborted(owner);
            }
            _ => self.instant_done.push(id),
        }
        Ok(Self::reply(id))
    }

    /// Extra outputs of an MC_MoveSuperImposed instance (Warning, Actual*).
    pub fn superimposed_outputs(
        &self,
        id: CmdId,
    ) -> Option<crate::superposition::SuperImposedOutputs> {
        self.fbs.superimposed.get(&id).copied()
    }
}
