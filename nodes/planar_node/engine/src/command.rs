//! The command enum: one variant per method of §3 (manual parameters in snake_case, objects
//! addressed by their configured names). Feedback objects are the returned [`motion_core::CmdId`].

use crate::types::{
    AdoptTrackOrientationOptions, DynamicConstraint, ErrorReaction,
    ExternalSetpointGenerationOptions, GearInPosOnTrackOptions,
    GearInPosOnTrackWithMasterMoverOptions, MoveCOptions, MoveOnTrackOptions,
    MoveToPositionOptions, MoverVector, PositionXYC, TrackLinkAdvancedOptions,
};
use serde::{Deserialize, Serialize};

/// Kind of object addressed by [`PlanarCommand::InjectError`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ObjectKind {
    /// A mover.
    Mover,
    /// A group.
    Group,
    /// A part.
    Part,
    /// A track.
    Track,
}

/// A method call (§3). Variant names keep the manual's method names, prefixed with the
/// object type where several objects share a method name.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PlanarCommand {
    // --- MC_PlanarEnvironment (§3.1)
    /// `Clear(fb)`.
    EnvironmentClear,
    /// `AddStator(fb, lowerX, lowerY)`.
    AddStator {
        /// Lower-left x \[mm\].
        lower_x: f64,
        /// Lower-left y \[mm\].
        lower_y: f64,
    },
    /// `CreateBoundary(fb)`.
    CreateBoundary,
    /// `AddToGroup(fb, group)` of the environment.
    EnvironmentAddToGroup {
        /// Group name.
        group: String,
    },
    /// `RemoveFromGroup(fb)` of the environment.
    EnvironmentRemoveFromGroup,
    /// `GetPlanarObjectInfo()` of the environment.
    EnvironmentGetPlanarObjectInfo,

    // --- MC_PlanarMover (§3.2)
    /// `MoveToPosition(fb, targetPosition, constraint, options)`.
    MoveToPosition {
        /// Mover name.
        mover: String,
        /// Target.
        target_position: PositionXYC,
        /// Limits (0 = default).
        constraint: DynamicConstraint,
        /// Options.
        options: MoveToPositionOptions,
    },
    /// `MoveZ(fb, targetPosition, constraint)`.
    MoveZ {
        /// Mover name.
        mover: String,
        /// Target z \[mm\].
        target_position: f64,
        /// Limits (0 = default).
        constraint: DynamicConstraint,
    },
    /// `MoveA(fb, targetPosition, constraint)`.
    MoveA {
        /// Mover name.
        mover: String,
        /// Target a \[deg\].
        target_position: f64,
        /// Limits (0 = default).
        constraint: DynamicConstraint,
    },
    /// `MoveB(fb, targetPosition, constraint)`.
    MoveB {
        /// Mover name.
        mover: String,
        /// Target b \[deg\].
        target_position: f64,
        /// Limits (0 = default).
        constraint: DynamicConstraint,
    },
    /// `MoveC(fb, targetPosition, constraint, options)`.
    MoveC {
        /// Mover name.
        mover: String,
        /// Target c \[deg\].
        target_position: f64,
        /// Limits (0 = default).
        constraint: DynamicConstraint,
        /// Options.
        options: MoveCOptions,
    },
    /// `Halt(fb, constraint)`.
    Halt {
        /// Mover name.
        mover: String,
        /// Deceleration/jerk (0 = default).
        constraint: DynamicConstraint,
    },
    /// `Enable(fb)` of a mover.
    MoverEnable {
        /// Mover name.
        mover: String,
    },
    /// `Disable(fb)` of a mover.
    MoverDisable {
        /// Mover name.
        mover: String,
    },
    /// `Reset(fb)` of a mover.
    MoverReset {
        /// Mover name.
        mover: String,
    },
    /// `SetPosition(fb, position)` (Disabled only).
    SetPosition {
        /// Mover name.
        mover: String,
        /// New pose.
        position: PositionXYC,
    },
    /// `StartExternalSetpointGeneration(fb, options)`.
    StartExternalSetpointGeneration {
        /// Mover name.
        mover: String,
        /// Options.
        options: ExternalSetpointGenerationOptions,
    },
    /// `StopExternalSetpointGeneration(fb)`.
    StopExternalSetpointGeneration {
        /// Mover name.
        mover: String,
    },
    /// `SetExternalSetpoint(setPosition, setVelocity, setAcceleration)` (mover's CS).
    SetExternalSetpoint {
        /// Mover name.
        mover: String,
        /// Position (absolute) or offset (relative).
        set_position: MoverVector,
        /// Velocity.
        set_velocity: MoverVector,
        /// Acceleration.
        set_acceleration: MoverVector,
    },
    /// `SetExternalSetpointReferenceId(fb, setPosition, setVelocity, setAcceleration, referenceSystemOid)`.
    SetExternalSetpointReferenceId {
        /// Mover name.
        mover: String,
        /// Position.
        set_position: MoverVector,
        /// Velocity.
        set_velocity: MoverVector,
        /// Acceleration.
        set_acceleration: MoverVector,
        /// CS or part OID (0 only in the static single-CS case).
        reference_system_oid: u32,
    },
    /// `AddToGroup(fb, group)` of a mover.
    MoverAddToGroup {
        /// Mover name.
        mover: String,
        /// Group name.
        group: String,
    },
    /// `RemoveFromGroup(fb)` of a mover.
    MoverRemoveFromGroup {
        /// Mover name.
        mover: String,
    },
    /// `GetPositionOnCurrentPart(position)`.
    GetPositionOnCurrentPart {
        /// Mover name.
        mover: String,
    },
    /// `GetPlanarObjectInfo()` of a mover.
    MoverGetPlanarObjectInfo {
        /// Mover name.
        mover: String,
    },

    // --- MC_PlanarMover on tracks (§3.2)
    /// `JoinTrack(fb, targetTrack, constraint, options)`.
    JoinTrack {
        /// Mover name.
        mover: String,
        /// Track name.
        track: String,
        /// Limits (0 = default).
        constraint: DynamicConstraint,
        /// Options (`use_orientation`, default TRUE).
        options: MoveToPositionOptions,
    },
    /// `LeaveTrack(fb, targetPosition, constraint, options)`.
    LeaveTrack {
        /// Mover name.
        mover: String,
        /// Free target.
        target_position: PositionXYC,
        /// Limits (0 = default).
        constraint: DynamicConstraint,
        /// Options (`use_orientation`, default TRUE).
        options: MoveToPositionOptions,
    },
    /// `MoveOnTrack(fb, targetTrack, targetPositionOnTrack, constraint, options)`.
    MoveOnTrack {
        /// Mover name.
        mover: String,
        /// Target track; empty = the mover's current track (`targetTrack = 0`).
        track: String,
        /// Arc length on the target track \[mm\].
        target_position: f64,
        /// Tangential limits (0 = default).
        constraint: DynamicConstraint,
        /// Options (gap, direction, additional turns, modulo tolerance).
        options: MoveOnTrackOptions,
    },
    /// `AdoptTrackOrientation(fb, constraint, options)`.
    AdoptTrackOrientation {
        /// Mover name.
        mover: String,
        /// C limits (0 = default).
        constraint: DynamicConstraint,
        /// Options (default ShortestWay).
        options: AdoptTrackOrientationOptions,
    },
    /// `GearInPosOnTrackWithMasterMover(fb, masterMover, trackTrail, masterSyncPosition,
    /// masterSyncPositionTrack, slaveSyncPosition, slaveSyncPositionTrack, constraint, options)`
    /// (§3.2, §5.8): never Done; Aborted by the next XY command, or Error.
    GearInPosOnTrackWithMasterMover {
        /// Slave mover name.
        mover: String,
        /// Master mover name.
        master_mover: String,
        /// Track trail (names in order); empty = the slave's current track only.
        track_trail: Vec<String>,
        /// Master position for synchronism \[mm\] (arc length on its track).
        master_sync_position: f64,
        /// Track of the master sync position.
        master_sync_position_track: String,
        /// Slave position for synchronism \[mm\].
        slave_sync_position: f64,
        /// Track of the slave sync position.
        slave_sync_position_track: String,
        /// Tangential limits (0 = default).
        constraint: DynamicConstraint,
        /// Options.
        options: GearInPosOnTrackWithMasterMoverOptions,
    },
    /// `GearInPosOnTrack(fb, masterAxis, trackTrail, masterSyncPosition, slaveSyncPosition,
    /// slaveSyncPositionTrack, constraint, options)` with a virtual master axis (§5.8).
    GearInPosOnTrack {
        /// Slave mover name.
        mover: String,
        /// Virtual master axis name.
        master_axis: String,
        /// Track trail (names in order); empty = the slave's current track only.
        track_trail: Vec<String>,
        /// Master axis position for synchronism \[mm\].
        master_sync_position: f64,
        /// Slave position for synchronism \[mm\].
        slave_sync_position: f64,
        /// Track of the slave sync position.
        slave_sync_position_track: String,
        /// Tangential limits (0 = default).
        constraint: DynamicConstraint,
        /// Options.
        options: GearInPosOnTrackOptions,
    },

    // --- virtual master axes (§5.8.4)
    /// Power (Enable level) of a virtual axis.
    AxisPower {
        /// Axis name.
        axis: String,
        /// Enable.
        enable: bool,
    },
    /// MoveAbsolute of a virtual axis.
    AxisMoveAbsolute {
        /// Axis name.
        axis: String,
        /// Target \[mm\].
        position: f64,
        /// Velocity \[mm/s\] (> 0).
        velocity: f64,
        /// Acceleration \[mm/s²\] (> 0).
        acceleration: f64,
        /// Deceleration \[mm/s²\] (> 0).
        deceleration: f64,
        /// Jerk \[mm/s³\] (> 0).
        jerk: f64,
    },
    /// Halt of a virtual axis.
    AxisHalt {
        /// Axis name.
        axis: String,
        /// Deceleration \[mm/s²\] (> 0).
        deceleration: f64,
        /// Jerk \[mm/s³\] (> 0).
        jerk: f64,
    },

    // --- MC_PlanarTrack (§3.3)
    /// `AppendPosition(fb, position)`: `position.c` is the heading \[deg\].
    TrackAppendPosition {
        /// Track name.
        track: String,
        /// Point and heading.
        position: PositionXYC,
    },
    /// `AppendLine(fb, start, end)`.
    TrackAppendLine {
        /// Track name.
        track: String,
        /// Line start.
        start: PositionXYC,
        /// Line end.
        end: PositionXYC,
    },
    /// `AppendCircle(fb, start, end, center, clockwise)`.
    TrackAppendCircle {
        /// Track name.
        track: String,
        /// Arc start.
        start: PositionXYC,
        /// Arc end (= start: full circle).
        end: PositionXYC,
        /// Centre (c ignored).
        center: PositionXYC,
        /// Sense of rotation.
        clockwise: bool,
    },
    /// `CloseLoop(fb)`.
    TrackCloseLoop {
        /// Track name.
        track: String,
    },
    /// `StartFromTrack(fb, track)`: this track starts at the other's end.
    TrackStartFromTrack {
        /// This track.
        track: String,
        /// The other track.
        other: String,
    },
    /// `EndAtTrack(fb, track)`: this track ends at the other's start.
    TrackEndAtTrack {
        /// This track.
        track: String,
        /// The other track.
        other: String,
    },
    /// `StartFromTrackAdvanced(fb, track, options)`.
    TrackStartFromTrackAdvanced {
        /// This track.
        track: String,
        /// The other track.
        other: String,
        /// Part positions of the link.
        options: TrackLinkAdvancedOptions,
    },
    /// `EndAtTrackAdvanced(fb, track, options)`.
    TrackEndAtTrackAdvanced {
        /// This track.
        track: String,
        /// The other track.
        other: String,
        /// Part positions of the link.
        options: TrackLinkAdvancedOptions,
    },
    /// `Clear(fb)` of a track.
    TrackClear {
        /// Track name.
        track: String,
    },
    /// `Enable(fb)` of a track.
    TrackEnable {
        /// Track name.
        track: String,
    },
    /// `Disable(fb)` of a track.
    TrackDisable {
        /// Track name.
        track: String,
    },
    /// `Reset(fb)` of a track.
    TrackReset {
        /// Track name.
        track: String,
    },
    /// `AddToGroup(fb, group)` of a track (§5.11): a Moving member track blocks its area.
    TrackAddToGroup {
        /// Track name.
        track: String,
        /// Group name.
        group: String,
    },
    /// `RemoveFromGroup(fb)` of a track.
    TrackRemoveFromGroup {
        /// Track name.
        track: String,
    },
    /// `GetLength()`: reply [`crate::ReplyValue::Scalar`] (−1 never: unknown names are rejected).
    TrackGetLength {
        /// Track name.
        track: String,
    },
    /// `GetArcLengthClosestTo(geometry)`: reply `Scalar` \[mm\].
    TrackGetArcLengthClosestTo {
        /// Track name.
        track: String,
        /// Point (c ignored).
        point: PositionXYC,
    },
    /// `GetPositionAt(arcLength, position)`: reply `Position` (c = heading \[deg\]).
    TrackGetPositionAt {
        /// Track name.
        track: String,
        /// Arc length \[mm\].
        arc_length: f64,
    },
    /// `GetPlanarObjectInfo()` of a track.
    TrackGetPlanarObjectInfo {
        /// Track name.
        track: String,
    },
    /// Sets the track's collision init parameters of §1.6 (the launch-config keys of the same
    /// names) while the track is Disabled (proposal: init parameters take effect at Enable).
    TrackSetInitParameters {
        /// Track name.
        track: String,
        /// "Maximal mover width" \[mm\] (> 0).
        max_mover_width: f64,
        /// "Maximal mover height" \[mm\] (> 0).
        max_mover_height: f64,
        /// "Check collision against static objects".
        check_static_collision: bool,
        /// "Collision range mode".
        collision_range_mode: crate::config::CollisionRangeMode,
        /// "Collision range at start" \[mm\] (Manual mode; 0 in Automatic mode).
        collision_range_start: f64,
        /// "Collision range at end" \[mm\] (Manual mode; 0 in Automatic mode).
        collision_range_end: f64,
    },

    // --- MC_PlanarGroup (§3.4)
    /// `Enable(fb)` of a group.
    GroupEnable {
        /// Group name.
        group: String,
    },
    /// `Disable(fb)` of a group.
    GroupDisable {
        /// Group name.
        group: String,
    },
    /// `Reset(fb)` of a group.
    GroupReset {
        /// Group name.
        group: String,
    },

    // --- MC_PlanarPart (§3.5)
    /// `Initialize(fb, partOID, environment)`.
    PartInitialize {
        /// Part (wrapper) name.
        part: String,
        /// OID to connect to.
        part_oid: u32,
    },
    /// `ActivatePosition(fb, positionIndex)`.
    ActivatePosition {
        /// Part name.
        part: String,
        /// 1-based position index.
        position_index: u32,
    },
    /// `AllowEnable(fb)`.
    AllowEnable {
        /// Part name.
        part: String,
    },
    /// `ForceDisable(fb)`.
    ForceDisable {
        /// Part name.
        part: String,
    },
    /// `Reset(fb)` of a part.
    PartReset {
        /// Part name.
        part: String,
    },
    /// `GetPosition(position)` of a part.
    PartGetPosition {
        /// Part name.
        part: String,
    },

    // --- test hook (§6.2)
    /// `InjectError(object, reaction)`: puts the object into ErrorPending (E_OBJECT_ERROR).
    InjectError {
        /// Object kind.
        kind: ObjectKind,
        /// Object name.
        name: String,
        /// Error reaction.
        reaction: ErrorReaction,
    },
}
