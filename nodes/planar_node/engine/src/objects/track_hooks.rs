//! The narrow interface through which the objects reach the track subsystem, only where a
//! mover's motion or state touches a track. `crate::track::TrackSystem` implements it (wired in
//! `crate::engine`); the objects never see the tracks' state.

use super::{Mover, Objects};
use crate::command::PlanarCommand;
use crate::guard::Grid;
use crate::snapshot::{OnTrackSnapshot, PlanarReply, TrackSnapshot, VirtualAxisSnapshot};
use crate::state::Timing;
use crate::types::ErrorReaction;
use motion_core::{CommandEvent, Rejection};

/// What the objects need from the track subsystem.
pub(crate) trait TrackHooks {
    /// A track command or an on-track mover command (§3.2, §3.3).
    fn command(
        &mut self,
        objects: &mut Objects,
        cmd: PlanarCommand,
    ) -> Result<PlanarReply, Rejection>;

    /// One cycle of mover `i`, which is on a track (gap control, switches, gear-in; §5.6).
    fn step_mover(
        &mut self,
        objects: &mut Objects,
        i: usize,
        dt: f64,
        grid: &mut Grid,
        cand: &mut Vec<u32>,
    );

    /// Mover `i`'s axes came to rest: joining completes, modes end.
    fn finish_idle(&mut self, objects: &mut Objects, i: usize);

    /// §5.11: Moving member tracks of mover `i`'s group block the area it would sweep.
    fn check_swept(
        &mut self,
        objects: &mut Objects,
        i: usize,
        swept: &crate::geometry::ConvexPolygon,
    ) -> Result<(), Rejection>;

    /// Mover `i` leaves its track (state change: disabled, error).
    fn detach(&mut self, objects: &mut Objects, i: usize);

    /// The part with `part_oid` moved into coordinate system `cs`: its tracks go with it (§1.6).
    fn part_moved(&mut self, part_oid: u32, cs: u32);

    /// InjectError on the named track (§1.5 simulation).
    fn inject_error(
        &mut self,
        name: &str,
        reaction: ErrorReaction,
        timing: &Timing,
        events: &mut Vec<CommandEvent>,
    ) -> Result<(), Rejection>;

    /// The on-track part of mover `m`'s snapshot (None off the tracks), in `old`'s buffers.
    /// The snapshot hooks reuse an older snapshot's memory (`Engine::snapshot_into`).
    fn mover_on_track(
        &self,
        objects: &Objects,
        m: &Mover,
        old: Option<OnTrackSnapshot>,
    ) -> Option<OnTrackSnapshot>;

    /// The name of track `k`.
    fn track_name(&self, k: usize) -> &str;

    /// The names of the tracks that are members of group `g`, in `old`'s buffers.
    fn group_tracks(&self, g: usize, old: Vec<String>) -> Vec<String>;

    /// Snapshots of the tracks and the virtual axes, in the buffers of the old ones.
    fn snapshots(
        &self,
        objects: &Objects,
        old_tracks: Vec<TrackSnapshot>,
        old_axes: Vec<VirtualAxisSnapshot>,
    ) -> (Vec<TrackSnapshot>, Vec<VirtualAxisSnapshot>);
}
