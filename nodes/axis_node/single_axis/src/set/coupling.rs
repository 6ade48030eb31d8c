//! MC_GearIn, MC_GearInDyn and MC_GearOut (§4.12): coupling a slave to a master (the
//! coupling's cycle is `crate::gearing`).

use super::*;

impl AxisSet {
    // ------------------------------------------------------------------ gearing (§4.12)

    /// MC_GearIn (§4.12.1).
    pub fn gear_in(&mut self, slave: usize, c: GearIn) -> Result<FbReply, Rejection> {
        let fb = "MC_GearIn";
        let name = self.axes[slave].name.clone();
        let master = self.axis_index(&c.master)?;
        finite(&name, fb, "RatioNumerator", c.ratio_numerator)?;
        if c.ratio_denominator == 0 {
            return Err(not_correct(
                &name,
                fb,
                "RatioDenominator",
                0.0,
                "must not be 0",
            ));
        }
        if master == slave {
            return Err(reject(
                PARAMETER_NOT_CORRECT,
                format!("axis '{name}': {fb}: master and slave are the same axis"),
            ));
        }
        // No cycles: the master must not (indirectly) follow the slave.
        let mut i = master;
        while let Some(cp) = self.axes[i].coupling {
            if cp.master == slave {
                return Err(reject(
                    PARAMETER_NOT_CORRECT,
                    format!(
                        "axis '{name}': {fb}: coupling to '{}' would close a loop",
                        c.master
                    ),
                ));
            }
            i = cp.master;
        }
        self.admit_state(slave, FbClass::GearIn, fb)?;
        let m = &self.axes[master];
        if m.set.vel.abs() > 1e-9 {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{name}': {fb}: master '{}' is moving (v = {})",
                    c.master, m.set.vel
                ),
            ));
        }
        let ms = MasterState::of(m);
        let id = self.fbs.admit(slave, FbKind::GearIn, CommandState::Active);
        let ratio = c.ratio_numerator / c.ratio_denominator as f64;
        let a = &mut self.axes[slave];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        a.abort_motion(&mut self.fbs);
        a.couple(master, ratio, &ms);
        self.recompute_order();
        // InGear the cycle after the edge; the command is then complete (§4.12.1).
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    /// MC_GearInDyn (§4.12.2).
    pub fn gear_in_dyn(&mut self, slave: usize, c: GearInDyn) -> Result<FbReply, Rejection> {
        let fb = "MC_GearInDyn";
        let name = self.axes[slave].name.clone();
        let master = self.axis_index(&c.master)?;
        for (f, v) in [
            ("GearRatio", c.gear_ratio),
            ("Acceleration", c.acceleration),
            ("Deceleration", c.deceleration),
            ("Jerk", c.jerk),
        ] {
            finite(&name, fb, f, v)?;
        }
        for (f, v) in [
            ("Acceleration", c.acceleration),
            ("Deceleration", c.deceleration),
            ("Jerk", c.jerk),
        ] {
            if v < 0.0 {
                return Err(not_correct(
                    &name,
                    fb,
                    f,
                    v,
                    "must be >= 0 (0 = axis default)",
                ));
            }
        }
        if master == slave {
            return Err(reject(
                PARAMETER_NOT_CORRECT,
                format!("axis '{name}': {fb}: master and slave are the same axis"),
            ));
        }
        let acc = if c.acceleration > 0.0 {
            c.acceleration
        } else {
            self.axes[slave].cfg.acceleration
        };
        let rate = acc / self.axes[master].cfg.max_velocity;
        let current = self.axes[slave].coupling.filter(|cp| cp.master == master);
        let running = current.and_then(|cp| cp.dynamic).and_then(|d| d.owner);
        if !c.enable {
            // Enable↓: the command ends, the coupling stays with the frozen ratio.
            if let (Some(id), Some(mut cp)) = (running, current) {
                if let Some(mut d) = cp.dynamic {
                    d.owner = None;
                    d.target = cp.ratio;
                    cp.dynamic = Some(d);
                }
                self.axes[slave].coupling = Some(cp);
                self.fbs.done(id);
                self.fbs.set_execute(id, false);
                return Ok(Self::reply(id));
            }
            return Ok(self.untracked(FbValue::None));
        }
        if let (Some(id), Some(mut cp)) = (running, current) {
            // Cyclic update of the running instance.
            if let Some(mut d) = cp.dynamic {
                d.target = c.gear_ratio;
                d.rate = rate;
                cp.dynamic = Some(d);
            }
            self.axes[slave].coupling = Some(cp);
            return Ok(Self::reply(id));
        }
        // No loops.
        let mut i = master;
        while let Some(cp) = self.axes[i].coupling {
            if cp.master == slave {
                return Err(reject(
                    PARAMETER_NOT_CORRECT,
                    format!(
                        "axis '{name}': {fb}: coupling to '{}' would close a loop",
                        c.master
                    ),
                ));
            }
            i = cp.master;
        }
        self.admit_state(slave, FbClass::GearInDyn, fb)?;
        let m = &self.axes[master];
        let recouple = current.is_some();
        if !recouple && m.set.vel.abs() > 1e-9 {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{name}': {fb}: master '{}' is moving (v = {})",
                    c.master, m.set.vel
                ),
            ));
        }
        let ms = MasterState::of(m);
        let id = self
            .fbs
            .admit(slave, FbKind::GearInDyn, CommandState::Active);
        let a = &mut self.axes[slave];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        a.abort_motion(&mut self.fbs);
        // A re-coupling starts from the frozen ratio and slews; a new one starts at GearRatio.
        let r_eff = current.map_or(c.gear_ratio, |cp| cp.ratio);
        let d = crate::gearing::DynCoupling {
            owner: Some(id),
            target: c.gear_ratio,
            rate,
            m_prev: 0.0,
        };
        a.couple_dyn(master, r_eff, d, &ms);
        if r_eff == c.gear_ratio {
            if let Some(i) = self.fbs.get_mut(id) {
                i.in_velocity = true;
            }
        }
        self.recompute_order();
        Ok(Self::reply(id))
    }

    /// MC_GearOut (§4.12.3).
    pub fn gear_out(&mut self, slave: usize) -> Result<FbReply, Rejection> {
        self.admit_state(slave, FbClass::GearOut, "MC_GearOut")?;
        let id = self.fbs.admit(slave, FbKind::GearOut, CommandState::Busy);
        let a = &mut self.axes[slave];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        // With an MC_GearInDyn still enabled the slave is decoupled only briefly: the FB
        // couples again at once (§4.12.2), i.e. the coupling stays.
        let dyn_enabled = a
            .coupling
            .and_then(|c| c.dynamic)
            .is_some_and(|d| d.owner.is_some())
            || a.coupling
                .and_then(|c| c.ext.multi)
                .is_some_and(|m| m.owner.is_some());
        if !dyn_enabled {
            a.decouple_keep_velocity();
        }
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }
}
