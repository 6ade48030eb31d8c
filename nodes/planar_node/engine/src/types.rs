//! Data types of the manual (xplanar.md §3.8, §4): positions, vectors, constraints, options,
//! and the enums with their proposal numbering (§4.3).

use crate::errors::{finite, reject, E_INVALID_PARAMETER};
use motion_core::Rejection;
use serde::{Deserialize, Serialize};

/// `PositionXYC {x, y, c, ReferenceId}` (§3.8): a pose in a coordinate system or part system.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PositionXYC {
    /// x \[mm\].
    pub x: f64,
    /// y \[mm\].
    pub y: f64,
    /// c \[deg\].
    pub c: f64,
    /// Coordinate-system OID, part OID, or 0 (§1.4).
    pub reference_id: u32,
}

impl PositionXYC {
    /// A pose with ReferenceId 0.
    pub fn new(x: f64, y: f64, c: f64) -> Self {
        PositionXYC {
            x,
            y,
            c,
            reference_id: 0,
        }
    }

    /// A pose with a ReferenceId.
    pub fn with_ref(x: f64, y: f64, c: f64, reference_id: u32) -> Self {
        PositionXYC {
            x,
            y,
            c,
            reference_id,
        }
    }

    pub(crate) fn check_finite(&self, object: &str, field: &str) -> Result<(), Rejection> {
        finite(object, &format!("{field}.x"), self.x)?;
        finite(object, &format!("{field}.y"), self.y)?;
        finite(object, &format!("{field}.c"), self.c)?;
        Ok(())
    }
}

/// `MoverVector {x, y, z, a, b, c}` (§3.8) [mm, deg].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MoverVector {
    /// x \[mm\].
    pub x: f64,
    /// y \[mm\].
    pub y: f64,
    /// z (lift) \[mm\].
    pub z: f64,
    /// a (tilt) \[deg\].
    pub a: f64,
    /// b (tilt) \[deg\].
    pub b: f64,
    /// c (rotation) \[deg\].
    pub c: f64,
}

impl MoverVector {
    /// All six components as an array in the order x, y, z, a, b, c.
    pub fn to_array(self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }

    /// From an array in the order x, y, z, a, b, c.
    pub fn from_array(v: [f64; 6]) -> Self {
        MoverVector {
            x: v[0],
            y: v[1],
            z: v[2],
            a: v[3],
            b: v[4],
            c: v[5],
        }
    }

    pub(crate) fn check_finite(&self, object: &str, field: &str) -> Result<(), Rejection> {
        for (name, v) in ["x", "y", "z", "a", "b", "c"].iter().zip(self.to_array()) {
            finite(object, &format!("{field}.{name}"), v)?;
        }
        Ok(())
    }
}

/// `IPlcDynamicConstraint` / `DynamicConstraint_PathXY` (§3.8): 0 in a field = the mover's
/// default for that field; negative values are rejected.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DynamicConstraint {
    /// Velocity [mm/s or deg/s]; 0 = default.
    pub velocity: f64,
    /// Acceleration [mm/s² or deg/s²]; 0 = default.
    pub acceleration: f64,
    /// Deceleration [mm/s² or deg/s²]; 0 = default.
    pub deceleration: f64,
    /// Jerk [mm/s³ or deg/s³]; 0 = default.
    pub jerk: f64,
}

/// A complete set of dynamics limits (config `default_dynamics` / `max_dynamics`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dynamics {
    /// Velocity [u/s].
    pub velocity: f64,
    /// Acceleration [u/s²].
    pub acceleration: f64,
    /// Deceleration [u/s²].
    pub deceleration: f64,
    /// Jerk [u/s³].
    pub jerk: f64,
}

impl Dynamics {
    /// Same acceleration and deceleration.
    pub const fn new(velocity: f64, acc: f64, jerk: f64) -> Self {
        Dynamics {
            velocity,
            acceleration: acc,
            deceleration: acc,
            jerk,
        }
    }

    pub(crate) fn limits(&self) -> motion_core::trajectory::Limits {
        motion_core::trajectory::Limits {
            velocity: self.velocity,
            acceleration: self.acceleration,
            deceleration: self.deceleration,
            jerk: self.jerk,
        }
    }

    pub(crate) fn fields(&self) -> [(&'static str, f64); 4] {
        [
            ("velocity", self.velocity),
            ("acceleration", self.acceleration),
            ("deceleration", self.deceleration),
            ("jerk", self.jerk),
        ]
    }

    /// Resolves a command constraint against these defaults and the maximum (§5.1):
    /// 0 → default, above max → max (returns `reduced = true`, a warning, not an error).
    pub(crate) fn resolve(
        default: &Dynamics,
        max: &Dynamics,
        c: &DynamicConstraint,
        object: &str,
        field: &str,
    ) -> Result<(Dynamics, bool), Rejection> {
        let req = [c.velocity, c.acceleration, c.deceleration, c.jerk];
        let def = [
            default.velocity,
            default.acceleration,
            default.deceleration,
            default.jerk,
        ];
        let mx = [max.velocity, max.acceleration, max.deceleration, max.jerk];
        let names = ["velocity", "acceleration", "deceleration", "jerk"];
        let mut out = [0.0; 4];
        let mut reduced = false;
        for i in 0..4 {
            let v = finite(object, &format!("{field}.{}", names[i]), req[i])?;
            if v < 0.0 {
                return Err(reject(
                    E_INVALID_PARAMETER,
                    format!(
                        "{object}: {field}.{} = {v} must not be negative (0 = default)",
                        names[i]
                    ),
                ));
            }
            let v = if v == 0.0 { def[i] } else { v };
            if v > mx[i] {
                reduced = true;
                out[i] = mx[i];
            } else {
                out[i] = v;
            }
        }
        Ok((
            Dynamics {
                velocity: out[0],
                acceleration: out[1],
                deceleration: out[2],
                jerk: out[3],
            },
            reduced,
        ))
    }

    /// These limits scaled by `k` (> 0), used to map C limits onto the path parameter.
    pub(crate) fn scaled(&self, k: f64) -> Dynamics {
        Dynamics {
            velocity: self.velocity * k,
            acceleration: self.acceleration * k,
            deceleration: self.deceleration * k,
            jerk: self.jerk * k,
        }
    }

    /// Field-wise minimum.
    pub(crate) fn min(&self, o: &Dynamics) -> Dynamics {
        Dynamics {
            velocity: self.velocity.min(o.velocity),
            acceleration: self.acceleration.min(o.acceleration),
            deceleration: self.deceleration.min(o.deceleration),
            jerk: self.jerk.min(o.jerk),
        }
    }
}

/// `EPlanarObjectType` (§4.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PlanarObjectType {
    /// No connection / not ready (0).
    #[default]
    Invalid = 0,
    /// No planar object (301).
    None = 301,
    /// Planar mover (302).
    Mover = 302,
    /// Planar track (303).
    Track = 303,
    /// Planar environment (304); also reported for part borders.
    Environment = 304,
}

/// `PlanarObjectInfo {ObjectType, Id}` (§4.2); the blocker of a collision error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PlanarObjectInfo {
    /// Object type.
    pub object_type: PlanarObjectType,
    /// Object OID.
    pub id: u32,
}

/// `MC_PLANAR_STATE` (§4.3, proposal values).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PlanarState {
    /// Not connected (0).
    Invalid = 0,
    /// Powered off (1); start-up state.
    #[default]
    Disabled = 1,
    /// Enable procedure running (2).
    Enabling = 2,
    /// Ready for commands (3).
    Enabled = 3,
    /// Disable procedure running (4).
    Disabling = 4,
    /// Error, waiting for Reset (5).
    Error = 5,
    /// Error reaction running (6).
    ErrorPending = 6,
    /// Reset running (7).
    Resetting = 7,
}

/// `MC_PLANAR_MOVER_COMMAND_MODE` (§2.2, §4.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CommandMode {
    /// Not enabled (0).
    #[default]
    Invalid = 0,
    /// Free XY movement (101).
    FreeMovement = 101,
    /// Coupled to a track (102).
    OnTrack = 102,
    /// Executing JoinTrack (103).
    JoiningTrack = 103,
    /// Executing LeaveTrack (104).
    LeavingTrack = 104,
    /// Absolute external set points (105).
    ExternalSetpointGeneration = 105,
    /// Rotation outside the C windows, free (106).
    CRotationFreeMovement = 106,
    /// Rotation outside the C windows, on a track (107).
    CRotationOnTrack = 107,
}

/// `MC_EXTERNAL_SET_POSITION_MODE` (§4.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ExternalSetpointMode {
    /// Invalid (0).
    Invalid = 0,
    /// The mover follows only the user set points (1); default.
    #[default]
    Absolute = 1,
    /// User values are offsets on the internal set points (2).
    Relative = 2,
    /// No external set points (3).
    None = 3,
}

/// `C_COORDINATE_MODE` (§4.3, §5.9).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CCoordinateMode {
    /// c changes only through C commands (1).
    #[default]
    Independent = 1,
    /// c coupled to the track heading (2).
    Dependent = 2,
}

/// `ERROR_REACTION` (§4.3).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub enum ErrorReaction {
    /// No error (0).
    #[default]
    None = 0,
    /// Controlled stop with maximum dynamics, stays powered (1).
    QuickStop = 1,
    /// Set points frozen, power off (2).
    Abort = 2,
}

/// `MC_DIRECTION` (§4.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Direction {
    /// Absolute target (0).
    #[default]
    NonModulo = 0,
    /// Forward only (1).
    Positive = 1,
    /// Shortest way (2).
    ShortestWay = 2,
    /// Backward only (3).
    Negative = 3,
}

/// `ST_MoveToPositionOptions` (also JoinTrack/LeaveTrack) (§4.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MoveToPositionOptions {
    /// TRUE: the target c is approached too (default TRUE).
    pub use_orientation: bool,
}

impl Default for MoveToPositionOptions {
    fn default() -> Self {
        MoveToPositionOptions {
            use_orientation: true,
        }
    }
}

/// `ST_MoveCOptions` (§4.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MoveCOptions {
    /// Extra full turns (Positive/Negative only).
    pub additional_turns: u32,
    /// How the target is approached (default NonModulo).
    pub direction: Direction,
}

/// `ST_ExternalSetpointGenerationOptions` (§4.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ExternalSetpointGenerationOptions {
    /// Absolute (default) or Relative.
    pub mode: ExternalSetpointMode,
}

// ---------------------------------------------------------------- tracks (§2.5, §4.1–§4.3)

/// Default gap between movers on a track \[mm\] (ST_MoveOnTrackOptions.gap, §4.2).
pub const DEFAULT_GAP: f64 = 200.0;

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
