//! [`PlanarEngine`]: the objects ([`Objects`]) and the track subsystem ([`TrackSystem`]),
//! each with its own state, composed into the commands and the cycle's stages (xplanar.md
//! §1–§3, §5). The no-overlap guard ([`crate::guard`]) runs on every cycle. The two layers
//! reach each other through one trait each, wired in `wiring`.

use crate::command::PlanarCommand;
use crate::errors::error_name;
use crate::objects::Objects;
use crate::snapshot::{PlanarReply, PlanarSnapshot};
use crate::track::TrackSystem;
use crate::types::{PlanarObjectInfo, PositionXYC};
use motion_core::{CmdId, CommandEvent, Engine, ErrorId, Rejection, Tick};

mod wiring;

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
        let mut s = PlanarSnapshot::default();
        self.snapshot_into(&mut s);
        s
    }

    fn snapshot_into(&self, out: &mut PlanarSnapshot) {
        self.objects.snapshot_into(&self.tracks, out)
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
