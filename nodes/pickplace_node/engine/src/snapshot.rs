//! The published state (pick_and_place.md §3.3 outputs, §18 `~/state`, `~/workpieces`, `~/events`).

use crate::belt::{WorkpieceEventKind, WorkpieceState};
use crate::state::TmState;
use serde::{Deserialize, Serialize};

/// `scStatusAGBC` (proposal §3.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StatusAgbc {
    /// Group enabled.
    pub group_enabled: bool,
    /// Group error.
    pub group_error: bool,
    /// Group error id.
    pub group_error_id: u32,
    /// Group homed.
    pub group_homed: bool,
}

/// `L_TT1P_scErrorInfo` per axis (proposal §3.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisErrorInfo {
    /// Axis in error.
    pub error: bool,
    /// Its error id.
    pub error_id: u32,
}

/// `scSignalFlow` (UNSPECIFIED by the manual; proposal §3.3: mirror of latched command inputs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SignalFlow {
    /// `eSetTarget` latched at the last execute edge.
    pub set_target: u8,
    /// `eSelectAxis` latched at the last jog start.
    pub select_axis: u8,
    /// `eTrackingMode` of the running profile (or of `scPar` when idle).
    pub tracking_mode: u8,
    /// Override in effect (after clamping).
    pub override_applied: f64,
    /// Level inputs `xPathStop`, `xPathHalt`, `xStopALL`, `xPathInterrupt`.
    pub stop_inputs: [bool; 4],
}

/// The outputs of `L_TT1P_TrackPickAndPlaceBase` (§3.3), arrays indexed 0 … 17 = axis 1 … 18.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Outputs {
    /// `xInternalControlActive`.
    pub internal_control_active: bool,
    /// `eTMState`.
    pub tm_state: TmState,
    /// `scStatusAGBC`.
    pub status_agbc: StatusAgbc,
    /// `xError`.
    pub error: bool,
    /// `xWarning`.
    pub warning: bool,
    /// `eErrorID` (0 = none; an error wins over a warning).
    pub error_id: u32,
    /// `ascErrorInfo[1..18]`.
    pub error_info: [AxisErrorInfo; 18],
    /// `xAxesEnabled`.
    pub axes_enabled: bool,
    /// `xAxesGroupEnabled`.
    pub axes_group_enabled: bool,
    /// `scSignalFlow`.
    pub signal_flow: SignalFlow,
    /// `xDone`.
    pub done: bool,
    /// `xBusy`.
    pub busy: bool,
    /// `xAxesGroupHomed`.
    pub axes_group_homed: bool,
    /// `xInPosition`.
    pub in_position: bool,
    /// `xHwLimitSwitchActive`.
    pub hw_limit_switch_active: bool,
    /// `xSwLimitSwitchActive`.
    pub sw_limit_switch_active: bool,
    /// `axHwLimitSwitchNeg`.
    pub hw_limit_switch_neg: [bool; 18],
    /// `axHwLimitSwitchPos`.
    pub hw_limit_switch_pos: [bool; 18],
    /// `axSwLimitEnabled`.
    pub sw_limit_enabled: [bool; 18],
    /// `axSwLimitSwitchActive`.
    pub sw_limit_switch_active_axes: [bool; 18],
    /// `xPathHold`.
    pub path_hold: bool,
    /// `xGripperCtrlActive`.
    pub gripper_ctrl_active: bool,
    /// `xPulseGripper` (one cycle).
    pub pulse_gripper: bool,
    /// `lrSetPathVelOut` [units/s].
    pub set_path_vel_out: f64,
    /// `lrPathPreparationTime` [s].
    pub path_preparation_time: f64,
    /// `lrPreCalcProfileTime` [s].
    pub pre_calc_profile_time: f64,
    /// `alrActPos[1..18]`.
    pub act_pos: [f64; 18],
    /// `alrActVel[1..18]`.
    pub act_vel: [f64; 18],
    /// `iProfilePointPassed`.
    pub profile_point_passed: i16,
    /// `xProfileInPreparation`.
    pub profile_in_preparation: bool,
    /// `xAccDecSync`.
    pub acc_dec_sync: bool,
    /// `xSynchronised`.
    pub synchronised: bool,
    /// `xInTarget`.
    pub in_target: bool,
    /// `xInParkPos`.
    pub in_park_pos: bool,
    /// `eSetTargetOut`.
    pub set_target_out: u8,
}

/// One tracked workpiece (`~/workpieces`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorkpieceSnapshot {
    /// Id.
    pub id: u64,
    /// Pending (no coordinates yet) or visible.
    pub visible: bool,
    /// Reserved as a target.
    pub reserved: bool,
    /// Position in belt coordinates now.
    pub belt_position: [f64; 3],
    /// Position in MCS now.
    pub mcs_position: [f64; 3],
}

/// One belt.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BeltSnapshot {
    /// Belt number 1 … 16.
    pub belt: u8,
    /// Configured (working area not empty).
    pub configured: bool,
    /// Belt position [units].
    pub position: f64,
    /// Belt velocity [units/s].
    pub velocity: f64,
    /// Tracked workpieces (FIFO order).
    pub workpieces: Vec<WorkpieceSnapshot>,
}

/// Which part of a profile runs (`~/state`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ProfilePhase {
    /// Moving to the target.
    ToTarget,
    /// Moving to a belt's park position.
    ToPark,
    /// Waiting at the park position (workpiece not yet reachable).
    WaitingAtPark,
    /// Synchronous dwell over the workpiece.
    SyncDwell,
    /// At a static target (e.g. waiting for a negative-lead gripper pulse).
    AtTarget,
}

/// The profile being run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ProfileSnapshot {
    /// `eSetTarget` of the profile (0 static, 1 … 16 belt).
    pub set_target: u8,
    /// Phase.
    pub phase: ProfilePhase,
    /// Path parameter σ [units].
    pub sigma: f64,
    /// Path length [units].
    pub length: f64,
    /// Coupling factor k.
    pub coupling: f64,
    /// Target workpiece id (belt targets).
    pub workpiece: Option<u64>,
}

/// The engine state as published.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PickPlaceSnapshot {
    /// Cycle counter (last step's tick index).
    pub cycle: u64,
    /// Simulated time at the end of the last step [s].
    pub time: f64,
    /// State (also in `outputs.tm_state`).
    pub state: TmState,
    /// TCP set-point pose X, Y, Z, A, B, C, Aux1.
    pub tcp: [f64; 7],
    /// TCP velocity [units/s].
    pub tcp_velocity: [f64; 7],
    /// Logical gripper closed (modes 1 … 4).
    pub gripper_closed: bool,
    /// Id of the workpiece attached by the last close pulse (modes 1 … 4, §10).
    pub held_workpiece: Option<u64>,
    /// Belts 1 … 16.
    pub belts: Vec<BeltSnapshot>,
    /// Running profile.
    pub active_profile: Option<ProfileSnapshot>,
    /// Queued (prepared, not yet running) profiles.
    pub queued_profiles: usize,
    /// FB outputs.
    pub outputs: Outputs,
}

/// Kind of a gripper pulse (§10).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum GripperEvent {
    /// Closing event (`lrGripperClosingTime`).
    Close,
    /// Opening event (`lrGripperOpenTime`).
    Open,
}

/// A single-cycle event (`~/events`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum CellEvent {
    /// `eTMState` changed.
    StateChanged {
        /// Cycle.
        cycle: u64,
        /// Old state.
        from: TmState,
        /// New state.
        to: TmState,
    },
    /// `xPulseGripper`.
    GripperPulse {
        /// Cycle.
        cycle: u64,
        /// Close or open.
        kind: GripperEvent,
    },
    /// Workpiece tracking.
    Workpiece {
        /// Cycle.
        cycle: u64,
        /// Belt 1 … 16.
        belt: u8,
        /// Workpiece id (0 for a rejected receive edge).
        id: u64,
        /// What happened.
        kind: WorkpieceEventKind,
    },
    /// A warning or error id was raised.
    Diagnostic {
        /// Cycle.
        cycle: u64,
        /// Id.
        id: u32,
        /// Error (true) or warning.
        error: bool,
    },
}

pub(crate) fn visible(s: WorkpieceState) -> bool {
    s == WorkpieceState::Visible
}
