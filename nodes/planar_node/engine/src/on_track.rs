//! A mover's state on a track (SETONTRACK, xplanar.md §4.4, §5.6, §5.8): the part of the
//! mover record that the track subsystem drives and the objects read (rest, Halt, Stop,
//! Disable). Plain data with its own small rules; below both `objects` and `track`.

use crate::types::{Dynamics, SyncDirections, DEFAULT_GAP};
use motion_core::trajectory::Profile1;

/// The master of a gear-in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Master {
    /// A planar mover (position along its route).
    Mover(usize),
    /// A virtual axis.
    Axis(usize),
}

/// A running gear-in of a slave on its trail (§5.8): `s*(t) = s_sync + (m(t) − m_sync)`.
#[derive(Clone, Debug)]
pub(crate) struct GearIn {
    pub master: Master,
    /// Master route coordinate of the start of the master sync track.
    pub master_origin: f64,
    pub m_sync: f64,
    /// Slave sync position (slave route coordinate).
    pub s_sync: f64,
    /// Trail bounds (slave route coordinates).
    pub lo: f64,
    pub hi: f64,
    pub dyn_: Dynamics,
    pub tol: f64,
    pub allowed: SyncDirections,
    pub follow: bool,
    pub in_sync: bool,
    pub ever_synced: bool,
    /// On the law and following the master's own motion (direct coupling, §5.8.1).
    pub coupled: bool,
    /// Braking to the trail boundary (ends with E_TRACK_BOUNDARY_REACHED).
    pub boundary: bool,
}

/// What the mover is doing on its track (§5.6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum TrackTarget {
    /// No command (standing, or stopping after Halt / an error).
    None,
    /// MoveOnTrack to this route coordinate.
    Position(f64),
}

/// A mover's on-track state (SETONTRACK, §4.4). Positions are route coordinates `r`:
/// on a closed loop the unwrapped arc length; on open tracks the arc length on the track
/// the route started from (`s = r - base` on the current track).
#[derive(Clone, Debug)]
pub(crate) struct TrackMotion {
    pub track: usize,
    pub base: f64,
    pub r: f64,
    pub v: f64,
    pub a: f64,
    pub plan: Option<(Profile1, f64)>,
    /// Dynamics of the running plan.
    pub plan_dyn: Dynamics,
    /// (deceleration, jerk) with which the current state was verified against the gap.
    pub safe: (f64, f64),
    /// Following a committed stop (no gap checks needed: the reach only shrinks).
    pub braking: bool,
    pub target: TrackTarget,
    /// Dynamics of the MoveOnTrack command (re-plans after waiting use them).
    pub cmd_dyn: Dynamics,
    pub gap: f64,
    /// Tracks still to pass, in order (cross-track MoveOnTrack, §5.6.5).
    pub route: Vec<usize>,
    /// Cycles since the last re-plan while gap-limited.
    pub since_replan: u32,
    /// The plan ends short of the target because of the gap.
    pub limited: bool,
    /// Index in `Track::order`.
    pub slot: usize,
    /// Dependent C: c = heading + c_off \[deg\] (§5.9).
    pub c_off: f64,
    /// AdoptTrackOrientation running: C becomes dependent when it ends on the heading.
    pub adopt: bool,
    /// Gear-in on a master mover running (§5.8).
    pub gear: Option<GearIn>,
}

impl TrackMotion {
    pub fn new(track: usize, s: f64, dyn_: Dynamics) -> Self {
        TrackMotion {
            track,
            base: 0.0,
            r: s,
            v: 0.0,
            a: 0.0,
            plan: None,
            plan_dyn: dyn_,
            safe: (dyn_.deceleration, dyn_.jerk),
            braking: false,
            target: TrackTarget::None,
            cmd_dyn: dyn_,
            gap: DEFAULT_GAP,
            route: Vec::new(),
            since_replan: 0,
            limited: false,
            slot: 0,
            c_off: 0.0,
            adopt: false,
            gear: None,
        }
    }

    /// Arc length on the current track.
    pub fn s(&self) -> f64 {
        self.r - self.base
    }

    pub fn state(&self) -> motion_core::trajectory::State1 {
        motion_core::trajectory::State1 {
            pos: self.r,
            vel: self.v,
            acc: self.a,
        }
    }

    /// A plan or a pending target keeps the mover (and its tracks) Moving.
    pub fn active(&self) -> bool {
        self.plan.is_some()
            || self.target != TrackTarget::None
            || self.v != 0.0
            || self.gear.is_some()
    }

    /// Stops along the track with `d` (Halt, Disable, QuickStop): a committed stop.
    pub fn plan_stop(&mut self, d: &Dynamics) {
        self.target = TrackTarget::None;
        self.gear = None;
        self.route.clear();
        self.limited = false;
        if self.v == 0.0 && self.a == 0.0 {
            self.plan = None;
            return;
        }
        if let Ok(p) = Profile1::stopping(self.state(), &d.limits()) {
            self.plan = Some((p, 0.0));
            self.plan_dyn = *d;
            self.braking = false;
        }
    }

    /// Freezes the motion (Abort reaction).
    pub fn freeze(&mut self) {
        self.plan = None;
        self.v = 0.0;
        self.a = 0.0;
        self.target = TrackTarget::None;
        self.gear = None;
        self.route.clear();
        self.braking = false;
        self.limited = false;
    }
}
