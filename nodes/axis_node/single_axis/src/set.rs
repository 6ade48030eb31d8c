//! [`AxisSet`]: the configured axes with their FB instances, and the FB calls of Tc2_MC2 on
//! them (single_axis.md §4): input screening (NaN/inf → NOT_FINITE, ranges → 0x4B06), the
//! admission matrix (§2.4), BufferMode (§3.6) and each FB's semantics, one child module per
//! concept. `step_axes` runs one cycle of every axis, masters before their slaves (§1.1, §4.12).
//!
//! A platform profile changes single-axis behaviour only through [`AxisProfile`]; groups,
//! collision avoidance and profiles compose an `AxisSet` (crate `axis_engine`), it knows none
//! of them.

use crate::axis::{shift_coordinates, Axis, Job, JobKind, Lock, Pending, Spec};
use crate::buffer;
use crate::config::AxisConfig;
use crate::error_ids::*;
use crate::gearing::MasterState;
use crate::handshake::{ExtraOutputs, FbKind, FbOutputs, Handshake};
use crate::modulo;
use crate::params::{self, ParamType, Slot, StatusValue};
use crate::state::{admission, Admission, FbClass};
use crate::status::AxisStatus;
use motion_core::{CmdId, CommandState, ErrorId, Limits, Rejection, State1};
use std::collections::HashMap;

pub use crate::added_inputs::*;
pub use crate::extension_inputs::*;
pub use crate::fb_inputs::*;
pub use crate::inputs::*;
pub use profile::{AxisProfile, Tc2Mc2};
pub use reply::{FbReply, FbValue, InstanceOutputs};

/// The configured axes, their FB instances and the step order.
#[derive(Debug)]
pub struct AxisSet {
    /// The axes in configuration order.
    pub axes: Vec<Axis>,
    /// Axis name → index in `axes`.
    pub index: HashMap<String, usize>,
    /// The FB instances of all axes (§3 handshake).
    pub fbs: Handshake,
    /// Instantaneous commands reported Done in the next cycle (§3.1 rule 2).
    instant_done: Vec<CmdId>,
    /// Step order: masters before their slaves (§4.12).
    order: Vec<usize>,
    /// Where the platform profile changes single-axis behaviour.
    profile: Box<dyn AxisProfile>,
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
pub(crate) enum Request {
    Absolute(f64),
    Relative(f64),
    Additive(f64),
    Modulo { position: f64, direction: Direction },
    Velocity(Direction),
    Halt,
    ContinuousAbsolute(f64, f64),
    ContinuousRelative(f64, f64),
}

impl AxisSet {
    /// Builds the set from `(name, config)` pairs; names must be unique and non-empty, every
    /// config valid (message names axis, key and value). A zero `axis_id` becomes the index + 1.
    pub fn new(axes: Vec<(String, AxisConfig)>) -> Result<Self, Rejection> {
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
        Ok(AxisSet {
            axes: list,
            index,
            fbs: Handshake::new(),
            instant_done: Vec::with_capacity(64),
            order,
            profile: Box::new(Tc2Mc2),
        })
    }

    /// Installs the platform profile's rules (default: plain Tc2_MC2).
    pub fn set_profile(&mut self, profile: Box<dyn AxisProfile>) {
        self.profile = profile;
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

    /// NcToPlc status of axis `i` with its CoupleState, given whether it is a master.
    pub fn axis_status(&self, i: usize, master: bool) -> AxisStatus {
        let mut s = AxisStatus::default();
        self.axis_status_into(i, master, &mut s);
        s
    }

    /// [`Self::axis_status`] written into `s` in place (a snapshot's refill).
    pub fn axis_status_into(&self, i: usize, master: bool, s: &mut AxisStatus) {
        self.axes[i].status_into(s);
        s.couple_state = self.couple_state(i, master);
    }

    /// Per axis: whether it is the master of a coupling.
    /// Empty while no axis is coupled: a snapshot of every cycle allocates nothing for it.
    pub fn masters(&self) -> Vec<bool> {
        if self.axes.iter().all(|a| a.coupling.is_none()) {
            return Vec::new();
        }
        let mut master = vec![false; self.axes.len()];
        for a in &self.axes {
            if let Some(c) = &a.coupling {
                for m in c.masters() {
                    master[m] = true;
                }
            }
        }
        master
    }

    /// Whether axis `i` is the master of a coupling.
    pub fn is_master(&self, i: usize) -> bool {
        self.axes.iter().any(|a| {
            a.coupling
                .as_ref()
                .is_some_and(|c| c.masters().any(|m| m == i))
        })
    }

    /// All outputs of an instance (incl. InVelocity), as the profile shows them.
    pub fn fb_outputs(&self, id: CmdId) -> Option<FbOutputs> {
        let mut o = self.fbs.outputs_with(id, self.profile.latch_done())?;
        if o.standard.error {
            o.standard.error_id = self.shown_error_id(id, o.standard.error_id);
        }
        Some(o)
    }

    /// The ErrorID instance `inst` shows for `id` under the profile (`id` for an unknown
    /// instance).
    pub fn shown_error_id(&self, inst: CmdId, id: ErrorId) -> ErrorId {
        match self.fbs.get(inst) {
            Some(i) => self.profile.shown_error_id(&self.axes[i.axis], id),
            None => id,
        }
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
            .map(|i| (self.axes[i.axis].name.as_ref(), i.kind))
    }

    /// Index of the named axis; unknown → UNKNOWN_OBJECT.
    pub fn axis_index(&self, name: &str) -> Result<usize, Rejection> {
        self.index
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("axis", name))
    }

    fn reply(id: CmdId) -> FbReply {
        FbReply {
            id,
            value: FbValue::None,
            tracked: true,
        }
    }

    /// A reply without a lifetime of its own (MC_Power, read FBs), with a fresh id.
    pub fn untracked(&mut self, value: FbValue) -> FbReply {
        FbReply {
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

    // ------------------------------------------------------------------ SetExecute

    /// A later Execute (or Enable) level of an instance: Execute falling resets the outputs,
    /// unlocks MC_Stop and releases the MC_Jog button (§3.1, §4.11).
    pub fn set_execute(&mut self, id: CmdId, execute: bool) -> Result<FbReply, Rejection> {
        let inst = self.fbs.set_execute(id, execute).ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        if !execute && matches!(inst.kind, FbKind::PhasingAbsolute | FbKind::PhasingRelative) {
            self.phasing_execute_fell(id);
        }
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

    /// The §1.5 simulation inputs of one axis.
    pub fn sim(&mut self, ax: usize, s: Sim) -> Result<FbReply, Rejection> {
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
        Ok(self.untracked(FbValue::None))
    }

    // ------------------------------------------------------------------ cycle

    /// Start of a cycle: the instantaneous commands of the last cycle report Done.
    pub fn begin_cycle(&mut self) {
        self.fbs.cycle += 1;
        self.fbs.in_step = true;
        for i in 0..self.instant_done.len() {
            let id = self.instant_done[i];
            self.fbs.done(id);
        }
        self.instant_done.clear();
    }

    /// One cycle of every axis, masters before their slaves, with the added functions'
    /// work before (external set points, multi-master inputs, phasing) and after (drive mode,
    /// position corrections) each axis. No alloc.
    pub fn step_axes(&mut self, dt: f64) {
        for k in 0..self.order.len() {
            let i = self.order[k];
            let master = self.axes[i]
                .coupling
                .map(|c| MasterState::of(&self.axes[c.master]));
            self.ext_setpoint_step(i);
            self.multi_master_step(i);
            self.phasing_step(i, dt);
            self.axes[i].step(dt, master, &mut self.fbs);
            self.extensions_step(i, dt);
        }
    }

    /// End of a cycle's work: later changes are reported in the next cycle.
    pub fn end_cycle(&mut self) {
        self.fbs.in_step = false;
    }

    /// A cancelled goal: an MC_Jog lets go of its button, a phasing FB halts the phasing, a
    /// buffered command is dropped, a running motion halts with its own dynamics (MC_Halt
    /// semantics), a settling command ends CommandAborted. Unknown id → UNKNOWN_OBJECT.
    pub fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
        let Some(inst) = self.fbs.get(id).copied() else {
            return Err(reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            ));
        };
        if inst.state.is_final() {
            return Ok(());
        }
        if matches!(inst.kind, FbKind::PhasingAbsolute | FbKind::PhasingRelative) {
            // MC_HaltPhasing with the slave's default dynamics (CommandAborted).
            self.halt_phasing_of(inst.axis, id);
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
pub fn apply_override(a: &mut Axis, pct: f64, fbs: &mut Handshake) {
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

// ---- The FB calls by concept: child modules (the helpers above are theirs too).
mod coupling;
pub mod ext_setpoint;
pub mod extensions;
mod home;
mod jog;
mod moves;
pub mod multi_master;
mod outputs;
mod parameters;
pub mod phasing;
mod power;
pub mod profile;
pub mod reply;
mod superimposed;
mod torque_control;
mod touch_probe;
