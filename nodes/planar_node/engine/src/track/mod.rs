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
pub(crate) use crate::on_track::{GearIn, Master, TrackMotion, TrackTarget};
/// The track's public option and mode types live in `crate::types` (below the commands and
/// snapshots that carry them); here for `planar_engine::track::…` paths.
pub use crate::types::{
    AdoptTrackOrientationOptions, GearInPosOnTrackOptions, GearInPosOnTrackWithMasterMoverOptions,
    MoveOnTrackOptions, SyncDirections, TrackLinkAdvancedOptions, TrackOperationMode, DEFAULT_GAP,
};
pub(crate) use drive::MoverDrive;
pub use system::TrackSystem;
pub(crate) mod gap;
pub mod geometry;
pub(crate) mod params;
mod static_check;

use crate::state::PlanarStateMachine;
use geometry::TrackGeometry;

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
