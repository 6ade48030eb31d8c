//! The published state (xplanar.md §3.1 cyclic status, §4.4 mover blocks).

use crate::types::TrackOperationMode;
use crate::types::{
    CCoordinateMode, CommandMode, ErrorReaction, ExternalSetpointMode, MoverVector,
    PlanarObjectInfo, PlanarState, PositionXYC,
};
use motion_core::{CmdId, ErrorId};
use serde::{Deserialize, Serialize};

/// Busy flags of a mover (§2.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct BusyFlags {
    /// Any domain busy.
    pub busy_mover: bool,
    /// XY-domain command active (or C controlled through it).
    pub busy_xyc: bool,
    /// C-domain command active.
    pub busy_c: bool,
    /// Z command active.
    pub busy_z: bool,
    /// A command active.
    pub busy_a: bool,
    /// B command active.
    pub busy_b: bool,
}

/// Active command ids per domain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ActiveCommands {
    /// XY domain (MoveToPosition, Halt, ...).
    pub xy: Option<CmdId>,
    /// C domain (MoveC).
    pub c: Option<CmdId>,
    /// Z.
    pub z: Option<CmdId>,
    /// A.
    pub a: Option<CmdId>,
    /// B.
    pub b: Option<CmdId>,
    /// Running external set-point session.
    pub external_setpoint: Option<CmdId>,
}

/// One mover (STD / SET / COORDMODE).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MoverSnapshot {
    /// Configured name.
    pub name: String,
    /// OID.
    pub oid: u32,
    /// `STD.State`.
    pub state: PlanarState,
    /// `STD.CommandMode` (Invalid unless Enabled).
    pub command_mode: CommandMode,
    /// `STD.Busy`.
    pub busy: BusyFlags,
    /// `STD.GroupOID` (0 = none).
    pub group_oid: u32,
    /// Group name.
    pub group: Option<String>,
    /// `STD.PartOID` (0 = no part / part feature off).
    pub part_oid: u32,
    /// Part name.
    pub part: Option<String>,
    /// `STD.CoordinateSystemOID`.
    pub coordinate_system_oid: u32,
    /// `STD.ErrorId`.
    pub error_id: ErrorId,
    /// `STD.ErrorReaction`.
    pub error_reaction: ErrorReaction,
    /// `STD.ExternalSetpointMode` (None when inactive).
    pub external_setpoint_mode: ExternalSetpointMode,
    /// `STD.WarningId` (W_DYNAMICS_REDUCED after a clamped command).
    pub warning_id: ErrorId,
    /// `objectInfo` of the mover's last E_COLLISION stop: the blocking object (§6.1).
    pub object_info: PlanarObjectInfo,
    /// `SET.SetPos` = `ACT.ActPos` (ideal tracking) in the mover's CS.
    pub set_pos: MoverVector,
    /// `SET.SetVelo`.
    pub set_velo: MoverVector,
    /// `SET.SetAcc`.
    pub set_acc: MoverVector,
    /// `COORDMODE.CCoordinateMode`.
    pub c_coordinate_mode: CCoordinateMode,
    /// Active command per domain.
    pub active: ActiveCommands,
    /// `SETONTRACK` (None while not on a track).
    pub on_track: Option<OnTrackSnapshot>,
    /// Track being joined or left (JoiningTrack / LeavingTrack).
    pub joining_or_leaving: Option<String>,
}

/// `SETONTRACK` of a mover (§4.4).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OnTrackSnapshot {
    /// Track name.
    pub track: String,
    /// `TrackOID`.
    pub track_oid: u32,
    /// `SetPos`: arc length on the track \[mm\]; unwrapped on closed loops (§5.6.2).
    pub set_pos: f64,
    /// `SetPosModulo`: `set_pos` mod L ∈ [0, L) \[mm\].
    pub set_pos_modulo: f64,
    /// `SetVelo` along the track \[mm/s\].
    pub set_velo: f64,
    /// `SetAcc` along the track \[mm/s²\].
    pub set_acc: f64,
    /// `Gap` in force \[mm\].
    pub gap: f64,
    /// Held back by gap control (the command waits, §5.6.3).
    pub waiting: bool,
    /// A gear-in is running and the slave is synchronous (`inSync`, §5.8.1).
    pub in_sync: bool,
    /// Master mover of a running gear-in.
    pub gear_master: Option<String>,
}

/// A track (`MCTOPLC_STD` and online values, §1.6, §3.3).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrackSnapshot {
    /// Name.
    pub name: String,
    /// OID.
    pub oid: u32,
    /// Planar state.
    pub state: PlanarState,
    /// Operation mode (§2.5).
    pub operation_mode: TrackOperationMode,
    /// Length \[mm\].
    pub length: f64,
    /// Closed loop online information.
    pub closed_loop: bool,
    /// Number of movers on the track.
    pub mover_count: usize,
    /// Mover names in track order.
    pub movers: Vec<String>,
    /// Previous Tracks (their end is this start).
    pub previous_tracks: Vec<String>,
    /// Subsequent Tracks (their start is this end).
    pub subsequent_tracks: Vec<String>,
    /// Part OID (0 = none).
    pub part_oid: u32,
    /// Collision range at the start (automatic: 0 without a switch there; manual: the
    /// configured value) \[mm\] (§5.6.4).
    pub collision_range_start: f64,
    /// Collision range at the end \[mm\].
    pub collision_range_end: f64,
    /// "Collision range mode" (§1.6).
    pub collision_range_mode: crate::config::CollisionRangeMode,
    /// "Maximal mover width" \[mm\].
    pub max_mover_width: f64,
    /// "Maximal mover height" \[mm\].
    pub max_mover_height: f64,
    /// "Check collision against static objects".
    pub check_static_collision: bool,
    /// Subsequent Tracks whose link is traversable with the current part positions (§5.12).
    pub traversable_subsequent_tracks: Vec<String>,
}

/// A group.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GroupSnapshot {
    /// Name.
    pub name: String,
    /// OID.
    pub oid: u32,
    /// Planar state.
    pub state: PlanarState,
    /// Number of managed objects (movers + environment).
    pub member_count: usize,
    /// Member mover names in joining order.
    pub movers: Vec<String>,
    /// True if the environment is a member.
    pub environment_member: bool,
    /// Member track names (§5.11).
    pub tracks: Vec<String>,
}

/// A part (`PlanarPartsInfo`, §1.2, §1.10).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PartSnapshot {
    /// Name.
    pub name: String,
    /// OID.
    pub oid: u32,
    /// Planar state.
    pub state: PlanarState,
    /// Active position index (1-based).
    pub position_index: u32,
    /// Position (x, y in its CS; ReferenceId = CS OID).
    pub position: PositionXYC,
    /// `DisableForced`.
    pub disable_forced: bool,
    /// `IsInitialized` of the PLC wrapper.
    pub is_initialized: bool,
    /// ActivatePosition running.
    pub moving: bool,
}

/// The environment.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EnvironmentSnapshot {
    /// Name.
    pub name: String,
    /// OID.
    pub oid: u32,
    /// `MCTOPLC_STD.GroupOID`.
    pub group_oid: u32,
    /// Number of stators (added, or of the parts when the processing unit is configured).
    pub stator_count: usize,
    /// Number of boundary elements (0 until CreateBoundary).
    pub boundary_element_count: usize,
    /// `PartCount`.
    pub part_count: usize,
    /// Lower-left corners \[mm\] of the stators added by `AddStator` (empty when the parts
    /// define the area: their tiles are in the configuration).
    pub added_stators: Vec<[f64; 2]>,
}

/// Everything published in one cycle.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlanarSnapshot {
    /// Simulated time \[s\].
    pub time: f64,
    /// Environment.
    pub environment: EnvironmentSnapshot,
    /// Movers in configuration order.
    pub movers: Vec<MoverSnapshot>,
    /// Groups in configuration order.
    pub groups: Vec<GroupSnapshot>,
    /// Parts in configuration order.
    pub parts: Vec<PartSnapshot>,
    /// Tracks in configuration order.
    pub tracks: Vec<TrackSnapshot>,
    /// Virtual master axes in configuration order (§5.8.4).
    pub axes: Vec<VirtualAxisSnapshot>,
}

/// A virtual master axis (§5.8.4).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VirtualAxisSnapshot {
    /// Name.
    pub name: String,
    /// OID.
    pub oid: u32,
    /// Power enabled.
    pub powered: bool,
    /// Position \[mm\].
    pub position: f64,
    /// Velocity \[mm/s\].
    pub velocity: f64,
    /// Acceleration \[mm/s²\].
    pub acceleration: f64,
    /// A MoveAbsolute/Halt is running.
    pub busy: bool,
}

impl PlanarSnapshot {
    /// The mover with this name.
    pub fn mover(&self, name: &str) -> Option<&MoverSnapshot> {
        self.movers.iter().find(|m| m.name == name)
    }

    /// The group with this name.
    pub fn group(&self, name: &str) -> Option<&GroupSnapshot> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// The track with this name.
    pub fn track(&self, name: &str) -> Option<&TrackSnapshot> {
        self.tracks.iter().find(|t| t.name == name)
    }

    /// The part with this name.
    pub fn part(&self, name: &str) -> Option<&PartSnapshot> {
        self.parts.iter().find(|p| p.name == name)
    }
}

/// What an accepted command answers at once.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanarReply {
    /// The command instance (for ESG set points: the running session).
    pub id: CmdId,
    /// W_DYNAMICS_REDUCED when the limits were clamped (§5.1), else 0.
    pub warning_id: ErrorId,
    /// Result of a query.
    pub value: ReplyValue,
}

/// Query results.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ReplyValue {
    /// Nothing.
    None,
    /// A position (GetPositionOnCurrentPart, part GetPosition).
    Position(PositionXYC),
    /// GetPlanarObjectInfo.
    ObjectInfo(PlanarObjectInfo),
    /// A number (track GetLength, GetArcLengthClosestTo) \[mm\].
    Scalar(f64),
}
