//! Simulator configuration (xplanar.md §1.12, proposal) as read from a launch YAML.
//!
//! Every struct denies unknown keys; [`PlanarConfig::validate`] refuses inconsistent values
//! with a message naming the key and the value. Defaults are the spec's tables (§1.5).
//!
//! ```yaml
//! cycle_time: 0.001
//! coordinate_systems: [0x01010060]
//! parts:
//!   - {name: L, oid: 0x01010020, tiles: [[0, 0]], positions: {1: {cs: 0x01010060, x: 0, y: 0}}}
//!   - {name: R, oid: 0x01010030, tiles: [[0, 0]], positions: {1: {cs: 0x01010060, x: 240, y: 0}}}
//! environment: {name: env, oid: 0x01010001, processing_unit_oid: 0x01010002}
//! movers:
//!   - {name: M, initial_pose: {x: 120, y: 120, c: 0}, part_oid: 0x01010020}
//! groups: [{name: G}]
//! ```
//! Tracks (`tracks: [{name: T1, oid: 0x01050001, part_oid: 0x01010020, geometry: [...]}]`)
//! get their geometry from the init parameters (`starts_from`, `geometry`, `ends_at`,
//! `closed_loop`, applied at start-up by `build::tracks`) and/or the commands; virtual master axes
//! (`axes: [{name: X}]`, §5.8.4) drive GearInPosOnTrack.

use crate::errors::reject;
use crate::geometry::{tiles_overlap, ConvexPolygon, STATOR_SIDE, V2};
use crate::types::{DynamicConstraint, Dynamics};
use motion_core::{ErrorId, Rejection};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashSet};

// Automatic OIDs (proposal; xplanar.md §1 leaves them open). Objects configured without an
// `oid` get one from a block that no configured OID may use, so they never clash with the
// TwinCAT object ids users copy from their projects (0x01xxxxxx): 0xFE00_0000 | class << 16 |
// n, with n = 1-based position in the config list and the class of MC object below.

/// Configured OIDs must stay outside this block (`0xFE000000..=0xFEFFFFFF`).
pub const AUTO_OID_BLOCK: std::ops::RangeInclusive<u32> = 0xFE00_0000..=0xFEFF_FFFF;
/// Movers configured without an OID: `0xFE020001`, `0xFE020002`, …
pub const AUTO_MOVER_OID: u32 = 0xFE02_0000;
/// Groups configured without an OID: `0xFE030001`, …
pub const AUTO_GROUP_OID: u32 = 0xFE03_0000;
/// The environment without a configured OID: `0xFE040001`.
pub const AUTO_ENVIRONMENT_OID: u32 = 0xFE04_0001;
/// Tracks configured without an OID: `0xFE050001`, …
pub const AUTO_TRACK_OID: u32 = 0xFE05_0000;
/// Virtual master axes configured without an OID: `0xFE060001`, …
pub const AUTO_AXIS_OID: u32 = 0xFE06_0000;

fn d_cycle() -> f64 {
    0.001
}
fn d_state_time() -> f64 {
    0.1
}
fn d_error_pending() -> f64 {
    0.05
}
fn d_part_move() -> f64 {
    0.5
}
fn d_esg_timeout() -> u32 {
    10
}

/// The whole planar node configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanarConfig {
    /// Cycle time \[s\] (default 0.001).
    #[serde(default = "d_cycle")]
    pub cycle_time: f64,
    /// User coordinate systems (OIDs). Empty: one implicit CS with OID 0.
    #[serde(default)]
    pub coordinate_systems: Vec<u32>,
    /// Parts (V3.2.60). Empty: no part feature.
    #[serde(default)]
    pub parts: Vec<PartConfig>,
    /// The environment.
    #[serde(default)]
    pub environment: EnvironmentConfig,
    /// Movers.
    #[serde(default)]
    pub movers: Vec<MoverConfig>,
    /// Groups.
    #[serde(default)]
    pub groups: Vec<GroupConfig>,
    /// Tracks (§1.6); geometry comes from the track commands.
    #[serde(default)]
    pub tracks: Vec<TrackConfig>,
    /// Virtual master axes for GearInPosOnTrack (§5.8.4).
    #[serde(default)]
    pub axes: Vec<VirtualAxisConfig>,
    /// Enabling → Enabled \[s\] (default 0.1).
    #[serde(default = "d_state_time")]
    pub enable_time: f64,
    /// Disabling → Disabled \[s\] (default 0.1).
    #[serde(default = "d_state_time")]
    pub disable_time: f64,
    /// Resetting → Enabled/Disabled \[s\] (default 0.1).
    #[serde(default = "d_state_time")]
    pub reset_time: f64,
    /// ErrorPending → Error \[s\] (default 0.05).
    #[serde(default = "d_error_pending")]
    pub error_pending_time: f64,
    /// Duration of a part's ActivatePosition \[s\] (default 0.5, §3.5).
    #[serde(default = "d_part_move")]
    pub part_move_time: f64,
    /// Cycles an external set point may be missing before E_EXT_SETPOINT_MISSING (default 10).
    #[serde(default = "d_esg_timeout")]
    pub esg_timeout_cycles: u32,
}

impl Default for PlanarConfig {
    fn default() -> Self {
        PlanarConfig {
            cycle_time: d_cycle(),
            coordinate_systems: vec![],
            parts: vec![],
            environment: EnvironmentConfig::default(),
            movers: vec![],
            groups: vec![],
            tracks: vec![],
            axes: vec![],
            enable_time: d_state_time(),
            disable_time: d_state_time(),
            reset_time: d_state_time(),
            error_pending_time: d_error_pending(),
            part_move_time: d_part_move(),
            esg_timeout_cycles: d_esg_timeout(),
        }
    }
}

/// `environment:` block.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EnvironmentConfig {
    /// Name used in commands (default "environment").
    pub name: String,
    /// OID (0 → [`AUTO_ENVIRONMENT_OID`]).
    pub oid: u32,
    /// "XPlanar processing unit OID" (§1.2); > 0 → stators come from the parts.
    pub processing_unit_oid: u32,
}

impl Default for EnvironmentConfig {
    fn default() -> Self {
        EnvironmentConfig {
            name: "environment".into(),
            oid: 0,
            processing_unit_oid: 0,
        }
    }
}

/// One position of a part: CS OID and the part origin (lower-left corner) in it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartPositionConfig {
    /// Coordinate-system OID.
    pub cs: u32,
    /// x of the part origin \[mm\].
    pub x: f64,
    /// y of the part origin \[mm\].
    pub y: f64,
}

fn d_index() -> u32 {
    1
}

/// `parts:` entry (§1.3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartConfig {
    /// Name used in commands.
    pub name: String,
    /// Part OID (non-zero).
    pub oid: u32,
    /// Stator tiles: part-local lower-left corners \[mm\].
    pub tiles: Vec<[f64; 2]>,
    /// Positions by 1-based index.
    pub positions: BTreeMap<u32, PartPositionConfig>,
    /// Position index at start (default 1).
    #[serde(default = "d_index")]
    pub initial_index: u32,
}

/// Initial pose of a mover (simulation) [mm, deg].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InitialPose {
    /// x \[mm\].
    pub x: f64,
    /// y \[mm\].
    pub y: f64,
    /// c \[deg\].
    pub c: f64,
}

fn d_size() -> f64 {
    155.0
}
fn d_c_min() -> f64 {
    -15.0
}
fn d_c_max() -> f64 {
    15.0
}
fn d_modulus() -> f64 {
    360.0
}
fn d_default_dyn() -> Dynamics {
    Dynamics::new(1000.0, 10000.0, 100_000.0)
}
fn d_max_dyn() -> Dynamics {
    Dynamics::new(4000.0, 30000.0, 1_000_000.0)
}
fn d_c_default_dyn() -> Dynamics {
    Dynamics::new(360.0, 3600.0, 36000.0)
}
fn d_c_max_dyn() -> Dynamics {
    Dynamics::new(1440.0, 20000.0, 500_000.0)
}
fn d_aux_dyn() -> Dynamics {
    Dynamics::new(50.0, 500.0, 5000.0)
}
fn d_z_range() -> [f64; 2] {
    [0.0, 6.0]
}
fn d_ab_range() -> [f64; 2] {
    [-5.0, 5.0]
}

/// `movers:` entry (§1.5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MoverConfig {
    /// Name used in commands.
    pub name: String,
    /// OID (0 → [`AUTO_MOVER_OID`] + index).
    #[serde(default)]
    pub oid: u32,
    /// Start pose, given in the system of `part_oid` when set (§1.5).
    #[serde(default)]
    pub initial_pose: InitialPose,
    /// Part carrying the initial pose; required when more than one part exists.
    #[serde(default)]
    pub part_oid: u32,
    /// Footprint width \[mm\] (default 155).
    #[serde(default = "d_size")]
    pub width: f64,
    /// Footprint height \[mm\] (default 155).
    #[serde(default = "d_size")]
    pub height: f64,
    /// C window minimum \[deg\] (default −15).
    #[serde(default = "d_c_min")]
    pub c_min: f64,
    /// C window maximum \[deg\] (default 15).
    #[serde(default = "d_c_max")]
    pub c_max: f64,
    /// C coordinate modulus \[deg\] (default 360).
    #[serde(default = "d_modulus")]
    pub c_modulus: f64,
    /// C coordinate modulo tolerance window \[deg\] (default 0).
    #[serde(default)]
    pub c_modulo_tolerance: f64,
    /// XY default dynamics (constraint 0).
    #[serde(default = "d_default_dyn")]
    pub default_dynamics: Dynamics,
    /// XY maximum dynamics (hard limits; also QuickStop and ESG stop).
    #[serde(default = "d_max_dyn")]
    pub max_dynamics: Dynamics,
    /// C default dynamics \[deg\].
    #[serde(default = "d_c_default_dyn")]
    pub c_default_dynamics: Dynamics,
    /// C maximum dynamics \[deg\].
    #[serde(default = "d_c_max_dyn")]
    pub c_max_dynamics: Dynamics,
    /// Z/A/B default dynamics [mm, deg].
    #[serde(default = "d_aux_dyn")]
    pub aux_default_dynamics: Dynamics,
    /// Z/A/B maximum dynamics [mm, deg].
    #[serde(default = "d_aux_dyn")]
    pub aux_max_dynamics: Dynamics,
    /// z travel \[mm\] (default [0, 6]).
    #[serde(default = "d_z_range")]
    pub z_range: [f64; 2],
    /// a travel \[deg\] (default [−5, 5]).
    #[serde(default = "d_ab_range")]
    pub a_range: [f64; 2],
    /// b travel \[deg\] (default [−5, 5]).
    #[serde(default = "d_ab_range")]
    pub b_range: [f64; 2],
}

impl MoverConfig {
    /// XY dynamics of a command: its constraint against the XY defaults and maxima (§5.1);
    /// `reduced` = a value was above its maximum (a warning).
    pub(crate) fn xy_dynamics(
        &self,
        c: &DynamicConstraint,
        who: &str,
    ) -> Result<(Dynamics, bool), Rejection> {
        Dynamics::resolve(
            &self.default_dynamics,
            &self.max_dynamics,
            c,
            who,
            "constraint",
        )
    }

    /// C dynamics of a command, as [`Self::xy_dynamics`] \[deg\].
    pub(crate) fn c_dynamics(
        &self,
        c: &DynamicConstraint,
        who: &str,
    ) -> Result<(Dynamics, bool), Rejection> {
        Dynamics::resolve(
            &self.c_default_dynamics,
            &self.c_max_dynamics,
            c,
            who,
            "constraint",
        )
    }

    /// Z/A/B dynamics of a command, as [`Self::xy_dynamics`] \[mm, deg\].
    pub(crate) fn aux_dynamics(
        &self,
        c: &DynamicConstraint,
        who: &str,
    ) -> Result<(Dynamics, bool), Rejection> {
        Dynamics::resolve(
            &self.aux_default_dynamics,
            &self.aux_max_dynamics,
            c,
            who,
            "constraint",
        )
    }

    /// A mover with the spec defaults at (x, y, c).
    pub fn new(name: &str, x: f64, y: f64, c: f64) -> Self {
        MoverConfig {
            name: name.into(),
            oid: 0,
            initial_pose: InitialPose { x, y, c },
            part_oid: 0,
            width: d_size(),
            height: d_size(),
            c_min: d_c_min(),
            c_max: d_c_max(),
            c_modulus: d_modulus(),
            c_modulo_tolerance: 0.0,
            default_dynamics: d_default_dyn(),
            max_dynamics: d_max_dyn(),
            c_default_dynamics: d_c_default_dyn(),
            c_max_dynamics: d_c_max_dyn(),
            aux_default_dynamics: d_aux_dyn(),
            aux_max_dynamics: d_aux_dyn(),
            z_range: d_z_range(),
            a_range: d_ab_range(),
            b_range: d_ab_range(),
        }
    }
}

/// `groups:` entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupConfig {
    /// Name used in commands.
    pub name: String,
    /// OID (0 → [`AUTO_GROUP_OID`] + index).
    #[serde(default)]
    pub oid: u32,
}

/// `axes:` entry: a virtual master axis (§5.8.4).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VirtualAxisConfig {
    /// Name used in commands.
    pub name: String,
    /// OID (0 → [`AUTO_AXIS_OID`] + index).
    #[serde(default)]
    pub oid: u32,
}

/// "Collision range mode" of a track (§1.6, §5.6.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CollisionRangeMode {
    /// The track computes its ranges at switches (default).
    #[default]
    Automatic,
    /// `collision_range_start` / `collision_range_end` are used.
    Manual,
}

/// `tracks:` entry (§1.6 init parameters).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackConfig {
    /// Name used in commands.
    pub name: String,
    /// OID (0 → [`AUTO_TRACK_OID`] + index).
    #[serde(default)]
    pub oid: u32,
    /// Part the track is fixed to (V3.2.60; required when more than one part exists).
    #[serde(default)]
    pub part_oid: u32,
    /// "Starts from tracks" (V3.1.10.44): StartFromTrack(Advanced) calls, before the geometry.
    #[serde(default)]
    pub starts_from: Vec<TrackLinkConfig>,
    /// "Geometric information" (V3.1.10.44): AppendPosition / AppendLine / AppendCircle
    /// calls in this order; points in the system of the track's part (§1.6).
    #[serde(default)]
    pub geometry: Vec<TrackGeometryItem>,
    /// "Ends at tracks": EndAtTrack(Advanced) calls, after the geometry.
    #[serde(default)]
    pub ends_at: Vec<TrackLinkConfig>,
    /// "Closed loop": CloseLoop after everything else.
    #[serde(default)]
    pub closed_loop: bool,
    /// "Maximal mover width" \[mm\] (default 155).
    #[serde(default = "d_size")]
    pub max_mover_width: f64,
    /// "Maximal mover height" \[mm\] (default 155).
    #[serde(default = "d_size")]
    pub max_mover_height: f64,
    /// "Check collision against static objects" (default FALSE): in a group the track must
    /// lie on the stators and keep clear of the other member tracks.
    #[serde(default)]
    pub check_static_collision: bool,
    /// "Collision range mode" (default automatic).
    #[serde(default)]
    pub collision_range_mode: CollisionRangeMode,
    /// "Collision range at start" \[mm\] (manual mode).
    #[serde(default)]
    pub collision_range_start: f64,
    /// "Collision range at end" \[mm\] (manual mode).
    #[serde(default)]
    pub collision_range_end: f64,
}

impl TrackConfig {
    /// Checks the collision init parameters (§1.6); `key` names the track in messages.
    pub(crate) fn check_init_params(&self, key: &str) -> Result<(), Rejection> {
        positive(&format!("{key}.max_mover_width"), self.max_mover_width)?;
        positive(&format!("{key}.max_mover_height"), self.max_mover_height)?;
        for (f, v) in [
            ("collision_range_start", self.collision_range_start),
            ("collision_range_end", self.collision_range_end),
        ] {
            non_negative(&format!("{key}.{f}"), v)?;
            if v != 0.0 && self.collision_range_mode == CollisionRangeMode::Automatic {
                return Err(bad(
                    &format!("{key}.{f}"),
                    v,
                    "used only with collision_range_mode: manual",
                ));
            }
        }
        Ok(())
    }
}

impl Default for TrackConfig {
    fn default() -> Self {
        TrackConfig {
            name: String::new(),
            oid: 0,
            part_oid: 0,
            starts_from: vec![],
            geometry: vec![],
            ends_at: vec![],
            closed_loop: false,
            max_mover_width: d_size(),
            max_mover_height: d_size(),
            check_static_collision: false,
            collision_range_mode: CollisionRangeMode::Automatic,
            collision_range_start: 0.0,
            collision_range_end: 0.0,
        }
    }
}

/// One element of a track's "Geometric information": the geometry command it stands for
/// (§3.3), written as a one-key map `{line: {...}}`, `{circle: {...}}` or `{position: {...}}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "GeometryItemMap", into = "GeometryItemMap")]
pub enum TrackGeometryItem {
    /// `AppendPosition`.
    Position(TrackPositionConfig),
    /// `AppendLine`.
    Line(TrackLineConfig),
    /// `AppendCircle`.
    Circle(TrackCircleConfig),
}

/// `AppendPosition(position)`: the point becomes the new end, reached with heading `c`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackPositionConfig {
    /// x \[mm\].
    pub x: f64,
    /// y \[mm\].
    pub y: f64,
    /// Heading \[deg\] (default 0).
    #[serde(default)]
    pub c: f64,
}

/// `AppendLine(start, end)`; points `[x, y]` \[mm\].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackLineConfig {
    /// Line start.
    pub start: [f64; 2],
    /// Line end.
    pub end: [f64; 2],
}

/// `AppendCircle(start, end, center, clockwise)`; start = end is a full circle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackCircleConfig {
    /// Arc start.
    pub start: [f64; 2],
    /// Arc end.
    pub end: [f64; 2],
    /// Centre.
    pub center: [f64; 2],
    /// Sense of rotation (default counter-clockwise).
    #[serde(default)]
    pub clockwise: bool,
}

/// The YAML form of a [`TrackGeometryItem`]: exactly one of the keys.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct GeometryItemMap {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<TrackPositionConfig>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    line: Option<TrackLineConfig>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    circle: Option<TrackCircleConfig>,
}

impl TryFrom<GeometryItemMap> for TrackGeometryItem {
    type Error = &'static str;
    fn try_from(m: GeometryItemMap) -> Result<Self, Self::Error> {
        match (m.position, m.line, m.circle) {
            (Some(p), None, None) => Ok(TrackGeometryItem::Position(p)),
            (None, Some(l), None) => Ok(TrackGeometryItem::Line(l)),
            (None, None, Some(c)) => Ok(TrackGeometryItem::Circle(c)),
            _ => Err("a geometry element needs exactly one of `position`, `line`, `circle`"),
        }
    }
}

impl From<TrackGeometryItem> for GeometryItemMap {
    fn from(g: TrackGeometryItem) -> Self {
        let mut m = GeometryItemMap::default();
        match g {
            TrackGeometryItem::Position(p) => m.position = Some(p),
            TrackGeometryItem::Line(l) => m.line = Some(l),
            TrackGeometryItem::Circle(c) => m.circle = Some(c),
        }
        m
    }
}

/// An entry of "Starts from tracks" / "Ends at tracks": the other track's name (the plain
/// method) or the Advanced method with its options (§5.12).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum TrackLinkConfig {
    /// `StartFromTrack(other)` / `EndAtTrack(other)`.
    Plain(String),
    /// `StartFromTrackAdvanced` / `EndAtTrackAdvanced`.
    Advanced(TrackLinkAdvancedConfig),
}

/// `{track, this_track_part_position_index, other_track_part_position_index,
/// link_only_in_specified_part_positions}` of an Advanced link.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackLinkAdvancedConfig {
    /// The other track.
    pub track: String,
    /// Position index of this track's part (0 = current).
    #[serde(default)]
    pub this_track_part_position_index: u32,
    /// Position index of the other track's part (0 = current).
    #[serde(default)]
    pub other_track_part_position_index: u32,
    /// The link exists only in exactly these part positions.
    #[serde(default)]
    pub link_only_in_specified_part_positions: bool,
}

impl TrackConfig {
    /// A track with an automatic OID and no part.
    pub fn new(name: &str) -> Self {
        TrackConfig {
            name: name.into(),
            ..Default::default()
        }
    }
}

fn bad(key: &str, value: impl std::fmt::Display, why: &str) -> Rejection {
    reject(
        ErrorId::VALUE_OUT_OF_RANGE,
        format!("config {key} = {value}: {why}"),
    )
}

fn positive(key: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(bad(key, v, "must be a positive finite number"))
    }
}

fn non_negative(key: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(bad(key, v, "must be a finite number >= 0"))
    }
}

fn dynamics(key: &str, d: &Dynamics) -> Result<(), Rejection> {
    for (f, v) in d.fields() {
        positive(&format!("{key}.{f}"), v)?;
    }
    Ok(())
}

fn range(key: &str, r: [f64; 2]) -> Result<(), Rejection> {
    if r[0].is_finite() && r[1].is_finite() && r[0] <= r[1] {
        Ok(())
    } else {
        Err(bad(
            key,
            format!("[{}, {}]", r[0], r[1]),
            "must be [min, max] with min <= max",
        ))
    }
}

impl PlanarConfig {
    /// OIDs after auto-assignment: (environment, movers, groups).
    pub(crate) fn resolved_oids(&self) -> (u32, Vec<u32>, Vec<u32>) {
        let env = if self.environment.oid == 0 {
            AUTO_ENVIRONMENT_OID
        } else {
            self.environment.oid
        };
        let movers = self
            .movers
            .iter()
            .enumerate()
            .map(|(i, m)| {
                if m.oid == 0 {
                    AUTO_MOVER_OID + i as u32 + 1
                } else {
                    m.oid
                }
            })
            .collect();
        let groups = self
            .groups
            .iter()
            .enumerate()
            .map(|(i, g)| {
                if g.oid == 0 {
                    AUTO_GROUP_OID + i as u32 + 1
                } else {
                    g.oid
                }
            })
            .collect();
        (env, movers, groups)
    }

    /// Checks every value; the error names the key and the value.
    pub fn validate(&self) -> Result<(), Rejection> {
        positive("cycle_time", self.cycle_time)?;
        non_negative("enable_time", self.enable_time)?;
        non_negative("disable_time", self.disable_time)?;
        non_negative("reset_time", self.reset_time)?;
        non_negative("error_pending_time", self.error_pending_time)?;
        non_negative("part_move_time", self.part_move_time)?;
        if self.esg_timeout_cycles == 0 {
            return Err(bad("esg_timeout_cycles", 0, "must be >= 1"));
        }
        // A configured OID inside the automatic block could clash with an automatic one.
        let configured = std::iter::once(("environment.oid".to_string(), self.environment.oid))
            .chain(
                self.coordinate_systems
                    .iter()
                    .enumerate()
                    .map(|(i, o)| (format!("coordinate_systems[{i}]"), *o)),
            )
            .chain(
                self.parts
                    .iter()
                    .enumerate()
                    .map(|(i, p)| (format!("parts[{i}].oid"), p.oid)),
            )
            .chain(
                self.movers
                    .iter()
                    .enumerate()
                    .map(|(i, m)| (format!("movers[{i}].oid"), m.oid)),
            )
            .chain(
                self.groups
                    .iter()
                    .enumerate()
                    .map(|(i, g)| (format!("groups[{i}].oid"), g.oid)),
            )
            .chain(
                self.tracks
                    .iter()
                    .enumerate()
                    .map(|(i, t)| (format!("tracks[{i}].oid"), t.oid)),
            )
            .chain(
                self.axes
                    .iter()
                    .enumerate()
                    .map(|(i, a)| (format!("axes[{i}].oid"), a.oid)),
            );
        for (key, oid) in configured {
            if AUTO_OID_BLOCK.contains(&oid) {
                return Err(bad(
                    &key,
                    format!("0x{oid:08X}"),
                    "0xFE000000..0xFEFFFFFF is reserved for automatic OIDs",
                ));
            }
        }
        let mut oids: HashSet<u32> = HashSet::new();
        let mut uniq = |key: &str, oid: u32| -> Result<(), Rejection> {
            if oid == 0 {
                return Err(bad(key, oid, "OID must be non-zero"));
            }
            if !oids.insert(oid) {
                return Err(bad(key, format!("0x{oid:08X}"), "OID used twice"));
            }
            Ok(())
        };
        for (i, cs) in self.coordinate_systems.iter().enumerate() {
            uniq(&format!("coordinate_systems[{i}]"), *cs)?;
        }
        let (env_oid, mover_oids, group_oids) = self.resolved_oids();
        uniq("environment.oid", env_oid)?;
        if !self.parts.is_empty() && self.coordinate_systems.is_empty() {
            return Err(bad(
                "coordinate_systems",
                "[]",
                "parts need at least one coordinate system",
            ));
        }
        let mut names: HashSet<&str> = HashSet::new();
        for (i, p) in self.parts.iter().enumerate() {
            let key = format!("parts[{i}]");
            uniq(&format!("{key}.oid"), p.oid)?;
            if p.name.is_empty() || !names.insert(&p.name) {
                return Err(bad(
                    &format!("{key}.name"),
                    &p.name,
                    "names must be non-empty and unique among parts",
                ));
            }
            if p.tiles.is_empty() {
                return Err(bad(
                    &format!("{key}.tiles"),
                    "[]",
                    "a part needs at least one tile",
                ));
            }
            for (k, t) in p.tiles.iter().enumerate() {
                if !t[0].is_finite() || !t[1].is_finite() {
                    return Err(bad(
                        &format!("{key}.tiles[{k}]"),
                        format!("{t:?}"),
                        "must be finite",
                    ));
                }
                for (l, u) in p.tiles.iter().enumerate().take(k) {
                    if tiles_overlap(V2::new(t[0], t[1]), V2::new(u[0], u[1])) {
                        return Err(bad(
                            &format!("{key}.tiles[{k}]"),
                            format!("{t:?}"),
                            &format!("overlaps tiles[{l}]"),
                        ));
                    }
                }
            }
            if p.positions.is_empty() {
                return Err(bad(
                    &format!("{key}.positions"),
                    "{}",
                    "a part needs at least one position",
                ));
            }
            for (idx, pos) in &p.positions {
                let pk = format!("{key}.positions.{idx}");
                if *idx == 0 {
                    return Err(bad(&pk, idx, "position indices are 1-based"));
                }
                if !self.coordinate_systems.contains(&pos.cs) {
                    return Err(bad(
                        &format!("{pk}.cs"),
                        format!("0x{:08X}", pos.cs),
                        "unknown coordinate system",
                    ));
                }
                if !pos.x.is_finite() || !pos.y.is_finite() {
                    return Err(bad(
                        &pk,
                        format!("({}, {})", pos.x, pos.y),
                        "must be finite",
                    ));
                }
            }
            if !p.positions.contains_key(&p.initial_index) {
                return Err(bad(
                    &format!("{key}.initial_index"),
                    p.initial_index,
                    "no such position",
                ));
            }
        }
        // Parts never overlap at their initial positions (§1.3).
        let world_tiles = |p: &PartConfig| -> (u32, Vec<V2>) {
            let pos = p.positions[&p.initial_index];
            (
                pos.cs,
                p.tiles
                    .iter()
                    .map(|t| V2::new(t[0] + pos.x, t[1] + pos.y))
                    .collect(),
            )
        };
        for (i, a) in self.parts.iter().enumerate() {
            let (ca, ta) = world_tiles(a);
            for b in self.parts.iter().take(i) {
                let (cb, tb) = world_tiles(b);
                if ca == cb && ta.iter().any(|x| tb.iter().any(|y| tiles_overlap(*x, *y))) {
                    return Err(bad(
                        &format!("parts[{i}].initial_index"),
                        a.initial_index,
                        &format!("part '{}' overlaps part '{}'", a.name, b.name),
                    ));
                }
            }
        }
        let mut names: HashSet<&str> = HashSet::new();
        let mut placed: Vec<(u32, ConvexPolygon, &str)> = vec![];
        for (i, m) in self.movers.iter().enumerate() {
            let key = format!("movers[{i}]");
            uniq(&format!("{key}.oid"), mover_oids[i])?;
            if m.name.is_empty() || !names.insert(&m.name) {
                return Err(bad(
                    &format!("{key}.name"),
                    &m.name,
                    "names must be non-empty and unique among movers",
                ));
            }
            for (f, v) in [
                ("x", m.initial_pose.x),
                ("y", m.initial_pose.y),
                ("c", m.initial_pose.c),
            ] {
                if !v.is_finite() {
                    return Err(bad(&format!("{key}.initial_pose.{f}"), v, "must be finite"));
                }
            }
            positive(&format!("{key}.width"), m.width)?;
            positive(&format!("{key}.height"), m.height)?;
            if !(m.c_min.is_finite()
                && m.c_max.is_finite()
                && m.c_min <= 0.0
                && m.c_max >= 0.0
                && m.c_max - m.c_min < 90.0)
            {
                return Err(bad(
                    &format!("{key}.c_min/c_max"),
                    format!("[{}, {}]", m.c_min, m.c_max),
                    "need c_min <= 0 <= c_max and a window narrower than 90",
                ));
            }
            positive(&format!("{key}.c_modulus"), m.c_modulus)?;
            non_negative(&format!("{key}.c_modulo_tolerance"), m.c_modulo_tolerance)?;
            if m.c_modulo_tolerance >= m.c_modulus / 2.0 {
                return Err(bad(
                    &format!("{key}.c_modulo_tolerance"),
                    m.c_modulo_tolerance,
                    "must be below half the modulus",
                ));
            }
            dynamics(&format!("{key}.default_dynamics"), &m.default_dynamics)?;
            dynamics(&format!("{key}.max_dynamics"), &m.max_dynamics)?;
            dynamics(&format!("{key}.c_default_dynamics"), &m.c_default_dynamics)?;
            dynamics(&format!("{key}.c_max_dynamics"), &m.c_max_dynamics)?;
            dynamics(
                &format!("{key}.aux_default_dynamics"),
                &m.aux_default_dynamics,
            )?;
            dynamics(&format!("{key}.aux_max_dynamics"), &m.aux_max_dynamics)?;
            range(&format!("{key}.z_range"), m.z_range)?;
            range(&format!("{key}.a_range"), m.a_range)?;
            range(&format!("{key}.b_range"), m.b_range)?;
            // Where the mover starts: (cs, x, y) in its coordinate system.
            let (cs, x, y) = if self.parts.is_empty() {
                if m.part_oid != 0 {
                    return Err(bad(
                        &format!("{key}.part_oid"),
                        format!("0x{:08X}", m.part_oid),
                        "no parts are configured",
                    ));
                }
                (
                    self.coordinate_systems.first().copied().unwrap_or(0),
                    m.initial_pose.x,
                    m.initial_pose.y,
                )
            } else {
                let part = if m.part_oid == 0 {
                    if self.parts.len() > 1 {
                        return Err(bad(
                            &format!("{key}.part_oid"),
                            0,
                            "required when more than one part exists",
                        ));
                    }
                    &self.parts[0]
                } else {
                    self.parts
                        .iter()
                        .find(|p| p.oid == m.part_oid)
                        .ok_or_else(|| {
                            bad(
                                &format!("{key}.part_oid"),
                                format!("0x{:08X}", m.part_oid),
                                "unknown part",
                            )
                        })?
                };
                let pos = part.positions[&part.initial_index];
                let on = part.tiles.iter().any(|t| {
                    m.initial_pose.x >= t[0]
                        && m.initial_pose.x <= t[0] + STATOR_SIDE
                        && m.initial_pose.y >= t[1]
                        && m.initial_pose.y <= t[1] + STATOR_SIDE
                });
                if !on {
                    return Err(bad(
                        &format!("{key}.initial_pose"),
                        format!("({}, {})", m.initial_pose.x, m.initial_pose.y),
                        &format!("not on part '{}'", part.name),
                    ));
                }
                (pos.cs, pos.x + m.initial_pose.x, pos.y + m.initial_pose.y)
            };
            let fp = ConvexPolygon::rect(V2::new(x, y), m.width, m.height, m.initial_pose.c);
            for (ocs, other, oname) in &placed {
                if *ocs == cs && fp.intersects(other) {
                    return Err(bad(
                        &format!("{key}.initial_pose"),
                        format!("({}, {})", m.initial_pose.x, m.initial_pose.y),
                        &format!("footprint overlaps mover '{oname}'"),
                    ));
                }
            }
            placed.push((cs, fp, &m.name));
        }
        let mut names: HashSet<&str> = HashSet::new();
        for (i, g) in self.groups.iter().enumerate() {
            let key = format!("groups[{i}]");
            uniq(&format!("{key}.oid"), group_oids[i])?;
            if g.name.is_empty() || !names.insert(&g.name) {
                return Err(bad(
                    &format!("{key}.name"),
                    &g.name,
                    "names must be non-empty and unique among groups",
                ));
            }
        }
        let mut tnames: HashSet<&str> = HashSet::new();
        for (i, t) in self.tracks.iter().enumerate() {
            let key = format!("tracks[{i}]");
            uniq(&format!("{key}.oid"), self.track_oid(i))?;
            if t.name.is_empty() || !tnames.insert(&t.name) {
                return Err(bad(
                    &format!("{key}.name"),
                    &t.name,
                    "names must be non-empty and unique among tracks",
                ));
            }
            t.check_init_params(&key)?;
            if t.part_oid != 0 && !self.parts.iter().any(|p| p.oid == t.part_oid) {
                return Err(bad(
                    &format!("{key}.part_oid"),
                    format!("0x{:08X}", t.part_oid),
                    "no such part",
                ));
            }
        }
        let mut anames: HashSet<&str> = HashSet::new();
        for (i, a) in self.axes.iter().enumerate() {
            let key = format!("axes[{i}]");
            uniq(&format!("{key}.oid"), self.axis_oid(i))?;
            if a.name.is_empty() || !anames.insert(&a.name) {
                return Err(bad(
                    &format!("{key}.name"),
                    &a.name,
                    "names must be non-empty and unique among axes",
                ));
            }
        }
        Ok(())
    }

    /// OID of virtual axis `i`.
    pub(crate) fn axis_oid(&self, i: usize) -> u32 {
        match self.axes[i].oid {
            0 => AUTO_AXIS_OID + i as u32 + 1,
            o => o,
        }
    }

    /// OID of track `i` (configured or automatic).
    pub(crate) fn track_oid(&self, i: usize) -> u32 {
        match self.tracks[i].oid {
            0 => AUTO_TRACK_OID + i as u32 + 1,
            o => o,
        }
    }
}
