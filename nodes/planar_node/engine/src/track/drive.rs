//! [`MoverDrive`]: everything the track subsystem may do to the movers it drives, in one list.
//! The track code compiles against this trait and the object records only; it does not see
//! the objects' indices, guard grid, part transits or external set-point sessions.
//! `crate::objects::Objects` implements it (`objects/mover_drive.rs`).

pub(crate) use crate::objects::{end, ev, started, traj_err, Environment, Group, Mover, Part};

use crate::admission::CommandKind;
use crate::geometry::{ConvexPolygon, V2};
use crate::objects::TrackHooks;
use crate::snapshot::PlanarReply;
use crate::state::Timing;
use crate::types::{
    DynamicConstraint, MoveCOptions, MoveToPositionOptions, PlanarObjectInfo, PositionXYC,
};
use motion_core::{CmdId, CommandEvent, Rejection};

/// What the track subsystem needs from the objects (xplanar.md §3.2, §5.6–§5.11).
pub(crate) trait MoverDrive {
    // ---------------------------------------------------------------- records
    /// The movers, indexed as everywhere in the engine.
    fn movers(&self) -> &[Mover];
    fn mover_mut(&mut self, i: usize) -> &mut Mover;
    /// Mover `i` and the command events of this cycle, borrowed together.
    fn mover_and_events(&mut self, i: usize) -> (&mut Mover, &mut Vec<CommandEvent>);
    /// The index of the named mover (unknown names: UNKNOWN_OBJECT).
    fn mover(&self, name: &str) -> Result<usize, Rejection>;
    /// The index of the named group (unknown names: UNKNOWN_OBJECT).
    fn group(&self, name: &str) -> Result<usize, Rejection>;
    fn parts(&self) -> &[Part];
    fn groups(&self) -> &[Group];
    fn environment(&self) -> &Environment;
    fn coordinate_system_count(&self) -> usize;
    /// Stator tiles of a coordinate system (empty = unbounded plane).
    fn area_tiles(&self, cs: u32) -> Vec<V2>;
    /// Resolves (x, y, ReferenceId) to (coordinate system, point in it) (§1.3, §1.4).
    fn resolve(&self, who: &str, x: f64, y: f64, reference_id: u32)
        -> Result<(u32, V2), Rejection>;

    // ---------------------------------------------------------------- commands and events
    fn timing(&self) -> Timing;
    fn new_id(&mut self) -> CmdId;
    /// The command events reported in the next cycle.
    fn events(&mut self) -> &mut Vec<CommandEvent>;
    /// A command that is done as it is accepted.
    fn done_now(&mut self) -> Result<PlanarReply, Rejection>;

    // ---------------------------------------------------------------- admission
    fn require_enabled(&self, i: usize, what: &str) -> Result<(), Rejection>;
    fn require_mode(&self, i: usize, kind: CommandKind, what: &str) -> Result<(), Rejection>;
    fn require_group_ready(&self, i: usize) -> Result<(), Rejection>;

    // ---------------------------------------------------------------- collisions (§5.11, §6.1)
    /// E_COLLISION with the blocking object, remembered as `objectInfo`.
    fn collision(&mut self, who: &str, info: PlanarObjectInfo, name: &str) -> Rejection;
    /// E_COLLISION with mover `j` as the blocking object.
    fn mover_collision(&mut self, who: &str, j: usize) -> Rejection;
    /// Remembers the blocking object of a guard stop (`objectInfo`).
    fn set_blocking_object(&mut self, info: PlanarObjectInfo);
    /// The area mover `j` reserves in its group.
    fn reservation(&self, j: usize) -> ConvexPolygon;
    /// False while every mover is on one track (the guard grid is not filled).
    fn guard_full(&self) -> bool;

    // ---------------------------------------------------------------- free motion (§3.2)
    /// MoveToPosition of mover `i` (joining and leaving a track drive it off or onto one).
    fn move_to_position(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        target: PositionXYC,
        constraint: DynamicConstraint,
        options: MoveToPositionOptions,
    ) -> Result<PlanarReply, Rejection>;
    /// MoveC of mover `i` (AdoptTrackOrientation).
    fn move_c(
        &mut self,
        tracks: &mut dyn TrackHooks,
        i: usize,
        target: f64,
        constraint: DynamicConstraint,
        options: MoveCOptions,
    ) -> Result<PlanarReply, Rejection>;
    /// Mover `i`'s axes may have come to rest: the objects' bookkeeping (Halt done, modes end).
    fn finish_idle(&mut self, tracks: &mut dyn TrackHooks, i: usize);
}
