//! The slave side of a coupling (§4.12): the set point a coupled axis takes from its
//! master each cycle, coupling and decoupling. The coupling's data are in [`crate::gearing`].

use super::{Axis, Job, JobKind};
use crate::gearing::*;
use motion_core::{Limits, Profile1, State1};

impl Axis {
    /// The master value the coupling uses (set or actual, parameter 1064).
    pub fn master_value(&self, m: &MasterState) -> State1 {
        if self.cfg.couple_slave_to_actual_values {
            State1 {
                pos: m.act_pos,
                vel: m.act_velo,
                acc: 0.0,
            }
        } else {
            m.set
        }
    }

    /// Couples this axis as slave (at standstill).
    pub fn couple(&mut self, master: usize, ratio: f64, m: &MasterState) {
        let mv = self.master_value(m);
        self.job = None;
        self.coupling = Some(Coupling {
            master,
            ratio,
            m0: mv.pos - m.coord_offset,
            s0: self.set.pos,
            dynamic: None,
            ext: Default::default(),
        });
        self.last_target = None;
    }

    /// Couples (or re-couples) with MC_GearInDyn: velocity-type, starting at `r_eff`.
    pub fn couple_dyn(&mut self, master: usize, r_eff: f64, d: DynCoupling, m: &MasterState) {
        let mv = self.master_value(m);
        self.job = None;
        self.coupling = Some(Coupling {
            master,
            ratio: r_eff,
            m0: mv.pos - m.coord_offset,
            s0: self.set.pos,
            dynamic: Some(DynCoupling {
                m_prev: mv.pos - m.coord_offset,
                ..d
            }),
            ext: Default::default(),
        });
        self.last_target = None;
    }

    /// Set point of a coupled slave for this cycle.
    pub fn follow(
        &mut self,
        mut c: Coupling,
        m: &MasterState,
        dt: f64,
        fbs: &mut crate::handshake::Handshake,
    ) {
        if let Some(mm) = c.ext.multi {
            return self.follow_multi(c, mm, dt, fbs);
        }
        let mv = self.master_value(m);
        if let Some(mut d) = c.dynamic {
            // Velocity-type coupling: ΔSlavePos = r_eff·ΔMasterPos, r_eff slewed (§4.12.2).
            let r0 = c.ratio;
            let step = d.rate * dt;
            let diff = d.target - r0;
            c.ratio = if diff.abs() <= step {
                d.target
            } else {
                r0 + step * diff.signum()
            };
            let raw = mv.pos - m.coord_offset;
            let pos = self.set.pos + c.ratio * (raw - d.m_prev);
            d.m_prev = raw;
            self.set = State1 {
                pos,
                vel: c.ratio * mv.vel,
                acc: c.ratio * mv.acc + (c.ratio - r0) / dt * mv.vel,
            };
            self.target_pos = self.set.pos;
            if let Some(id) = d.owner {
                if let Some(i) = fbs.get_mut(id) {
                    i.in_velocity = c.ratio == d.target;
                }
            }
            c.dynamic = Some(d);
            self.coupling = Some(c);
            return;
        }
        // Phasing (§4.13): an additive slave offset φ with its derivatives.
        let ph = c.ext.phase.s;
        self.set = State1 {
            pos: c.s0 + c.ratio * (mv.pos - m.coord_offset - c.m0) + ph.pos,
            vel: c.ratio * mv.vel + ph.vel,
            acc: c.ratio * mv.acc + ph.acc,
        };
        self.target_pos = self.set.pos;
    }

    /// Decouples; a moving slave keeps its velocity for ever (T10, manual warning), a slave
    /// at rest is in Standstill (T10b).
    pub fn decouple_keep_velocity(&mut self) {
        if self.coupling.take().is_none() {
            return;
        }
        if self.set.vel.abs() > 1e-9 {
            let s = State1 {
                pos: self.set.pos,
                vel: self.set.vel,
                acc: 0.0,
            };
            let l = Limits {
                velocity: self.cfg.max_velocity.max(s.vel.abs()),
                acceleration: self.cfg.acceleration,
                deceleration: self.cfg.deceleration,
                jerk: self.cfg.jerk,
            };
            let mut j = Job::internal(JobKind::Velocity, Profile1::hold(s), f64::NAN, l);
            j.dir = s.vel.signum();
            j.velocity = s.vel.abs();
            j.held = true;
            self.set.acc = 0.0;
            self.start_job(j);
        } else {
            self.set = State1::at_rest(self.set.pos);
        }
    }
}

impl MasterState {
    /// What a slave reads from master axis `m`.
    pub fn of(m: &Axis) -> Self {
        MasterState {
            set: m.set,
            act_pos: m.act_pos,
            act_velo: m.act_velo,
            coord_offset: m.coord_offset,
        }
    }
}
