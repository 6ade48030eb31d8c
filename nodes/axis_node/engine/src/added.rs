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
pub(crate) struct ExtGen {
    pub enabled: bool,
    pub use_torque_offset: bool,
    /// Last fed values (`PlcToNc.ExtSetPos/Velo/Acc/Direction`).
    pub fed: State1,
    pub direction: i32,
    pub fed_since_enable: bool,
    /// `PlcToNc.ExtTorque` as forwarded \[%\].
    pub torque_offset: f64,
}

/// MC_BacklashCompensation while enabled.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Backlash {
    pub owner: CmdId,
    pub backlash: f64,
    pub positive: bool,
    pub ramp: f64,
}

/// MC_PositionCorrectionLimiter while enabled.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limiter {
    pub owner: CmdId,
    pub value: f64,
    pub mode: PositionCorrectionMode,
    pub acceleration: f64,
    pub length: f64,
    /// FULLLENGTH: the change to spread (value − correction when the value last changed).
    pub change: f64,
}

/// MC_TableBasedPositionCompensation while enabled.
#[derive(Clone, Debug)]
pub(crate) struct Table {
    pub owner: CmdId,
    pub table: Vec<PositionCompensationTableElement>,
    pub param: PositionCompensationTableParameter,
    pub ramp: f64,
}

/// Extension state of one axis.
#[derive(Clone, Debug, Default)]
pub(crate) struct ExtState {
    pub drive_mode: DriveOperationMode,
    pub torque_seen: bool,
    pub control_loop_index: u16,
    /// `[device][output]` images of MC_WriteNcIoOutput.
    pub nc_io: [[u32; 14]; 2],
    pub backlash: Option<Backlash>,
    pub backlash_corr: f64,
    pub limiter: Option<Limiter>,
    pub limiter_corr: f64,
    pub table: Option<Table>,
    pub table_corr: f64,
    /// Last travel direction (sign of the last non-zero set velocity).
    pub last_dir: f64,
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
pub(crate) enum PhasingType {
    /// NC_PHASINGTYPE_ABSOLUTE (1).
    Absolute,
    /// NC_PHASINGTYPE_RELATIVE (2).
    Relative,
    /// NC_PHASINGTYPE_STOP (4096).
    Stop,
}

/// The phasing offset of a coupling: φ with its derivatives and the running command.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Phase {
    /// φ, dφ/dt, d²φ/dt² \[slave u, u/s, u/s²\].
    pub s: State1,
    pub job: Option<PhaseJob>,
}

/// A running phasing command.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PhaseJob {
    pub owner: CmdId,
    pub ty: PhasingType,
    pub profile: Profile1,
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

/// A multi-master coupling (on [`Coupling`]`.ext.multi`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Multi {
    /// The enabled instance (None after Enable↓: ratios frozen).
    pub owner: Option<CmdId>,
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
    pub m0: [f64; 4],
    pub asd: bool,
    pub sync_mode: GearInMultiMasterSyncMode,
    /// Acceleration, Deceleration, Jerk inputs after defaulting.
    pub acc: f64,
    pub dec: f64,
    pub jerk: f64,
    /// Limiter state (slave set state without φ).
    pub ls: State1,
    /// Ideal position (POSSYNC) and whether POSSYNC1 reached velocity sync.
    pub p_star: f64,
    pub pos_synced: bool,
    /// ASD: synchronous in the last cycle (the slave then follows the ideal motion exactly
    /// while that stays within its acceleration limit; the limiter plans only otherwise).
    pub synced: bool,
    /// v* of the last cycle.
    pub v_prev: f64,
}

/// Per-axis state of the added FBs (field `ext` of the axis).
#[derive(Clone, Debug, Default)]
pub(crate) struct AxisExt {
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
pub(crate) struct CouplingExt {
    pub phase: Phase,
    pub multi: Option<Multi>,
}
