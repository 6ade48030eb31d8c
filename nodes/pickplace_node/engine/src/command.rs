//! Commands of the ROS shell (pick_and_place.md §18): level inputs, pulses, parameter writes,
//! belt inputs and simulation hooks. Levels take effect at the start of the next cycle; pulses
//! are TRUE for exactly one cycle, repeated pulses of one input are queued one per two cycles.

use crate::params::{ConveyorBeltPar, ScPar};
use serde::{Deserialize, Serialize};

/// Optional stop levels; `None` leaves an input unchanged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StopInputs {
    /// `xPathStop`.
    pub path_stop: Option<bool>,
    /// `xPathHalt`.
    pub path_halt: Option<bool>,
    /// `xStopALL`.
    pub stop_all: Option<bool>,
    /// `xPathInterrupt`.
    pub path_interrupt: Option<bool>,
}

/// A simulated fault (§18 `~/sim/inject_fault`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FaultKind {
    /// Following error on the axis (error 90011).
    FollowingError,
    /// Drive fault on the axis (reported as 90011 too, proposal).
    DriveFault,
}

/// `scCtrlAGBC` service request (proposal §4.4): single-axis absolute move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ServiceRequest {
    /// `xServiceMoveAbs` (level): request pending.
    pub move_abs: bool,
    /// `eServiceAxis`: axis index 1 … 13.
    pub axis: u8,
    /// `lrServicePos` [units].
    pub pos: f64,
    /// `lrServiceVel` [units/s].
    pub vel: f64,
    /// `lrServiceAcc` [units/s²].
    pub acc: f64,
    /// `lrServiceDec` [units/s²].
    pub dec: f64,
    /// `lrServiceJerk` [units/s³].
    pub jerk: f64,
}

/// One command to the engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PickPlaceCommand {
    /// `xEnable` (level).
    SetEnable(bool),
    /// `xRegulatorOnALL` (level).
    SetRegulatorOn(bool),
    /// `xEnableInternalControl` (level).
    SetEnableInternalControl(bool),
    /// `xResetError` (pulse).
    ResetError,
    /// HMI (`~/hmi/*`): switch Internal Control on/off; allowed only while
    /// `xEnableInternalControl` is TRUE (§3.1).
    HmiSetInternalControl(bool),
    /// HMI (`~/hmi/*`): a command from the visualisation; accepted only under Internal Control.
    Hmi(Box<PickPlaceCommand>),
    /// `xPathStop`, `xPathHalt`, `xStopALL`, `xPathInterrupt` (levels).
    SetStopInputs(StopInputs),
    /// `lrOverride` (level).
    SetOverride(f64),
    /// `eSelectAxis`, `xJogPos`, `xJogNeg` (levels).
    Jog {
        /// `eSelectAxis` 0 … 13.
        select_axis: u8,
        /// `xJogPos`.
        jog_pos: bool,
        /// `xJogNeg`.
        jog_neg: bool,
    },
    /// `eSetTarget` + `xExecutePickAndPlace` (pulse); answers a `CmdId` tracked by events.
    Execute {
        /// `eSetTarget` 0 … 5 (latched at the edge).
        set_target: u8,
    },
    /// `xAbort` (pulse).
    Abort,
    /// `xAckGripper` (pulse).
    AckGripper,
    /// `xGroupHomeExecute` (pulse); answers a `CmdId` tracked by events.
    GroupHome,
    /// `scPar` write (whole structure; the shell merges partial updates). Rejected with 90001 /
    /// 90002 / 90003 and the old value kept.
    SetParams(Box<ScPar>),
    /// `ascConveyorBeltPar[belt]` write, belt 1 … 16.
    SetBeltParams {
        /// Belt 1 … 16.
        belt: u8,
        /// New parameters.
        params: ConveyorBeltPar,
    },
    /// `ascBeltInput[belt]` levels.
    BeltInput {
        /// Belt 1 … 16.
        belt: u8,
        /// `xWorkpieceOnBeltReceive`.
        receive: bool,
        /// `xValidPos`.
        valid_pos: bool,
        /// `ascInitialObjectPosition` (belt coordinates, valid at the receive edge).
        initial_object_position: [f64; 6],
        /// `lrAux1TargetPos`.
        aux1_target_pos: f64,
    },
    /// Convenience: receive edge next cycle, valid edge after `valid_delay_cycles` (0 = same cycle).
    DetectWorkpiece {
        /// Belt 1 … 16.
        belt: u8,
        /// Workpiece pose in belt coordinates at the receive edge.
        position: [f64; 6],
        /// Cycles between the receive and the valid edge.
        valid_delay_cycles: u32,
    },
    /// `scCtrlAGBC` (levels).
    Service(ServiceRequest),
    /// Simulated belt: velocity [units/s] reached with `acceleration` [units/s²] (0 = jump).
    SimSetBeltVelocity {
        /// Belt 1 … 16.
        belt: u8,
        /// Target velocity.
        velocity: f64,
        /// Ramp acceleration (≥ 0).
        acceleration: f64,
    },
    /// Simulated switches.
    SimSetDigitalInputs {
        /// `axHwLimitPos[1..18]`.
        hw_limit_pos: [bool; 18],
        /// `axHwLimitNeg[1..18]`.
        hw_limit_neg: [bool; 18],
        /// `axHomeAbsSwitch[1..12]`.
        home_switch: [bool; 12],
        /// `xGroupEnableHWLimit`.
        enable_hw_limit: bool,
    },
    /// Simulated fault on axis index 1 … 13.
    SimInjectFault {
        /// Axis index 1 … 13.
        axis: u8,
        /// Fault kind.
        kind: FaultKind,
    },
}
