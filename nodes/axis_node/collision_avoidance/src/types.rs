//! CA group configuration, enumerations, commands and published state
//! (collision_avoidance.md §3.1, §4.1, §5, §6, §7.2, §9.5).

use motion_core::{CmdId, ErrorId, Rejection};
use serde::{Deserialize, Serialize};

pub use super::errors;

macro_rules! ca_enum {
    ($(#[$m:meta])* $name:ident : $field:literal, $err:expr, { $($(#[$vm:meta])* $var:ident = $val:expr),+ $(,)? }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
        pub enum $name {
            $($(#[$vm])* $var = $val),+
        }
        impl $name {
            /// Converts the manual's numeric value; unknown values are refused with the
            /// spec's error id (§7.2) and a message naming field and value.
            pub fn from_raw(value: u32) -> Result<Self, Rejection> {
                match value {
                    $(v if v == $val => Ok($name::$var),)+
                    _ => Err(Rejection::new(
                        $err,
                        format!("{} = {} is not a valid {}", $field, value, stringify!($name)),
                    )),
                }
            }
            /// The manual's numeric value.
            pub fn raw(self) -> u32 {
                self as u32
            }
        }
    };
}

ca_enum! {
    /// MC_GAP_CONTROL_MODE (per command, §1.4).
    GapControlMode: "GapControlMode", errors::INVALID_MODE, {
        /// 0: the group's `default_gap_control_mode`.
        #[default]
        GroupDefault = 0,
        /// 1: brick-wall control, followers fan out.
        Standard = 1,
        /// 2: predict the predecessor's hardest stop, gaps nearly constant.
        Fast = 2,
        /// 3: no gap control for this axis' own motion.
        None = 3,
    }
}

ca_enum! {
    /// MC_DEFAULT_GAP_CONTROL_MODE (group parameter).
    DefaultGapControlMode: "default_gap_control_mode", errors::INVALID_MODE, {
        /// 1 (default).
        #[default]
        Standard = 1,
        /// 2.
        Fast = 2,
    }
}

ca_enum! {
    /// MC_GAP_CONTROL_DIRECTION (§1.5; values are the spec's proposal).
    GapControlDirection: "gap_control_direction", errors::INVALID_MODE, {
        /// 1: only the successor is responsible for its gap (default).
        #[default]
        Positive = 1,
        /// 2: both neighbours are responsible (reverse motion protected).
        Both = 2,
    }
}

ca_enum! {
    /// MC_DIRECTION of MC_MoveAbsoluteCA (§5.2.3).
    CaDirection: "Direction", errors::INVALID_MODE, {
        /// 0: Position is an absolute target (default).
        #[default]
        NonModulo = 0,
        /// 1.
        Positive = 1,
        /// 2.
        ShortestWay = 2,
        /// 3.
        Negative = 3,
    }
}

ca_enum! {
    /// MC_SYNC_STRATEGY of MC_GearInPosCA (§5.5.3).
    SyncStrategy: "SyncStrategy", errors::INVALID_MODE, {
        /// 1 (preset): start as late as possible with the full sync dynamics.
        #[default]
        Late = 1,
        /// 2: start at once with reduced dynamics, arrive when the master reaches its sync position.
        Slow = 2,
        /// 3: start at once with full dynamics, InSync as early as possible.
        Early = 3,
    }
}

ca_enum! {
    /// MC_GearInPosDefaultDynamicsAfterSync (group parameter, §5.5.4).
    DynamicsAfterSync: "gear_in_pos_default_dynamics_after_sync", errors::INVALID_MODE, {
        /// 0: slave axis maxima, jerk unlimited.
        MaximumSlaveDynamics = 0,
        /// 1 (default): the block's own Velocity/Acceleration/Deceleration/Jerk.
        #[default]
        JobDynamics = 1,
    }
}

ca_enum! {
    /// MC_SYNC_MODE of MC_GearInPosCA: how SlaveSyncPosition is read on a ring (§5.5.3).
    SyncMode: "SyncMode", errors::INVALID_MODE, {
        /// 0 (preset): absolute slave position.
        #[default]
        NonModulo = 0,
        /// 1: next occurrence of the modulo position in positive direction.
        Positive = 1,
        /// 3: next occurrence in negative direction.
        Negative = 3,
    }
}

ca_enum! {
    /// MC_MASTER_SIGNAL_CORRECTION of MC_GearInPosCA (§5.5.2).
    MasterSignalCorrection: "MasterSignalCorrection", errors::INVALID_MODE, {
        /// 0 (preset): correct the master signal automatically.
        #[default]
        Auto = 0,
        /// 1: use the raw master signal.
        None = 1,
    }
}

ca_enum! {
    /// What an axis of a CA group is doing (`command_kind` of CaAxisState, §9.5; values are
    /// the simulator's).
    CaCommandKind: "command_kind", errors::INVALID_MODE, {
        /// 0: no command, not moving by itself.
        #[default]
        None = 0,
        /// 1: MC_MoveAbsoluteCA.
        MoveAbsolute = 1,
        /// 2: MC_MoveRelativeCA.
        MoveRelative = 2,
        /// 3: MC_HaltCA (also a cancelled goal's halt).
        Halt = 3,
        /// 4: MC_GearInPosCA.
        GearInPos = 4,
        /// 5: braking for MC_GroupHalt.
        GroupHalt = 5,
        /// 6: braking for MC_GroupStop.
        GroupStop = 6,
        /// 7: braking after a group error (ErrorStop).
        ErrorStop = 7,
        /// 8: standby gap control of an idle axis (§1.7).
        StandbyGapControl = 8,
    }
}

ca_enum! {
    /// MC_BUFFER_MODE as accepted by the CA blocks (§5.0): only Aborting and Buffered.
    CaBufferMode: "BufferMode", errors::INVALID_BUFFER_MODE, {
        /// 0 (default): replace the running command at once.
        #[default]
        Aborting = 0,
        /// 1: start when the running command is Done.
        Buffered = 1,
    }
}

/// MC_LREAL: a value or one of the manual's markers (§5.0, ROS encoding §9.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum McLreal {
    /// Not given: the input's preset (MC_INVALID for mandatory inputs ⇒ error).
    #[default]
    Unset,
    /// A number.
    Value(f64),
    /// MC_DEFAULT.
    Default,
    /// MC_MAXIMUM.
    Maximum,
    /// MC_IGNORE.
    Ignore,
}

/// `UDINT_TO_IDENTINGROUP(id)`: the per-group identifier of a PTP axis (§5.10); no spatial
/// meaning.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct IdentInGroup(pub u32);

/// UDINT_TO_IDENTINGROUP.
pub fn udint_to_identingroup(id: u32) -> IdentInGroup {
    IdentInGroup(id)
}

/// CA group parameters (§3.1); `Default` is the spec's table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CaGroupConfig {
    /// Length of the rail; modulo factor on a ring \[mm\] (> 0).
    pub rail_length: f64,
    /// Closed rail: CA also between the last and the first axis.
    pub rail_is_ring: bool,
    /// Group default gap control algorithm.
    pub default_gap_control_mode: DefaultGapControlMode,
    /// Who is responsible for a gap.
    pub gap_control_direction: GapControlDirection,
    /// TRUE: CA moves commanded axes back to re-establish a too small gap (§1.7).
    pub active_gap_establishing: bool,
    /// TRUE: gap control also for idle axes (§1.7).
    pub standby_gap_control: bool,
    /// Gap for standby control and for commands with Gap MC_DEFAULT \[mm\] (≥ 0).
    pub default_gap: f64,
    /// Standby gap control velocity \[mm/s\] (> 0).
    pub default_velocity: f64,
    /// Standby gap control acceleration \[mm/s²\] (≥ 1).
    pub default_acceleration: f64,
    /// Standby gap control deceleration \[mm/s²\] (≥ 1).
    pub default_deceleration: f64,
    /// Standby gap control jerk \[mm/s³\] (≥ 100).
    pub default_jerk: f64,
    /// Override ramp time \[s\] (≥ 0, §1.11).
    pub override_ramp_time: f64,
    /// After-sync defaults of MC_GearInPosCA (§5.5.4).
    pub gear_in_pos_default_dynamics_after_sync: DynamicsAfterSync,
    /// Rail geometry, mover templates, parts and tracks (§3.4).
    pub geometry: super::geometry::CaGeometry,
}

impl Default for CaGroupConfig {
    fn default() -> Self {
        CaGroupConfig {
            rail_length: 3000.0,
            rail_is_ring: true,
            default_gap_control_mode: DefaultGapControlMode::Standard,
            gap_control_direction: GapControlDirection::Positive,
            active_gap_establishing: false,
            standby_gap_control: false,
            default_gap: 100.0,
            default_velocity: 500.0,
            default_acceleration: 5000.0,
            default_deceleration: 5000.0,
            default_jerk: 50000.0,
            override_ramp_time: 0.1,
            gear_in_pos_default_dynamics_after_sync: DynamicsAfterSync::JobDynamics,
            geometry: super::geometry::CaGeometry::default(),
        }
    }
}

impl CaGroupConfig {
    /// Startup validation (§3.1): the message names group, key and value.
    pub fn validate(&self, group: &str) -> Result<(), Rejection> {
        let checks = [
            ("rail_length", self.rail_length, self.rail_length > 0.0),
            ("default_gap", self.default_gap, self.default_gap >= 0.0),
            (
                "default_velocity",
                self.default_velocity,
                self.default_velocity > 0.0,
            ),
            (
                "default_acceleration",
                self.default_acceleration,
                self.default_acceleration >= 1.0,
            ),
            (
                "default_deceleration",
                self.default_deceleration,
                self.default_deceleration >= 1.0,
            ),
            (
                "default_jerk",
                self.default_jerk,
                self.default_jerk >= 100.0,
            ),
            (
                "override_ramp_time",
                self.override_ramp_time,
                self.override_ramp_time >= 0.0,
            ),
        ];
        for (key, v, ok) in checks {
            if !(ok && v.is_finite()) {
                return Err(Rejection::new(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("CA group '{group}': {key} = {v} is out of range"),
                ));
            }
        }
        self.geometry.validate(group, self.rail_length)?;
        if self.rail_is_ring && self.default_gap >= self.rail_length {
            return Err(Rejection::new(
                ErrorId::VALUE_OUT_OF_RANGE,
                format!(
                    "CA group '{group}': default_gap = {} must be below rail_length on a ring",
                    self.default_gap
                ),
            ));
        }
        Ok(())
    }
}

/// MC_MoveAbsoluteCA (§5.2).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MoveAbsoluteCa {
    /// Axis name.
    pub axis: String,
    /// ContinuousUpdate: later Gap changes take effect (`UpdateGap`).
    pub continuous_update: bool,
    /// Position \[mm\] (mandatory).
    pub position: McLreal,
    /// Velocity \[mm/s\] (mandatory).
    pub velocity: McLreal,
    /// Acceleration \[mm/s²\].
    pub acceleration: McLreal,
    /// Deceleration \[mm/s²\].
    pub deceleration: McLreal,
    /// Jerk \[mm/s³\].
    pub jerk: McLreal,
    /// Gap \[mm\] (MC_DEFAULT ⇒ group `default_gap`).
    pub gap: McLreal,
    /// BufferMode.
    pub buffer_mode: CaBufferMode,
    /// Direction (modulo directions only on a ring).
    pub direction: CaDirection,
    /// Options.GapControlMode.
    pub gap_control_mode: GapControlMode,
    /// Options.AdditionalTurns (Positive/Negative only).
    pub additional_turns: u32,
    /// Options.PositionReferenceSystem: 0 = motor path; a registered template OID = Position
    /// is an offset-path coordinate (§5.9; modulo directions: modulo the offset lap).
    pub position_reference_system: u32,
    /// Options.DynamicsReferenceSystem: a registered template OID = Velocity/Acc/Dec/Jerk
    /// apply on its offset path (§5.9).
    pub dynamics_reference_system: u32,
}

/// MC_MoveRelativeCA (§5.3).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MoveRelativeCa {
    /// Axis name.
    pub axis: String,
    /// ContinuousUpdate.
    pub continuous_update: bool,
    /// Distance \[mm\] (mandatory, signed).
    pub distance: McLreal,
    /// Velocity \[mm/s\] (mandatory).
    pub velocity: McLreal,
    /// Acceleration \[mm/s²\].
    pub acceleration: McLreal,
    /// Deceleration \[mm/s²\].
    pub deceleration: McLreal,
    /// Jerk \[mm/s³\].
    pub jerk: McLreal,
    /// Gap \[mm\].
    pub gap: McLreal,
    /// BufferMode.
    pub buffer_mode: CaBufferMode,
    /// Options.GapControlMode.
    pub gap_control_mode: GapControlMode,
    /// Options.PositionReferenceSystem: a registered template OID = Distance on its offset path.
    pub position_reference_system: u32,
    /// Options.DynamicsReferenceSystem (see [`MoveAbsoluteCa`]).
    pub dynamics_reference_system: u32,
}

/// MC_HaltCA (§5.4): always aborting.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HaltCa {
    /// Axis name.
    pub axis: String,
    /// Deceleration \[mm/s²\].
    pub deceleration: McLreal,
    /// Jerk \[mm/s³\].
    pub jerk: McLreal,
    /// Gap \[mm\].
    pub gap: McLreal,
    /// Options.GapControlMode.
    pub gap_control_mode: GapControlMode,
    /// Options.DynamicsReferenceSystem (see [`MoveAbsoluteCa`]).
    pub dynamics_reference_system: u32,
}

/// MC_GearInPosCA (§5.5): the slave (a CA group axis) follows
/// `s* = SlaveSyncPosition + ratio · (m − MasterSyncPosition)` of the master's set position.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GearInPosCa {
    /// Master axis (any axis, inside or outside the group).
    pub master: String,
    /// Slave axis (CA group member).
    pub slave: String,
    /// ContinuousUpdate (only the Gap).
    pub continuous_update: bool,
    /// RatioNumerator (Unset/DEFAULT = 1).
    pub ratio_numerator: McLreal,
    /// RatioDenumerator (≠ 0; send 1 for the preset).
    pub ratio_denumerator: u16,
    /// MasterSyncPosition \[mm\] (mandatory).
    pub master_sync_position: McLreal,
    /// SlaveSyncPosition \[mm\] (mandatory).
    pub slave_sync_position: McLreal,
    /// SyncStrategy.
    pub sync_strategy: SyncStrategy,
    /// SyncMode (modulo modes only on a ring).
    pub sync_mode: SyncMode,
    /// MasterStartDistance \[mm\]: Unset/IGNORE = start when Active; > 0: start once
    /// master ≥ MasterSyncPosition − d; < 0: once master ≤ MasterSyncPosition − d.
    pub master_start_distance: McLreal,
    /// Velocity of the sync phase (mandatory).
    pub velocity: McLreal,
    /// Acceleration of the sync phase.
    pub acceleration: McLreal,
    /// Deceleration of the sync phase.
    pub deceleration: McLreal,
    /// Jerk of the sync phase.
    pub jerk: McLreal,
    /// Gap.
    pub gap: McLreal,
    /// BufferMode.
    pub buffer_mode: CaBufferMode,
    /// Options.GapControlMode.
    pub gap_control_mode: GapControlMode,
    /// Options.MasterVelocityUndershootAllowed, negated (ROS encoding §9.3): TRUE ⇒ during
    /// the sync phase, once the slave has reached the synchronous velocity `ratio · ṁ`, it
    /// never runs slower than that in the sync direction (a slower slave first accelerates).
    /// Both `forbid_…` TRUE ⇒ INVALID_SYNC_OPTIONS.
    pub forbid_master_velocity_undershoot: bool,
    /// Options.MasterVelocityOvershootAllowed, negated: TRUE ⇒ never faster than the
    /// synchronous velocity during the sync phase (a faster slave first decelerates).
    pub forbid_master_velocity_overshoot: bool,
    /// Options.DirectionReversalAllowed, negated: TRUE ⇒ during the sync phase the slave
    /// never moves against the direction of its sync velocity (sign of `ratio · ṁ`).
    #[serde(default)]
    pub forbid_direction_reversal: bool,
    /// Options.MinimalSlavePosition \[mm\]: lowest absolute (motor-path) slave position
    /// during the sync phase; Unset/IGNORE = none; other markers or a non-finite value ⇒
    /// INVALID_SYNC_OPTIONS.
    #[serde(default)]
    pub minimal_slave_position: McLreal,
    /// Options.SlaveSyncPositionReferenceSystem: 0 = motor path; a mover template OID
    /// registered for the slave = SlaveSyncPosition is an offset-path coordinate (§5.9);
    /// otherwise COMPENSATION_ERROR.
    #[serde(default)]
    pub slave_sync_position_reference_system: u32,
    /// Options.DynamicsReferenceSystem: 0 = motor path; a registered template OID = the
    /// coupling (coupled law, sync and after-sync dynamics) runs on that offset path.
    #[serde(default)]
    pub dynamics_reference_system: u32,
    /// Options.MasterSignalCorrection (master set values are noise-free: both values
    /// behave identically, §5.5.2).
    #[serde(default)]
    pub master_signal_correction: MasterSignalCorrection,
    /// Options.AfterSyncVelocity (Unset/DEFAULT: per group parameter, §5.5.4).
    pub after_sync_velocity: McLreal,
    /// Options.AfterSyncAcceleration.
    pub after_sync_acceleration: McLreal,
    /// Options.AfterSyncDeceleration.
    pub after_sync_deceleration: McLreal,
    /// Options.AfterSyncJerk.
    pub after_sync_jerk: McLreal,
    /// Options.OverrideSlaveDynamicRestrictions (Late/Slow): TRUE keeps the cam over the
    /// master position when the master velocity changes (may exceed the FB dynamics); FALSE
    /// re-plans it and fails with SLAVE_CANNOT_SYNC when no feasible cam exists.
    pub override_slave_dynamic_restrictions: bool,
}

/// StartSync / InSync of an MC_GearInPosCA instance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct GearOutputs {
    /// StartSync: synchronising.
    pub start_sync: bool,
    /// InSync: coupled.
    pub in_sync: bool,
}

/// One CA block call (one Execute edge / Enable call).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum CaCommand {
    /// MC_AddAxisToGroup.
    AddAxisToGroup {
        /// AxesGroup.
        group: String,
        /// Axis.
        axis: String,
        /// IdentInGroup (UDINT_TO_IDENTINGROUP).
        ident_in_group: IdentInGroup,
    },
    /// MC_RemoveAxisFromGroup.
    RemoveAxisFromGroup {
        /// AxesGroup.
        group: String,
        /// IdentInGroup.
        ident_in_group: IdentInGroup,
    },
    /// MC_UngroupAllAxes.
    UngroupAllAxes {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupEnable.
    GroupEnable {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupDisable.
    GroupDisable {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupReset.
    GroupReset {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupReadStatus (reply [`CaValue::Status`]).
    GroupReadStatus {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupReadError (reply [`CaValue::GroupErrorId`]).
    GroupReadError {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupSetOverride (Enable-type; reply [`CaValue::Override`]).
    GroupSetOverride {
        /// AxesGroup.
        group: String,
        /// Enable level.
        enable: bool,
        /// VelFactor in [0, 1] (clamped).
        vel_factor: f64,
    },
    /// MC_GroupHalt.
    GroupHalt {
        /// AxesGroup.
        group: String,
        /// Deceleration (DEFAULT/MAXIMUM per axis).
        deceleration: McLreal,
        /// Jerk (IGNORE = unlimited).
        jerk: McLreal,
    },
    /// MC_GroupStop: `execute` TRUE = rising edge; FALSE = falling edge (releases the lock).
    GroupStop {
        /// AxesGroup.
        group: String,
        /// Execute level.
        execute: bool,
        /// Deceleration.
        deceleration: McLreal,
        /// Jerk.
        jerk: McLreal,
    },
    /// MC_MoveAbsoluteCA.
    MoveAbsolute(MoveAbsoluteCa),
    /// MC_MoveRelativeCA.
    MoveRelative(MoveRelativeCa),
    /// MC_HaltCA.
    Halt(HaltCa),
    /// MC_GearInPosCA.
    GearInPos(GearInPosCa),
    /// A later call of a running CA move started with ContinuousUpdate: new Gap (§1.3).
    UpdateGap {
        /// Axis name.
        axis: String,
        /// Gap.
        gap: McLreal,
    },
    /// MC_ActivateTrack (§5.6): later commands use track coordinates; 0 = absolute.
    ActivateTrack {
        /// Axis name.
        axis: String,
        /// TrackId (OTCID).
        track_id: u32,
    },
    /// MC_ReadTrackPositions (§5.7; reply [`CaValue::TrackPositions`]).
    ReadTrackPositions {
        /// Axis name.
        axis: String,
    },
    /// MC_RegisterCompensation (§5.8): CompensationType 1 = geo; id 0 unregisters.
    RegisterCompensation {
        /// Axis name.
        axis: String,
        /// MC_COMPENSATION_TYPE (0 invalid, 1 geo).
        compensation_type: u32,
        /// CompensationId (mover template OID).
        compensation_id: u32,
    },
    /// MC_TransformPosition (§5.9; reply [`CaValue::Position`]).
    TransformPosition {
        /// AxesGroup whose geometry is used.
        group: String,
        /// OriginOid (0 = motor path).
        origin_oid: u32,
        /// DestinationOid (0 = motor path).
        destination_oid: u32,
        /// OriginPosition \[mm\] (mandatory).
        origin_position: McLreal,
    },
    /// Activates/deactivates a mover template at run time (§1.13).
    SetTemplateActive {
        /// AxesGroup.
        group: String,
        /// Template OID.
        oid: u32,
        /// Active.
        active: bool,
    },
    /// Resets `min_gap_margin` of every axis of the group (§8.7).
    ResetDiagnostics {
        /// AxesGroup.
        group: String,
    },
}

/// MC_GROUP_STATE (§4.1, proposal values).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum GroupState {
    /// 1: not enabled.
    #[default]
    GroupDisabled = 1,
    /// 2: enabled, nothing commanded.
    GroupStandby = 2,
    /// 3: a CA command is active or an axis moves.
    GroupMoving = 3,
    /// 4: MC_GroupStop in progress or held.
    GroupStopping = 4,
    /// 5: error while enabled.
    GroupErrorStop = 5,
    /// 7: enabled, some axis' loop open.
    GroupNotReady = 7,
    /// 9: error while disabled (simulator extension).
    GroupErrorDisabled = 9,
}

/// MC_GroupReadStatus outputs (§5.16).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GroupReadStatus {
    /// GroupMoving.
    pub group_moving: bool,
    /// GroupHoming (never).
    pub group_homing: bool,
    /// GroupErrorStop.
    pub group_error_stop: bool,
    /// GroupNotReady.
    pub group_not_ready: bool,
    /// GroupStandby.
    pub group_standby: bool,
    /// GroupStopping.
    pub group_stopping: bool,
    /// GroupDisabled (also TRUE in ErrorDisabled).
    pub group_disabled: bool,
    /// AllAxesStanding.
    pub all_axes_standing: bool,
    /// InPosition (not supported: FALSE).
    pub in_position: bool,
}

/// The answer to an accepted CA block call (the engine turns it into its `AxisReply`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaReply {
    /// Identity of the block instance started by this call.
    pub id: CmdId,
    /// Value of read/enable blocks.
    pub value: Option<CaValue>,
    /// True when the id names a tracked instance whose outputs follow as events.
    pub tracked: bool,
}

/// Values of CA read/enable blocks.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum CaValue {
    /// MC_GroupReadStatus.
    Status(GroupReadStatus),
    /// MC_GroupReadError: GroupErrorId.
    GroupErrorId(u32),
    /// MC_TransformPosition: DestinationPosition.
    Position(f64),
    /// MC_ReadTrackPositions outputs.
    TrackPositions {
        /// Valid.
        valid: bool,
        /// TrackPosition \[mm\].
        track_position: f64,
        /// TrackId (0 = absolute).
        track_id: u32,
        /// PartPosition \[mm\].
        part_position: f64,
        /// PartId (0 = none).
        part_id: u32,
    },
    /// `AxisCommand::ReadFbOutputs` of a CA block instance: its standard outputs and, for a
    /// running MC_GearInPosCA, StartSync / InSync.
    Outputs {
        /// Done/Busy/Active/CommandAborted/Error/ErrorID.
        outputs: motion_core::ExecuteOutputs,
        /// StartSync / InSync of a running coupling (None: not a running MC_GearInPosCA).
        gear: Option<GearOutputs>,
    },
    /// MC_GroupSetOverride: Enabled, ActualVelFactor.
    Override {
        /// Value accepted.
        enabled: bool,
        /// Currently effective factor.
        actual_vel_factor: f64,
    },
}

/// Which CA block an instance belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CaFbKind {
    /// MC_MoveAbsoluteCA.
    MoveAbsolute,
    /// MC_MoveRelativeCA.
    MoveRelative,
    /// MC_HaltCA.
    Halt,
    /// MC_GearInPosCA.
    GearInPos,
    /// MC_GroupHalt.
    GroupHalt,
    /// MC_GroupStop.
    GroupStop,
    /// Administrative blocks (Done at once).
    Admin,
}

/// One axis of a CA group as published (CaAxisState.msg, §9.5).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CaAxisStatus {
    /// Axis name.
    pub name: String,
    /// IdentInGroup.
    pub ident_in_group: u32,
    /// Predecessor name (None: no predecessor).
    pub predecessor: Option<String>,
    /// Absolute set position \[mm\].
    pub position: f64,
    /// Position modulo `rail_length` on a ring (= position on an open rail) \[mm\].
    pub modulo_position: f64,
    /// Set velocity \[mm/s\].
    pub velocity: f64,
    /// Set acceleration \[mm/s²\].
    pub acceleration: f64,
    /// Active CA command (None: idle).
    pub active_command_id: Option<CmdId>,
    /// What the axis is doing (block of the active command, group braking, standby).
    #[serde(default)]
    pub command_kind: CaCommandKind,
    /// Effective gap \[mm\].
    pub gap_target: f64,
    /// Pair gap to the predecessor \[mm\] (NaN if none).
    pub gap_actual: f64,
    /// C4 bounded the motion in the last cycle.
    pub ca_limited: bool,
    /// `gap_actual < gap_target − 1e-6`.
    pub gap_violation: bool,
    /// Minimum of `gap_actual − gap_target` since enable / reset_diagnostics (+inf: none).
    pub min_gap_margin: f64,
    /// Active track (0 = absolute reference).
    pub track_id: u32,
    /// Registered compensation (mover template OID, 0 = none).
    pub compensation_id: u32,
    /// StartSync of the axis' running MC_GearInPosCA (FALSE without one).
    #[serde(default)]
    pub start_sync: bool,
    /// InSync of the axis' running MC_GearInPosCA (FALSE without one).
    #[serde(default)]
    pub in_sync: bool,
}

/// One CA group as published (CaGroupState.msg, §9.5).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CaGroupStatus {
    /// Group name.
    pub name: String,
    /// MC_GROUP_STATE.
    pub state: GroupState,
    /// IsEnableRequested.
    pub is_enable_requested: bool,
    /// AllAxesStanding (v = a = 0 for every axis).
    pub all_axes_standing: bool,
    /// InPosition: not supported, always FALSE.
    pub in_position: bool,
    /// GroupErrorId (0 = none).
    pub group_error_id: u32,
    /// GroupAxesCount.
    pub group_axes_count: u32,
    /// ActOverrideFactor.
    pub act_override_factor: f64,
    /// Sum of effective gaps exceeds the ring (§1.7).
    pub gap_budget_exceeded: bool,
    /// Axes in CA order, front first.
    pub axes: Vec<CaAxisStatus>,
}
