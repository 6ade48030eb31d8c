//! [`AxisEngine`]: a set of named axes implementing [`motion_core::Engine`].
//!
//! `command` screens the inputs (NaN/inf → NOT_FINITE, unknown axis → UNKNOWN_OBJECT, ranges
//! → 0x4B06 ...), applies the admission matrix (§2.4) and BufferMode (§3.6) and acts at once
//! (the state changes with the command, §2.1). `step` runs one cycle of every axis in the
//! order of §1.1 and hands out the command events.

use crate::axis::{Axis, Job, JobKind, Lock, Pending, Spec};
use crate::buffer;
use crate::command::*;
use crate::config::AxisConfig;
use crate::error_ids::*;
use crate::gearing::MasterState;
use crate::handshake::{FbKind, FbOutputs, Handshake};
use crate::modulo;
use crate::params::{self, ParamType, Slot, StatusValue};
use crate::snapshot::{AxisSnapshot, AxisStatus};
use crate::state::{admission, Admission, FbClass};
use motion_core::{
    CmdId, CommandEvent, CommandState, Engine, ErrorId, ExecuteOutputs, Limits, Rejection, State1,
    Tick,
};
use std::collections::HashMap;

/// The single-axis engine: all configured axes and their FB instances.
#[derive(Debug)]
pub struct AxisEngine {
    pub(crate) axes: Vec<Axis>,
    pub(crate) index: HashMap<String, usize>,
    pub(crate) fbs: Handshake,
    /// Part 4 axis groups (plcopen_platform.md §3.2, §5).
    pub(crate) groups: crate::group::Groups,
    /// Platform profile, safety functions, start-up (plcopen_platform.md §6–§10).
    pub(crate) platform: crate::platform::Platform,
    /// Raw FB layer state (plcopen_platform.md §12.2).
    pub(crate) raw: crate::platform::raw::Raw,
    /// Instantaneous commands reported Done in the next cycle (§3.1 rule 2).
    instant_done: Vec<CmdId>,
    tick: u64,
    /// Step order: masters before their slaves (§4.12).
    order: Vec<usize>,
    /// Collision-avoidance groups (collision_avoidance.md).
    ca: crate::ca::CaGroups,
}

fn reject(id: ErrorId, msg: String) -> Rejection {
    Rejection::new(id, msg)
}

/// NaN/inf screening: `axis 'x': MC_MoveAbsolute.Velocity = NaN is not finite`.
fn finite(axis: &str, fb: &str, field: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(Rejection::not_finite(
            &format!("axis '{axis}': {fb}"),
            field,
            v,
        ))
    }
}

fn not_correct(axis: &str, fb: &str, field: &str, v: f64, need: &str) -> Rejection {
    reject(
        PARAMETER_NOT_CORRECT,
        format!("axis '{axis}': {fb}: {field} = {v} {need}"),
    )
}

/// Move dynamics (§3.5): finite, Velocity in (0, AxisMaxVelocity], the rest ≥ 0 (0 = default).
fn move_limits(
    a: &Axis,
    fb: &str,
    velocity: Option<f64>,
    acc: f64,
    dec: f64,
    jerk: f64,
) -> Result<Limits, Rejection> {
    let n = &a.name;
    if let Some(v) = velocity {
        finite(n, fb, "Velocity", v)?;
    }
    finite(n, fb, "Acceleration", acc)?;
    finite(n, fb, "Deceleration", dec)?;
    finite(n, fb, "Jerk", jerk)?;
    if let Some(v) = velocity {
        if v <= 0.0 || v > a.cfg.max_velocity {
            return Err(not_correct(
                n,
                fb,
                "Velocity",
                v,
                &format!("must be in (0, {}]", a.cfg.max_velocity),
            ));
        }
    }
    for (f, x) in [("Acceleration", acc), ("Deceleration", dec), ("Jerk", jerk)] {
        if x < 0.0 {
            return Err(not_correct(n, fb, f, x, "must be >= 0 (0 = axis default)"));
        }
    }
    let or = |x: f64, d: f64| if x > 0.0 { x } else { d };
    Ok(Limits {
        velocity: velocity.unwrap_or(a.cfg.max_velocity),
        acceleration: or(acc, a.cfg.acceleration),
        deceleration: or(dec, a.cfg.deceleration),
        jerk: or(jerk, a.cfg.jerk),
    })
}

/// Outputs of MC_Power.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct PowerOutputs {
    /// Status: axis ready for operation.
    pub status: bool,
    /// Busy: called with Enable TRUE.
    pub busy: bool,
    /// Active: Enable applied.
    pub active: bool,
}

/// EndVelocity of MC_MoveContinuous*: finite, in [0, AxisMaxVelocity] (§4.8.7).
fn end_velocity(a: &Axis, fb: &str, ev: f64) -> Result<f64, Rejection> {
    finite(&a.name, fb, "EndVelocity", ev)?;
    if ev < 0.0 || ev > a.cfg.max_velocity {
        return Err(not_correct(
            &a.name,
            fb,
            "EndVelocity",
            ev,
            &format!("must be in [0, {}]", a.cfg.max_velocity),
        ));
    }
    Ok(ev)
}

/// What a motion FB asks for, before the takeover point is known.
#[derive(Clone, Copy, Debug)]
enum Request {
    Absolute(f64),
    Relative(f64),
    Additive(f64),
    Modulo { position: f64, direction: Direction },
    Velocity(Direction),
    Halt,
    ContinuousAbsolute(f64, f64),
    ContinuousRelative(f64, f64),
}

impl AxisEngine {
    /// Builds the engine from `(name, config)` pairs; names must be unique and non-empty,
    /// every config valid (message names axis, key and value).
    pub fn new(axes: Vec<(String, AxisConfig)>) -> Result<Self, Rejection> {
        Self::with_config(axes, &crate::platform::EngineConfig::default())
    }

    /// Builds the engine with an engine-level configuration: `platform_profile`, Part 4
    /// groups and platform settings (plcopen_platform.md). Unknown axis names in it are
    /// refused with `UNKNOWN_OBJECT`.
    pub fn with_config(
        axes: Vec<(String, AxisConfig)>,
        config: &crate::platform::EngineConfig,
    ) -> Result<Self, Rejection> {
        let mut index = HashMap::new();
        let mut list = Vec::with_capacity(axes.len());
        for (i, (name, mut cfg)) in axes.into_iter().enumerate() {
            if name.is_empty() {
                return Err(reject(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("axis #{i}: empty axis name"),
                ));
            }
            if index.insert(name.clone(), i).is_some() {
                return Err(reject(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("axis '{name}' is configured twice"),
                ));
            }
            cfg.validate(&name)?;
            if cfg.axis_id == 0 {
                cfg.axis_id = i as u32 + 1;
            }
            list.push(Axis::new(name, cfg));
        }
        let order = (0..list.len()).collect();
        let mut e = AxisEngine {
            axes: list,
            index,
            fbs: Handshake::new(),
            groups: Default::default(),
            platform: Default::default(),
            raw: Default::default(),
            instant_done: Vec::with_capacity(64),
            tick: 0,
            order,
            ca: crate::ca::CaGroups::default(),
        };
        e.build_groups(&config.groups)?;
        e.build_platform(config)?;
        Ok(e)
    }

    /// The collision-avoidance groups (outputs of CA instances, e.g. MC_GearInPosCA's InSync).
    pub fn ca_groups(&self) -> &crate::ca::CaGroups {
        &self.ca
    }

    /// Adds a collision-avoidance group (startup configuration, collision_avoidance.md §3.1).
    pub fn add_ca_group(
        &mut self,
        name: impl Into<String>,
        cfg: crate::ca::CaGroupConfig,
    ) -> Result<(), Rejection> {
        self.ca.add_group(name.into(), cfg)
    }

    /// Masters before slaves; recomputed when a coupling is made.
    fn recompute_order(&mut self) {
        // Longest master chain above an axis (MC_GearInMultiMaster: over all its masters).
        fn depth(axes: &[Axis], i: usize, guard: usize) -> usize {
            match axes[i].coupling {
                Some(c) if guard > 0 => {
                    1 + c
                        .masters()
                        .map(|m| depth(axes, m, guard - 1))
                        .max()
                        .unwrap_or(0)
                }
                _ => 0,
            }
        }
        let depth = |i: usize| depth(&self.axes, i, self.axes.len());
        let mut order: Vec<(usize, usize)> = (0..self.axes.len()).map(|i| (depth(i), i)).collect();
        order.sort();
        self.order = order.into_iter().map(|(_, i)| i).collect();
    }

    /// CoupleState of axis `i` (0 single, 1 master, 2 master-slave, 3 slave) given whether it
    /// is a master.
    fn couple_state(&self, i: usize, master: bool) -> u32 {
        match (master, self.axes[i].coupling.is_some()) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        }
    }

    fn axis_status(&self, i: usize, master: bool) -> AxisStatus {
        let mut s = self.axes[i].status();
        s.couple_state = self.couple_state(i, master);
        self.ca.patch_status(i, &mut s);
        s
    }

    fn is_master(&self, i: usize) -> bool {
        self.axes
            .iter()
            .any(|a| a.coupling.is_some_and(|c| c.masters().any(|m| m == i)))
    }

    /// Axis names in configuration order.
    pub fn axis_names(&self) -> impl Iterator<Item = &str> {
        self.axes.iter().map(|a| a.name.as_str())
    }

    /// The status of one axis.
    pub fn status(&self, axis: &str) -> Option<AxisStatus> {
        self.index
            .get(axis)
            .map(|&i| self.axis_status(i, self.is_master(i)))
    }

    /// Standard outputs of an admitted Execute-type instance (§3.1–§3.3).
    pub fn outputs(&self, id: CmdId) -> Option<ExecuteOutputs> {
        self.fb_outputs(id)
            .map(|o| o.standard)
            .or_else(|| self.group_outputs(id))
            .or_else(|| self.ca.outputs(id))
    }

    /// All outputs of an instance (incl. InVelocity).
    pub fn fb_outputs(&self, id: CmdId) -> Option<FbOutputs> {
        let mut o = self.fbs.outputs_with(id, self.platform.isg())?;
        if o.standard.error {
            o.standard.error_id = self.platform_error_id(id, o.standard.error_id);
        }
        Some(o)
    }

    /// Outputs of the axis' MC_Power (Enable-type, §4.1): Status, Busy (= Enable), Active
    /// (= Enable and the enable applied). FB errors of MC_Power are rejections of the call.
    pub fn power_outputs(&self, axis: &str) -> Option<PowerOutputs> {
        self.index.get(axis).map(|&i| {
            let a = &self.axes[i];
            PowerOutputs {
                status: a.status,
                busy: a.enable,
                active: a.enable && a.controller_on,
            }
        })
    }

    /// The axis an instance belongs to and its FB.
    pub fn instance(&self, id: CmdId) -> Option<(&str, FbKind)> {
        self.fbs
            .get(id)
            .map(|i| (self.axes[i.axis].name.as_str(), i.kind))
    }

    fn axis_index(&self, name: &str) -> Result<usize, Rejection> {
        self.index
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("axis", name))
    }

    fn reply(id: CmdId) -> AxisReply {
        AxisReply {
            id,
            value: ReplyValue::None,
            tracked: true,
        }
    }

    fn untracked(&mut self, value: ReplyValue) -> AxisReply {
        AxisReply {
            id: self.fbs.untracked_id(),
            value,
            tracked: false,
        }
    }

    // ------------------------------------------------------------------ admission

    fn admit_state(&self, ax: usize, fb: FbClass, fb_name: &str) -> Result<Admission, Rejection> {
        self.ext_setpoint_admission(ax, fb, fb_name)?;
        let a = &self.axes[ax];
        let state = a.state();
        match admission(fb, state) {
            Admission::Reject(id) => Err(reject(
                id,
                format!(
                    "axis '{}': {fb_name} not allowed in state {state:?}",
                    a.name
                ),
            )),
            Admission::IfSlaveAllowed(_) => Err(reject(
                AXIS_CANNOT_BE_STARTED,
                format!(
                    "axis '{}': {fb_name} not allowed on a coupled slave",
                    a.name
                ),
            )),
            ok => Ok(ok),
        }
    }

    /// Admission for commands with an "S?" cell (§2.5): on a coupled slave they are allowed
    /// only with AxisAllowMotionCmdToSlaveAxis = TRUE (else 0x4B01) and BufferMode Aborting
    /// (else 0x4B05). Returns whether the slave must be decoupled first.
    fn admit_motion(
        &self,
        ax: usize,
        fb: FbClass,
        fb_name: &str,
        mode: BufferMode,
    ) -> Result<bool, Rejection> {
        let a = &self.axes[ax];
        match admission(fb, a.state()) {
            Admission::IfSlaveAllowed(_) => {
                if !a.cfg.allow_motion_cmd_to_slave_axis {
                    Err(reject(
                        AXIS_CANNOT_BE_STARTED,
                        format!("axis '{}': {fb_name} not allowed on a coupled slave (AxisAllowMotionCmdToSlaveAxis = FALSE)", a.name),
                    ))
                } else if mode != BufferMode::Aborting {
                    Err(reject(
                        COMMAND_NOT_PERMITTED,
                        format!("axis '{}': {fb_name} on a slave needs BufferMode MC_Aborting, not {mode:?}", a.name),
                    ))
                } else {
                    Ok(true)
                }
            }
            _ => self.admit_state(ax, fb, fb_name).map(|_| false),
        }
    }

    // ------------------------------------------------------------------ MC_Power

    pub(crate) fn power(&mut self, ax: usize, c: Power) -> Result<AxisReply, Rejection> {
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
                let l = Limits {
                    velocity: a.cfg.max_velocity,
                    acceleration: a.cfg.acceleration,
                    deceleration: a.cfg.deceleration,
                    jerk: a.cfg.jerk,
                };
                let profile = a.plan_stop(&l);
                let stop = profile.end().pos;
                a.start_job(Job::internal(JobKind::Halt, profile, stop, l));
            }
        }
        // The reply carries MC_Power.Status at this call (TRUE one cycle after Enable↑).
        let status = self.axes[ax].status;
        Ok(AxisReply {
            id,
            value: ReplyValue::Bool(status),
            tracked: false,
        })
    }

    // ------------------------------------------------------------------ MC_Reset

    pub(crate) fn reset(&mut self, ax: usize) -> Result<AxisReply, Rejection> {
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

    // ------------------------------------------------------------------ motion FBs

    #[allow(clippy::too_many_arguments)]
    fn motion(
        &mut self,
        ax: usize,
        kind: FbKind,
        fb: &str,
        req: Request,
        limits: Limits,
        mode: BufferMode,
        options: MoveOptions,
    ) -> Result<AxisReply, Rejection> {
        let class = match req {
            Request::Velocity(_)
            | Request::ContinuousAbsolute(..)
            | Request::ContinuousRelative(..) => FbClass::MoveContinuous,
            Request::Halt => FbClass::Halt,
            _ => FbClass::MoveDiscrete,
        };
        let decouple = self.admit_motion(ax, class, fb, mode)?;
        let a = &self.axes[ax];
        let name = a.name.clone();
        if options.enable_blending_position {
            finite(
                &name,
                fb,
                "Options.BlendingPosition",
                options.blending_position,
            )?;
        }
        // Is the axis executing another command (BufferMode is evaluated only then)?
        let running = a.job.filter(|j| {
            j.owner.is_some()
                && matches!(
                    j.kind,
                    JobKind::Position | JobKind::Velocity | JobKind::Halt
                )
        });
        let settling = a.settle.is_some();
        let mut buffered = mode != BufferMode::Aborting && (running.is_some() || settling);
        // Endless motions have no end: buffered acts like aborting unless a blending position
        // is given (rule 3/6).
        let mut blend_at: Option<f64> = None;
        if let Some(j) = running {
            if buffered {
                let dir1 = travel_dir(a, &j);
                // Behind a running MC_Halt the follow-up starts at rest (no blending point).
                if options.enable_blending_position && j.kind != JobKind::Halt {
                    let bp = options.blending_position;
                    if j.kind == JobKind::Position {
                        let p1 = j.target + j.offset;
                        if (p1 - bp) * dir1 < 0.0 {
                            return Err(reject(
                                BLENDING_POSITION_INVALID,
                                format!("axis '{name}': {fb}: BlendingPosition {bp} lies beyond the end position {p1} of the running command"),
                            ));
                        }
                    }
                    if (bp - a.set.pos) * dir1 < 0.0 {
                        buffered = false; // already passed: at once (like Aborting)
                    } else {
                        blend_at = Some(bp);
                    }
                } else if j.kind == JobKind::Velocity {
                    buffered = false;
                }
            }
        }
        if buffered && a.pending.is_some() {
            return Err(reject(
                BUFFER_FULL,
                format!("axis '{name}': {fb}: a command is already buffered (Buffer Full)"),
            ));
        }
        // MC_MoveModulo against the current travel direction: the FB ends with Error 0x4B04
        // and the axis is stopped safely (manual, §4.8.4) - an execution error, not a
        // rejection.
        if let Request::Modulo {
            position,
            direction,
        } = req
        {
            let v = a.set.vel;
            let wanted = match direction {
                Direction::Positive => 1.0,
                Direction::Negative => -1.0,
                _ => 0.0,
            };
            if !buffered && position >= 0.0 && v.abs() > 1e-9 && wanted * v < 0.0 {
                let id = self.fbs.admit(ax, kind, CommandState::Active);
                let a = &mut self.axes[ax];
                let fbs = &mut self.fbs;
                a.cmd_no = a.cmd_no.wrapping_add(1);
                a.abort_motion(fbs);
                let profile = a.plan_stop(&limits);
                let stop = profile.end().pos;
                a.start_job(Job::internal(JobKind::Halt, profile, stop, limits));
                a.last_target = Some(stop);
                fbs.error(id, INVALID_MODE);
                return Ok(Self::reply(id));
            }
        }
        // The set position at which the command will take over.
        let base = match (buffered, running) {
            (true, Some(j)) => blend_at.unwrap_or(j.target + j.offset),
            _ => a.set.pos,
        };
        let last_target = if buffered {
            Some(base)
        } else {
            a.last_target
                .filter(|_| !running.is_some_and(|j| j.kind == JobKind::Velocity))
        };
        let spec = match req {
            Request::Absolute(p) => Spec::Position {
                target: p,
                limits,
                monitor: !options.ignore_position_monitoring,
            },
            Request::Relative(d) => Spec::Position {
                target: base + d,
                limits,
                monitor: !options.ignore_position_monitoring,
            },
            Request::Additive(d) => Spec::Position {
                target: last_target.unwrap_or(base) + d,
                limits,
                monitor: !options.ignore_position_monitoring,
            },
            Request::Modulo {
                position,
                direction,
            } => {
                let target =
                    modulo_target(a, &name, fb, position, direction, &limits, buffered, base)?;
                Spec::Position {
                    target,
                    limits,
                    monitor: !options.ignore_position_monitoring,
                }
            }
            Request::ContinuousAbsolute(p, ev) => Spec::Continuous {
                target: p,
                end_velocity: ev,
                limits,
            },
            Request::ContinuousRelative(d, ev) => Spec::Continuous {
                target: base + d,
                end_velocity: ev,
                limits,
            },
            Request::Velocity(direction) => {
                let dir = match direction {
                    Direction::Positive => 1.0,
                    Direction::Negative => -1.0,
                    Direction::Current if a.set.vel.abs() > 1e-9 => a.set.vel.signum(),
                    d => {
                        return Err(reject(
                            COMMAND_NOT_PERMITTED,
                            format!(
                                "axis '{name}': {fb}: Direction {d:?} gives no direction of motion"
                            ),
                        ))
                    }
                };
                Spec::Velocity { dir, limits }
            }
            Request::Halt => Spec::Halt {
                limits,
                monitor: options.enable_stop_position_monitoring,
            },
        };
        // R-SYS-2 (`isg_mcp` modulo axes): a discrete motion started while moving.
        let spec = match spec {
            Spec::Position {
                target,
                limits,
                monitor,
            } if !buffered && matches!(req, Request::Absolute(_) | Request::Relative(_)) => {
                Spec::Position {
                    target: self.platform_modulo_abort_target(ax, target, &limits),
                    limits,
                    monitor,
                }
            }
            s => s,
        };
        let a = &self.axes[ax];
        // Software limits (§1.3) and feed enables (§2.4).
        if let Spec::Position { target, .. } | Spec::Continuous { target, .. } = spec {
            if !target.is_finite() {
                return Err(reject(
                    ErrorId::NOT_FINITE,
                    format!("axis '{name}': {fb}: target {target} is not finite"),
                ));
            }
            if a.soft_limit(1.0).is_some_and(|l| target > l)
                || a.soft_limit(-1.0).is_some_and(|l| target < l)
            {
                return Err(reject(
                    SOFT_LIMIT_TARGET,
                    format!(
                        "axis '{name}': {fb}: target {target} outside the software limits [{}, {}]",
                        a.cfg.min_soft_pos_limit, a.cfg.max_soft_pos_limit
                    ),
                ));
            }
        }
        let start_dir = match spec {
            Spec::Position { target, .. } | Spec::Continuous { target, .. } => {
                (target - base).signum() * ((target - base).abs() > 1e-12) as i32 as f64
            }
            Spec::Velocity { dir, .. } => dir,
            Spec::Halt { .. } => 0.0,
        };
        if (start_dir > 0.0 && !a.enable_positive) || (start_dir < 0.0 && !a.enable_negative) {
            return Err(reject(
                AXIS_CANNOT_BE_STARTED,
                format!(
                    "axis '{name}': {fb}: feed enable for the {} direction is missing",
                    if start_dir > 0.0 {
                        "positive"
                    } else {
                        "negative"
                    }
                ),
            ));
        }

        // Admitted.
        if decouple {
            self.axes[ax].decouple_keep_velocity();
        }
        let id = self.fbs.admit(
            ax,
            kind,
            if buffered {
                CommandState::Busy
            } else {
                CommandState::Active
            },
        );
        let a = &mut self.axes[ax];
        let fbs = &mut self.fbs;
        a.cmd_no = a.cmd_no.wrapping_add(1);
        if !matches!(spec, Spec::Halt { .. }) {
            a.last_dec = limits.deceleration;
            a.last_jerk = limits.jerk;
        }
        if !buffered {
            a.abort_motion(fbs);
            if let Some(r) = a.reset_waiting.take() {
                fbs.done(r);
            }
            if !a.start_spec(id, spec, fbs) {
                fbs.error(id, PARAMETER_NOT_CORRECT);
            }
            return Ok(Self::reply(id));
        }
        let pending = Pending { owner: id, spec };
        match running {
            None => {
                // Settling after the end of the previous move: it is complete, start now.
                if let Some(s) = a.settle.take() {
                    fbs.done(s.owner);
                }
                a.take_over(pending, fbs);
            }
            Some(j) => {
                blend(a, j, pending, mode, blend_at);
            }
        }
        Ok(Self::reply(id))
    }

    fn halt_limits(&self, ax: usize, fb: &str, dec: f64, jerk: f64) -> Result<Limits, Rejection> {
        let a = &self.axes[ax];
        finite(&a.name, fb, "Deceleration", dec)?;
        finite(&a.name, fb, "Jerk", jerk)?;
        // ≤ 0 → last move's values; never weaker than the active command (§4.8.9).
        let mut d = if dec > 0.0 { dec } else { a.last_dec };
        let mut j = if jerk > 0.0 { jerk } else { a.last_jerk };
        if let Some(job) = a.job {
            d = d.max(job.limits.deceleration);
            j = j.max(job.limits.jerk);
        }
        Ok(Limits {
            velocity: a.cfg.max_velocity,
            acceleration: a.cfg.acceleration.max(d),
            deceleration: d,
            jerk: j,
        })
    }

    fn stop(&mut self, ax: usize, c: Stop) -> Result<AxisReply, Rejection> {
        let limits = self.halt_limits(ax, "MC_Stop", c.deceleration, c.jerk)?;
        if self.admit_motion(ax, FbClass::Stop, "MC_Stop", BufferMode::Aborting)? {
            self.axes[ax].decouple_keep_velocity();
        }
        let id = self.fbs.admit(ax, FbKind::Stop, CommandState::Active);
        let a = &mut self.axes[ax];
        let fbs = &mut self.fbs;
        a.cmd_no = a.cmd_no.wrapping_add(1);
        if let Some(old) = a.lock.take() {
            fbs.aborted(old.owner);
            if let Some(i) = fbs.get_mut(old.owner) {
                i.locked = false;
            }
        }
        a.abort_motion(fbs);
        if let Some(r) = a.reset_waiting.take() {
            fbs.done(r);
        }
        let profile = a.plan_stop(&limits);
        let stop = profile.end().pos;
        a.start_job(Job {
            owner: Some(id),
            ..Job::internal(JobKind::Stop, profile, stop, limits)
        });
        let monitor =
            c.options.enable_stop_position_monitoring && a.cfg.en_target_position_monitoring;
        a.lock = Some(Lock {
            owner: id,
            execute: true,
            at_rest: false,
            monitor,
            done: false,
            unlock_in: 2,
        });
        a.has_been_stopped = true;
        a.last_target = Some(stop);
        Ok(Self::reply(id))
    }

    // ------------------------------------------------------------------ MC_SetPosition

    fn set_position(&mut self, ax: usize, c: SetPosition) -> Result<AxisReply, Rejection> {
        let a = &self.axes[ax];
        finite(&a.name, "MC_SetPosition", "Position", c.position)?;
        if c.options.select_encoder_index && c.options.encoder_index != 0 {
            return Err(not_correct(
                &a.name,
                "MC_SetPosition",
                "Options.EncoderIndex",
                c.options.encoder_index as f64,
                "must be 0 (one encoder)",
            ));
        }
        self.admit_state(ax, FbClass::SetPosition, "MC_SetPosition")?;
        let id = self.fbs.admit(ax, FbKind::SetPosition, CommandState::Busy);
        let a = &mut self.axes[ax];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        let moving = a.job.is_some() || a.moving();
        if c.options.clear_position_offset {
            let d = -a.set_position_offset;
            shift_coordinates(a, d);
            a.set_position_offset = 0.0;
        } else if c.mode {
            shift_coordinates(a, c.position);
        } else if moving {
            // Absolute while moving = relative with Δ = Position − ActPos (§4.3 proposal).
            shift_coordinates(a, c.position - a.act_pos);
        } else {
            // Absolute at rest: ActPos := Position; the lag is kept unless ClearPositionLag.
            let lag = a.set.pos - a.act_pos;
            shift_coordinates(a, c.position - a.act_pos);
            a.act_pos = c.position;
            if c.options.clear_position_lag {
                a.following_offset = 0.0;
                a.set.pos = c.position;
            } else {
                a.set.pos = c.position + lag;
            }
            a.target_pos = a.set.pos;
        }
        a.last_target = None;
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    // ------------------------------------------------------------------ parameters (§4.4)

    fn param_def(
        &self,
        ax: usize,
        fb: &str,
        number: u32,
    ) -> Result<&'static params::ParamDef, Rejection> {
        params::lookup(number).ok_or_else(|| {
            reject(
                UNKNOWN_PARAMETER,
                format!(
                    "axis '{}': {fb}: unknown ParameterNumber {number}",
                    self.axes[ax].name
                ),
            )
        })
    }

    fn read_param(
        &self,
        ax: usize,
        fb: &str,
        number: u32,
        want_bool: bool,
    ) -> Result<f64, Rejection> {
        let def = self.param_def(ax, fb, number)?;
        let a = &self.axes[ax];
        if want_bool && def.ty != ParamType::Bool {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{}': {fb}: parameter {number} {} is not BOOL",
                    a.name, def.name
                ),
            ));
        }
        Ok(match def.slot {
            Slot::Config(k) => k.get(&a.cfg),
            Slot::Other(off) => a.other_params.get(&off).copied().unwrap_or(0.0),
            // The coupling's (effective) ratio while the axis is a coupled slave (§6).
            Slot::GearRatio => match a.coupling {
                Some(c) => c.ratio,
                None => {
                    return Err(reject(
                        COMMAND_NOT_PERMITTED,
                        format!(
                            "axis '{}': {fb}: AxisGearRatio (3000) only on a coupled slave",
                            a.name
                        ),
                    ))
                }
            },
            Slot::Status(s) => match s {
                StatusValue::CommandedPosition => a.set.pos,
                StatusValue::ActualVelocity => a.act_velo,
                StatusValue::CommandedVelocity => a.set.vel,
                StatusValue::AxisId => a.cfg.axis_id as f64,
                StatusValue::TargetPosition => a.status().target_pos,
                StatusValue::RemainingTimeToGo => {
                    a.job.map_or(0.0, |j| (j.profile.duration() - j.t).max(0.0))
                }
                StatusValue::RemainingDistanceToGo => a
                    .job
                    .filter(|j| j.kind != JobKind::Velocity)
                    .map_or(0.0, |j| (j.target + j.offset - a.set.pos).abs()),
                StatusValue::SetPositionOffset => a.set_position_offset,
                StatusValue::SafCycleTime => a.cfg.cycle_time,
                StatusValue::SvbCycleTime => a.cfg.svb_cycle_time,
            },
        })
    }

    fn write_param(
        &mut self,
        ax: usize,
        fb: &str,
        number: u32,
        value: f64,
        is_bool: bool,
    ) -> Result<AxisReply, Rejection> {
        let def = self.param_def(ax, fb, number)?;
        let name = self.axes[ax].name.clone();
        finite(&name, fb, "Value", value)?;
        if def.read_only() {
            return Err(reject(
                READ_ONLY_PARAMETER,
                format!(
                    "axis '{name}': {fb}: parameter {number} {} is read-only",
                    def.name
                ),
            ));
        }
        if is_bool != (def.ty == ParamType::Bool) {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{name}': {fb}: parameter {number} {} has type {:?}",
                    def.name, def.ty
                ),
            ));
        }
        match def.slot {
            Slot::Config(k) => {
                let a = &mut self.axes[ax];
                let mut cfg = a.cfg.clone();
                k.set(&mut cfg, value);
                cfg.validate(&name).map_err(|r| {
                    let id = if r.error_id == ErrorId::NOT_FINITE {
                        r.error_id
                    } else {
                        PARAMETER_NOT_CORRECT
                    };
                    reject(
                        id,
                        format!("{fb}: parameter {number} {}: {}", def.name, r.message),
                    )
                })?;
                a.cfg = cfg;
            }
            Slot::Other(off) => {
                self.axes[ax].other_params.insert(off, value);
            }
            Slot::GearRatio => self.write_gear_ratio(ax, value, fb)?,
            Slot::Status(_) => unreachable!("read-only checked above"),
        }
        let id = self
            .fbs
            .admit(ax, FbKind::WriteParameter, CommandState::Busy);
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    /// AxisGearRatio (3000) written on a coupled slave (§4.4.8): applied at once. A position
    /// coupling is re-anchored at the current master value so the slave does not jump (the
    /// new ratio applies to the master's further travel); MC_GearInDyn takes it as its
    /// effective ratio and target. Not a coupled slave, or several masters → 0x4B05.
    fn write_gear_ratio(&mut self, ax: usize, value: f64, fb: &str) -> Result<(), Rejection> {
        let name = self.axes[ax].name.clone();
        let refuse = |why: &str| {
            Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("axis '{name}': {fb}: AxisGearRatio (3000) {why}"),
            ))
        };
        let Some(mut c) = self.axes[ax].coupling else {
            return refuse("only on a coupled slave");
        };
        if c.ext.multi.is_some() {
            return refuse("of a multi-master coupling: the ratios are MC_GearInMultiMaster's");
        }
        if value == 0.0 {
            return refuse("must not be 0");
        }
        match c.dynamic.as_mut() {
            Some(d) => d.target = value,
            None => {
                let raw = self.master_raw(ax, c.master).pos;
                c.s0 += c.ratio * (raw - c.m0);
                c.m0 = raw;
            }
        }
        c.ratio = value;
        self.axes[ax].coupling = Some(c);
        Ok(())
    }

    // ------------------------------------------------------------------ MC_Home (§4.10)

    fn home(&mut self, ax: usize, c: Home) -> Result<AxisReply, Rejection> {
        let fb = "MC_Home";
        let a = &self.axes[ax];
        let name = a.name.clone();
        if !c.use_default_position {
            finite(&name, fb, "Position", c.position)?;
        }
        finite(
            &name,
            fb,
            "Options.SearchVelocity",
            c.options.search_velocity,
        )?;
        finite(&name, fb, "Options.SyncVelocity", c.options.sync_velocity)?;
        let position = if c.use_default_position {
            a.cfg.homing_calib_value
        } else {
            c.position
        };
        let class = match c.homing_mode {
            HomingMode::DefaultHoming => FbClass::HomeDefault,
            _ => FbClass::HomeNoMotion,
        };
        if c.homing_mode != HomingMode::DefaultHoming {
            self.admit_state(ax, class, fb)?;
            let id = self.fbs.admit(ax, FbKind::Home, CommandState::Busy);
            let a = &mut self.axes[ax];
            a.cmd_no = a.cmd_no.wrapping_add(1);
            match c.homing_mode {
                HomingMode::Direct => {
                    // ActPos := Position; SetPos keeps the lag unless ClearPositionLag.
                    let lag = a.set.pos - a.act_pos;
                    shift_coordinates(a, position - a.act_pos);
                    a.act_pos = position;
                    if c.options.clear_position_lag {
                        a.following_offset = 0.0;
                        a.set.pos = position;
                    } else {
                        a.set.pos = position + lag;
                    }
                    a.target_pos = a.set.pos;
                    a.set_position_offset = 0.0;
                    a.last_target = None;
                    a.homed = true;
                }
                HomingMode::ForceCalibration => a.homed = true,
                HomingMode::ResetCalibration => a.homed = false,
                HomingMode::DefaultHoming => unreachable!(),
            }
            self.instant_done.push(id);
            return Ok(Self::reply(id));
        }
        let dir = |d: Direction, inv: bool, field: &str| -> Result<f64, Rejection> {
            match d {
                Direction::Positive => Ok(1.0),
                Direction::Negative => Ok(-1.0),
                Direction::Undefined => Ok(if inv { -1.0 } else { 1.0 }),
                other => Err(reject(
                    INVALID_MODE,
                    format!("axis '{name}': {fb}: {field} = {other:?} is not a homing direction"),
                )),
            }
        };
        let search_dir = dir(
            c.options.search_direction,
            a.cfg.homing_inv_dir_cam_search,
            "Options.SearchDirection",
        )?;
        let sync_dir = dir(
            c.options.sync_direction,
            a.cfg.homing_inv_dir_sync_search,
            "Options.SyncDirection",
        )?;
        let speed = |v: f64, default: f64, field: &str| -> Result<f64, Rejection> {
            if v < 0.0 || v > a.cfg.max_velocity {
                Err(not_correct(
                    &name,
                    fb,
                    field,
                    v,
                    &format!("must be in [0, {}] (0 = default)", a.cfg.max_velocity),
                ))
            } else if v == 0.0 {
                Ok(default)
            } else {
                Ok(v)
            }
        };
        let search_velocity = speed(
            c.options.search_velocity,
            a.cfg.calibration_velocity_forward,
            "Options.SearchVelocity",
        )?;
        let sync_velocity = speed(
            c.options.sync_velocity,
            a.cfg.calibration_velocity_backward,
            "Options.SyncVelocity",
        )?;
        let mode = if c.options.reference_mode == 0 {
            a.cfg.encoder_reference_mode
        } else {
            c.options.reference_mode
        };
        if !matches!(mode, 0..=7) {
            return Err(reject(
                INVALID_MODE,
                format!("axis '{name}': {fb}: reference mode {mode} is not an E_EncoderReferenceMode (0..7)"),
            ));
        }
        self.admit_state(ax, class, fb)?;
        let id = self.fbs.admit(ax, FbKind::Home, CommandState::Active);
        let a = &mut self.axes[ax];
        a.cmd_no = a.cmd_no.wrapping_add(1);
        a.start_homing(crate::homing::Homing {
            owner: id,
            phase: 1,
            position,
            search_dir,
            search_velocity,
            sync_dir,
            sync_velocity,
            mode: if mode == 0 { 1 } else { mode },
            cam_input: c.calibration_cam,
            prev_cam: false,
            prev_raw: 0.0,
            pulse: 0.0,
            ref_raw: 0.0,
            start_raw: 0.0,
            homed_before: false,
        });
        Ok(Self::reply(id))
    }

    fn home_cam(&mut self, id: CmdId, cam: bool) -> Result<AxisReply, Rejection> {
        let inst = self.fbs.get(id).copied().ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        if inst.kind != FbKind::Home {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("command instance {} is not an MC_Home", id.0),
            ));
        }
        if let Some(h) = self.axes[inst.axis]
            .homing
            .as_mut()
            .filter(|h| h.owner == id)
        {
            h.cam_input = cam;
        }
        Ok(Self::reply(id))
    }

    // ------------------------------------------------------------------ MC_Jog (§4.11)

    fn jog(&mut self, ax: usize, c: Jog) -> Result<AxisReply, Rejection> {
        let fb = "MC_Jog";
        let a = &self.axes[ax];
        let name = a.name.clone();
        finite(&name, fb, "Position", c.position)?;
        if !c.jog_forward && !c.jog_backwards {
            return Err(reject(
                ErrorId::VALUE_OUT_OF_RANGE,
                format!("axis '{name}': {fb}: neither JogForward nor JogBackwards is TRUE (no rising edge)"),
            ));
        }
        let dir = if c.jog_forward { 1.0 } else { -1.0 };
        let standard = |v: f64| Limits {
            velocity: v,
            acceleration: a.cfg.acceleration,
            deceleration: a.cfg.deceleration,
            jerk: a.cfg.jerk,
        };
        let (req, limits) = match c.mode {
            JogMode::StandardSlow => (
                Request::Velocity(Direction::Positive),
                standard(a.cfg.manual_velocity_slow.min(a.cfg.max_velocity)),
            ),
            JogMode::StandardFast => (
                Request::Velocity(Direction::Positive),
                standard(a.cfg.manual_velocity_fast.min(a.cfg.max_velocity)),
            ),
            JogMode::Continous => {
                let l = move_limits(
                    a,
                    fb,
                    Some(c.velocity),
                    c.acceleration,
                    c.deceleration,
                    c.jerk,
                )?;
                (Request::Velocity(Direction::Positive), l)
            }
            JogMode::Inching | JogMode::InchingModulo => {
                let l = move_limits(
                    a,
                    fb,
                    Some(c.velocity),
                    c.acceleration,
                    c.deceleration,
                    c.jerk,
                )?;
                if c.position <= 0.0 {
                    return Err(not_correct(
                        &name,
                        fb,
                        "Position",
                        c.position,
                        "must be > 0 for the INCHING modes",
                    ));
                }
                let req = if c.mode == JogMode::Inching {
                    Request::Relative(dir * c.position)
                } else {
                    // Snap to the next multiple of Position strictly beyond SetPos (§4.11).
                    let p = c.position;
                    let s = a.set.pos;
                    let t = if dir > 0.0 {
                        ((s + 1e-9) / p).floor() * p + p
                    } else {
                        ((s - 1e-9) / p).ceil() * p - p
                    };
                    Request::Absolute(t)
                };
                (req, l)
            }
        };
        let req = match req {
            Request::Velocity(_) => Request::Velocity(if dir > 0.0 {
                Direction::Positive
            } else {
                Direction::Negative
            }),
            r => r,
        };
        let opts = MoveOptions {
            ignore_position_monitoring: true,
            ..Default::default()
        };
        self.motion(ax, FbKind::Jog, fb, req, limits, BufferMode::Aborting, opts)
    }

    // ------------------------------------------------------------------ MC_SetOverride

    fn set_override(&mut self, ax: usize, c: SetOverride) -> Result<AxisReply, Rejection> {
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
        Ok(self.untracked(ReplyValue::None))
    }

    /// MC_SetOverride.Enabled of the axis.
    pub fn set_override_enabled(&self, axis: &str) -> Option<bool> {
        self.index
            .get(axis)
            .map(|&i| self.axes[i].set_override.is_some())
    }

    // ------------------------------------------------------------------ gearing (§4.12)

    fn gear_in(&mut self, slave: usize, c: GearIn) -> Result<AxisReply, Rejection> {
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

    fn gear_in_dyn(&mut self, slave: usize, c: GearInDyn) -> Result<AxisReply, Rejection> {
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
            return Ok(self.untracked(ReplyValue::None));
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

    fn gear_out(&mut self, slave: usize) -> Result<AxisReply, Rejection> {
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

    // ------------------------------------------------------------------ MC_TorqueControl

    fn torque_inputs(
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

    fn torque_control(&mut self, ax: usize, c: TorqueControl) -> Result<AxisReply, Rejection> {
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

    fn torque_update(
        &mut self,
        id: CmdId,
        torque: f64,
        ramp: f64,
        hi: f64,
        lo: f64,
    ) -> Result<AxisReply, Rejection> {
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

    // ------------------------------------------------------------------ superposition (§4.9)

    fn move_superimposed(
        &mut self,
        ax: usize,
        c: MoveSuperImposed,
    ) -> Result<AxisReply, Rejection> {
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

    fn abort_superposition(&mut self, ax: usize) -> Result<AxisReply, Rejection> {
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

    // ------------------------------------------------------------------ touch probe (§4.5)

    fn probe_slot(name: &str, fb: &str, t: &TriggerRef) -> Result<usize, Rejection> {
        match t.touch_probe {
            TouchProbeUnit::TouchProbe1 => Ok(0),
            TouchProbeUnit::TouchProbe2 => Ok(1),
            TouchProbeUnit::PlcEvent => Ok(2),
            u => Err(reject(
                INVALID_MODE,
                format!("axis '{name}': {fb}: TriggerInput.TouchProbe = {u:?} is not available"),
            )),
        }
    }

    fn touch_probe(&mut self, ax: usize, c: TouchProbe) -> Result<AxisReply, Rejection> {
        let fb = "MC_TouchProbe";
        let name = self.axes[ax].name.clone();
        finite(&name, fb, "FirstPosition", c.first_position)?;
        finite(&name, fb, "LastPosition", c.last_position)?;
        let k = Self::probe_slot(&name, fb, &c.trigger_input)?;
        if c.window_only && !c.trigger_input.modulo_positions && c.first_position > c.last_position
        {
            return Err(not_correct(
                &name,
                fb,
                "FirstPosition",
                c.first_position,
                "must not exceed LastPosition (non-modulo window)",
            ));
        }
        self.admit_state(ax, FbClass::TouchProbe, fb)?;
        if self.axes[ax].probes[k].is_some() {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!(
                    "axis '{name}': {fb}: the latch {:?} is already armed (use MC_AbortTrigger)",
                    c.trigger_input.touch_probe
                ),
            ));
        }
        let id = self.fbs.admit(ax, FbKind::TouchProbe, CommandState::Active);
        self.axes[ax].probes[k] = Some(crate::probe::Probe {
            owner: id,
            edge: c.trigger_input.edge,
            mode: c.trigger_input.mode,
            window_only: c.window_only,
            first: c.first_position,
            last: c.last_position,
            modulo_positions: c.trigger_input.modulo_positions,
            plc_event: c.trigger_input.plc_event,
            // An already TRUE PlcEvent is no rising edge.
            plc_prev: c.trigger_input.plc_event,
        });
        Ok(Self::reply(id))
    }

    fn abort_trigger(&mut self, ax: usize, c: AbortTrigger) -> Result<AxisReply, Rejection> {
        let fb = "MC_AbortTrigger";
        let name = self.axes[ax].name.clone();
        let k = Self::probe_slot(&name, fb, &c.trigger_input)?;
        let id = self.fbs.admit(ax, FbKind::AbortTrigger, CommandState::Busy);
        if let Some(p) = self.axes[ax].probes[k].take() {
            self.fbs.aborted(p.owner);
        }
        self.instant_done.push(id);
        Ok(Self::reply(id))
    }

    fn probe_plc_event(&mut self, id: CmdId, level: bool) -> Result<AxisReply, Rejection> {
        let inst = self.fbs.get(id).copied().ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        if inst.kind != FbKind::TouchProbe {
            return Err(reject(
                COMMAND_NOT_PERMITTED,
                format!("command instance {} is not an MC_TouchProbe", id.0),
            ));
        }
        if let Some(p) = self.axes[inst.axis].probes[2]
            .as_mut()
            .filter(|p| p.owner == id)
        {
            p.plc_event = level;
        }
        Ok(Self::reply(id))
    }

    /// Recorded data of an MC_TouchProbe instance (after its first accepted edge).
    pub fn probe_outputs(&self, id: CmdId) -> Option<crate::probe::ProbeOutputs> {
        self.fbs.probes.get(&id).copied()
    }

    /// The outputs of an axis' MC_Power instance (Enable-type, §4.1).
    fn power_instance_outputs(&self, id: CmdId) -> Option<InstanceOutputs> {
        let a = self.axes.iter().find(|a| a.power_id == Some(id))?;
        let error = !a.power_error.is_none();
        let mut outputs = FbOutputs::default();
        outputs.standard.busy = a.enable;
        outputs.standard.active = a.enable && a.controller_on;
        outputs.standard.error = error;
        outputs.standard.error_id = a.power_error;
        Some(InstanceOutputs {
            axis: a.name.clone(),
            kind: FbKind::Power,
            outputs,
            superimposed: None,
            probe: None,
            extra: Some(ExtraOutputs::Power {
                status: a.status,
                valid: a.enable && !error,
            }),
        })
    }

    fn read_fb_outputs(&mut self, id: CmdId) -> Result<AxisReply, Rejection> {
        if let Some(outputs) = self.power_instance_outputs(id) {
            return Ok(AxisReply {
                id,
                value: ReplyValue::Outputs(Box::new(outputs)),
                tracked: false,
            });
        }
        let (axis, kind) = self
            .instance(id)
            .map(|(a, k)| (a.to_string(), k))
            .ok_or_else(|| {
                reject(
                    ErrorId::UNKNOWN_OBJECT,
                    format!("unknown command instance {}", id.0),
                )
            })?;
        let outputs = InstanceOutputs {
            axis,
            kind,
            outputs: self.fb_outputs(id).unwrap_or_default(),
            superimposed: self.superimposed_outputs(id),
            probe: self.probe_outputs(id),
            extra: self.extra_outputs(id),
        };
        // The instance's own id, so the reply names what was read.
        Ok(AxisReply {
            id,
            value: ReplyValue::Outputs(Box::new(outputs)),
            tracked: false,
        })
    }

    // ------------------------------------------------------------------ SetExecute

    fn set_execute(&mut self, id: CmdId, execute: bool) -> Result<AxisReply, Rejection> {
        let inst = self.fbs.set_execute(id, execute).ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        self.set_execute_axis3(&inst, id, execute);
        if inst.kind == FbKind::Stop && !execute {
            let a = &mut self.axes[inst.axis];
            if let Some(lock) = a.lock.as_mut().filter(|l| l.owner == id) {
                lock.execute = false;
            }
        }
        if inst.kind == FbKind::Jog && !execute {
            // Jog button released: continuous modes decelerate, Done at rest (§4.11).
            let a = &mut self.axes[inst.axis];
            if let Some(j) = a
                .job
                .filter(|j| j.owner == Some(id) && j.kind == JobKind::Velocity)
            {
                let l = Limits {
                    velocity: a.cfg.max_velocity,
                    ..j.limits
                };
                a.start_spec(
                    id,
                    Spec::Halt {
                        limits: l,
                        monitor: false,
                    },
                    &mut self.fbs,
                );
            }
        }
        Ok(Self::reply(id))
    }

    // ------------------------------------------------------------------ sim hooks (§1.5)

    fn sim(&mut self, ax: usize, s: Sim) -> Result<AxisReply, Rejection> {
        let a = &mut self.axes[ax];
        match s {
            Sim::InjectAxisError { error_id, .. } => {
                let e = if error_id == 0 {
                    POSITION_LAG
                } else {
                    ErrorId(error_id)
                };
                a.raise_error(e, false, &mut self.fbs);
            }
            Sim::DriveFault { error_id, .. } => {
                let e = if error_id == 0 {
                    POSITION_LAG
                } else {
                    ErrorId(error_id)
                };
                a.raise_error(e, true, &mut self.fbs);
            }
            Sim::ProbeInput { unit, level, .. } => {
                if !(1..=2).contains(&unit) {
                    return Err(reject(
                        ErrorId::VALUE_OUT_OF_RANGE,
                        format!(
                            "axis '{}': sim.probe_input: unit = {unit} must be 1 or 2",
                            a.name
                        ),
                    ));
                }
                a.probe_level[unit as usize - 1] = level;
            }
            Sim::SetFollowingOffset { offset, .. } => {
                finite(&a.name, "sim.set_following_offset", "offset", offset)?;
                a.following_offset = offset;
            }
        }
        Ok(self.untracked(ReplyValue::None))
    }
}

/// Travel direction (±1) of a running job.
fn travel_dir(a: &Axis, j: &Job) -> f64 {
    match j.kind {
        JobKind::Velocity => j.dir,
        _ => {
            let d = j.target + j.offset - a.set.pos;
            if d.abs() > 1e-12 {
                d.signum()
            } else if a.set.vel.abs() > 1e-12 {
                a.set.vel.signum()
            } else {
                1.0
            }
        }
    }
}

/// Installs `pending` behind the running job `j` with the BufferMode's transition velocity
/// (§3.6 rules 4–7), replanning `j` so that it reaches the transition point with it.
fn blend(a: &mut Axis, j: Job, pending: Pending, mode: BufferMode, blend_at: Option<f64>) {
    let dir1 = travel_dir(a, &j);
    let p_trans = blend_at.unwrap_or(j.target + j.offset);
    // A MC_MoveContinuous* arrives with its EndVelocity: that is v1 at the target (§4.8.7).
    let v1 = if j.continuous {
        j.end_vel.abs()
    } else {
        j.velocity
    };
    let (v2, reverse, cap) = match pending.spec {
        Spec::Position { target, limits, .. } => (
            Some(limits.velocity),
            (target - p_trans) * dir1 <= 0.0,
            buffer::stop_capable_velocity(
                (target - p_trans).abs(),
                limits.deceleration,
                limits.jerk,
            ),
        ),
        Spec::Velocity { dir, limits } => (Some(limits.velocity), dir != dir1, f64::INFINITY),
        Spec::Halt { .. } => (None, false, f64::INFINITY),
        Spec::Continuous {
            target,
            end_velocity,
            limits,
        } => (
            Some(limits.velocity),
            (target - p_trans) * dir1 <= 0.0,
            if end_velocity > 0.0 {
                f64::INFINITY
            } else {
                buffer::stop_capable_velocity(
                    (target - p_trans).abs(),
                    limits.deceleration,
                    limits.jerk,
                )
            },
        ),
    };
    let mut v_t = buffer::transition_velocity(mode, v1, v2);
    if reverse || j.kind == JobKind::Halt {
        v_t = 0.0;
    }
    v_t = v_t.min(cap);
    a.pending = Some(pending);
    if v_t <= 0.0 && blend_at.is_none() {
        return; // Buffered: the running job stops at its end, then the follow-up starts.
    }
    let limits = Limits {
        velocity: j.velocity.max(v1).max(v_t),
        ..j.limits
    };
    let try_plan = |a: &Axis, v: f64| {
        a.plan_position(p_trans, v * dir1, &limits)
            .filter(|p| !p.reverses())
    };
    // Rule 5 ("as well as possible"): if v_t cannot be reached at the transition point
    // without a reversal, take the highest reachable velocity below it (0 = like Buffered).
    let (profile, v_t) = match try_plan(a, v_t) {
        Some(p) => (p, v_t),
        None => {
            let Some(mut best) = try_plan(a, 0.0) else {
                return;
            };
            let (mut lo, mut hi) = (0.0, v_t);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                match try_plan(a, mid) {
                    Some(p) => {
                        best = p;
                        lo = mid;
                    }
                    None => hi = mid,
                }
            }
            (best, lo)
        }
    };
    if let Some(job) = a.job.as_mut() {
        job.kind = JobKind::Position;
        job.profile = profile;
        job.t = 0.0;
        job.offset = 0.0;
        job.target = p_trans;
        job.end_vel = v_t * dir1;
        job.limits = limits;
        job.velocity = limits.velocity;
        job.monitor = false;
        job.owner_aborts_at_end = j.kind == JobKind::Velocity || j.continuous;
        job.paused = a.override_pct <= 0.0;
        job.held = false;
        a.target_pos = p_trans;
    }
}

/// Sets the effective override and replans if it changed.
pub(crate) fn apply_override(a: &mut Axis, pct: f64, fbs: &mut Handshake) {
    if pct != a.override_pct {
        a.override_pct = pct;
        override_changed(a, fbs);
    }
}

/// Replans the running job after an override change (§1.1, §4.8.6).
fn override_changed(a: &mut Axis, fbs: &mut Handshake) {
    let Some(mut j) = a.job else { return };
    let paused = a.override_pct <= 0.0;
    match j.kind {
        JobKind::Position => {
            let target = j.target + j.offset;
            if let Some(p) = a.plan_position(target, j.end_vel, &j.limits) {
                j.profile = p;
                j.t = 0.0;
                j.offset = 0.0;
                j.target = target;
                j.paused = paused;
            }
        }
        JobKind::Velocity => {
            // MC_MoveVelocity reports CommandAborted; the axis keeps moving (§4.8.6).
            if let Some(id) = j
                .owner
                .filter(|&id| fbs.get(id).is_some_and(|i| i.kind == FbKind::MoveVelocity))
            {
                fbs.aborted(id);
                j.owner = None;
            }
            if let Some((p, limit)) = a.plan_velocity(j.dir, &j.limits) {
                j.profile = p;
                j.t = 0.0;
                j.offset = 0.0;
                j.target = limit.unwrap_or(f64::NAN);
                j.paused = paused;
                j.held = false;
            }
        }
        _ => return,
    }
    a.job = Some(j);
}

/// Shifts the coordinate system by `delta` (MC_SetPosition, §4.3).
pub(crate) fn shift_coordinates(a: &mut Axis, delta: f64) {
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

/// MC_MoveModulo target (§4.8.4).
#[allow(clippy::too_many_arguments)]
fn modulo_target(
    a: &Axis,
    name: &str,
    fb: &str,
    position: f64,
    direction: Direction,
    limits: &Limits,
    buffered: bool,
    base: f64,
) -> Result<f64, Rejection> {
    let period = a.cfg.modulo_value;
    let tol = a.cfg.modulo_tolerance_window;
    if position < 0.0 {
        return Err(not_correct(name, fb, "Position", position, "must be >= 0"));
    }
    let moving = a.set.vel.abs() > 1e-9;
    if direction == Direction::Undefined
        || (direction == Direction::Current && (!moving || buffered))
    {
        return Err(reject(
            INVALID_MODE,
            format!("axis '{name}': {fb}: Direction {direction:?} not allowed here"),
        ));
    }
    if direction == Direction::ShortestWay && position >= period {
        return Err(not_correct(
            name,
            fb,
            "Position",
            position,
            &format!("must be < {period} for MC_Shortest_Way"),
        ));
    }
    if !moving || buffered {
        let d = modulo::standstill_distance(base, position, period, tol, direction).ok_or_else(
            || {
                reject(
                    INVALID_MODE,
                    format!("axis '{name}': {fb}: Direction {direction:?} not allowed here"),
                )
            },
        )?;
        return Ok(base + d);
    }
    // Moving and aborting: first position with that modulo value at or beyond the stopping
    // point; no reversal allowed.
    let travel = a.set.vel.signum();
    let wanted = match direction {
        Direction::Positive => 1.0,
        Direction::Negative => -1.0,
        _ => travel,
    };
    if wanted != travel && direction != Direction::ShortestWay {
        return Err(reject(
            INVALID_MODE,
            format!("axis '{name}': {fb}: Direction {direction:?} opposite to the current travel"),
        ));
    }
    let stop = a.plan_stop(limits).end().pos;
    Ok(modulo::moving_target(stop, position, period, travel))
}

impl AxisEngine {
    /// One FB call: group and platform calls, instance updates, then single-axis FBs through
    /// the profile hooks.
    pub(crate) fn dispatch(&mut self, mut cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        match cmd {
            AxisCommand::Group(g) => return self.group_command_screened(g),
            AxisCommand::Platform(p) => return self.platform_command(p),
            AxisCommand::SetExecute { id, execute } => {
                if let Some(r) = self.group_set_execute(id, execute) {
                    return Ok(r);
                }
                return self.set_execute(id, execute);
            }
            AxisCommand::ReadFbOutputs { id } => {
                if let Some(o) = self.group_outputs(id) {
                    return Ok(AxisReply {
                        id,
                        value: ReplyValue::Group(crate::group::GroupReply::Outputs(o)),
                        tracked: false,
                    });
                }
                if self.fbs.get(id).is_none() {
                    if let Some(outputs) = self.ca.outputs(id) {
                        let gear = self.ca.gear_outputs(id);
                        let v = crate::ca::CaValue::Outputs { outputs, gear };
                        return Ok(AxisReply {
                            id,
                            value: ReplyValue::Ca(Box::new(v)),
                            tracked: false,
                        });
                    }
                }
                return self.read_fb_outputs(id);
            }
            AxisCommand::Ca(c) => {
                return self
                    .ca
                    .command(c, &mut self.axes, &self.index, &mut self.fbs)
            }
            AxisCommand::HomeCalibrationCam {
                id,
                calibration_cam,
            } => return self.home_cam(id, calibration_cam),
            AxisCommand::TouchProbePlcEvent { id, plc_event } => {
                return self.probe_plc_event(id, plc_event)
            }
            AxisCommand::TorqueControlUpdate {
                id,
                torque,
                torque_ramp,
                velocity_limit_high,
                velocity_limit_low,
            } => {
                return self.torque_update(
                    id,
                    torque,
                    torque_ramp,
                    velocity_limit_high,
                    velocity_limit_low,
                )
            }
            // A later call of a running phasing instance (by id, like the updates above).
            AxisCommand::PhasingUpdate(_) => return self.command_axis3(cmd),
            _ => {}
        }
        let ax = self.axis_index(cmd.axis().unwrap_or_default())?;
        // Profile hooks (plcopen_platform.md): screening, then bookkeeping of the result.
        self.platform_pre(ax, &mut cmd)?;
        self.group_screen_axis_command(ax, &cmd)?;
        self.ca.screen_single_axis(ax, &cmd)?;
        let (order, kind) = crate::platform::classify(&cmd);
        // The FBs of engine/phasing.rs, multi_master.rs, ext_setpoint.rs, extensions.rs.
        let res = if is_axis3(&cmd) {
            self.command_axis3(cmd)
        } else {
            self.axis_command(ax, cmd)
        };
        self.platform_post(ax, order, kind, res)
    }
}

impl AxisEngine {
    /// The Tc2_MC2 FB semantics of one single-axis call (after the profile hooks).
    fn axis_command(&mut self, ax: usize, cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        // A move FB: its dynamics screened (§3.5), then admitted through the buffer logic (§3.6).
        macro_rules! positioning {
            ($c:expr, $kind:ident, $req:expr) => {{
                let fb = concat!("MC_", stringify!($kind));
                let l = move_limits(
                    &self.axes[ax],
                    fb,
                    Some($c.velocity),
                    $c.acceleration,
                    $c.deceleration,
                    $c.jerk,
                )?;
                self.motion(ax, FbKind::$kind, fb, $req, l, $c.buffer_mode, $c.options)
            }};
        }
        match cmd {
            AxisCommand::Power(c) => self.power(ax, c),
            AxisCommand::Reset(_) => self.reset(ax),
            AxisCommand::MoveAbsolute(c) => {
                finite(&c.axis, "MC_MoveAbsolute", "Position", c.position)?;
                positioning!(c, MoveAbsolute, Request::Absolute(c.position))
            }
            AxisCommand::MoveRelative(c) => {
                finite(&c.axis, "MC_MoveRelative", "Distance", c.distance)?;
                positioning!(c, MoveRelative, Request::Relative(c.distance))
            }
            AxisCommand::MoveAdditive(c) => {
                finite(&c.axis, "MC_MoveAdditive", "Distance", c.distance)?;
                positioning!(c, MoveAdditive, Request::Additive(c.distance))
            }
            AxisCommand::MoveModulo(c) => {
                finite(&c.axis, "MC_MoveModulo", "Position", c.position)?;
                let req = Request::Modulo {
                    position: c.position,
                    direction: c.direction,
                };
                positioning!(c, MoveModulo, req)
            }
            AxisCommand::MoveVelocity(c) => {
                positioning!(c, MoveVelocity, Request::Velocity(c.direction))
            }
            AxisCommand::MoveContinuousAbsolute(c) => {
                let fb = "MC_MoveContinuousAbsolute";
                finite(&c.axis, fb, "Position", c.position)?;
                let ev = end_velocity(&self.axes[ax], fb, c.end_velocity)?;
                positioning!(
                    c,
                    MoveContinuousAbsolute,
                    Request::ContinuousAbsolute(c.position, ev)
                )
            }
            AxisCommand::MoveContinuousRelative(c) => {
                let fb = "MC_MoveContinuousRelative";
                finite(&c.axis, fb, "Distance", c.distance)?;
                let ev = end_velocity(&self.axes[ax], fb, c.end_velocity)?;
                positioning!(
                    c,
                    MoveContinuousRelative,
                    Request::ContinuousRelative(c.distance, ev)
                )
            }
            AxisCommand::Halt(c) => {
                let l = self.halt_limits(ax, "MC_Halt", c.deceleration, c.jerk)?;
                self.motion(
                    ax,
                    FbKind::Halt,
                    "MC_Halt",
                    Request::Halt,
                    l,
                    c.buffer_mode,
                    c.options,
                )
            }
            AxisCommand::Stop(c) => self.stop(ax, c),
            AxisCommand::SetPosition(c) => self.set_position(ax, c),
            AxisCommand::ReadParameter(c) => {
                let v = self.read_param(ax, "MC_ReadParameter", c.parameter_number, false)?;
                Ok(self.untracked(ReplyValue::Real(v)))
            }
            AxisCommand::ReadBoolParameter(c) => {
                let v = self.read_param(ax, "MC_ReadBoolParameter", c.parameter_number, true)?;
                Ok(self.untracked(ReplyValue::Bool(v != 0.0)))
            }
            AxisCommand::WriteParameter(c) => {
                self.write_param(ax, "MC_WriteParameter", c.parameter_number, c.value, false)
            }
            AxisCommand::WriteBoolParameter(c) => self.write_param(
                ax,
                "MC_WriteBoolParameter",
                c.parameter_number,
                c.value as u8 as f64,
                true,
            ),
            AxisCommand::ReadStatus(_) => {
                // The same source as the snapshot (CoupleState 1/2 of a master, CA fields).
                let s = self.axis_status(ax, self.is_master(ax));
                Ok(self.untracked(ReplyValue::Status(Box::new(s))))
            }
            AxisCommand::ReadActualPosition(_) => {
                let v = self.axes[ax].act_pos;
                Ok(self.untracked(ReplyValue::Real(v)))
            }
            AxisCommand::ReadActualVelocity(_) => {
                let v = self.axes[ax].act_velo;
                Ok(self.untracked(ReplyValue::Real(v)))
            }
            AxisCommand::ReadAxisError(_) => {
                let v = self.axes[ax].error_id.0;
                Ok(self.untracked(ReplyValue::DWord(v)))
            }
            AxisCommand::Sim(s) => self.sim(ax, s),
            AxisCommand::Home(c) => self.home(ax, c),
            AxisCommand::Jog(c) => self.jog(ax, c),
            AxisCommand::SetOverride(c) => self.set_override(ax, c),
            AxisCommand::GearIn(c) => self.gear_in(ax, c),
            AxisCommand::GearOut(_) => self.gear_out(ax),
            AxisCommand::GearInDyn(c) => self.gear_in_dyn(ax, c),
            AxisCommand::TorqueControl(c) => self.torque_control(ax, c),
            AxisCommand::MoveSuperImposed(c) => self.move_superimposed(ax, c),
            AxisCommand::TouchProbe(c) => self.touch_probe(ax, c),
            AxisCommand::AbortTrigger(c) => self.abort_trigger(ax, c),
            AxisCommand::AbortSuperposition(_) => self.abort_superposition(ax),
            AxisCommand::SetExecute { .. }
            | AxisCommand::HomeCalibrationCam { .. }
            | AxisCommand::TorqueControlUpdate { .. }
            | AxisCommand::TouchProbePlcEvent { .. }
            | AxisCommand::ReadFbOutputs { .. }
            | AxisCommand::Group(_)
            | AxisCommand::Platform(_)
            | AxisCommand::Ca(_) => {
                unreachable!("handled above")
            }
            AxisCommand::PhasingAbsolute(_)
            | AxisCommand::PhasingRelative(_)
            | AxisCommand::HaltPhasing(_)
            | AxisCommand::PhasingUpdate(_)
            | AxisCommand::GearInMultiMaster(_)
            | AxisCommand::ExtSetPointGenEnable(_)
            | AxisCommand::ExtSetPointGenDisable(_)
            | AxisCommand::ExtSetPointGenFeed(_)
            | AxisCommand::ExtSetPointGenFeedWithTorque(_)
            | AxisCommand::ReadDriveOperationMode(_)
            | AxisCommand::WriteDriveOperationMode(_)
            | AxisCommand::BacklashCompensation(_)
            | AxisCommand::PositionCorrectionLimiter(_)
            | AxisCommand::ReadDriveAddress(_)
            | AxisCommand::SelectControlLoop(_)
            | AxisCommand::SetAcceptBlockedDriveSignal(_)
            | AxisCommand::SetEncoderScalingFactor(_)
            | AxisCommand::WriteNcIoOutput(_)
            | AxisCommand::TableBasedPositionCompensation(_)
            | AxisCommand::ConvertIncPosToPos(_)
            | AxisCommand::ConvertPosToIncPos(_)
            | AxisCommand::ReadParameterSet(_)
            | AxisCommand::ReadAxisComponents(_)
            | AxisCommand::WriteParameterPersistent(_)
            | AxisCommand::WriteBoolParameterPersistent(_) => {
                unreachable!("handled by command_axis3")
            }
        }
    }
}

impl Engine for AxisEngine {
    type Command = AxisCommand;
    type Reply = AxisReply;
    type Snapshot = AxisSnapshot;

    fn command(&mut self, cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        self.dispatch(cmd)
    }

    /// MC_Stop on every axis with its AxisFastDec/AxisFastJerk (the error reaction's
    /// dynamics); an axis that cannot take it (disabled, already stopping) is left as it is.
    fn fail_safe_stop(&mut self) {
        for i in 0..self.axes.len() {
            let cfg = &self.axes[i].cfg;
            let stop = Stop {
                axis: self.axes[i].name.clone(),
                deceleration: cfg.fast_deceleration,
                jerk: cfg.fast_jerk,
                options: MoveOptions::default(),
            };
            let _ = self.dispatch(AxisCommand::Stop(stop));
        }
    }

    fn at_rest(&self) -> bool {
        (0..self.axes.len()).all(|i| self.axis_status(i, false).set_velo == 0.0)
    }

    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        // A non-positive or non-finite cycle time cannot advance anything (defensive: the
        // runtime always passes the configured period).
        if !(tick.dt > 0.0 && tick.dt.is_finite()) {
            events.append(&mut self.fbs.events);
            return;
        }
        self.fbs.cycle += 1;
        self.fbs.in_step = true;
        self.tick = tick.index;
        for i in 0..self.instant_done.len() {
            let id = self.instant_done[i];
            self.fbs.done(id);
        }
        self.instant_done.clear();
        self.platform_step_pre();
        self.groups_step(tick.dt);
        self.ca.step(tick.dt, &mut self.axes, &mut self.fbs);
        for k in 0..self.order.len() {
            let i = self.order[k];
            let master = self.axes[i]
                .coupling
                .map(|c| MasterState::of(&self.axes[c.master]));
            self.pre_step_axis3(i, tick.dt);
            self.axes[i].step(tick.dt, master, &mut self.fbs);
            self.post_step_axis3(i, tick.dt);
        }
        self.platform_step_post();
        self.fbs.in_step = false;
        let from = events.len();
        events.append(&mut self.fbs.events);
        self.platform_map_events(&mut events[from..]);
        self.raw_route(events, from);
    }

    fn snapshot(&self) -> AxisSnapshot {
        AxisSnapshot {
            tick: self.tick,
            axes: {
                let mut master = vec![false; self.axes.len()];
                for a in &self.axes {
                    if let Some(c) = a.coupling {
                        for m in c.masters() {
                            master[m] = true;
                        }
                    }
                }
                let starting = self.platform.starting();
                (0..self.axes.len())
                    .map(|i| {
                        let mut s = self.axis_status(i, master[i]);
                        s.ext = self.ext_values(i);
                        if starting {
                            // INIT_STATE during start-up (§9).
                            s.motion_state = crate::state::MotionState::Undefined;
                        }
                        s
                    })
                    .collect()
            },
            groups: (0..self.groups.list.len())
                .map(|g| self.group_status(g))
                .collect(),
            platform: self.platform_status(),
            ca_groups: self.ca.snapshot(&self.axes),
        }
    }

    fn reply_id(reply: &AxisReply) -> Option<CmdId> {
        // Read-type calls and MC_Power have no lifetime of their own: nothing to watch.
        reply.tracked.then_some(reply.id)
    }

    fn error_text(id: ErrorId) -> String {
        if let Some(t) = crate::platform::ids::text(id) {
            return format!("{}: {t}", id.0);
        }
        crate::error_ids::text(id)
    }

    fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
        if let Some(r) = self.group_cancel(id) {
            return r;
        }
        // A cancelled goal halts the axis with the command's own dynamics (MC_Halt semantics).
        if self.fbs.get(id).is_none() && self.ca.owns(id) {
            return self.ca.cancel(id, &self.axes, &mut self.fbs);
        }
        let Some(inst) = self.fbs.get(id).copied() else {
            return Err(reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            ));
        };
        if inst.state.is_final() {
            return Ok(());
        }
        if self.cancel_axis3(&inst, id) {
            return Ok(());
        }
        if inst.kind == FbKind::Jog {
            // A jog goal's cancel lets go of its button (Execute falling, §4.11): continuous
            // modes brake with the jog's own deceleration and end Done, as for an operator.
            return self.set_execute(id, false).map(|_| ());
        }
        let a = &mut self.axes[inst.axis];
        if a.pending.is_some_and(|p| p.owner == id) {
            a.pending = None;
            self.fbs.aborted(id);
            return Ok(());
        }
        if a.job
            .is_some_and(|j| j.owner == Some(id) && j.kind != JobKind::Stop)
        {
            let j = a.job.unwrap_or_else(|| unreachable!());
            a.abort_motion(&mut self.fbs);
            let profile = a.plan_stop(&j.limits);
            let stop = profile.end().pos;
            a.start_job(Job::internal(JobKind::Halt, profile, stop, j.limits));
        } else if a.settle.is_some_and(|s| s.owner == id) {
            a.settle = None;
            self.fbs.aborted(id);
        }
        Ok(())
    }
}

// ---- FBs added after the first release (phasing, multi-master gearing, external setpoint
// generator, §4.7 extensions): child modules, so they can use the engine's private helpers;
// `hooks` is the one place where they plug into `command` and `step`.
pub mod ext_setpoint;
pub mod extensions;
pub mod hooks;
pub(crate) use hooks::is_axis3;
pub mod multi_master;
pub mod phasing;
