//! MC_TorqueControl (single_axis.md §4.14, W14) with the torque model of §1.1:
//! `dv/dt = k_t·SetTorque − b·v`, velocity clamped to `[VelocityLimitLow, VelocityLimitHigh]`;
//! SetTorque ramps to Torque at TorqueRamp. InTorque = torque reached and no velocity limit
//! active.

use motion_core::CmdId;

/// A running MC_TorqueControl.
#[derive(Clone, Copy, Debug)]
pub struct TorqueJob {
    /// The MC_TorqueControl instance.
    pub owner: CmdId,
    /// ContinuousUpdate: later calls change the inputs of the running instance.
    pub continuous_update: bool,
    /// Target torque \[%\].
    pub torque: f64,
    /// Ramp \[%/s\].
    pub ramp: f64,
    /// VelocityLimitHigh \[u/s\].
    pub v_high: f64,
    /// VelocityLimitLow \[u/s\].
    pub v_low: f64,
    /// The velocity limit is active in this cycle (DriveLimitActive).
    pub clamped: bool,
}
