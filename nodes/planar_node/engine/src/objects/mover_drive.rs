//! The objects as the track subsystem sees them ([`MoverDrive`]): each method hands out a
//! record or runs the objects' own check, command or bookkeeping.

use super::*;
use crate::track::MoverDrive;
use crate::types::{DynamicConstraint, MoveCOptions, MoveToPositionOptions};

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
