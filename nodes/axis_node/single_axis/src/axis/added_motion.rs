//! The added FBs' part of the single axis' own motion and status: the MC_GearInMultiMaster
//! slave set point (§4.12.4), stopping the external set-point generator (§4.6), the phasing
//! status (§4.13) and the StateDWord bits of these functions. Their per-axis and per-coupling
//! data live in [`crate::added`]; the FB calls that start them are in the engine.

use super::{Axis, Job, JobKind};
use crate::added::{GearInMultiMasterSyncMode, Multi};
use crate::gearing::Coupling;
use motion_core::{Limits, Profile1, State1};

impl Axis {
    /// StateDWord bits of the added functions: 14 ExtSetPointGenEnabled, 15 PhasingActive.
    pub fn ext_state_bits(&self) -> u32 {
        let mut w = 0;
        if self.ext.ext_gen.enabled {
            w |= 1 << 14;
        }
        if self.phasing_active() {
            w |= 1 << 15;
        }
        w
    }
}

impl Axis {
    /// Current phasing offset φ (NcToPlc.AbsPhasingPos), 0 when not coupled.
    pub fn abs_phasing_pos(&self) -> f64 {
        self.coupling.map_or(0.0, |c| c.ext.phase.s.pos)
    }

    /// Status.PhasingActive (StateDWord bit 15): a phasing motion is running.
    pub fn phasing_active(&self) -> bool {
        self.coupling
            .is_some_and(|c| c.ext.phase.job.is_some_and(|j| !j.reached))
    }
}

impl Axis {
    /// Disables the generator; a fed velocity ≠ 0 is stopped with AxisDec/AxisJerk.
    pub fn disable_ext_gen(&mut self) {
        if !std::mem::take(&mut self.ext.ext_gen.enabled) {
            return;
        }
        self.ext.ext_gen.torque_offset = 0.0;
        if self.set.vel.abs() > 1e-9 || self.set.acc.abs() > 1e-9 {
            let l = self.default_limits();
            let profile = self.plan_stop(&l);
            let stop = profile.end().pos;
            self.start_job(Job::internal(JobKind::Halt, profile, stop, l));
        } else {
            self.set = State1::at_rest(self.set.pos);
        }
    }
}

impl Axis {
    /// Set point of a multi-master slave for this cycle (called from `follow`). No alloc.
    pub fn follow_multi(
        &mut self,
        mut c: Coupling,
        mut m: Multi,
        dt: f64,
        fbs: &mut crate::handshake::Handshake,
    ) {
        let slew = !m.asd || m.sync_mode == GearInMultiMasterSyncMode::PosSync1;
        let mut dp = 0.0;
        let mut v_star = 0.0;
        let mut a_star = 0.0;
        for k in 0..4 {
            if m.masters[k].is_none() {
                continue;
            }
            let r0 = m.ratio[k];
            m.ratio[k] = if slew {
                let step = m.rate[k] * dt;
                let diff = m.target[k] - r0;
                if diff.abs() <= step {
                    m.target[k]
                } else {
                    r0 + step * diff.signum()
                }
            } else {
                m.target[k]
            };
            let s = m.inputs[k];
            dp += m.ratio[k] * (s.pos - m.m_prev[k]);
            v_star += m.ratio[k] * s.vel;
            a_star += m.ratio[k] * s.acc + (m.ratio[k] - r0) / dt * s.vel;
            m.m_prev[k] = s.pos;
        }
        let ratios_reached = (0..4).all(|k| m.masters[k].is_none() || m.ratio[k] == m.target[k]);
        let in_gear;
        if !m.asd {
            self.set = State1 {
                pos: self.set.pos + dp,
                vel: v_star,
                acc: a_star,
            };
            m.ls = self.set;
            in_gear = ratios_reached;
        } else {
            let jerk = m.jerk.min(m.acc.max(m.dec) / dt);
            let l = Limits {
                velocity: self.cfg.max_velocity,
                acceleration: m.acc,
                deceleration: m.dec,
                jerk,
            };
            let v_t = v_star.clamp(-l.velocity, l.velocity);
            let track_pos = match m.sync_mode {
                GearInMultiMasterSyncMode::VeloSync => false,
                GearInMultiMasterSyncMode::PosSync1 => {
                    if m.pos_synced {
                        m.p_star += dp;
                    } else if (m.ls.vel - v_t).abs() <= 1e-6 && m.ls.acc.abs() <= 1e-6 {
                        m.pos_synced = true;
                        m.p_star = m.ls.pos + dp;
                    }
                    m.pos_synced
                }
                GearInMultiMasterSyncMode::PosSync2 => {
                    m.p_star = c.s0
                        + (0..4)
                            .filter(|&k| m.masters[k].is_some())
                            .map(|k| m.ratio[k] * (m.inputs[k].pos - m.m0[k]))
                            .sum::<f64>();
                    true
                }
            };
            let within = (v_star - m.v_prev).abs()
                <= l.acceleration.max(l.deceleration) * dt * (1.0 + 1e-9)
                && v_star.abs() <= l.velocity;
            m.synced &= within && ratios_reached;
            if m.synced {
                // Synchronous: the ideal motion (no planning in steady state).
                m.ls = State1 {
                    pos: if track_pos { m.p_star } else { m.ls.pos + dp },
                    vel: v_star,
                    acc: a_star,
                };
            } else if track_pos {
                // Track p* in the frame moving with the masters: the error (to the previous
                // cycle's p*) is brought to 0 jerk-limited, then the frame is moved on.
                let err = State1 {
                    pos: m.ls.pos - (m.p_star - dp),
                    vel: m.ls.vel - v_star,
                    acc: m.ls.acc - a_star,
                };
                match Profile1::to_position(err, 0.0, 0.0, &l) {
                    Ok(p) => {
                        let r = p.at(dt);
                        m.ls = State1 {
                            pos: m.p_star + r.pos,
                            vel: v_star + r.vel,
                            acc: a_star + r.acc,
                        };
                    }
                    Err(_) => m.ls.pos += m.ls.vel * dt,
                }
            } else {
                match Profile1::to_velocity(m.ls, v_t, &l) {
                    Ok(p) => m.ls = p.at(dt),
                    Err(_) => m.ls.pos += m.ls.vel * dt,
                }
            }
            let vel_sync = (m.ls.vel - v_star).abs() <= 1e-6;
            let pos_sync = !track_pos || (m.ls.pos - m.p_star).abs() <= 1e-6;
            in_gear = ratios_reached
                && vel_sync
                && pos_sync
                && (m.sync_mode == GearInMultiMasterSyncMode::VeloSync || track_pos);
            m.synced = in_gear;
            m.v_prev = v_star;
            let ph = c.ext.phase.s;
            self.set = State1 {
                pos: m.ls.pos + ph.pos,
                vel: m.ls.vel + ph.vel,
                acc: m.ls.acc + ph.acc,
            };
        }
        self.target_pos = self.set.pos;
        if let Some(id) = m.owner {
            if let Some(i) = fbs.get_mut(id) {
                i.in_velocity = in_gear;
            }
        }
        if let Some(k) = m.masters.iter().position(|x| Some(c.master) == *x) {
            c.ratio = m.ratio[k];
        }
        c.ext.multi = Some(m);
        self.coupling = Some(c);
    }
}

impl Coupling {
    /// All master axes of this coupling.
    pub fn masters(&self) -> impl Iterator<Item = usize> + '_ {
        let multi = self.ext.multi.map(|m| m.masters);
        let single = multi.is_none().then_some(self.master);
        single
            .into_iter()
            .chain(multi.into_iter().flat_map(|m| m.into_iter().flatten()))
    }
}
