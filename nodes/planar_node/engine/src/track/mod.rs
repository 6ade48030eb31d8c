//! Tracks (xplanar.md §1.6, §2.5, §3.3, §5.4–§5.6, §5.9, §5.12): geometry, operation modes,
//! on-track motion with gap control, and networks of linked tracks.
//!
//! Module map: [`geometry`] (§5.4 segments, transitions, arc length), `gap` (§5.6.3 reach
//! intervals), `system` ([`TrackSystem`]: the tracks' own state, with the track commands,
//! operation modes and the on-track cycle; its children `membership`
//! join/leave/AdoptTrackOrientation, `ride` MoveOnTrack, `switches`, `gear_in`, `cycle` the
//! on-track cycle, `snapshots`), `params` and `static_check` (the §1.6 init parameters and
//! the static collision check).
//!
//! The track subsystem owns the tracks, the network's switches and the virtual axes. It
//! drives the movers only through [`MoverDrive`] (module `drive`: the mover records, admission
//! checks, free-movement starts for join/leave, collisions, events and ids, all listed in
//! one trait implemented by the objects); it never names `Objects`. The objects reach back
//! (`TrackHooks`, wired in `crate::engine`) only where a mover's motion touches a track: its
//! on-track cycle, coming to rest, the swept-area check, leaving a track on a state change,
//! snapshots.

mod drive;
mod system;
pub(crate) use drive::MoverDrive;
pub use system::TrackSystem;
pub(crate) mod gap;
pub mod geometry;
pub(crate) mod params;
mod static_check;

use crate::state::PlanarStateMachine;
use crate::types::{Direction, Dynamics};
use geometry::TrackGeometry;
use motion_core::trajectory::Profile1;
use serde::{Deserialize, Serialize};

/// Default gap between movers on a track \[mm\] (ST_MoveOnTrackOptions.gap, §4.2).
pub const DEFAULT_GAP: f64 = 200.0;

/// `MC_PLANAR_TRACK_OPERATION_MODE` (§2.5, §4.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum TrackOperationMode {
    /// Not connected (0).
    Invalid = 0,
    /// Not enabled / no geometry (201); unusable by movers.
    #[default]
    Uninitialized = 201,
    /// Enabled, no mover moving, joining or leaving (202).
    Standing = 202,
    /// A mover joins or leaves (203): MoveOnTrack rejected.
    Configuring = 203,
    /// A mover moves on the track (204): JoinTrack/LeaveTrack rejected.
    Moving = 204,
}

/// `ST_MoveOnTrackOptions` (§4.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MoveOnTrackOptions {
    /// Minimal arc-length distance to the mover in front \[mm\] (default 200).
    pub gap: f64,
    /// How the target is approached (default NonModulo).
    pub direction: Direction,
    /// Extra laps on a closed loop (Positive/Negative only).
    pub additional_turns: u32,
    /// Modulo tolerance window \[mm\] (not with NonModulo).
    pub modulo_tolerance: f64,
}

impl Default for MoveOnTrackOptions {
    fn default() -> Self {
        MoveOnTrackOptions {
            gap: DEFAULT_GAP,
            direction: Direction::NonModulo,
            additional_turns: 0,
            modulo_tolerance: 0.0,
        }
    }
}

/// `ST_AdoptTrackOrientationOptions` (§4.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AdoptTrackOrientationOptions {
    /// Extra full turns (Positive/Negative only).
    pub additional_turns: u32,
    /// How the heading is approached (default ShortestWay).
    pub direction: Direction,
}

impl Default for AdoptTrackOrientationOptions {
    fn default() -> Self {
        AdoptTrackOrientationOptions {
            additional_turns: 0,
            direction: Direction::ShortestWay,
        }
    }
}

/// `ST_StartFromTrackAdvancedOptions` / `ST_EndAtTrackAdvancedOptions` (§4.2, §5.12).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrackLinkAdvancedOptions {
    /// Position index of the part carrying the track the method is called on (0 = current).
    pub this_track_part_position_index: u32,
    /// Position index of the part carrying the other track (0 = current).
    pub other_track_part_position_index: u32,
    /// TRUE: the link exists only in exactly this combination of part positions.
    pub link_only_in_specified_part_positions: bool,
}

/// `MC_SYNC_DIRECTIONS` (§4.1): slave directions allowed while synchronising.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SyncDirections {
    /// Forward only (1); default.
    #[default]
    Positive = 1,
    /// Backward only (2).
    Negative = 2,
    /// Both (3).
    Both = 3,
}

/// `ST_GearInPosOnTrackWithMasterMoverOptions` (§4.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GearInPosOnTrackWithMasterMoverOptions {
    /// Minimal distance to the next mover on the track \[mm\] (default 200).
    pub gap: f64,
    /// Allowed |position difference| for `inSync` \[mm\] (default 0 → 1e-3).
    pub in_sync_tolerance_distance: f64,
    /// How the slave sync position is approached on a closed loop (default NonModulo).
    pub direction_slave_sync_position: Direction,
    /// Modulo tolerance of the slave sync position \[mm\].
    pub modulo_tolerance_slave_sync_position: f64,
    /// How the master sync position is interpreted on a closed loop (default NonModulo).
    pub direction_master_sync_position: Direction,
    /// Modulo tolerance of the master sync position \[mm\].
    pub modulo_tolerance_master_sync_position: f64,
    /// Slave directions while synchronising (default Positive).
    pub allowed_slave_sync_directions: SyncDirections,
    /// TRUE: after the master passed the sync position the slave follows its path.
    pub follow_mover: bool,
}

impl Default for GearInPosOnTrackWithMasterMoverOptions {
    fn default() -> Self {
        GearInPosOnTrackWithMasterMoverOptions {
            gap: DEFAULT_GAP,
            in_sync_tolerance_distance: 0.0,
            direction_slave_sync_position: Direction::NonModulo,
            modulo_tolerance_slave_sync_position: 0.0,
            direction_master_sync_position: Direction::NonModulo,
            modulo_tolerance_master_sync_position: 0.0,
            allowed_slave_sync_directions: SyncDirections::Positive,
            follow_mover: false,
        }
    }
}

/// `ST_GearInPosOnTrackOptions` (§4.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GearInPosOnTrackOptions {
    /// Minimal distance to the next mover on the track \[mm\] (default 200).
    pub gap: f64,
    /// Allowed |position difference| for `inSync` \[mm\] (default 0 → 1e-3).
    pub in_sync_tolerance_distance: f64,
    /// How the slave sync position is approached on a closed loop (default NonModulo).
    pub direction_slave_sync_position: Direction,
    /// Modulo tolerance of the slave sync position \[mm\].
    pub modulo_tolerance_slave_sync_position: f64,
    /// Slave directions while synchronising (default Positive).
    pub allowed_slave_sync_directions: SyncDirections,
}

impl Default for GearInPosOnTrackOptions {
    fn default() -> Self {
        GearInPosOnTrackOptions {
            gap: DEFAULT_GAP,
            in_sync_tolerance_distance: 0.0,
            direction_slave_sync_position: Direction::NonModulo,
            modulo_tolerance_slave_sync_position: 0.0,
            allowed_slave_sync_directions: SyncDirections::Positive,
        }
    }
}

/// A virtual master axis (§5.8.4): Power, MoveAbsolute, Halt.
#[derive(Clone, Debug)]
pub(crate) struct VirtualAxis {
    pub name: String,
    pub oid: u32,
    pub powered: bool,
    pub ax: crate::motion::Axis1,
    pub cmd: Option<motion_core::CmdId>,
}

/// Builds the configured virtual axes (unpowered, at 0) and their name index.
pub(crate) fn build_axes(
    cfg: &crate::config::PlanarConfig,
) -> (Vec<VirtualAxis>, std::collections::HashMap<String, usize>) {
    let axes: Vec<VirtualAxis> = cfg
        .axes
        .iter()
        .enumerate()
        .map(|(i, a)| VirtualAxis {
            name: a.name.clone(),
            oid: cfg.axis_oid(i),
            powered: false,
            ax: crate::motion::Axis1::at(0.0),
            cmd: None,
        })
        .collect();
    let idx = axes
        .iter()
        .enumerate()
        .map(|(i, a)| (a.name.clone(), i))
        .collect();
    (axes, idx)
}

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

/// MC_PlanarTrack.
#[derive(Clone, Debug)]
pub(crate) struct Track {
    pub name: String,
    pub oid: u32,
    /// Part the track is fixed to (0 = none / the only part).
    pub part_oid: u32,
    /// Coordinate system of the geometry.
    pub cs: u32,
    pub sm: PlanarStateMachine,
    pub geo: TrackGeometry,
    /// Movers on the track in track order (by s; cyclic on a closed loop).
    pub order: Vec<usize>,
    /// Linked tracks whose end is this track's start.
    pub prev: Vec<usize>,
    /// Linked tracks whose start is this track's end.
    pub next: Vec<usize>,
    /// Tracks whose links block changes of this one (itself after EndAtTrack).
    pub locked_by: Vec<usize>,
    /// Start already linked by StartFromTrack (same part).
    pub start_linked: bool,
    /// End already linked by EndAtTrack (same part).
    pub end_linked: bool,
    /// Group membership (§5.11).
    pub group: Option<usize>,
    /// The track's area when Moving (tube of half-width max mover width / 2), built when the
    /// track joins a group.
    pub tube: Vec<crate::geometry::ConvexPolygon>,
    /// Switch at the end / start (index into the track system's switches) (§5.6.4).
    pub end_switch: Option<usize>,
    pub start_switch: Option<usize>,
    /// Automatic collision range at the end / start \[mm\] (0 without a switch).
    pub range_end: f64,
    pub range_start: f64,
    /// Origin of the track's part when the geometry was defined (the geometry is stored in CS
    /// coordinates of that part position) (§1.6 tracks move with their part).
    pub geo_origin: crate::geometry::V2,
    /// Links to `next` tracks that exist only in specified part positions:
    /// (to, this part's index, other part's index) (§5.12 linkOnlyInSpecifiedPartPositions).
    pub link_only: Vec<(usize, u32, u32)>,
    /// Collision init parameters (§1.6).
    pub params: params::TrackParams,
}

/// A point where more than two track ends/starts meet (§5.6.4).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Switch {
    /// Tracks ending here.
    pub incoming: Vec<usize>,
    /// Tracks starting here.
    pub outgoing: Vec<usize>,
}

impl Track {
    /// Convex pieces covering the tube around the path (§5.11), every ≤ 20 mm.
    pub fn build_tube(&self) -> Vec<crate::geometry::ConvexPolygon> {
        let l = self.geo.length();
        let n = (l / 20.0).ceil().max(1.0) as usize;
        let h = self.params.tube_half_width();
        let at = |k: usize| {
            let p = self.geo.pose_at(l * k as f64 / n as f64);
            let t = p.tangent();
            let nrm = crate::geometry::V2::new(-t.y, t.x);
            (p.p + nrm * h, p.p - nrm * h, p.p - t * h, p.p + t * h)
        };
        (0..n)
            .map(|k| {
                let (a1, a2, a3, a4) = at(k);
                let (b1, b2, b3, b4) = at(k + 1);
                crate::geometry::ConvexPolygon::hull(&[a1, a2, a3, a4, b1, b2, b3, b4])
            })
            .collect()
    }
}

impl Track {
    pub fn length(&self) -> f64 {
        self.geo.length()
    }
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

/// What the track subsystem needs to know of a part when it builds its tracks: its OID and
/// where its current position puts its origin.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PartFrame {
    pub oid: u32,
    /// Coordinate system of the part's current position.
    pub cs: u32,
    /// The part's origin in that system.
    pub origin: crate::geometry::V2,
}

/// Builds the configured tracks (all Disabled, no geometry) and their name index; `parts` in
/// configuration order.
pub(crate) fn build_tracks(
    cfg: &crate::config::PlanarConfig,
    parts: &[PartFrame],
) -> (Vec<Track>, std::collections::HashMap<String, usize>) {
    let tracks: Vec<Track> = cfg
        .tracks
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let part = if t.part_oid != 0 {
                parts.iter().find(|p| p.oid == t.part_oid)
            } else {
                parts.first()
            };
            let cs = match part {
                Some(p) => p.cs,
                None => cfg.coordinate_systems.first().copied().unwrap_or(0),
            };
            Track {
                name: t.name.clone(),
                oid: cfg.track_oid(i),
                // With several parts the PartOID must be configured (checked at Enable).
                part_oid: if t.part_oid != 0 || parts.len() > 1 {
                    t.part_oid
                } else {
                    part.map(|p| p.oid).unwrap_or(0)
                },
                cs,
                sm: PlanarStateMachine::default(),
                geo: TrackGeometry::default(),
                order: Vec::new(),
                prev: Vec::new(),
                next: Vec::new(),
                locked_by: Vec::new(),
                start_linked: false,
                end_linked: false,
                group: None,
                tube: Vec::new(),
                end_switch: None,
                start_switch: None,
                range_end: 0.0,
                range_start: 0.0,
                geo_origin: part.map(|p| p.origin).unwrap_or_default(),
                link_only: Vec::new(),
                params: params::TrackParams::of(t),
            }
        })
        .collect();
    let idx = tracks
        .iter()
        .enumerate()
        .map(|(i, t)| (t.name.clone(), i))
        .collect();
    (tracks, idx)
}
