//! PLCopen axis state machine (single_axis.md §2): the states, the derived-state rule (§2.3)
//! and the admission matrix (§2.4).
//!
//! The engine never stores the state: it derives it every time from the axis facts
//! ([`StateFacts`]) with the first matching rule of §2.3. The transitions T1..T17 of §2.2 follow
//! from the commands changing those facts (e.g. MC_Stop sets the lock → Stopping, T14).

use crate::error_ids::AXIS_CANNOT_BE_STARTED;
use motion_core::ErrorId;
use serde::{Deserialize, Serialize};

/// `MC_AxisStates` (§2.1), values as in Tc2_MC2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum MotionState {
    /// MC_AXISSTATE_UNDEFINED (0).
    #[default]
    Undefined = 0,
    /// MC_AXISSTATE_DISABLED (1).
    Disabled = 1,
    /// MC_AXISSTATE_STANDSTILL (2).
    Standstill = 2,
    /// MC_AXISSTATE_ERRORSTOP (3).
    ErrorStop = 3,
    /// MC_AXISSTATE_STOPPING (4).
    Stopping = 4,
    /// MC_AXISSTATE_HOMING (5).
    Homing = 5,
    /// MC_AXISSTATE_DISCRETEMOTION (6).
    DiscreteMotion = 6,
    /// MC_AXISSTATE_CONTINUOUSMOTION (7).
    ContinuousMotion = 7,
    /// MC_AXISSTATE_SYNCHRONIZEDMOTION (8).
    SynchronizedMotion = 8,
}

/// The facts the published state is derived from (§2.3).
#[derive(Clone, Copy, Debug, Default)]
pub struct StateFacts {
    /// An axis error is present.
    pub error: bool,
    /// Controller enabled and operational (MC_Power.Enable ∧ Status).
    pub operational: bool,
    /// MC_Stop ramp active or axis locked by MC_Stop.
    pub stopping: bool,
    /// Homing run active.
    pub homing: bool,
    /// Coupled as slave.
    pub coupled: bool,
    /// Endless job active (StateDWord bit 19).
    pub continuous: bool,
    /// The setpoint generator has a job (StateDWord bit 8).
    pub has_job: bool,
}

/// Derived-state rule of §2.3: the first matching rule wins.
pub fn derive_state(f: &StateFacts) -> MotionState {
    if f.error {
        MotionState::ErrorStop
    } else if !f.operational {
        MotionState::Disabled
    } else if f.stopping {
        MotionState::Stopping
    } else if f.homing {
        MotionState::Homing
    } else if f.coupled {
        MotionState::SynchronizedMotion
    } else if f.continuous {
        MotionState::ContinuousMotion
    } else if f.has_job {
        MotionState::DiscreteMotion
    } else {
        MotionState::Standstill
    }
}

/// FB groups as rows of the admission matrix (§2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FbClass {
    /// MC_Power Enable↑.
    PowerOn,
    /// MC_Power Enable↓.
    PowerOff,
    /// MC_Reset.
    Reset,
    /// MC_Stop.
    Stop,
    /// MC_Halt.
    Halt,
    /// MC_MoveAbsolute/Relative/Additive/Modulo.
    MoveDiscrete,
    /// MC_MoveVelocity, MC_MoveContinuousAbsolute/Relative.
    MoveContinuous,
    /// MC_TorqueControl.
    TorqueControl,
    /// MC_Jog.
    Jog,
    /// MC_Home (DefaultHoming).
    HomeDefault,
    /// MC_Home (Direct/ForceCalibration/ResetCalibration).
    HomeNoMotion,
    /// MC_MoveSuperImposed.
    MoveSuperImposed,
    /// MC_AbortSuperposition.
    AbortSuperposition,
    /// MC_GearIn (slave).
    GearIn,
    /// MC_GearInDyn (slave).
    GearInDyn,
    /// MC_GearInMultiMaster (slave); `asd` = Options.AdvancedSlaveDynamics.
    GearInMultiMaster {
        /// AdvancedSlaveDynamics.
        asd: bool,
    },
    /// MC_GearOut (slave).
    GearOut,
    /// MC_PhasingAbsolute/Relative, MC_HaltPhasing (slave).
    Phasing,
    /// MC_SetPosition.
    SetPosition,
    /// MC_SetOverride, MC_OverrideFilter, MC_CalcDynamicsByRampTime.
    Override,
    /// Read FBs, Write(Bool)Parameter(Persistent), ReadParameterSet, ... (never change state).
    ReadWrite,
    /// MC_TouchProbe, MC_AbortTrigger.
    TouchProbe,
    /// MC_BacklashCompensation, MC_PositionCorrectionLimiter, ... MC_SelectControlLoop.
    Correction,
    /// MC_ExtSetPointGenEnable.
    ExtSetPointGenEnable,
    /// MC_ExtSetPointGenDisable.
    ExtSetPointGenDisable,
    /// MC_Read/WriteDriveOperationMode.
    DriveOperationMode,
}

/// One cell of the admission matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Admission {
    /// "=": accepted, no state change.
    Keep,
    /// Accepted; the axis enters this state.
    To(MotionState),
    /// MC_Jog: ContinuousMotion (STANDARD/CONTINOUS) or DiscreteMotion (INCHING).
    ToJog,
    /// MC_Reset in ErrorStop: Standstill (Power enabled and ready) or Disabled (T4/T5).
    ToStandstillOrDisabled,
    /// GearOut on a slave: ContinuousMotion if moving, else Standstill (T10/T10b).
    ToContinuousOrStandstill,
    /// "S?": on a slave only with AxisAllowMotionCmdToSlaveAxis = TRUE (auto-decouple,
    /// Aborting only), then this state; else rejected with 0x4B01.
    IfSlaveAllowed(MotionState),
    /// "E": rejected with this error id; the axis is not affected.
    Reject(ErrorId),
}

/// The admission matrix of §2.4, one row per FB group, columns in the table's order.
pub fn admission(fb: FbClass, state: MotionState) -> Admission {
    use Admission::{IfSlaveAllowed as S, Keep as K, To, ToJog, ToStandstillOrDisabled};
    use MotionState::*;
    const E: Admission = Admission::Reject(AXIS_CANNOT_BE_STARTED);
    const E5: Admission = Admission::Reject(crate::error_ids::COMMAND_NOT_PERMITTED);
    const E3: Admission = Admission::Reject(crate::error_ids::AXIS_NOT_MOVING);
    let col = match state {
        Disabled => 0,
        Standstill => 1,
        Homing => 2,
        DiscreteMotion => 3,
        ContinuousMotion => 4,
        SynchronizedMotion => 5,
        Stopping => 6,
        ErrorStop => 7,
        Undefined => return E,
    };
    let (ss, hom, dm, cm, syn, stp) = (
        To(Standstill),
        To(Homing),
        To(DiscreteMotion),
        To(ContinuousMotion),
        To(SynchronizedMotion),
        To(Stopping),
    );
    #[rustfmt::skip]
    let row: [Admission; 8] = match fb {
        //                                  Dis      SS       Hom    Dis-M    Con      Syn                  Stp      Err
        FbClass::PowerOn =>               [ss,     K,       K,     K,       K,       K,                   K,       K],
        FbClass::PowerOff =>              [K,      To(Disabled), To(Disabled), To(Disabled), To(Disabled), To(Disabled), To(Disabled), K],
        FbClass::Reset =>                 [K,      K,       ss,    ss,      ss,      ss,                  ss,      ToStandstillOrDisabled],
        FbClass::Stop =>                  [E,      stp,     stp,   stp,     stp,     S(Stopping),         stp,     E],
        FbClass::Halt =>                  [E,      dm,      E,     dm,      dm,      S(DiscreteMotion),   E,       E],
        FbClass::MoveDiscrete =>          [E,      dm,      E,     dm,      dm,      S(DiscreteMotion),   E,       E],
        FbClass::MoveContinuous =>        [E,      cm,      E,     cm,      cm,      S(ContinuousMotion), E,       E],
        FbClass::TorqueControl =>         [E,      cm,      E,     cm,      cm,      S(ContinuousMotion), E,       E],
        FbClass::Jog =>                   [E,      ToJog,   E,     ToJog,   ToJog,   S(ContinuousMotion), E,       E],
        FbClass::HomeDefault =>           [E,      hom,     E,     E,       E,       E,                   E,       E],
        FbClass::HomeNoMotion =>          [E,      K,       E,     E,       E,       E,                   E,       E],
        FbClass::MoveSuperImposed =>      [E,      E3,      E,     K,       K,       K,                   E,       E],
        FbClass::AbortSuperposition =>    [E,      K,       K,     K,       K,       K,                   K,       E],
        FbClass::GearIn =>                [E,      syn,     E,     E,       E,       E,                   E,       E],
        FbClass::GearInDyn =>             [E,      syn,     E,     E,       E,       K,                   E,       E],
        FbClass::GearInMultiMaster { asd } => {
            let moving = if asd { syn } else { E };
            [E, syn, E, moving, moving, K, E, E]
        }
        FbClass::GearOut =>               [E5,     E5,      E,     E5,      E5,      Admission::ToContinuousOrStandstill, E, E],
        FbClass::Phasing =>               [E,      E5,      E,     E5,      E5,      K,                   E,       E],
        FbClass::SetPosition =>           [K,      K,       E,     K,       K,       E,                   K,       E],
        FbClass::Override =>              [K,      K,       K,     K,       K,       K,                   K,       K],
        FbClass::ReadWrite =>             [K,      K,       K,     K,       K,       K,                   K,       K],
        FbClass::TouchProbe =>            [K,      K,       K,     K,       K,       K,                   K,       K],
        FbClass::Correction =>            [K,      K,       K,     K,       K,       K,                   K,       K],
        FbClass::ExtSetPointGenEnable =>  [E,      cm,      E,     E,       E,       E,                   E,       E],
        FbClass::ExtSetPointGenDisable => [K,      K,       K,     K,       K,       K,                   K,       K],
        FbClass::DriveOperationMode =>    [K,      K,       E,     E,       E,       E,                   K,       K],
    };
    row[col]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derived_state_rule_order() {
        let all = StateFacts {
            error: true,
            operational: true,
            stopping: true,
            homing: true,
            coupled: true,
            continuous: true,
            has_job: true,
        };
        assert_eq!(derive_state(&all), MotionState::ErrorStop);
        let f = StateFacts {
            error: false,
            operational: false,
            ..all
        };
        assert_eq!(derive_state(&f), MotionState::Disabled);
        let f = StateFacts {
            error: false,
            ..all
        };
        assert_eq!(derive_state(&f), MotionState::Stopping);
        let f = StateFacts {
            error: false,
            stopping: false,
            ..all
        };
        assert_eq!(derive_state(&f), MotionState::Homing);
        let f = StateFacts {
            error: false,
            stopping: false,
            homing: false,
            ..all
        };
        assert_eq!(derive_state(&f), MotionState::SynchronizedMotion);
        let f = StateFacts {
            coupled: false,
            ..f
        };
        assert_eq!(derive_state(&f), MotionState::ContinuousMotion);
        let f = StateFacts {
            continuous: false,
            ..f
        };
        assert_eq!(derive_state(&f), MotionState::DiscreteMotion);
        let f = StateFacts {
            has_job: false,
            ..f
        };
        assert_eq!(derive_state(&f), MotionState::Standstill);
    }
}
