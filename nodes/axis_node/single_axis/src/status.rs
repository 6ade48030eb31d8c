//! The status of one axis: NCTOPLC_AXIS_REF / ST_AxisStatus essentials (single_axis.md §5.1,
//! §5.2), field for field what `msgs/msg/AxisState.msg` carries, plus a few ST_AxisStatus
//! flags. It belongs to the single axis and knows nothing of groups, CA or platforms.

use crate::state::MotionState;
use serde::{Deserialize, Serialize};

/// StateDWord bit numbers (§5.1).
pub mod bits {
    /// Operational (bit 0).
    pub const OPERATIONAL: u32 = 1 << 0;
    /// Homed (bit 1).
    pub const HOMED: u32 = 1 << 1;
    /// NotMoving (bit 2).
    pub const NOT_MOVING: u32 = 1 << 2;
    /// InPositionArea (bit 3).
    pub const IN_POSITION_AREA: u32 = 1 << 3;
    /// InTargetPosition (bit 4).
    pub const IN_TARGET_POSITION: u32 = 1 << 4;
    /// Protected (bit 5).
    pub const PROTECTED: u32 = 1 << 5;
    /// HasBeenStopped (bit 7).
    pub const HAS_BEEN_STOPPED: u32 = 1 << 7;
    /// HasJob (bit 8).
    pub const HAS_JOB: u32 = 1 << 8;
    /// PositiveDirection (bit 9).
    pub const POSITIVE_DIRECTION: u32 = 1 << 9;
    /// NegativeDirection (bit 10).
    pub const NEGATIVE_DIRECTION: u32 = 1 << 10;
    /// HomingBusy (bit 11).
    pub const HOMING_BUSY: u32 = 1 << 11;
    /// ConstantVelocity (bit 12).
    pub const CONSTANT_VELOCITY: u32 = 1 << 12;
    /// Compensating: superposition active (bit 13).
    pub const COMPENSATING: u32 = 1 << 13;
    /// NewTargetPos (bit 17).
    pub const NEW_TARGET_POS: u32 = 1 << 17;
    /// DriveLimitActive (bit 18).
    pub const DRIVE_LIMIT_ACTIVE: u32 = 1 << 18;
    /// ContinuousMotion (bit 19).
    pub const CONTINUOUS_MOTION: u32 = 1 << 19;
    /// ControlLoopClosed (bit 20).
    pub const CONTROL_LOOP_CLOSED: u32 = 1 << 20;
    /// CmdBuffered (bit 24).
    pub const CMD_BUFFERED: u32 = 1 << 24;
    /// PTPmode (bit 25).
    pub const PTP_MODE: u32 = 1 << 25;
    /// SoftLimitMinExceeded (bit 26).
    pub const SOFT_LIMIT_MIN_EXCEEDED: u32 = 1 << 26;
    /// SoftLimitMaxExceeded (bit 27).
    pub const SOFT_LIMIT_MAX_EXCEEDED: u32 = 1 << 27;
    /// DriveDeviceError (bit 28).
    pub const DRIVE_DEVICE_ERROR: u32 = 1 << 28;
    /// MotionCommandsLocked (bit 29).
    pub const MOTION_COMMANDS_LOCKED: u32 = 1 << 29;
    /// Error (bit 31).
    pub const ERROR: u32 = 1 << 31;
}

/// `NCTOPLC.AxisState` values of a continuous master axis (§5.1).
pub mod axis_state {
    /// INACTIVE: setpoint generator idle.
    pub const INACTIVE: u32 = 0;
    /// RUNNING.
    pub const RUNNING: u32 = 1;
    /// OVERRIDE_ZERO.
    pub const OVERRIDE_ZERO: u32 = 2;
    /// PHASE_VELOCONST.
    pub const PHASE_VELOCONST: u32 = 3;
    /// PHASE_ACCPOS (accelerating).
    pub const PHASE_ACCPOS: u32 = 4;
    /// PHASE_ACCNEG (decelerating).
    pub const PHASE_ACCNEG: u32 = 5;
    /// Slave: SYNCHRON (coupled).
    pub const SYNCHRON: u32 = 13;
}

/// State of one axis.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisStatus {
    /// Axis name.
    pub name: std::sync::Arc<str>,
    /// MC_AxisStates (§2.1).
    pub motion_state: MotionState,
    /// StateDWord bits ([`bits`]).
    pub state_dword: u32,
    /// Axis error code (0 = none).
    pub error_code: u32,
    /// NCTOPLC AxisState ([`axis_state`]).
    pub axis_state: u32,
    /// CoupleState: 0 single, 1 master, 2 master-slave, 3 slave.
    pub couple_state: u32,
    /// SetPos \[u\].
    pub set_pos: f64,
    /// SetVelo \[u/s\].
    pub set_velo: f64,
    /// SetAcc \[u/s²\].
    pub set_acc: f64,
    /// SetJerk \[u/s³\].
    pub set_jerk: f64,
    /// ActPos \[u\].
    pub act_pos: f64,
    /// ActVelo \[u/s\].
    pub act_velo: f64,
    /// ActAcc \[u/s²\].
    pub act_acc: f64,
    /// PosDiff = SetPos − ActPos \[u\].
    pub pos_diff: f64,
    /// TargetPos \[u\] (= SetPos during endless motion).
    pub target_pos: f64,
    /// ModuloActPos \[u\] in [0, period).
    pub modulo_act_pos: f64,
    /// ModuloActTurns.
    pub modulo_act_turns: i32,
    /// ModuloSetPos \[u\] in [0, period).
    pub modulo_set_pos: f64,
    /// ModuloSetTurns.
    pub modulo_set_turns: i32,
    /// Velocity override \[%\].
    pub override_percent: f64,
    /// MC_Power.Status.
    pub power_status: bool,
    /// Homed (calibrated).
    pub homed: bool,
    /// HasJob.
    pub has_job: bool,
    /// CmdBuffered.
    pub cmd_buffered: bool,
    /// CmdNo: increments for each accepted command (wrapping).
    pub cmd_no: u16,
    /// HomingState 0..6 (§4.10).
    pub homing_state: u32,
    /// Raw machine position (before MC_SetPosition/homing offsets) \[u\] (§1.5 diagnostics).
    pub raw_pos: f64,
    /// Raw machine actual position \[u\] (§1.5 diagnostics; the virtual cam's coordinate).
    pub raw_act_pos: f64,
    /// Level of the virtual homing cam (`sim.home_cam`) at the raw actual position (§1.5).
    pub home_cam: bool,
    /// Accumulated MC_SetPosition offset (AxisMcSetPositionOffset, 2003) \[u\].
    pub set_position_offset: f64,
    /// SetTorque (= ActTorque) \[%\] (MC_TorqueControl).
    pub set_torque: f64,
    /// NcToPlc values of the added functions (phasing, position correction, external set
    /// points, encoder, control loop).
    pub ext: ExtValues,
}

impl AxisStatus {
    /// True if the bit (a [`bits`] constant) is set.
    pub fn bit(&self, bit: u32) -> bool {
        self.state_dword & bit != 0
    }

    /// MC_ReadStatus.Accelerating (§4.4.7): moving and |SetVelo| increasing.
    pub fn accelerating(&self) -> bool {
        self.set_velo.abs() > 1e-9 && self.set_acc * self.set_velo > 1e-9
    }

    /// MC_ReadStatus.Decelerating: moving and |SetVelo| decreasing.
    pub fn decelerating(&self) -> bool {
        self.set_velo.abs() > 1e-9 && self.set_acc * self.set_velo < -1e-9
    }

    /// MC_ReadStatus.ConstantVelocity (StateDWord bit 12).
    pub fn constant_velocity(&self) -> bool {
        self.bit(bits::CONSTANT_VELOCITY)
    }
}

/// NcToPlc values of the added functions of one axis (single_axis.md §4.7 and the phasing /
/// external set-point FBs), the scalar part of `AxisEngine::ext_status`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ExtValues {
    /// AbsPhasingPos: phasing offset φ \[u\].
    pub abs_phasing_pos: f64,
    /// ActPosWithoutPosCorrection \[u\].
    pub act_pos_without_pos_correction: f64,
    /// Total position correction (backlash + limiter + table) \[u\].
    pub position_correction: f64,
    /// Set position sent to the drive (SetPos − correction) \[u\].
    pub drive_set_pos: f64,
    /// ExtSetPos / ExtSetVelo / ExtSetAcc as last fed.
    pub ext_set_pos: f64,
    /// ExtSetVelo \[u/s\].
    pub ext_set_velo: f64,
    /// ExtSetAcc \[u/s²\].
    pub ext_set_acc: f64,
    /// ExtTorque (torque offset) \[%\].
    pub ext_torque: f64,
    /// Encoder counter (32 bit) at the actual position.
    pub encoder_increments: u32,
    /// ActiveControlLoopIndex.
    pub control_loop_index: u16,
}
