//! The technology module: inputs, state machine (pick_and_place.md §4), controlled start (§2.3),
//! jogging (§5), homing (§6), profiles and their queue (§8), stop/halt/interrupt/abort (§9),
//! gripper control (§10), tracking modes (§11), override (§12), workpiece tracking (§14), the
//! belt contour computation (§15) and monitoring (§16).
//!
//! One cycle (`step`): pulses → belt axes and workpiece detection (§2.2, §14) → state machine
//! (`state_machine`) → motion (`motion`, planning in `planning`) → drive lag and monitoring
//! (`monitor`). Commands are screened in `commands`.

use crate::axis_limits::{pose_axis_max, AxisMax};
use crate::belt::{Belt, WorkpieceEventKind, WorkpieceState};
use crate::command::{FaultKind, PickPlaceCommand, ServiceRequest, StopInputs};
use crate::config::{PickPlaceConfig, MAX_BELTS};
use crate::error_ids as ids;
use crate::geometry::{self, ParkDirection, PathGeometry, ProfilePoints, ShapeParams, Vec3};
use crate::kinematics::{IdentityKinematics, Kinematics};
use crate::params::{CoordSystem, PathMode, ScPar};
use crate::path_run::{Drive, MovingFrame, PathRun};
use crate::snapshot::*;
use crate::state::TmState;
use motion_core::trajectory::{Limits, Profile1, State1};
use motion_core::{CmdId, CommandEvent, CommandState, Engine, ErrorId, Rejection, Tick};
use std::collections::VecDeque;

/// Velocities below this count as standstill [units/s].
const STANDSTILL_VEL: f64 = 1e-6;
/// Distance within which the TCP counts as at a park pose [units].
const PARK_TOLERANCE: f64 = 1e-3;
/// Maximum number of stored cell events between two drains.
const MAX_EVENTS: usize = 4096;
/// Iterations of the intercept prediction (§15.2).
const PREDICTION_ITERATIONS: usize = 10;
/// Convergence of the intercept prediction [units].
const PREDICTION_TOLERANCE: f64 = 0.001;

/// The FB's level inputs (§3.1).
#[derive(Clone, Debug, Default, PartialEq)]
struct Inputs {
    enable_internal_control: bool,
    enable: bool,
    reset_error: bool,
    regulator_on_all: bool,
    path_stop: bool,
    path_halt: bool,
    stop_all: bool,
    group_home_execute: bool,
    home_abs_switch: [bool; 12],
    group_enable_hw_limit: bool,
    hw_limit_pos: [bool; 18],
    hw_limit_neg: [bool; 18],
    select_axis: u8,
    jog_pos: bool,
    jog_neg: bool,
    execute: bool,
    set_target: u8,
    path_interrupt: bool,
    abort: bool,
    override_: f64,
    ack_gripper: bool,
    service: ServiceRequest,
}

/// Rising edges of this cycle.
#[derive(Clone, Copy, Debug, Default)]
struct Edges {
    reset: bool,
    home: bool,
    jog_pos: bool,
    jog_neg: bool,
    execute: bool,
    abort: bool,
    ack_gripper: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PulseKind {
    ResetError,
    Execute,
    Abort,
    AckGripper,
    GroupHome,
}

#[derive(Clone, Copy, Debug)]
struct Pulse {
    kind: PulseKind,
    id: Option<CmdId>,
    set_target: u8,
}

/// Target of a profile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    /// `lr…TargetPos` in `eTargetCoordSystem`.
    Static,
    /// Next workpiece on belt n (1 … 16).
    Belt(usize),
    /// Only the park position of belt n (lift after `SyncLimitExceeded`).
    ParkOnly(usize),
}

/// Role of a leg in the tracking modes (§11): which gripper time applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// Mode 0: `lrGripperClosingTime` at every profile end.
    External,
    /// Pick leg (close).
    Pick,
    /// Place leg (open).
    Place,
}

/// One accepted profile (execute edge or endless-mode leg).
#[derive(Clone, Debug)]
struct Job {
    id: Option<CmdId>,
    par: ScPar,
    target: Target,
    role: Role,
    set_target: u8,
    /// Endless tracking mode 1 … 4 this leg belongs to (0 = mode 0).
    mode: u8,
    /// Workpiece to serve first (re-plan of a held profile, §9.2).
    preferred_wp: Option<u64>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Leg {
    Main,
    ToPark,
}

#[derive(Clone, Debug)]
enum Phase {
    Path {
        run: Box<PathRun>,
        leg: Leg,
        belt: Option<usize>,
        workpiece: Option<u64>,
    },
    WaitPark {
        belt: usize,
        prep_left: Option<u32>,
    },
    Dwell {
        remaining: f64,
        frame: MovingFrame,
        base: [f64; 7],
        belt: usize,
        /// The reached workpiece; consumed when the dwell ends.
        workpiece: Option<u64>,
    },
    /// At a static target, waiting |lead| for a negative-lead gripper pulse (§10).
    GripperDelay,
    Done,
}

#[derive(Clone, Copy, Debug)]
struct Gripper {
    enabled: bool,
    active: bool,
    lead: f64,
    kind: GripperEvent,
    pulsed: bool,
    /// Time left until a negative-lead pulse after the profile end [s].
    after: Option<f64>,
}

#[derive(Clone, Debug)]
struct Running {
    job: Job,
    phase: Phase,
    gripper: Gripper,
    /// The held path must be re-planned from the current pose on resume (§9.2 coupled stop, §9.3).
    replan: bool,
    active_emitted: bool,
    hold_pose: [f64; 7],
}

#[derive(Clone, Copy, Debug)]
struct JogRun {
    axis: u8,
    positive: bool,
    profile: Profile1,
    t: f64,
    stopping: bool,
    /// State to return to when both jog inputs are FALSE.
    return_to_stop: bool,
    /// Jog dynamics latched at the jog start (§5: changes during a jog have no effect).
    limits: Limits,
}

#[derive(Clone, Copy, Debug)]
struct AxisSearch {
    profile: Profile1,
    t: f64,
    start: f64,
    found: bool,
}

#[derive(Clone, Debug)]
struct HomingRun {
    id: Option<CmdId>,
    stage: u8,
    axes: Vec<usize>,
    timer: f64,
    search: Vec<Option<AxisSearch>>,
}

#[derive(Clone, Copy, Debug)]
struct ServiceRun {
    axis: u8,
    profile: Profile1,
    t: f64,
}

#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)] // one per engine; boxing would allocate in the cycle
enum Motion {
    /// Pose constant.
    Still,
    /// Following a belt frame after a belt target (§15.4 proposal): pose = base + Δ.
    Bound {
        frame: MovingFrame,
        base: [f64; 7],
        wp_x0: f64,
        wp_s0: f64,
    },
    /// Pose from `running`.
    Running,
    /// Individual axis stops of the 7 pose axes (xStopALL, limits, errors, coupled stops).
    AxisStop {
        profiles: [Profile1; 7],
        t: f64,
    },
    Jog(JogRun),
    Homing(Box<HomingRun>),
    Service(ServiceRun),
}

#[derive(Clone, Debug)]
enum Prep {
    New(Box<Job>),
    Resume,
}

#[derive(Clone, Copy, Debug, Default)]
struct SimDetect {
    position: [f64; 6],
    delay: u32,
}

/// The Track Pick & Place technology module with its simulated axis group and belts.
#[derive(Debug)]
pub struct PickPlaceEngine {
    cfg: PickPlaceConfig,
    kin: Box<dyn Kinematics>,
    par: ScPar,
    inputs: Inputs,
    prev: Inputs,
    pulses: VecDeque<Pulse>,
    current_pulse_ids: [Option<CmdId>; 5],
    next_cmd: u64,
    belts: Vec<Belt>,
    sim_detect: Vec<VecDeque<SimDetect>>,
    sim_detect_active: Vec<Option<(SimDetect, u32)>>,
    next_wp_id: u64,
    state: TmState,
    pose: [f64; 7],
    /// Actual pose of the drives: = set-point, or behind it by the optional lag (§2.1).
    actual: [f64; 7],
    prev_actual: [f64; 7],
    prev_pose: [f64; 7],
    vel: [f64; 7],
    acc: [f64; 7],
    motion: Motion,
    running: Option<Box<Running>>,
    queue: VecDeque<Job>,
    prep: Option<(u32, Prep)>,
    append_prep: Option<(u32, Job)>,
    path_hold: bool,
    abort_requested: bool,
    /// A new `eTrackingMode` selected by an execute edge while a loop runs: (mode, its id).
    next_mode: Option<(u8, Option<CmdId>)>,
    error: ErrorId,
    warning: ErrorId,
    axis_errors: [u32; 18],
    stop_all_sync: bool,
    pending_faults: Vec<(u8, FaultKind)>,
    homed: [bool; 7],
    done: bool,
    in_target: bool,
    in_position_target: Option<[f64; 7]>,
    in_window_time: f64,
    at_park: bool,
    pulse_gripper: bool,
    gripper_closed: bool,
    applied_override: f64,
    precalc_time: f64,
    sw_active: [bool; 18],
    /// The profile was started by the preparation of this cycle: motion begins next cycle (T16).
    start_next_cycle: bool,
    /// `eSetTargetOut`: the target being approached, or the one reached while `xInTarget`.
    target_out: u8,
    /// `eSetTarget` of the last execute edge.
    latched_set_target: u8,
    /// Internal Control via the HMI is active (`xInternalControlActive`).
    internal_control: bool,
    /// `Engine::cancel` of the running/held profile: halt, then abort at standstill (§18).
    cancel_request: Option<CmdId>,
    /// The current STOP was caused by a cancel: discard the path at standstill.
    cancel_stop: bool,
    /// (held profile's id, resume edge's id): the resume edge completes with the held profile.
    resume_ids: Vec<(CmdId, CmdId)>,
    /// Command events produced outside `step` (cancel), flushed in the next step.
    deferred_events: Vec<CommandEvent>,
    /// Workpiece attached to the gripper (belt, id), modes 1 … 4 (§10).
    held_workpiece: Option<(usize, u64)>,
    /// Cycle time of the last step [s] (the configured `cycle_time_s` before the first).
    last_dt: f64,
    cycle: u64,
    time: f64,
    events: Vec<CellEvent>,
    /// AXIS_REF maxima per pose axis (§7.8 (2)) and whether any is set.
    axis_max: [AxisMax; 7],
    axis_limited: bool,
    /// The path/belt set-point of the last cycle before the clamp (its velocity is the target
    /// velocity of a lagging axis).
    prev_nominal: [f64; 7],
    /// Scratch buffers reused every cycle (no allocation in steady state).
    scratch_wev: Vec<(WorkpieceEventKind, u64)>,
    scratch_ids: Vec<u64>,
}

fn axis_name(idx: u8) -> &'static str {
    crate::config::AXIS_NAMES
        .get((idx as usize).wrapping_sub(1))
        .copied()
        .unwrap_or("?")
}

/// Axis index (1 … 18) of pose component q (X … C, Aux1).
fn pose_axis_index(q: usize) -> usize {
    if q < 6 {
        q + 1
    } else {
        13
    }
}

fn norm_angle_near(c: f64, reference: f64) -> f64 {
    // Into (reference − 180, reference + 180] so C takes the shorter way (§7.1).
    let mut x = c;
    while x <= reference - 180.0 {
        x += 360.0;
    }
    while x > reference + 180.0 {
        x -= 360.0;
    }
    x
}

fn v3(p: &[f64; 7]) -> Vec3 {
    Vec3::new(p[0], p[1], p[2])
}

mod axis_ref;
mod commands;
mod monitor;
mod motion;
mod planning;
mod state_machine;

impl PickPlaceEngine {
    /// Builds the cell from a validated configuration.
    pub fn new(cfg: PickPlaceConfig) -> Result<Self, Rejection> {
        cfg.validate()?;
        let mut pose = [0.0; 7];
        for (q, p) in pose.iter_mut().enumerate() {
            *p = cfg.axis(pose_axis_index(q)).initial_position;
        }
        if let Some(t) = cfg.initial_tcp {
            pose = t;
        }
        let mut belts = vec![Belt::default(); MAX_BELTS];
        for (name, b) in &cfg.belts {
            if let Some(i) = crate::config::belt_index(name) {
                let belt = &mut belts[i - 1];
                belt.par = b.params;
                belt.axis.position = b.initial_position;
                belt.axis.velocity = b.initial_velocity;
                belt.axis.target_velocity = b.initial_velocity;
            }
        }
        let mut homed = [true; 7];
        for (h, flag) in homed.iter_mut().enumerate() {
            *flag = cfg.axis(7 + h).initially_homed;
        }
        let inputs = Inputs {
            override_: 1.0,
            ..Inputs::default()
        };
        let cfg_cycle = cfg.cycle_time_s;
        let axis_max = pose_axis_max(&cfg);
        Ok(PickPlaceEngine {
            axis_max,
            axis_limited: axis_max.iter().any(|m| !m.is_none()),
            prev_nominal: pose,
            par: cfg.params.clone(),
            cfg,
            kin: Box::new(IdentityKinematics),
            prev: inputs.clone(),
            inputs,
            pulses: VecDeque::new(),
            current_pulse_ids: [None; 5],
            next_cmd: 0,
            belts,
            sim_detect: vec![VecDeque::new(); MAX_BELTS],
            sim_detect_active: vec![None; MAX_BELTS],
            next_wp_id: 0,
            state: TmState::Disabled,
            pose,
            actual: pose,
            prev_actual: pose,
            prev_pose: pose,
            vel: [0.0; 7],
            acc: [0.0; 7],
            motion: Motion::Still,
            running: None,
            queue: VecDeque::new(),
            prep: None,
            append_prep: None,
            path_hold: false,
            abort_requested: false,
            next_mode: None,
            error: ErrorId::NONE,
            warning: ErrorId::NONE,
            axis_errors: [0; 18],
            stop_all_sync: false,
            pending_faults: Vec::new(),
            homed,
            done: false,
            in_target: false,
            in_position_target: None,
            in_window_time: 0.0,
            at_park: false,
            pulse_gripper: false,
            gripper_closed: false,
            applied_override: 1.0,
            precalc_time: 0.0,
            sw_active: [false; 18],
            start_next_cycle: false,
            target_out: 0,
            latched_set_target: 0,
            internal_control: false,
            held_workpiece: None,
            cancel_request: None,
            cancel_stop: false,
            resume_ids: Vec::new(),
            deferred_events: Vec::new(),
            last_dt: cfg_cycle,
            cycle: 0,
            time: 0.0,
            events: Vec::with_capacity(256),
            scratch_wev: Vec::with_capacity(8),
            scratch_ids: Vec::with_capacity(32),
        })
    }

    /// Replaces the kinematics (default: identity, §2.1).
    pub fn with_kinematics(mut self, kin: Box<dyn Kinematics>) -> Self {
        self.kin = kin;
        self
    }

    /// The current `scPar` (`~/get_params`).
    pub fn params(&self) -> &ScPar {
        &self.par
    }

    /// `ascConveyorBeltPar[belt]` (belt 1 … 16).
    pub fn belt_params(&self, belt: u8) -> Option<crate::params::ConveyorBeltPar> {
        self.belts
            .get((belt as usize).wrapping_sub(1))
            .map(|b| b.par)
    }

    /// The configuration the engine was built with.
    pub fn config(&self) -> &PickPlaceConfig {
        &self.cfg
    }

    /// The TCP path (X, Y, Z in MCS) of the running profile's current leg, `samples + 1`
    /// points evenly spaced in σ, with the belt frames where they are now (§15.1); empty when
    /// no path runs. For visualisation (`~/markers`); allocates, call at the state rate.
    pub fn active_path(&self, samples: usize) -> Vec<[f64; 3]> {
        let Some(Phase::Path { run, .. }) = self.running.as_deref().map(|r| &r.phase) else {
            return Vec::new();
        };
        let n = samples.max(1);
        let delta = |f: &Option<MovingFrame>| {
            f.map(|f| f.delta(self.belt_s(f.belt)))
                .unwrap_or_else(Vec3::zeros)
        };
        let (da, db) = (delta(&run.frame_a), delta(&run.frame_b));
        (0..=n)
            .map(|i| {
                let s = run.geom.length * i as f64 / n as f64;
                let k = run.geom.coupling(s);
                let p = run.geom.position(s) + da * (1.0 - k) + db * k;
                [p.x, p.y, p.z]
            })
            .collect()
    }

    /// Single-cycle events since the last call (`~/events`), oldest first.
    pub fn drain_events(&mut self) -> Vec<CellEvent> {
        std::mem::take(&mut self.events)
    }

    /// Current state.
    pub fn state(&self) -> TmState {
        self.state
    }

    fn push_event(&mut self, e: CellEvent) {
        if self.events.len() < MAX_EVENTS {
            self.events.push(e);
        }
    }

    fn new_id(&mut self) -> CmdId {
        self.next_cmd += 1;
        CmdId(self.next_cmd)
    }

    fn belt_checked(belt: u8) -> Result<usize, Rejection> {
        if (1..=MAX_BELTS as u8).contains(&belt) {
            Ok(belt as usize)
        } else {
            Err(Rejection::unknown_object("belt", &belt.to_string()))
        }
    }

    fn finite(field: &str, v: f64) -> Result<(), Rejection> {
        if v.is_finite() {
            Ok(())
        } else {
            Err(Rejection::not_finite("pickplace", field, v))
        }
    }

    /// Value of axis index 1 … 13 (§0 map) at the current set-point.
    fn axis_value(&self, idx: usize) -> f64 {
        match idx {
            1..=6 => self.pose[idx - 1],
            7..=12 => {
                let c = [
                    self.pose[0],
                    self.pose[1],
                    self.pose[2],
                    self.pose[3],
                    self.pose[4],
                    self.pose[5],
                ];
                self.kin.inverse(&c)[idx - 7]
            }
            13 => self.pose[6],
            _ => 0.0,
        }
    }

    fn set_axis_value(&mut self, idx: usize, v: f64) {
        match idx {
            1..=6 => self.pose[idx - 1] = v,
            7..=12 => {
                let c = [
                    self.pose[0],
                    self.pose[1],
                    self.pose[2],
                    self.pose[3],
                    self.pose[4],
                    self.pose[5],
                ];
                let mut j = self.kin.inverse(&c);
                j[idx - 7] = v;
                let c = self.kin.forward(&j);
                self.pose[..6].copy_from_slice(&c);
            }
            13 => self.pose[6] = v,
            _ => {}
        }
    }

    /// Actual value of axis index 1 … 13 (drive side, §2.1).
    fn actual_axis_value(&self, idx: usize) -> f64 {
        Self::value_of(&*self.kin, &self.actual, idx)
    }

    fn prev_actual_axis_value(&self, idx: usize) -> f64 {
        Self::value_of(&*self.kin, &self.prev_actual, idx)
    }

    fn value_of(kin: &dyn Kinematics, p: &[f64; 7], idx: usize) -> f64 {
        match idx {
            1..=6 => p[idx - 1],
            7..=12 => kin.inverse(&[p[0], p[1], p[2], p[3], p[4], p[5]])[idx - 7],
            13 => p[6],
            _ => 0.0,
        }
    }

    /// First-order lag of the drives towards the set-point (ideal when the time constant is 0).
    fn update_actual(&mut self, dt: f64) {
        self.prev_actual = self.actual;
        for q in 0..7 {
            let tau = self.cfg.axis(pose_axis_index(q)).lag_time_constant;
            self.actual[q] = if tau > 0.0 {
                self.actual[q] + (self.pose[q] - self.actual[q]) * (1.0 - (-dt / tau).exp())
            } else {
                self.pose[q]
            };
        }
    }

    fn axis_velocity(&self, idx: usize) -> f64 {
        match idx {
            1..=6 => self.vel[idx - 1],
            7..=12 => {
                let a = [
                    self.pose[0],
                    self.pose[1],
                    self.pose[2],
                    self.pose[3],
                    self.pose[4],
                    self.pose[5],
                ];
                let b = [
                    self.prev_pose[0],
                    self.prev_pose[1],
                    self.prev_pose[2],
                    self.prev_pose[3],
                    self.prev_pose[4],
                    self.prev_pose[5],
                ];
                let (ja, jb) = (self.kin.inverse(&a), self.kin.inverse(&b));
                let dt = self.last_dt;
                (ja[idx - 7] - jb[idx - 7]) / dt
            }
            13 => self.vel[6],
            _ => 0.0,
        }
    }

    fn belt_s(&self, belt: usize) -> f64 {
        self.belts[belt - 1].axis.position
    }

    fn set_warning(&mut self, id: ErrorId) {
        self.warning = id;
        let e = CellEvent::Diagnostic {
            cycle: self.cycle,
            id: id.0,
            error: false,
        };
        self.push_event(e);
    }

    fn set_state(&mut self, to: TmState) {
        if self.state != to {
            let e = CellEvent::StateChanged {
                cycle: self.cycle,
                from: self.state,
                to,
            };
            self.push_event(e);
            self.state = to;
        }
    }

    fn emit(&mut self, events: &mut Vec<CommandEvent>, id: Option<CmdId>, state: CommandState) {
        if let Some(id) = id {
            events.push(CommandEvent { id, state });
            if !self.resume_ids.is_empty() {
                // Resume edges of a held profile that already had an id end with it.
                for &(held, resume) in &self.resume_ids {
                    if held == id {
                        events.push(CommandEvent { id: resume, state });
                    }
                }
                if state.is_final() {
                    self.resume_ids.retain(|&(held, _)| held != id);
                }
            }
        }
    }

    /// Discards the running profile, the queue and the preparations, reporting `state` for each.
    fn discard_all(&mut self, events: &mut Vec<CommandEvent>, state: CommandState) {
        if let Some(r) = self.running.take() {
            self.release_reservation(&r);
            self.emit(events, r.job.id, state);
        }
        while let Some(j) = self.queue.pop_front() {
            self.emit(events, j.id, state);
        }
        if let Some((_, Prep::New(j))) = self.prep.take() {
            self.emit(events, j.id, state);
        }
        if let Some((_, j)) = self.append_prep.take() {
            self.emit(events, j.id, state);
        }
        self.path_hold = false;
        self.abort_requested = false;
        self.next_mode = None;
    }

    fn release_reservation(&mut self, r: &Running) {
        let (b, id) = match &r.phase {
            Phase::Path {
                belt: Some(b),
                workpiece: Some(id),
                leg: Leg::Main,
                ..
            } => (*b, *id),
            Phase::Dwell {
                belt,
                workpiece: Some(id),
                ..
            } if *belt > 0 => (*belt, *id),
            _ => return,
        };
        if let Some(w) = self.belts[b - 1].workpieces.iter_mut().find(|w| w.id == id) {
            w.reserved = false;
        }
    }

    /// T3: error → ERROR, individual axis stop with `alrStopDec`, queue discarded.
    fn raise_error(&mut self, id: ErrorId, axis: Option<usize>, events: &mut Vec<CommandEvent>) {
        if self.state == TmState::Error && !self.error.is_none() {
            return;
        }
        self.error = id;
        if let Some(a) = axis {
            self.axis_errors[a - 1] = id.0;
        }
        let e = CellEvent::Diagnostic {
            cycle: self.cycle,
            id: id.0,
            error: true,
        };
        self.push_event(e);
        if let Motion::Homing(h) = &self.motion {
            let hid = h.id;
            self.emit(events, hid, CommandState::Error(id));
        }
        self.discard_all(events, CommandState::Error(id));
        self.done = false;
        self.start_axis_stop(None);
        self.set_state(TmState::Error);
    }

    fn step_cycle(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        let dt = tick.dt;
        self.last_dt = dt;
        events.append(&mut self.deferred_events);
        self.cycle = tick.index;
        self.time = tick.time() + dt;
        self.pulse_gripper = false;
        self.apply_pulses();
        self.sim_detection();
        let e = self.edges();
        // Belts move first, independent of the TM state (§2.2).
        for b in &mut self.belts {
            b.axis.step(dt);
        }
        for n in 1..=MAX_BELTS {
            let mut wev = std::mem::take(&mut self.scratch_wev);
            wev.clear();
            let max = self.belts[n - 1].detect(&mut self.next_wp_id, &mut wev);
            for &(kind, id) in &wev {
                self.push_event(CellEvent::Workpiece {
                    cycle: self.cycle,
                    belt: n as u8,
                    id,
                    kind,
                });
            }
            self.scratch_wev = wev;
            if max {
                self.set_warning(ids::MAX_WORKPIECES);
            }
            self.delete_missed_on(n);
        }
        self.prev_pose = self.pose;
        self.transitions(&e, events);
        self.advance_motion(dt, &e, events);
        let prev_vel = self.vel;
        for q in 0..7 {
            self.vel[q] = (self.pose[q] - self.prev_pose[q]) / dt;
            self.acc[q] = (self.vel[q] - prev_vel[q]) / dt;
        }
        if let Motion::AxisStop { profiles, t } = &self.motion {
            // Exact states for a possible follow-up stop.
            for q in 0..7 {
                let s = profiles[q].at(*t);
                self.vel[q] = s.vel;
                self.acc[q] = s.acc;
            }
        }
        if self.pose.iter().any(|x| !x.is_finite()) {
            // Quarantine: never publish a non-finite set-point; hold the last one and stop.
            self.pose = self.prev_pose;
            self.motion = Motion::Still;
            self.vel = [0.0; 7];
            self.acc = [0.0; 7];
            self.raise_error(ErrorId::NOT_FINITE, None, events);
            self.motion = Motion::Still;
        }
        self.update_actual(dt);
        self.monitor(events);
        // Tolerance window for xInPosition (§7.10): actual = set-point in the ideal drive. The
        // window is watched against the static target of the running profile, so the dwell may
        // start before the set-point arrives.
        let window_target =
            self.in_position_target
                .or_else(|| match self.running.as_deref().map(|r| &r.phase) {
                    Some(Phase::Path {
                        run,
                        leg: Leg::Main,
                        belt: None,
                        ..
                    }) => Some(run.end_pose),
                    _ => None,
                });
        if let Some(t) = window_target {
            let d = (v3(&self.actual) - v3(&t)).norm();
            if d <= self.par.pos_in_window_size {
                self.in_window_time += dt;
            } else {
                self.in_window_time = 0.0;
            }
        } else {
            self.in_window_time = 0.0;
        }
        self.prev = self.inputs.clone();
    }
}
