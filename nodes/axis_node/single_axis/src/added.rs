//! State the added FBs keep per axis and per coupling, and their input types: the external
//! set-point generator (§4.6), the §4.7 extensions, phasing (§4.13) and multi-master gearing
//! (§4.12.4). It belongs to the single axis: the axis and its couplings hold it, the engine's
//! FB calls change it; it knows no engine.

use crate::extension_inputs::*;
use motion_core::trajectory::{Profile1, State1};
use motion_core::CmdId;
use serde::{Deserialize, Serialize};

/// State of the external setpoint generator of one axis.
#[derive(Clone, Copy, Debug, Default)]
pub struct ExtGen {
    /// Enabled by MC_ExtSetPointGenEnable (Status.ExtSetPointGenEnabled).
    pub enabled: bool,
    /// UseTorqueOffset of the enabling call: fed torques are forwarded as `PlcToNc.ExtTorque`.
    pub use_torque_offset: bool,
    /// Last fed values (`PlcToNc.ExtSetPos/Velo/Acc/Direction`).
    pub fed: State1,
    /// `PlcToNc.ExtSetDirection` as last fed (−1, 0, 1).
    pub direction: i32,
    /// At least one value was fed since the generator was enabled (until then it sets nothing).
    pub fed_since_enable: bool,
    /// `PlcToNc.ExtTorque` as forwarded \[%\].
    pub torque_offset: f64,
}

/// MC_BacklashCompensation while enabled.
#[derive(Clone, Copy, Debug)]
pub struct Backlash {
    /// The enabled MC_BacklashCompensation instance.
    pub owner: CmdId,
    /// Backlash input \[u\].
    pub backlash: f64,
    /// The backlash is compensated in positive direction (CompensationInPositiveDirection).
    pub positive: bool,
    /// Ramp of the compensation \[u/s\].
    pub ramp: f64,
}

/// MC_PositionCorrectionLimiter while enabled.
#[derive(Clone, Copy, Debug)]
pub struct Limiter {
    /// The enabled MC_PositionCorrectionLimiter instance.
    pub owner: CmdId,
    /// PositionCorrectionValue input \[u\].
    pub value: f64,
    /// CorrectionMode (STANDARD or FULLLENGTH).
    pub mode: PositionCorrectionMode,
    /// Acceleration of the correction (STANDARD) \[u/s²\].
    pub acceleration: f64,
    /// CorrectionLength over which a change is spread (FULLLENGTH) \[u\].
    pub length: f64,
    /// FULLLENGTH: the change to spread (value − correction when the value last changed).
    pub change: f64,
}

/// MC_TableBasedPositionCompensation while enabled.
#[derive(Clone, Debug)]
pub struct Table {
    /// The enabled MC_TableBasedPositionCompensation instance.
    pub owner: CmdId,
    /// The compensation table (position, compensation value), ascending positions.
    pub table: Vec<PositionCompensationTableElement>,
    /// Table parameters (minimum and maximum position, modulo, ...).
    pub param: PositionCompensationTableParameter,
    /// Ramp of the compensation \[u/s\].
    pub ramp: f64,
}

/// Extension state of one axis.
#[derive(Clone, Debug, Default)]
pub struct ExtState {
    /// Drive operation mode (MC_Read/WriteDriveOperationMode).
    pub drive_mode: DriveOperationMode,
    /// Torque mode ran since the drive mode was last set (it falls back to position mode after).
    pub torque_seen: bool,
    /// Control loop index (MC_SelectControlLoop).
    pub control_loop_index: u16,
    /// `[device][output]` images of MC_WriteNcIoOutput.
    pub nc_io: [[u32; 14]; 2],
    /// MC_BacklashCompensation while enabled.
    pub backlash: Option<Backlash>,
    /// Current backlash correction \[u\].
    pub backlash_corr: f64,
    /// MC_PositionCorrectionLimiter while enabled.
    pub limiter: Option<Limiter>,
    /// Current limited position correction \[u\].
    pub limiter_corr: f64,
    /// MC_TableBasedPositionCompensation while enabled.
    pub table: Option<Table>,
    /// Current table correction \[u\].
    pub table_corr: f64,
    /// Last travel direction (sign of the last non-zero set velocity).
    pub last_dir: f64,
    /// Set position of the previous cycle (the travel per cycle spreads a FULLLENGTH correction) \[u\].
    pub prev_pos: f64,
    /// MC_Write(Bool)ParameterPersistent initialization list, in write order (last wins).
    pub persistent: Vec<(u32, f64)>,
}

impl ExtState {
    /// The total position correction \[u\].
    pub fn correction(&self) -> f64 {
        self.backlash_corr + self.limiter_corr + self.table_corr
    }
}

/// `E_PhasingType` (§4.13, §5.3): the three operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhasingType {
    /// NC_PHASINGTYPE_ABSOLUTE (1).
    Absolute,
    /// NC_PHASINGTYPE_RELATIVE (2).
    Relative,
    /// NC_PHASINGTYPE_STOP (4096).
    Stop,
}

/// The phasing offset of a coupling: φ with its derivatives and the running command.
#[derive(Clone, Copy, Debug, Default)]
pub struct Phase {
    /// φ, dφ/dt, d²φ/dt² \[slave u, u/s, u/s²\].
    pub s: State1,
    /// The running phasing command, if any.
    pub job: Option<PhaseJob>,
}

/// A running phasing command.
#[derive(Clone, Copy, Debug)]
pub struct PhaseJob {
    /// The MC_PhasingAbsolute/Relative/HaltPhasing instance.
    pub owner: CmdId,
    /// Which operation.
    pub ty: PhasingType,
    /// Jerk-limited profile of φ from the edge (its end is the target phase shift).
    pub profile: Profile1,
    /// Time since the profile start \[s\].
    pub t: f64,
    /// φ at the edge (CoveredPhaseShift = φ − start).
    pub start: f64,
    /// ContinuousUpdate latched at the edge (and Execute still TRUE).
    pub continuous: bool,
    /// Done has been reported.
    pub reached: bool,
}

crate::inputs::raw_enum! {
    /// `E_GearInMultiMasterSyncMode` (§4.12.4).
    GearInMultiMasterSyncMode: "Options.SyncMode" {
        /// VELOSYNC (0, default): velocity-synchronous only.
        #[default]
        VeloSync = 0,
        /// POSSYNC1 (1): position difference of dynamic limitation caught up later.
        PosSync1 = 1,
        /// POSSYNC2 (2): all position differences caught up (absolute coupling).
        PosSync2 = 2,
    }
}

/// `ST_GearInMultiMasterOptions` (§5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GearInMultiMasterOptions {
    /// AdvancedSlaveDynamics: slave limited by v/a/j, may couple onto moving masters.
    pub advanced_slave_dynamics: bool,
    /// SyncMode (only with AdvancedSlaveDynamics).
    pub sync_mode: GearInMultiMasterSyncMode,
}

/// A multi-master coupling (on [`crate::gearing::Coupling`]`.ext.multi`).
#[derive(Clone, Copy, Debug)]
pub struct Multi {
    /// The enabled instance (None after Enable↓: ratios frozen).
    pub owner: Option<CmdId>,
    /// Master axes (indices) of the four master inputs; None = input not connected.
    pub masters: [Option<usize>; 4],
    /// GearRatio inputs.
    pub target: [f64; 4],
    /// Effective ratios.
    pub ratio: [f64; 4],
    /// Slew rates |dr/dt| \[1/s\].
    pub rate: [f64; 4],
    /// Master values (raw) of this cycle, filled before the slave's step.
    pub inputs: [State1; 4],
    /// Raw master positions of the previous cycle and at the coupling instant.
    pub m_prev: [f64; 4],
    /// Raw master positions at the coupling instant (POSSYNC2).
    pub m0: [f64; 4],
    /// AdvancedSlaveDynamics latched at Enable↑.
    pub asd: bool,
    /// SyncMode latched at Enable↑ (only with AdvancedSlaveDynamics).
    pub sync_mode: GearInMultiMasterSyncMode,
    /// Acceleration, Deceleration, Jerk inputs after defaulting.
    pub acc: f64,
    /// Deceleration of the limiter \[u/s²\].
    pub dec: f64,
    /// Jerk of the limiter \[u/s³\].
    pub jerk: f64,
    /// Limiter state (slave set state without φ).
    pub ls: State1,
    /// Ideal position (POSSYNC) and whether POSSYNC1 reached velocity sync.
    pub p_star: f64,
    /// POSSYNC1 has reached velocity synchronism and now tracks `p_star`.
    pub pos_synced: bool,
    /// ASD: synchronous in the last cycle (the slave then follows the ideal motion exactly
    /// while that stays within its acceleration limit; the limiter plans only otherwise).
    pub synced: bool,
    /// v* of the last cycle.
    pub v_prev: f64,
}

/// Per-axis state of the added FBs (field `ext` of the axis).
#[derive(Clone, Debug, Default)]
pub struct AxisExt {
    /// The running phasing instance (to end it when the coupling goes away).
    pub phasing_owner: Option<CmdId>,
    /// The enabled MC_GearInMultiMaster instance (to end it when decoupled).
    pub multi_owner: Option<CmdId>,
    /// External setpoint generator (§4.6).
    pub ext_gen: ExtGen,
    /// MC_SetAcceptBlockedDriveSignal (ControlDWord bit 8).
    pub accept_blocked_drive: bool,
    /// §4.7 extensions.
    pub x: ExtState,
}

impl AxisExt {
    /// The external setpoint generator moves the axis (state ContinuousMotion, §2.2 note).
    pub fn ext_gen_moving(&self) -> bool {
        self.ext_gen.enabled && self.ext_gen.fed_since_enable && self.ext_gen.fed.vel != 0.0
    }
}

/// Per-coupling state of the added FBs (field `ext` of a coupling): the phasing offset and
/// the MC_GearInMultiMaster data.
#[derive(Clone, Copy, Debug, Default)]
pub struct CouplingExt {
    /// Phasing offset φ (§4.13).
    pub phase: Phase,
    /// MC_GearInMultiMaster data when the coupling has several masters (§4.12.4).
    pub multi: Option<Multi>,
}
