//! Phasing: MC_PhasingAbsolute, MC_PhasingRelative, MC_HaltPhasing (single_axis.md §4.13).
//!
//! Model (spec proposal): the coupling equation of the slave gets an additive offset φ in
//! **slave** units, `SlavePos = s0 + ratio·(MasterPos − m0) + φ` (MC_GearIn) or
//! `SlavePos = limiter output + φ` (MC_GearInMultiMaster with AdvancedSlaveDynamics). φ is a
//! jerk-limited profile (the FB's Velocity, Acceleration, Deceleration and one Jerk for both
//! ramps; 0 = the slave's AxisAcc/AxisDec/AxisJerk) that starts from the current phasing
//! state, so a new phasing command or MC_HaltPhasing takes over without a velocity step.
//! φ lives on the coupling (`Phase`): a new coupling starts at φ = 0, decoupling (GearOut,
//! error, power off, reset, a motion command on an allowed slave) ends the phasing command
//! (CommandAborted, or Error with the axis error id).
//!
//! Admission (§2.4, §4.13): only on a coupled slave (Standstill/DiscreteMotion/
//! ContinuousMotion → 0x4B05, other states 0x4B01); not on MC_GearInDyn couplings and not on
//! MC_GearInMultiMaster couplings without AdvancedSlaveDynamics (0x4B05); `Master` must be a
//! master of that coupling (0x4B05, proposal); BufferMode other than MC_Aborting → 0x4B04;
//! Velocity < 0.01 or > AxisMaxVelocity, negative dynamics → 0x4B06.
//!
//! Outputs: Done when φ reached the target (MC_HaltPhasing: when the phasing velocity is 0);
//! `AbsolutePhaseShift` (Absolute) = φ, `CoveredPhaseShift` (Relative) = φ − φ at the edge
//! ([`ExtraOutputs::Phasing`]). With ContinuousUpdate at the edge the instance stays
//! Busy/Active together with Done once the target was reached and follows
//! [`PhasingUpdate`] calls until Execute falls (§3.2 exception). Simplification: Done, once
//! TRUE, stays TRUE while a later update moves φ again.

use super::*;
use crate::added::*;
use motion_core::Profile1;

/// Inputs common to the two phasing FBs.
struct PhaseRequest<'a> {
    master: &'a str,
    continuous_update: bool,
    phase_shift: f64,
    velocity: f64,
    acceleration: f64,
    deceleration: f64,
    jerk: f64,
    buffer_mode: BufferMode,
}

impl AxisSet {
    /// Screening shared by the three FBs; returns nothing but errors (axis untouched).
    fn phasing_admission(
        &self,
        slave: usize,
        master: &str,
        fb: &str,
        buffer_mode: BufferMode,
    ) -> Result<(), Rejection> {
        let m = self.axis_index(master)?;
        let name = &self.axes[slave].name;
        if buffer_mode != BufferMode::Aborting {
            return Err(reject(
                INVALID_MODE,
                format!("axis '{name}': {fb}: BufferMode {buffer_mode:?} (only MC_Aborting)"),
            ));
        }
        self.admit_state(slave, FbClass::Phasing, fb)?;
        let Some(c) = self.axes[slave].coupling else {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("axis '{name}': {fb}: the axis is not a coupled slave"),
            ));
        };
        if c.dynamic.is_some() {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("axis '{name}': {fb}: phasing is not supported on MC_GearInDyn couplings"),
            ));
        }
        if c.ext.multi.is_some_and(|mm| !mm.asd) {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{name}': {fb}: phasing on MC_GearInMultiMaster needs \
                     Options.AdvancedSlaveDynamics"
                ),
            ));
        }
        if !c.masters().any(|i| i == m) {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("axis '{name}': {fb}: '{master}' is not a master of this slave"),
            ));
        }
        Ok(())
    }

    /// Limits of the phasing motion: finite, Velocity in [0.01, AxisMaxVelocity], the rest
    /// ≥ 0 (0 = the slave's default).
    fn phasing_limits(
        &self,
        slave: usize,
        fb: &str,
        velocity: f64,
        acc: f64,
        dec: f64,
        jerk: f64,
    ) -> Result<Limits, Rejection> {
        let a = &self.axes[slave];
        if !(0.01..=a.cfg.max_velocity).contains(&velocity) {
            return Err(not_correct(
                &a.name,
                fb,
                "Velocity",
                velocity,
                &format!("must be in [0.01, {}]", a.cfg.max_velocity),
            ));
        }
        move_limits(a, fb, Some(velocity), acc, dec, jerk)
    }

    fn phasing(
        &mut self,
        slave: usize,
        ty: PhasingType,
        r: PhaseRequest,
    ) -> Result<FbReply, Rejection> {
        let (fb, kind) = match ty {
            PhasingType::Absolute => ("MC_PhasingAbsolute", FbKind::PhasingAbsolute),
            _ => ("MC_PhasingRelative", FbKind::PhasingRelative),
        };
        let name = self.axes[slave].name.clone();
        for (f, v) in [
            ("PhaseShift", r.phase_shift),
            ("Velocity", r.velocity),
            ("Acceleration", r.acceleration),
            ("Deceleration", r.deceleration),
            ("Jerk", r.jerk),
        ] {
            finite(&name, fb, f, v)?;
        }
        self.phasing_admission(slave, r.master, fb, r.buffer_mode)?;
        let limits = self.phasing_limits(
            slave,
            fb,
            r.velocity,
            r.acceleration,
            r.deceleration,
            r.jerk,
        )?;
        let Some(c) = self.axes[slave].coupling else {
            unreachable!("checked by phasing_admission")
        };
        let phase = c.ext.phase;
        let target = match ty {
            PhasingType::Absolute => r.phase_shift,
            _ => phase.s.pos + r.phase_shift,
        };
        let profile = Profile1::to_position(phase.s, target, 0.0, &limits)
            .map_err(|e| not_correct(&name, fb, "PhaseShift", r.phase_shift, &e.to_string()))?;
        let id = self.fbs.admit(slave, kind, CommandState::Active);
        self.start_phase_job(
            slave,
            PhaseJob {
                owner: id,
                ty,
                profile,
                t: 0.0,
                start: phase.s.pos,
                continuous: r.continuous_update,
                reached: false,
            },
        );
        Ok(Self::reply(id))
    }

    /// Ends a phasing command whose coupling went away (GearOut, error, power off, reset, a
    /// motion command): CommandAborted, or Error with the axis error id.
    fn end_orphan_phasing(&mut self, i: usize) {
        let a = &mut self.axes[i];
        let Some(owner) = a.ext.phasing_owner else {
            return;
        };
        let live = a.coupling.and_then(|c| c.ext.phase.job).map(|j| j.owner);
        if live == Some(owner) {
            return;
        }
        a.ext.phasing_owner = None;
        if a.error_id.is_none() {
            self.fbs.aborted(owner);
        } else {
            self.fbs.error(owner, a.error_id);
        }
        if let Some(inst) = self.fbs.get_mut(owner) {
            inst.locked = false;
        }
    }

    /// Installs a phasing job; the running one ends with CommandAborted.
    fn start_phase_job(&mut self, slave: usize, job: PhaseJob) {
        self.end_orphan_phasing(slave);
        let a = &mut self.axes[slave];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        let Some(mut c) = a.coupling else { return };
        if let Some(old) = c.ext.phase.job.take() {
            self.fbs.aborted(old.owner);
            if let Some(i) = self.fbs.get_mut(old.owner) {
                i.locked = false;
            }
        }
        c.ext.phase.job = Some(job);
        a.coupling = Some(c);
        a.ext.phasing_owner = Some(job.owner);
        let out = phasing_outputs(&job, c.ext.phase.s.pos);
        self.fbs.extra.insert(job.owner, out);
    }

    /// MC_PhasingAbsolute (§4.13.1).
    pub fn phasing_absolute(
        &mut self,
        slave: usize,
        c: PhasingAbsolute,
    ) -> Result<FbReply, Rejection> {
        self.phasing(
            slave,
            PhasingType::Absolute,
            PhaseRequest {
                master: &c.master,
                continuous_update: c.continuous_update,
                phase_shift: c.phase_shift,
                velocity: c.velocity,
                acceleration: c.acceleration,
                deceleration: c.deceleration,
                jerk: c.jerk,
                buffer_mode: c.buffer_mode,
            },
        )
    }

    /// MC_PhasingRelative (§4.13.2).
    pub fn phasing_relative(
        &mut self,
        slave: usize,
        c: PhasingRelative,
    ) -> Result<FbReply, Rejection> {
        self.phasing(
            slave,
            PhasingType::Relative,
            PhaseRequest {
                master: &c.master,
                continuous_update: c.continuous_update,
                phase_shift: c.phase_shift,
                velocity: c.velocity,
                acceleration: c.acceleration,
                deceleration: c.deceleration,
                jerk: c.jerk,
                buffer_mode: c.buffer_mode,
            },
        )
    }

    /// MC_HaltPhasing (§4.13.3).
    pub fn halt_phasing(&mut self, slave: usize, c: HaltPhasing) -> Result<FbReply, Rejection> {
        let fb = "MC_HaltPhasing";
        let name = self.axes[slave].name.clone();
        finite(&name, fb, "Deceleration", c.deceleration)?;
        finite(&name, fb, "Jerk", c.jerk)?;
        self.phasing_admission(slave, &c.master, fb, c.buffer_mode)?;
        let a = &self.axes[slave];
        let mut limits = move_limits(a, fb, None, 0.0, c.deceleration, c.jerk)?;
        let Some(cp) = a.coupling else {
            unreachable!("checked by phasing_admission")
        };
        let s = cp.ext.phase.s;
        // The braking ramp uses the halt's deceleration for both directions of |dφ/dt|.
        limits.velocity = limits.velocity.max(s.vel.abs()).max(1e-9);
        limits.acceleration = limits.deceleration.max(s.acc.abs());
        let profile = Profile1::stopping(s, &limits)
            .map_err(|e| not_correct(&name, fb, "Deceleration", c.deceleration, &e.to_string()))?;
        let id = self
            .fbs
            .admit(slave, FbKind::HaltPhasing, CommandState::Active);
        self.start_phase_job(
            slave,
            PhaseJob {
                owner: id,
                ty: PhasingType::Stop,
                profile,
                t: 0.0,
                start: s.pos,
                continuous: false,
                reached: false,
            },
        );
        Ok(Self::reply(id))
    }

    /// Halts the phasing run by instance `id` (a cancelled action goal): an internal
    /// MC_HaltPhasing with the slave's AxisDec/AxisJerk; `id` ends with CommandAborted.
    pub(crate) fn halt_phasing_of(&mut self, slave: usize, id: CmdId) {
        let a = &self.axes[slave];
        let Some(cp) = a
            .coupling
            .filter(|c| c.ext.phase.job.is_some_and(|j| j.owner == id))
        else {
            return;
        };
        let s = cp.ext.phase.s;
        let limits = Limits {
            velocity: a.cfg.max_velocity.max(s.vel.abs()),
            acceleration: a.cfg.deceleration.max(s.acc.abs()),
            deceleration: a.cfg.deceleration,
            jerk: a.cfg.jerk,
        };
        let Ok(profile) = Profile1::stopping(s, &limits) else {
            return;
        };
        let halt = self
            .fbs
            .admit(slave, FbKind::HaltPhasing, CommandState::Active);
        self.start_phase_job(
            slave,
            PhaseJob {
                owner: halt,
                ty: PhasingType::Stop,
                profile,
                t: 0.0,
                start: s.pos,
                continuous: false,
                reached: false,
            },
        );
    }

    /// A later call of a running MC_PhasingAbsolute/Relative with ContinuousUpdate.
    pub fn phasing_update(&mut self, u: PhasingUpdate) -> Result<FbReply, Rejection> {
        let id = u.id;
        let inst = self.fbs.get(id).copied().ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        if !matches!(inst.kind, FbKind::PhasingAbsolute | FbKind::PhasingRelative) {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("command instance {} is not an MC_Phasing* instance", id.0),
            ));
        }
        let slave = inst.axis;
        let fb = if inst.kind == FbKind::PhasingAbsolute {
            "MC_PhasingAbsolute"
        } else {
            "MC_PhasingRelative"
        };
        let name = self.axes[slave].name.clone();
        for (f, v) in [
            ("PhaseShift", u.phase_shift),
            ("Velocity", u.velocity),
            ("Acceleration", u.acceleration),
            ("Deceleration", u.deceleration),
            ("Jerk", u.jerk),
        ] {
            finite(&name, fb, f, v)?;
        }
        let limits = self.phasing_limits(
            slave,
            fb,
            u.velocity,
            u.acceleration,
            u.deceleration,
            u.jerk,
        )?;
        let a = &mut self.axes[slave];
        // Without ContinuousUpdate at the edge (or after the command ended) later input
        // changes are ignored (§3.1 rule 1).
        let Some(mut c) = a.coupling else {
            return Ok(Self::reply(id));
        };
        let Some(mut j) = c.ext.phase.job.filter(|j| j.owner == id && j.continuous) else {
            return Ok(Self::reply(id));
        };
        let target = match j.ty {
            PhasingType::Absolute => u.phase_shift,
            _ => j.start + u.phase_shift,
        };
        j.profile = Profile1::to_position(c.ext.phase.s, target, 0.0, &limits)
            .map_err(|e| not_correct(&name, fb, "PhaseShift", u.phase_shift, &e.to_string()))?;
        j.t = 0.0;
        j.reached = false;
        c.ext.phase.job = Some(j);
        a.coupling = Some(c);
        Ok(Self::reply(id))
    }

    /// One cycle of the phasing of axis `i` (before the slave follows its master): advances
    /// φ, reports Done, ends commands whose coupling went away. No alloc.
    pub(crate) fn phasing_step(&mut self, i: usize, dt: f64) {
        self.end_orphan_phasing(i);
        let a = &mut self.axes[i];
        let Some(mut c) = a.coupling else { return };
        let Some(mut j) = c.ext.phase.job else { return };
        j.t += dt;
        c.ext.phase.s = j.profile.at(j.t);
        if j.t >= j.profile.duration() {
            c.ext.phase.s = State1::at_rest(j.profile.end().pos);
            if !j.reached {
                // (Again after a ContinuousUpdate moved φ: Done is already shown then.)
                j.reached = true;
                let keep = j.continuous && self.fbs.get(j.owner).is_some_and(|i| i.execute);
                self.fbs.done(j.owner);
                if let Some(inst) = self.fbs.get_mut(j.owner) {
                    inst.locked = keep;
                }
                if !keep {
                    j.continuous = false;
                }
            }
        }
        let out = phasing_outputs(&j, c.ext.phase.s.pos);
        if let Some(slot) = self.fbs.extra.get_mut(&j.owner) {
            *slot = out;
        }
        if j.reached && !j.continuous {
            c.ext.phase.job = None;
            a.ext.phasing_owner = None;
        } else {
            c.ext.phase.job = Some(j);
        }
        a.coupling = Some(c);
    }

    /// Execute of a phasing instance fell: a continuous command stops following updates
    /// (Done shown for one more cycle if not yet reached, §3.1 rule 6).
    pub(crate) fn phasing_execute_fell(&mut self, id: CmdId) {
        let Some(inst) = self.fbs.get(id).copied() else {
            return;
        };
        let a = &mut self.axes[inst.axis];
        let Some(mut c) = a.coupling else { return };
        let Some(mut j) = c.ext.phase.job.filter(|j| j.owner == id) else {
            return;
        };
        if j.reached {
            c.ext.phase.job = None;
            a.ext.phasing_owner = None;
            if let Some(i) = self.fbs.get_mut(id) {
                i.locked = false;
                i.cleared = true;
            }
        } else {
            j.continuous = false;
            c.ext.phase.job = Some(j);
        }
        a.coupling = Some(c);
    }
}

fn phasing_outputs(j: &PhaseJob, phi: f64) -> ExtraOutputs {
    match j.ty {
        PhasingType::Relative => ExtraOutputs::Phasing {
            absolute_phase_shift: None,
            covered_phase_shift: Some(phi - j.start),
        },
        _ => ExtraOutputs::Phasing {
            absolute_phase_shift: Some(phi),
            covered_phase_shift: None,
        },
    }
}
