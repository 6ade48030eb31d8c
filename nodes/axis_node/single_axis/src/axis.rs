//! One simulated axis: setpoint generator jobs, actual-value model, monitoring and the error
//! reaction (single_axis.md §1.1, §1.3, §1.4). The per-cycle order of §1.1 is in
//! [`Axis::step`]: (2) state/buffer logic, (3) setpoint generator, (4) actual values,
//! (5) monitoring; (1) happened in `AxisEngine::command`, (6) is the event queue.

use crate::config::{AxisConfig, FollowingModel};
use crate::error_ids;
use crate::handshake::Handshake;
use crate::modulo;
use crate::state::{derive_state, MotionState, StateFacts};
use motion_core::{CmdId, ErrorId, Limits, Profile1, State1};
use std::collections::BTreeMap;

// What the axis does per concept, each an `impl Axis` over the data of its leaf module.
mod added_motion;
mod follow;
mod homing_run;
mod nctoplc;
mod overlay;
mod probe_latch;
mod torque_mode;

/// What the setpoint generator is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JobKind {
    /// Discrete move to `target` (MoveAbsolute/Relative/Additive/Modulo).
    Position,
    /// Endless motion (MoveVelocity); also an orphan after an override change.
    Velocity,
    /// MC_Halt ramp, or the stop after a missing feed enable (no owner).
    Halt,
    /// MC_Stop ramp.
    Stop,
    /// Error reaction / MC_Reset while moving: AxisFastDec/AxisFastJerk.
    FastStop,
}

/// The running job of the setpoint generator.
#[derive(Clone, Copy, Debug)]
pub struct Job {
    /// The FB instance that owns the job; None for internal jobs (error reaction, homing runs).
    pub owner: Option<CmdId>,
    /// What kind of motion (and which stop dynamics apply).
    pub kind: JobKind,
    /// The jerk-limited profile being run, in profile coordinates.
    pub profile: Profile1,
    /// Time since the profile start \[s\].
    pub t: f64,
    /// Coordinate shift added by MC_SetPosition while running \[u\].
    pub offset: f64,
    /// Target (Position) or stop point (Halt/Stop/FastStop), in profile coordinates.
    pub target: f64,
    /// Commanded velocity (> 0) before override \[u/s\].
    pub velocity: f64,
    /// Travel direction (±1) of Velocity jobs.
    pub dir: f64,
    /// Dynamics (velocity field = commanded velocity).
    pub limits: Limits,
    /// Signed velocity at the end (blending transition), 0 = stop at the target.
    pub end_vel: f64,
    /// Done waits for the position monitoring (§3.7).
    pub monitor: bool,
    /// Override 0: the job stands still but stays active.
    pub paused: bool,
    /// MoveVelocity converted to a run to a blending position ends with CommandAborted.
    pub owner_aborts_at_end: bool,
    /// MC_MoveContinuousAbsolute/Relative: endless after reaching the target (§4.8.7).
    pub continuous: bool,
    /// Endless motion at constant velocity: the profile is a `hold`, nothing ends any more.
    pub held: bool,
}

/// A command waiting in the buffer (§3.6: at most one).
#[derive(Clone, Copy, Debug)]
pub struct Pending {
    /// The buffered FB instance.
    pub owner: CmdId,
    /// Its motion, resolved at admission.
    pub spec: Spec,
}

/// A motion request, resolved at admission.
#[derive(Clone, Copy, Debug)]
pub enum Spec {
    /// Move to an absolute target.
    Position {
        /// Target position \[u\].
        target: f64,
        /// Dynamics of the move.
        limits: Limits,
        /// Done waits for the position monitoring (§3.7).
        monitor: bool,
    },
    /// Endless motion in direction `dir`.
    Velocity {
        /// Travel direction (±1).
        dir: f64,
        /// Dynamics of the move.
        limits: Limits,
    },
    /// MC_Halt with the given dynamics.
    Halt {
        /// Braking dynamics.
        limits: Limits,
        /// Done waits for the position monitoring (§3.7).
        monitor: bool,
    },
    /// MC_MoveContinuousAbsolute/Relative: to `target`, arriving with `end_velocity` (≥ 0).
    Continuous {
        /// Target position \[u\].
        target: f64,
        /// EndVelocity, ≥ 0 \[u/s\].
        end_velocity: f64,
        /// Dynamics of the move.
        limits: Limits,
    },
}

/// The MC_Stop lock (§4.8.10).
#[derive(Clone, Copy, Debug)]
pub struct Lock {
    /// The MC_Stop instance that holds the lock.
    pub owner: CmdId,
    /// Its Execute input (the lock lasts while it is TRUE).
    pub execute: bool,
    /// The axis has come to rest.
    pub at_rest: bool,
    /// Options.EnableStopPositionMonitoring: Done waits for InTargetPosition (§3.7).
    pub monitor: bool,
    /// Done has been reported (the unlock counts from then).
    pub done: bool,
    /// Cycles left until unlock once at rest with Execute FALSE (proposal: 2).
    pub unlock_in: u8,
}

/// A finished positioning command waiting for InTargetPosition (§3.7).
#[derive(Clone, Copy, Debug)]
pub struct Settle {
    /// The finished positioning instance.
    pub owner: CmdId,
    /// Time spent waiting so far \[s\].
    pub elapsed: f64,
}

/// Runtime state of one axis.
#[derive(Clone, Debug)]
pub struct Axis {
    /// Axis name (the key of every command).
    pub name: std::sync::Arc<str>,
    /// Configuration (§1.2 parameters, validated).
    pub cfg: AxisConfig,
    /// Parameters without simulator effect, by NC index offset (§6).
    pub other_params: BTreeMap<u32, f64>,
    // MC_Power (§4.1)
    /// MC_Power.Enable.
    pub enable: bool,
    /// MC_Power.Enable_Positive.
    pub enable_positive: bool,
    /// MC_Power.Enable_Negative.
    pub enable_negative: bool,
    /// Effective override \[%\] (`PlcToNc.Override`).
    pub override_pct: f64,
    /// Override written by MC_Power \[%\].
    pub power_override: f64,
    /// The command id of this axis' MC_Power instance (from its first call on).
    pub power_id: Option<motion_core::CmdId>,
    /// MC_Power.ErrorID of its last call (override out of range); NONE after a good call.
    pub power_error: ErrorId,
    /// MC_SetOverride while enabled (VelFactor × 100) \[%\]; has precedence (§4.7.10).
    pub set_override: Option<f64>,
    /// The controller is switched on (drive enabled by MC_Power).
    pub controller_on: bool,
    /// MC_Power.Status: the axis is ready for operation.
    pub status: bool,
    /// Status follows `controller_on` in the next cycle (the drive answers one cycle late).
    pub status_pending: bool,
    /// MC_Power Enable fell with a non-Aborting BufferMode while a command moves the axis: the
    /// controller switches off once that motion has ended.
    pub power_off_pending: bool,
    // Errors (§1.4)
    /// The axis error (NcToPlc.ErrorCode); NONE when there is none.
    pub error_id: ErrorId,
    /// Reaction class of the MC message that raised `error_id` (plcopen_platform.md §7.2);
    /// 0 = the error is no MC message. A group brakes with it (§5).
    pub error_reaction: u16,
    /// The error came from the (simulated) drive: Status stays FALSE until MC_Reset (§1.5).
    pub drive_fault: bool,
    // Kinematics
    /// Set position, velocity and acceleration (NcToPlc.SetPos/SetVelo/SetAcc).
    pub set: State1,
    /// Actual position (NcToPlc.ActPos) \[u\].
    pub act_pos: f64,
    /// Actual velocity (NcToPlc.ActVelo) \[u/s\].
    pub act_velo: f64,
    /// Actual acceleration \[u/s²\].
    pub act_acc: f64,
    /// Simulated following offset: ActPos = SetPos + offset (the `set_following_offset` hook).
    pub following_offset: f64,
    /// Raw machine position = SetPos − coordinate offset (SetPosition/homing).
    pub coord_offset: f64,
    /// Sum of the MC_SetPosition shifts since start-up (reported in the state).
    pub set_position_offset: f64,
    /// The axis is referenced (NcToPlc.StateDWord bit Homed).
    pub homed: bool,
    // Jobs
    /// The running job of the set-point generator.
    pub job: Option<Job>,
    /// The buffered command (§3.6: at most one).
    pub pending: Option<Pending>,
    /// A finished positioning waiting for InTargetPosition (§3.7).
    pub settle: Option<Settle>,
    /// The MC_Stop lock (§4.8.10).
    pub lock: Option<Lock>,
    /// An MC_Reset waiting for the axis to come to rest before it is Done.
    pub reset_waiting: Option<CmdId>,
    /// MC_MoveContinuous* that reached its target with EndVelocity 0: Busy/Active with
    /// InEndVelocity until replaced (§4.8.7).
    pub idle_owner: Option<CmdId>,
    /// Armed latches: unit 1, unit 2, PlcEvent.
    pub probes: [Option<crate::probe::Probe>; 3],
    /// Virtual probe input levels of units 1 and 2 (this and the previous cycle).
    pub probe_level: [bool; 2],
    /// Probe input levels of the previous cycle.
    pub probe_prev: [bool; 2],
    /// Superposition (MC_MoveSuperImposed).
    pub overlay: Option<crate::superposition::Overlay>,
    /// Torque mode (MC_TorqueControl).
    pub torque: Option<crate::torque::TorqueJob>,
    /// SetTorque \[%\] (kept after torque mode ends).
    pub set_torque: f64,
    /// Coupling as slave (MC_GearIn).
    pub coupling: Option<crate::gearing::Coupling>,
    /// Homing run (MC_Home DefaultHoming).
    pub homing: Option<crate::homing::Homing>,
    /// Target position of the running or last move (NcToPlc.TargetPos) \[u\].
    pub target_pos: f64,
    /// Last commanded target for MC_MoveAdditive (§4.8.3); None = unknown.
    pub last_target: Option<f64>,
    /// Deceleration and jerk of the last move (MC_Halt/MC_Stop defaults).
    pub last_dec: f64,
    /// Jerk of the last move \[u/s³\].
    pub last_jerk: f64,
    /// Command number of the last motion command (NcToPlc.CmdNo).
    pub cmd_no: u16,
    /// StateDWord HasBeenStopped: MC_Stop has stopped the axis (cleared by the next motion).
    pub has_been_stopped: bool,
    // Monitoring (§1.3)
    /// Time within the target position window \[s\] (InTargetPosition after the filter time).
    pub in_target_timer: f64,
    /// InTargetPosition (§1.3).
    pub in_target: bool,
    /// Time the position lag has been over its limit \[s\] (error after the filter time).
    pub lag_timer: f64,
    /// Driven by a Part 4 group motion (state SynchronizedMotion, plcopen_platform.md §5).
    pub group_motion: bool,
    /// What the enabled software limits do (Tc2_MC2 §1.3 or R-SYS-1).
    pub travel_limits: TravelLimits,
    /// State of the phasing / ext. setpoint / §4.7 extension FBs (single_axis::set).
    pub ext: crate::added::AxisExt,
}

/// What enabled software limits do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TravelLimits {
    /// Tc2_MC2 (§1.3): targets beyond are refused, endless motions stop exactly at them.
    Planned,
    /// `isg_mcp` linear axes (R-SYS-1): targets beyond are refused; the limits are monitored
    /// every cycle (crossing → 91001, braking with `a_limit`), endless motions are not
    /// planned to stop at them.
    Monitored,
    /// `isg_mcp` modulo axes: limit monitoring is not effective (R-SYS-1).
    Off,
}

/// Velocities below this count as standstill \[u/s\].
const V_REST: f64 = 1e-9;

impl Axis {
    /// A powered-off axis at rest at position 0 (a Tc2_MC2 axis starts disabled).
    pub fn new(name: String, cfg: AxisConfig) -> Self {
        let p = cfg.initial_position;
        Axis {
            name: name.into(),
            other_params: BTreeMap::new(),
            enable: false,
            enable_positive: false,
            enable_negative: false,
            override_pct: 100.0,
            power_override: 100.0,
            power_id: None,
            power_error: ErrorId::NONE,
            set_override: None,
            controller_on: false,
            status: false,
            status_pending: false,
            power_off_pending: false,
            error_id: ErrorId::NONE,
            error_reaction: 0,
            drive_fault: false,
            set: State1::at_rest(p),
            act_pos: p,
            act_velo: 0.0,
            act_acc: 0.0,
            following_offset: 0.0,
            coord_offset: 0.0,
            set_position_offset: 0.0,
            homed: false,
            job: None,
            pending: None,
            settle: None,
            lock: None,
            reset_waiting: None,
            idle_owner: None,
            coupling: None,
            torque: None,
            set_torque: 0.0,
            overlay: None,
            probes: [None; 3],
            probe_level: [false; 2],
            probe_prev: [false; 2],
            homing: None,
            target_pos: p,
            last_target: None,
            last_dec: cfg.deceleration,
            last_jerk: cfg.jerk,
            cmd_no: 0,
            has_been_stopped: false,
            in_target_timer: 0.0,
            in_target: false,
            lag_timer: 0.0,
            group_motion: false,
            travel_limits: TravelLimits::Planned,
            ext: Default::default(),
            cfg,
        }
    }

    // ---------------------------------------------------------------- state (§2.3)

    /// The facts the §2 state machine derives the state from.
    pub fn facts(&self) -> StateFacts {
        let kind = self.job.as_ref().map(|j| j.kind);
        StateFacts {
            error: !self.error_id.is_none(),
            operational: self.controller_on && self.status,
            stopping: self.lock.is_some(),
            homing: self.homing.is_some(),
            coupled: self.coupling.is_some() || self.group_motion,
            continuous: kind == Some(JobKind::Velocity)
                || self.job.as_ref().is_some_and(|j| j.continuous)
                || self.torque.is_some()
                || self.ext.ext_gen_moving(),
            has_job: self.job.is_some() || self.torque.is_some(),
        }
    }

    /// The PLCopen state (§2).
    pub fn state(&self) -> MotionState {
        derive_state(&self.facts())
    }

    /// The set velocity or acceleration is not zero.
    pub fn moving(&self) -> bool {
        self.set.vel.abs() > V_REST || self.set.acc.abs() > V_REST
    }

    /// The current set state in job coordinates.
    fn job_start_state(&self) -> State1 {
        self.set
    }

    // ---------------------------------------------------------------- dynamics

    /// Effective velocity limit with override (§1.1). `v` > 0.
    pub fn effective_velocity(&self, v: f64) -> f64 {
        v * self.override_pct / 100.0
    }

    /// Plans a position job profile from the current set state under the override.
    pub fn plan_position(&self, target: f64, end_vel: f64, limits: &Limits) -> Option<Profile1> {
        let v = self.effective_velocity(limits.velocity);
        if v <= 0.0 {
            return Profile1::stopping(self.job_start_state(), &self.stop_limits(limits)).ok();
        }
        let end_vel = end_vel.clamp(-v, v);
        let l = Limits {
            velocity: v,
            ..*limits
        };
        Profile1::to_position(self.job_start_state(), target, end_vel, &l).ok()
    }

    /// Enabled software limit in direction `dir` (§1.3).
    pub fn soft_limit(&self, dir: f64) -> Option<f64> {
        if self.travel_limits == TravelLimits::Off {
            None
        } else if dir > 0.0 && self.cfg.en_max_soft_pos_limit {
            Some(self.cfg.max_soft_pos_limit)
        } else if dir < 0.0 && self.cfg.en_min_soft_pos_limit {
            Some(self.cfg.min_soft_pos_limit)
        } else {
            None
        }
    }

    /// R-SYS-1: the set position lies beyond an enabled software limit and still moves
    /// outwards (moving back inside is allowed).
    pub fn beyond_travel_limit(&self) -> bool {
        if self.travel_limits != TravelLimits::Monitored {
            return false;
        }
        let v = self.set.vel;
        (v > V_REST && self.soft_limit(1.0).is_some_and(|l| self.set.pos > l))
            || (v < -V_REST && self.soft_limit(-1.0).is_some_and(|l| self.set.pos < l))
    }

    /// Plans an endless motion; with an enabled software limit in the travel direction it is
    /// planned to stop exactly at the limit (§1.3). Returns the profile and that limit.
    pub fn plan_velocity(&self, dir: f64, limits: &Limits) -> Option<(Profile1, Option<f64>)> {
        if let Some(lim) = self
            .soft_limit(dir)
            .filter(|_| self.travel_limits == TravelLimits::Planned)
        {
            let p = if (lim - self.set.pos) * dir > 0.0 {
                self.plan_position(lim, 0.0, limits)?
            } else {
                self.plan_stop(limits)
            };
            return Some((p, Some(lim)));
        }
        self.plan_velocity_free(dir, limits).map(|p| (p, None))
    }

    /// An endless motion in direction `dir` (±1) at the override-scaled velocity of `limits`,
    /// from the current set state, ignoring the software limits (homing searches use it).
    pub fn plan_velocity_free(&self, dir: f64, limits: &Limits) -> Option<Profile1> {
        let v = self.effective_velocity(limits.velocity);
        let l = Limits {
            velocity: limits.velocity.max(self.set.vel.abs()).max(1e-9),
            ..*limits
        };
        Profile1::to_velocity(self.job_start_state(), dir * v, &l).ok()
    }

    /// Limits for a stop ramp: the velocity bound must not be below the current velocity.
    pub fn stop_limits(&self, l: &Limits) -> Limits {
        Limits {
            velocity: l
                .velocity
                .max(self.set.vel.abs())
                .max(self.cfg.max_velocity),
            acceleration: l.acceleration.max(l.deceleration),
            ..*l
        }
    }

    /// A stop from the current set state with the given dynamics (at least the current velocity bound).
    pub fn plan_stop(&self, l: &Limits) -> Profile1 {
        Profile1::stopping(self.job_start_state(), &self.stop_limits(l))
            .unwrap_or_else(|_| Profile1::hold(State1::at_rest(self.set.pos)))
    }

    /// Installs a new job (clears the in-target monitor).
    pub fn start_job(&mut self, job: Job) {
        self.in_target = false;
        self.in_target_timer = 0.0;
        self.target_pos = match job.kind {
            JobKind::Velocity => self.set.pos,
            _ => job.target,
        };
        self.job = Some(job);
    }

    /// Starts a job from a resolved spec at the current set state. False if planning failed.
    pub fn start_spec(&mut self, owner: CmdId, spec: Spec, fbs: &mut Handshake) -> bool {
        let job = match spec {
            Spec::Position {
                target,
                limits,
                monitor,
            } => {
                let Some(profile) = self.plan_position(target, 0.0, &limits) else {
                    return false;
                };
                self.last_target = Some(target);
                Job {
                    owner: Some(owner),
                    kind: JobKind::Position,
                    profile,
                    t: 0.0,
                    offset: 0.0,
                    target,
                    velocity: limits.velocity,
                    dir: 0.0,
                    limits,
                    end_vel: 0.0,
                    monitor,
                    paused: self.override_pct <= 0.0,
                    owner_aborts_at_end: false,
                    continuous: false,
                    held: false,
                }
            }
            Spec::Velocity { dir, limits } => {
                let Some((profile, soft_limit)) = self.plan_velocity(dir, &limits) else {
                    return false;
                };
                self.last_target = None;
                Job {
                    owner: Some(owner),
                    kind: JobKind::Velocity,
                    profile,
                    t: 0.0,
                    offset: 0.0,
                    // A finite target on a Velocity job = planned stop at a software limit.
                    target: soft_limit.unwrap_or(f64::NAN),
                    velocity: limits.velocity,
                    dir,
                    limits,
                    end_vel: 0.0,
                    monitor: false,
                    paused: self.override_pct <= 0.0,
                    owner_aborts_at_end: false,
                    continuous: false,
                    held: false,
                }
            }
            Spec::Continuous {
                target,
                end_velocity,
                limits,
            } => {
                let d = target - self.set.pos;
                let dir = if d.abs() > 1e-12 {
                    d.signum()
                } else if self.set.vel.abs() > 1e-9 {
                    self.set.vel.signum()
                } else {
                    1.0
                };
                let l = Limits {
                    velocity: limits.velocity.max(end_velocity),
                    ..limits
                };
                let Some(profile) = self.plan_position(target, dir * end_velocity, &l) else {
                    return false;
                };
                self.last_target = None;
                Job {
                    owner: Some(owner),
                    kind: JobKind::Position,
                    profile,
                    t: 0.0,
                    offset: 0.0,
                    target,
                    velocity: limits.velocity,
                    dir,
                    limits: l,
                    end_vel: dir * end_velocity,
                    monitor: false,
                    paused: self.override_pct <= 0.0,
                    owner_aborts_at_end: true,
                    continuous: true,
                    held: false,
                }
            }
            Spec::Halt { limits, monitor } => {
                if !self.moving() && self.job.is_none() {
                    // MC_Halt at standstill: Done after one cycle (§4.8.9).
                    self.last_target = Some(self.set.pos);
                    fbs.active(owner);
                    self.settle = None;
                    return self.finish_halt_at_rest(owner, fbs);
                }
                let profile = self.plan_stop(&limits);
                let stop = profile.end().pos;
                self.last_target = Some(stop);
                Job {
                    owner: Some(owner),
                    kind: JobKind::Halt,
                    profile,
                    t: 0.0,
                    offset: 0.0,
                    target: stop,
                    velocity: limits.velocity,
                    dir: 0.0,
                    limits,
                    end_vel: 0.0,
                    monitor: monitor && self.cfg.en_target_position_monitoring,
                    paused: false,
                    owner_aborts_at_end: false,
                    continuous: false,
                    held: false,
                }
            }
        };
        self.has_been_stopped = false;
        fbs.active(owner);
        self.start_job(job);
        true
    }

    fn finish_halt_at_rest(&mut self, owner: CmdId, fbs: &mut Handshake) -> bool {
        // Reported Done in the next step (instantaneous command rule, §3.1 rule 2).
        self.job = Some(Job {
            owner: Some(owner),
            kind: JobKind::Halt,
            profile: Profile1::hold(State1::at_rest(self.set.pos)),
            t: 0.0,
            offset: 0.0,
            target: self.set.pos,
            velocity: 1.0,
            dir: 0.0,
            limits: Limits {
                velocity: 1.0,
                acceleration: 1.0,
                deceleration: 1.0,
                jerk: 1.0,
            },
            end_vel: 0.0,
            monitor: false,
            paused: false,
            owner_aborts_at_end: false,
            continuous: false,
            held: false,
        });
        let _ = fbs;
        true
    }

    // ---------------------------------------------------------------- aborting

    /// Ends every command of this axis (running, buffered, settling, stop lock) with `how`.
    pub fn end_all(&mut self, fbs: &mut Handshake, how: End) {
        let mut ids = [None; 7];
        ids[5] = self.idle_owner.take();
        ids[6] = self.torque.take().map(|t| t.owner);
        ids[0] = self.job.as_ref().and_then(|j| j.owner);
        ids[1] = self.pending.map(|p| p.owner);
        ids[2] = self.settle.map(|s| s.owner);
        ids[3] = self.lock.map(|l| l.owner);
        ids[4] = self.reset_waiting;
        for id in ids.into_iter().flatten() {
            if Some(id) == self.reset_waiting && how == End::Aborted {
                // An MC_Reset waiting for rest is not a motion command; it completes.
                continue;
            }
            match how {
                End::Aborted => fbs.aborted(id),
                End::Error(e) => fbs.error(id, e),
            }
            if let Some(i) = fbs.get_mut(id) {
                i.locked = false;
            }
        }
        self.pending = None;
        self.settle = None;
        if let Some(j) = self.job.as_mut() {
            j.owner = None;
        }
        if let Some(o) = self.overlay.take() {
            match how {
                End::Aborted => self.end_overlay(o, fbs, true),
                End::Error(e) => {
                    fbs.error(o.owner, e);
                    if let Some((id, _, _)) = o.abort {
                        fbs.error(id, e);
                    }
                }
            }
        }
        if let Some(h) = self.homing {
            let e = match how {
                End::Aborted => None,
                End::Error(e) => Some(e),
            };
            self.end_homing(fbs, e, h);
        }
    }

    /// Ends the running job's owner, the buffered and the settling command (an aborting
    /// command takes over, §3.6 rule 2). The running profile stays until replaced.
    pub fn abort_motion(&mut self, fbs: &mut Handshake) {
        if let Some(j) = self.job.as_mut() {
            if let Some(id) = j.owner.take() {
                fbs.aborted(id);
            }
        }
        if let Some(p) = self.pending.take() {
            fbs.aborted(p.owner);
        }
        if let Some(s) = self.settle.take() {
            fbs.aborted(s.owner);
        }
        if let Some(o) = self.idle_owner.take() {
            fbs.aborted(o);
        }
        if let Some(t) = self.torque.take() {
            fbs.aborted(t.owner);
        }
        if let Some(h) = self.homing {
            self.end_homing(fbs, None, h);
        }
    }

    // ---------------------------------------------------------------- errors (§1.4)

    /// Raises an axis error: all FBs end with Error, fast stop (or at once for a drive
    /// fault), state ErrorStop in the same cycle.
    pub fn raise_error(&mut self, id: ErrorId, drive_fault: bool, fbs: &mut Handshake) {
        if self.error_id.is_none() {
            self.error_id = id;
            self.error_reaction = 0;
        }
        // A slave error decouples the slave (§1.4, §2.5).
        if let Some(id) = self
            .coupling
            .take()
            .and_then(|c| c.dynamic)
            .and_then(|d| d.owner)
        {
            fbs.error(id, self.error_id);
        }
        self.end_all(fbs, End::Error(id));
        self.lock = None;
        if let Some(r) = self.reset_waiting.take() {
            fbs.error(r, id);
        }
        if drive_fault {
            self.drive_fault = true;
            self.status = false;
            self.status_pending = false;
            self.halt_immediately();
        } else if self.moving() {
            let l = self.fast_limits();
            let profile = self.plan_stop(&l);
            let stop = profile.end().pos;
            self.start_job(Job::internal(JobKind::FastStop, profile, stop, l));
        } else {
            self.job = None;
        }
    }

    /// The axis' default dynamics: AxisMaxVelocity with the default acceleration, deceleration
    /// and jerk (§1.2), e.g. for a stop that no command asked for.
    pub fn default_limits(&self) -> Limits {
        Limits {
            velocity: self.cfg.max_velocity,
            acceleration: self.cfg.acceleration,
            deceleration: self.cfg.deceleration,
            jerk: self.cfg.jerk,
        }
    }

    /// The error-reaction dynamics: AxisMaxVelocity with the fast acceleration, deceleration and jerk.
    pub fn fast_limits(&self) -> Limits {
        Limits {
            velocity: self.cfg.max_velocity,
            acceleration: self.cfg.fast_acceleration,
            deceleration: self.cfg.fast_deceleration,
            jerk: self.cfg.fast_jerk,
        }
    }

    /// Velocity 0 at once (power off, drive fault).
    pub fn halt_immediately(&mut self) {
        self.job = None;
        self.set.vel = 0.0;
        self.set.acc = 0.0;
        self.act_velo = 0.0;
        self.act_acc = 0.0;
        self.target_pos = self.set.pos;
    }

    // ---------------------------------------------------------------- cycle

    /// One cycle of this axis.
    pub fn step(
        &mut self,
        dt: f64,
        master: Option<crate::gearing::MasterState>,
        fbs: &mut Handshake,
    ) {
        // (2) state machine and buffer logic
        if self.status_pending {
            self.status_pending = false;
            self.status = self.controller_on && !self.drive_fault;
        }
        if let Some(lock) = self.lock.as_mut() {
            if lock.at_rest && lock.done && !lock.execute {
                if lock.unlock_in == 0 {
                    let owner = lock.owner;
                    self.lock = None;
                    if let Some(i) = fbs.get_mut(owner) {
                        // Unlocked with Execute FALSE: Busy/Active fall, Done is reset.
                        i.locked = false;
                        i.cleared = true;
                    }
                } else {
                    lock.unlock_in -= 1;
                }
            }
        }

        // (3) setpoint generator (a coupled slave follows its master instead)
        let had_job = self.job.is_some();
        let prev_pos = self.set.pos;
        let prev_raw = self.act_pos - self.coord_offset;
        if let (Some(c), Some(m)) = (self.coupling, master) {
            self.follow(c, &m, dt, fbs);
        } else if self.torque.is_some() {
            self.torque_step(dt, fbs);
        } else if let Some(job) = self.job.as_mut() {
            job.t += dt;
            let s = job.profile.at(job.t);
            self.set = State1 {
                pos: s.pos + job.offset,
                vel: s.vel,
                acc: s.acc,
            };
            if job.t >= job.profile.duration() && !job.held {
                self.job_end(fbs);
            }
        }
        if self.power_off_pending && self.job.is_none() {
            self.power_off_pending = false;
            self.switch_off(fbs);
        }

        if self.overlay.is_some() {
            self.overlay_step(prev_pos, dt, fbs);
        }

        // (4) actual values
        match self.cfg.following_model {
            FollowingModel::Ideal => {
                self.act_pos = self.set.pos + self.following_offset;
                self.act_velo = self.set.vel;
                self.act_acc = self.set.acc;
            }
            FollowingModel::FirstOrder => {
                let v = self.set.vel
                    + self.cfg.position_control_kv
                        * (self.set.pos + self.following_offset - self.act_pos);
                self.act_acc = (v - self.act_velo) / dt;
                self.act_velo = v;
                self.act_pos += v * dt;
            }
        }

        if self.homing.is_some() {
            self.homing_step(fbs);
        }
        if self.probes.iter().any(|p| p.is_some()) {
            self.probe_step(prev_raw, fbs);
        } else {
            self.probe_prev = self.probe_level;
        }

        // (5) monitoring
        self.monitor(dt, had_job, fbs);
    }

    fn job_end(&mut self, fbs: &mut Handshake) {
        let Some(job) = self.job else { return };
        match job.kind {
            JobKind::Velocity if job.target.is_finite() && !job.paused => {
                // Endless motion stopped at the software limit: FB Error 0x4D02, axis stays
                // operational (§1.3).
                self.set = State1::at_rest(job.profile.end().pos + job.offset);
                self.target_pos = self.set.pos;
                self.job = None;
                if let Some(id) = job.owner {
                    fbs.error(id, error_ids::SOFT_LIMIT_STOP);
                }
            }
            JobKind::Velocity => {
                let Some(j) = self.job.as_mut() else { return };
                if !j.paused {
                    if let Some(id) = j.owner {
                        if let Some(i) = fbs
                            .get_mut(id)
                            .filter(|i| i.kind == crate::handshake::FbKind::MoveVelocity)
                        {
                            i.in_velocity = true;
                        }
                    }
                }
                // Rebase: constant velocity from here, keeps long runs exact.
                j.profile = Profile1::hold(State1 {
                    pos: self.set.pos - j.offset,
                    vel: self.set.vel,
                    acc: 0.0,
                });
                j.t = 0.0;
                j.held = true;
                self.set.acc = 0.0;
            }
            JobKind::Position if job.paused => {}
            JobKind::Position => {
                let end = job.profile.end();
                self.set = State1 {
                    pos: end.pos + job.offset,
                    vel: end.vel,
                    acc: 0.0,
                };
                self.target_pos = self.set.pos;
                self.job = None;
                if job.continuous && self.pending.is_none() {
                    // Target reached with EndVelocity: InEndVelocity; endless from here.
                    if let Some(id) = job.owner {
                        if let Some(i) = fbs.get_mut(id) {
                            i.in_velocity = true;
                        }
                    }
                    if job.end_vel != 0.0 {
                        let mut j = Job::internal(
                            JobKind::Velocity,
                            Profile1::hold(self.set),
                            f64::NAN,
                            job.limits,
                        );
                        j.owner = job.owner;
                        j.dir = job.end_vel.signum();
                        j.velocity = job.end_vel.abs();
                        self.job = Some(j);
                    } else {
                        self.idle_owner = job.owner;
                    }
                    return;
                }
                if let Some(p) = self.pending.take() {
                    // Buffered/blended follow-up takes over at the end position (§3.6 rule 7).
                    if let Some(id) = job.owner {
                        if job.owner_aborts_at_end {
                            fbs.aborted(id)
                        } else {
                            fbs.done(id)
                        }
                    }
                    self.take_over(p, fbs);
                } else if let Some(id) = job.owner {
                    if job.monitor
                        && (self.cfg.en_target_position_monitoring
                            || self.cfg.en_position_range_monitoring)
                    {
                        self.settle = Some(Settle {
                            owner: id,
                            elapsed: 0.0,
                        });
                    } else {
                        fbs.done(id);
                    }
                }
            }
            JobKind::Halt => {
                self.set = State1::at_rest(job.target + job.offset);
                self.target_pos = self.set.pos;
                self.job = None;
                if let Some(p) = self.pending.take() {
                    if let Some(id) = job.owner {
                        fbs.done(id);
                    }
                    self.take_over(p, fbs);
                } else if let Some(id) = job.owner {
                    if job.monitor {
                        self.settle = Some(Settle {
                            owner: id,
                            elapsed: 0.0,
                        });
                    } else {
                        fbs.done(id);
                    }
                }
            }
            JobKind::Stop => {
                self.set = State1::at_rest(job.target + job.offset);
                self.target_pos = self.set.pos;
                self.job = None;
                if let Some(lock) = self.lock.as_mut() {
                    lock.at_rest = true;
                    lock.unlock_in = 2;
                    if !lock.monitor {
                        Self::stop_done(lock, fbs);
                    }
                }
            }
            JobKind::FastStop => {
                self.set = State1::at_rest(job.target + job.offset);
                self.target_pos = self.set.pos;
                self.job = None;
                if let Some(r) = self.reset_waiting.take() {
                    fbs.done(r);
                }
            }
        }
    }

    /// MC_Stop at rest: Done, with Busy/Active kept while locked (§3.2 exception).
    fn stop_done(lock: &mut Lock, fbs: &mut Handshake) {
        lock.done = true;
        fbs.done(lock.owner);
        if let Some(i) = fbs.get_mut(lock.owner) {
            i.locked = true;
        }
    }

    /// A buffered command becomes active at the current set state.
    pub fn take_over(&mut self, p: Pending, fbs: &mut Handshake) {
        if !self.start_spec(p.owner, p.spec, fbs) {
            fbs.error(p.owner, error_ids::PARAMETER_NOT_CORRECT);
        }
    }

    fn monitor(&mut self, dt: f64, had_job: bool, fbs: &mut Handshake) {
        // Position lag (§1.3).
        let pos_diff = self.set.pos - self.act_pos;
        if self.cfg.en_position_lag_monitoring
            && !self.ext.accept_blocked_drive
            && self.error_id.is_none()
            && pos_diff.abs() > self.cfg.max_pos_lag_value
        {
            self.lag_timer += dt;
            if self.lag_timer > self.cfg.max_pos_lag_filter_time + 1e-12 {
                self.lag_timer = 0.0;
                self.raise_error(error_ids::POSITION_LAG, false, fbs);
            }
        } else {
            self.lag_timer = 0.0;
        }
        // InTargetPosition: inside the window continuously for the monitoring time after
        // HasJob fell (the cycle in which the job ended does not count).
        if self.job.is_none() {
            let inside = (self.act_pos - self.target_pos).abs() <= self.cfg.target_position_window;
            if inside {
                if !had_job {
                    self.in_target_timer += dt;
                }
                if self.in_target_timer + 1e-9 >= self.cfg.target_position_monitoring_time {
                    self.in_target = true;
                }
            } else {
                self.in_target_timer = 0.0;
                self.in_target = false;
            }
        }
        if let Some(lock) = self.lock.as_mut() {
            if lock.at_rest && !lock.done && self.in_target {
                Self::stop_done(lock, fbs);
            }
        }
        if let Some(s) = self.settle.as_mut() {
            let done = if self.cfg.en_target_position_monitoring {
                self.in_target
            } else {
                (self.act_pos - self.target_pos).abs() <= self.cfg.position_range_window
            };
            if done {
                fbs.done(s.owner);
                self.settle = None;
            } else {
                s.elapsed += dt;
                if self.cfg.en_in_target_timeout && s.elapsed > self.cfg.in_target_timeout {
                    fbs.error(s.owner, error_ids::FB_TIMEOUT);
                    self.settle = None;
                }
            }
        }
    }

    /// Switches the controller off (Enable↓, §4.1): velocity 0 at once, FBs aborted.
    pub fn switch_off(&mut self, fbs: &mut Handshake) {
        if let Some(id) = self
            .coupling
            .take()
            .and_then(|c| c.dynamic)
            .and_then(|d| d.owner)
        {
            fbs.aborted(id);
        }
        self.end_all(fbs, End::Aborted);
        self.lock = None;
        if let Some(r) = self.reset_waiting.take() {
            fbs.done(r);
        }
        self.halt_immediately();
        self.controller_on = false;
        self.status = false;
        self.status_pending = false;
    }
}

/// How `end_all` ends the commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// With CommandAborted.
    Aborted,
    /// With Error and this ErrorID.
    Error(ErrorId),
}

impl Job {
    /// A job without FB owner (error reaction, feed-enable stop).
    pub fn internal(kind: JobKind, profile: Profile1, target: f64, limits: Limits) -> Job {
        Job {
            owner: None,
            kind,
            profile,
            t: 0.0,
            offset: 0.0,
            target,
            velocity: limits.velocity,
            dir: 0.0,
            limits,
            end_vel: 0.0,
            monitor: false,
            paused: false,
            owner_aborts_at_end: false,
            continuous: false,
            held: false,
        }
    }
}

/// Shifts the coordinate system by `delta` (MC_SetPosition, §4.3).
pub fn shift_coordinates(a: &mut Axis, delta: f64) {
    a.set.pos += delta;
    a.act_pos += delta;
    a.target_pos += delta;
    a.coord_offset += delta;
    a.set_position_offset += delta;
    if let Some(j) = a.job.as_mut() {
        j.offset += delta;
    }
    if let Some(p) = a.pending.as_mut() {
        if let Spec::Position { target, .. } = &mut p.spec {
            *target += delta;
        }
    }
}
