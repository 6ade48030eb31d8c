//! The two layers wired, the one place that knows both: the objects reach the track subsystem
//! through their trait `TrackHooks` (implemented here by `TrackSystem`); the tracks reach the
//! movers through theirs, `MoverDrive` (implemented here by `Objects`: each method hands out a
//! record or runs the objects' own check, command or bookkeeping).

use crate::admission::CommandKind;
use crate::command::PlanarCommand;
use crate::geometry::{ConvexPolygon, V2};
use crate::guard::Grid;
use crate::objects::{Environment, Group, Mover, Objects, Part, TrackHooks};
use crate::snapshot::{OnTrackSnapshot, PlanarReply, TrackSnapshot, VirtualAxisSnapshot};
use crate::state::Timing;
use crate::track::{MoverDrive, TrackSystem};
use crate::types::{
    DynamicConstraint, ErrorReaction, MoveCOptions, MoveToPositionOptions, PlanarObjectInfo,
    PositionXYC,
};
use motion_core::{CmdId, CommandEvent, Rejection};

impl MoverDrive for Objects {
    fn movers(&self) -> &[Mover] {
        &self.movers
    }

    fn mover_mut(&mut self, i: usize) -> &mut Mover {
        &mut self.movers[i]
    }

    fn mover_and_events(&mut self, i: usize) -> (&mut Mover, &mut Vec<CommandEvent>) {
        (&mut self.movers[i], &mut self.pending)
    }

    fn mover(&self, name: &str) -> Result<usize, Rejection> {
        Objects::mover(self, name)
    }

    fn group(&self, name: &str) -> Result<usize, Rejection> {
        Objects::group(self, name)
    }

    fn parts(&self) -> &[Part] {
        &self.parts
    }

    fn groups(&self) -> &[Group] {
        &self.groups
    }

    fn environment(&self) -> &Environment {
        &self.env
    }

    fn coordinate_system_count(&self) -> usize {
        self.coordinate_systems.len()
    }

    fn area_tiles(&self, cs: u32) -> Vec<V2> {
        Objects::area_tiles(self, cs)
    }

    fn resolve(
        &self,
        who: &str,
        x: f64,
        y: f64,
        reference_id: u32,
    ) -> Result<(u32, V2), Rejection> {
        Objects::resolve(self, who, x, y, reference_id)
    }

    fn timing(&self) -> Timing {
        self.timing
    }

    fn new_id(&mut self) -> CmdId {
        Objects::new_id(self)
    }

    fn events(&mut self) -> &mut Vec<CommandEvent> {
        &mut self.pending
    }

    fn done_now(&mut self) -> Result<PlanarReply, Rejection> {
        Objects::done_now(self)
    }

    fn require_enabled(&self, i: usize, what: &str) -> Result<(), Rejection> {
        Objects::require_enabled(self, i, what)
    }

    fn require_mode(&self, i: usize, kind: CommandKind, what: &str) -> Result<(), Rejection> {
        Objects::require_mode(self, i, kind, what)
    }

    fn require_group_ready(&self, i: usize) -> Result<(), Rejection> {
        Objects::require_group_ready(self, i)
    }

    fn collision(&mut self, who: &str, info: PlanarObjectInfo, name: &str) -> Rejection {
        Objects::collision(self, who, info, name)
    }

    fn mover_collision(&mut self, who: &str, j: usize) -> Rejection {
        Objects::mover_collision(self, who, j)
    }

    fn set_blocking_object(&mut self, info: PlanarObjectInfo) {
        self.last_object_info = info;
    }

    fn reservation(&self, j: usize) -> ConvexPolygon {
        Objects::reservation(self, j)
    }

    fn guard_full(&self) -> bool {
        self.guard_full
    }

    fn move_to_position(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        target: PositionXYC,
        constraint: DynamicConstraint,
        options: MoveToPositionOptions,
    ) -> Result<PlanarReply, Rejection> {
        Objects::move_to_position(self, tracks, i, target, constraint, options)
    }

    fn move_c(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        target: f64,
        constraint: DynamicConstraint,
        options: MoveCOptions,
    ) -> Result<PlanarReply, Rejection> {
        Objects::move_c(self, tracks, i, target, constraint, options)
    }

    fn finish_idle(&mut self, tracks: &mut dyn TrackHooks, i: usize) {
        Objects::finish_idle(self, tracks, i)
    }
}

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

    fn mover_on_track(
        &self,
        objects: &Objects,
        m: &Mover,
        old: Option<OnTrackSnapshot>,
    ) -> Option<OnTrackSnapshot> {
        self.on_track_snapshot(objects, m, old)
    }

    fn track_name(&self, k: usize) -> &str {
        TrackSystem::track_name(self, k)
    }

    fn group_tracks(&self, g: usize, old: Vec<String>) -> Vec<String> {
        TrackSystem::group_tracks(self, g, old)
    }

    fn snapshots(
        &self,
        objects: &Objects,
        old_tracks: Vec<TrackSnapshot>,
        old_axes: Vec<VirtualAxisSnapshot>,
    ) -> (Vec<TrackSnapshot>, Vec<VirtualAxisSnapshot>) {
        (
            self.track_snapshots(objects, old_tracks),
            self.axis_snapshots(old_axes),
        )
    }
}
