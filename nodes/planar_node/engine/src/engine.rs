//! [`PlanarEngine`]: the objects ([`Objects`]) and the track subsystem ([`TrackSystem`]),
//! each with its own state, composed into the commands and the cycle's stages (xplanar.md
//! §1–§3, §5). The no-overlap guard ([`crate::guard`]) runs on every cycle.

use crate::command::PlanarCommand;
use crate::errors::error_name;
use crate::geometry::ConvexPolygon;
use crate::guard::Grid;
use crate::objects::{Mover, Objects, TrackHooks};
use crate::snapshot::{
    OnTrackSnapshot, PlanarReply, PlanarSnapshot, TrackSnapshot, VirtualAxisSnapshot,
};
use crate::state::Timing;
use crate::track::TrackSystem;
use crate::types::{ErrorReaction, PlanarObjectInfo, PositionXYC};
use motion_core::{CmdId, CommandEvent, Engine, ErrorId, Rejection, Tick};

/// The XPlanar engine: the objects and the track subsystem, each with its own state.
pub struct PlanarEngine {
    pub(crate) objects: Objects,
    pub(crate) tracks: TrackSystem,
}

impl PlanarEngine {
    /// The configured cycle time \[s\].
    pub fn cycle_time(&self) -> f64 {
        self.objects.cycle_time()
    }

    /// `objectInfo` of the last E_COLLISION (rejection or guard stop): the blocking object (§6.1).
    pub fn last_object_info(&self) -> PlanarObjectInfo {
        self.objects.last_object_info()
    }

    /// Converts a position with ReferenceId (CS OID, part OID or 0) into its coordinate
    /// system (§1.3, §1.4); the result's `reference_id` is the CS OID.
    pub fn resolve_position(&self, p: &PositionXYC) -> Result<PositionXYC, Rejection> {
        self.objects.resolve_position(p)
    }

    /// The same point in the local system of the named part (part at its current position,
    /// §1.3); `None` if the point lies in another coordinate system than the part.
    pub fn to_part_local(
        &self,
        p: &PositionXYC,
        part: &str,
    ) -> Result<Option<PositionXYC>, Rejection> {
        self.objects.to_part_local(p, part)
    }

    /// GetPositionAt without a command: the pose at `arc_length` in the track's current part
    /// position. Pure, so the shell can sample whole tracks through the runtime's read-only
    /// query path (drawing markers must not flood `~/command_status`).
    pub fn track_position_at(
        &self,
        track: &str,
        arc_length: f64,
    ) -> Result<PositionXYC, Rejection> {
        self.tracks
            .track_position_at(&self.objects, track, arc_length)
    }
}

impl Engine for PlanarEngine {
    type Command = PlanarCommand;
    type Reply = PlanarReply;
    type Snapshot = PlanarSnapshot;

    fn command(&mut self, cmd: PlanarCommand) -> Result<PlanarReply, Rejection> {
        self.objects.last_object_info = PlanarObjectInfo::default();
        self.objects.dispatch(&mut self.tracks, cmd)
    }

    /// `Halt(fb)` of every mover with its default deceleration and jerk (§4.7); a mover that
    /// cannot take it (not enabled, in error) is left as it is.
    fn fail_safe_stop(&mut self) {
        for i in 0..self.objects.movers.len() {
            let mover = self.objects.movers[i].name.clone();
            let _ = self.command(PlanarCommand::Halt {
                mover,
                constraint: crate::types::DynamicConstraint::default(),
            });
        }
    }

    fn at_rest(&self) -> bool {
        self.snapshot()
            .movers
            .iter()
            .all(|m| m.set_velo.to_array().iter().all(|v| *v == 0.0))
    }

    /// One cycle in stages: parts move (carrying their tracks), state machines, the tracks'
    /// cycle (modes, switches, gear-in), the virtual axes, then every mover's motion under
    /// the no-overlap guard (movers on a track through the track's gap control).
    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        let dt = tick.dt;
        let (objects, tracks) = (&mut self.objects, &mut self.tracks);
        objects.step_parts(tracks, dt);
        objects.step_states(tracks, dt);
        tracks.step_tracks(objects, dt);
        tracks.step_axes(objects, dt);
        objects.step_motion(tracks, dt);
        objects.time += dt;
        events.append(&mut objects.pending);
    }

    fn snapshot(&self) -> PlanarSnapshot {
        self.objects.snapshot(&self.tracks)
    }

    /// Every accepted command has an id whose events follow (instant ones end Done at once).
    fn reply_id(reply: &PlanarReply) -> Option<CmdId> {
        Some(reply.id)
    }

    fn error_text(id: ErrorId) -> String {
        error_name(id).to_string()
    }

    fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
        self.objects.cancel(&mut self.tracks, id)
    }
}

/// The objects reach the track subsystem through their trait `TrackHooks`; the tracks reach
/// the movers through theirs (`MoverDrive`, implemented by `Objects`). Wired here, where both
/// are known.
impl TrackHooks for TrackSystem {
    fn command(
        &mut self,
        objects: &mut Objects,
        cmd: PlanarCommand,
    ) -> Result<PlanarReply, Rejection> {
        self.track_command(objects, cmd)
    }

    fn step_mover(
        &mut self,
        objects: &mut Objects,
        i: usize,
        dt: f64,
        grid: &mut Grid,
        cand: &mut Vec<u32>,
    ) {
        self.step_track_mover(objects, i, dt, grid, cand);
    }

    fn finish_idle(&mut self, objects: &mut Objects, i: usize) {
        self.track_finish_idle(objects, i);
    }

    fn check_swept(
        &mut self,
        objects: &mut Objects,
        i: usize,
        swept: &ConvexPolygon,
    ) -> Result<(), Rejection> {
        self.check_moving_tracks(objects, i, swept)
    }

    fn detach(&mut self, objects: &mut Objects, i: usize) {
        self.detach_from_track(objects, i);
    }

    fn part_moved(&mut self, part_oid: u32, cs: u32) {
        TrackSystem::part_moved(self, part_oid, cs);
    }

    fn inject_error(
        &mut self,
        name: &str,
        reaction: ErrorReaction,
        timing: &Timing,
        events: &mut Vec<CommandEvent>,
    ) -> Result<(), Rejection> {
        TrackSystem::inject_error(self, name, reaction, timing, events)
    }

    fn mover_on_track(&self, objects: &Objects, m: &Mover) -> Option<OnTrackSnapshot> {
        self.on_track_snapshot(objects, m)
    }

    fn track_name(&self, k: usize) -> String {
        TrackSystem::track_name(self, k)
    }

    fn group_tracks(&self, g: usize) -> Vec<String> {
        TrackSystem::group_tracks(self, g)
    }

    fn snapshots(&self, objects: &Objects) -> (Vec<TrackSnapshot>, Vec<VirtualAxisSnapshot>) {
        (self.track_snapshots(objects), self.axis_snapshots())
    }
}
