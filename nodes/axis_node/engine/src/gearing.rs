//! Linear master/slave coupling: MC_GearIn / MC_GearOut (single_axis.md §4.12.1, §4.12.3,
//! §2.5, W10). The slave follows the master's set position (or actual position with
//! AxisCoupleSlaveToActualValues, 1064) in the same cycle: masters are stepped before their
//! slaves. `SlavePos = SlavePos(t0) + ratio·(MasterPos − MasterPos(t0))`.

use crate::axis::{Axis, Job, JobKind};
use motion_core::{Limits, Profile1, State1};

/// An active coupling of this axis as slave.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coupling {
    pub master: usize,
    pub ratio: f64,
    /// Master position at the coupling instant, in the master's raw coordinates (so that
    /// MC_SetPosition/homing on the master do not move the slave).
    pub m0: f64,
    /// Slave set position at the coupling instant.
    pub s0: f64,
    /// MC_GearInDyn: velocity-type coupling with a slewed ratio.
    pub dynamic: Option<DynCoupling>,
    /// Phasing offset and MC_GearInMultiMaster data (engine/phasing.rs, multi_master.rs).
    pub ext: crate::added::CouplingExt,
}

/// State of an MC_GearInDyn coupling (§4.12.2): `ratio` of [`Coupling`] is r_eff.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DynCoupling {
    /// The enabled MC_GearInDyn instance (None after Enable↓: ratio frozen).
    pub owner: Option<motion_core::CmdId>,
    /// GearRatio input.
    pub target: f64,
    /// Slew rate |dr/dt| = Acceleration / master AxisMaxVelocity \[1/s\].
    pub rate: f64,
    /// Master raw position of the previous cycle.
    pub m_prev: f64,
}

/// What a slave reads from its master each cycle.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MasterState {
    pub set: State1,
    pub act_pos: f64,
    pub act_velo: f64,
    /// The master's coordinate offset (raw = position − offset).
    pub coord_offset: f64,
}

impl MasterState {
    /// What a slave reads from master axis `m`.
    pub(crate) fn of(m: &Axis) -> Self {
        MasterState {
            set: m.set,
            act_pos: m.act_pos,
            act_velo: m.act_velo,
            coord_offset: m.coord_offset,
        }
    }
}

impl Axis {
    /// The master value the coupling uses (set or actual, parameter 1064).
    pub(crate) fn master_value(&self, m: &MasterState) -> State1 {
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
    pub(crate) fn couple(&mut self, master: usize, ratio: f64, m: &MasterState) {
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
    pub(crate) fn couple_dyn(
        &mut self,
        master: usize,
        r_eff: f64,
        d: DynCoupling,
        m: &MasterState,
    ) {
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
    pub(crate) fn follow(
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
    pub(crate) fn decouple_keep_velocity(&mut self) {
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
