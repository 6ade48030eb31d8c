//! Commands (one per Tc2_MC2 function block call) and their replies (single_axis.md §4).
//!
//! One [`AxisCommand`] = one FB call with a rising Execute edge of a fresh FB instance (for
//! Enable-type FBs such as MC_Power: one call with the current input levels). Inputs keep the
//! manual's names in snake_case. Enumerations are typed; the ROS shell converts raw numbers with
//! `from_raw`, which refuses out-of-range values with `ErrorId::ENUM_OUT_OF_RANGE`.

use crate::status::AxisStatus;
use motion_core::CmdId;
use serde::{Deserialize, Serialize};

pub use crate::inputs::*;

// The single-axis FBs' inputs and the §1.5 simulation inputs (crate single_axis).
pub use single_axis::fb_inputs::*;

/// One FB call.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum AxisCommand {
    /// MC_Power.
    Power(Power),
    /// MC_Reset.
    Reset(Reset),
    /// MC_MoveAbsolute.
    MoveAbsolute(MoveAbsolute),
    /// MC_MoveRelative.
    MoveRelative(MoveRelative),
    /// MC_MoveAdditive.
    MoveAdditive(MoveAdditive),
    /// MC_MoveModulo.
    MoveModulo(MoveModulo),
    /// MC_MoveVelocity.
    MoveVelocity(MoveVelocity),
    /// MC_MoveContinuousAbsolute.
    MoveContinuousAbsolute(MoveContinuousAbsolute),
    /// MC_MoveContinuousRelative.
    MoveContinuousRelative(MoveContinuousRelative),
    /// MC_Halt.
    Halt(Halt),
    /// MC_Stop.
    Stop(Stop),
    /// MC_SetPosition.
    SetPosition(SetPosition),
    /// MC_ReadParameter.
    ReadParameter(ReadParameter),
    /// MC_ReadBoolParameter.
    ReadBoolParameter(ReadBoolParameter),
    /// MC_WriteParameter.
    WriteParameter(WriteParameter),
    /// MC_WriteBoolParameter.
    WriteBoolParameter(WriteBoolParameter),
    /// MC_ReadStatus.
    ReadStatus(ReadStatus),
    /// MC_ReadActualPosition.
    ReadActualPosition(ReadActualPosition),
    /// MC_ReadActualVelocity.
    ReadActualVelocity(ReadActualVelocity),
    /// MC_ReadAxisError.
    ReadAxisError(ReadAxisError),
    /// Sets the Execute level of an admitted instance (§3.1 rules 5/6). A falling edge resets
    /// the outputs of a finished instance; for MC_Stop it releases the lock (§4.8.10); for
    /// MC_Jog it is the release of the held jog button.
    SetExecute {
        /// The instance.
        id: CmdId,
        /// The new Execute level.
        execute: bool,
    },
    /// A simulation hook (§1.5).
    Sim(Sim),
    /// MC_Home.
    Home(Home),
    /// MC_Jog.
    Jog(Jog),
    /// MC_SetOverride.
    SetOverride(SetOverride),
    /// MC_GearIn.
    GearIn(GearIn),
    /// MC_GearOut.
    GearOut(GearOut),
    /// MC_GearInDyn.
    GearInDyn(GearInDyn),
    /// MC_TorqueControl.
    TorqueControl(TorqueControl),
    /// MC_MoveSuperImposed.
    MoveSuperImposed(MoveSuperImposed),
    /// MC_AbortSuperposition.
    AbortSuperposition(AbortSuperposition),
    /// MC_TouchProbe.
    TouchProbe(TouchProbe),
    /// MC_AbortTrigger.
    AbortTrigger(AbortTrigger),
    /// A later call of a running MC_TouchProbe with a new `TriggerInput.PlcEvent` level.
    TouchProbePlcEvent {
        /// The MC_TouchProbe instance.
        id: CmdId,
        /// PlcEvent level.
        plc_event: bool,
    },
    /// A later call of a running MC_TorqueControl started with ContinuousUpdate.
    TorqueControlUpdate {
        /// The instance.
        id: CmdId,
        /// Torque.
        torque: f64,
        /// TorqueRamp.
        torque_ramp: f64,
        /// VelocityLimitHigh.
        velocity_limit_high: f64,
        /// VelocityLimitLow.
        velocity_limit_low: f64,
    },
    /// A later call of a running MC_Home instance with a new bCalibrationCam level.
    HomeCalibrationCam {
        /// The MC_Home instance.
        id: CmdId,
        /// bCalibrationCam.
        calibration_cam: bool,
    },
    /// Not an FB: reads the current outputs of an admitted instance, as a PLC reads its FB
    /// instance (reply [`ReplyValue::Outputs`]; unknown id → `UNKNOWN_OBJECT`). Changes nothing.
    ReadFbOutputs {
        /// The instance.
        id: CmdId,
    },
    /// A PLCopen Part 4 axis-group FB call (plcopen_platform.md §3.2, §5).
    Group(crate::group::GroupCommand),
    /// A platform service: safety, simulation, session (plcopen_platform.md §8–§12).
    Platform(isg_platform::PlatformCommand),
    // ---- phasing, multi-master gearing, external setpoint generator, §4.7 extensions
    // (modules single_axis::set::{phasing, multi_master, ext_setpoint, extensions})
    /// MC_PhasingAbsolute (§4.13.1).
    PhasingAbsolute(PhasingAbsolute),
    /// MC_PhasingRelative (§4.13.2).
    PhasingRelative(PhasingRelative),
    /// MC_HaltPhasing (§4.13.3).
    HaltPhasing(HaltPhasing),
    /// A later call of a running MC_PhasingAbsolute/Relative started with ContinuousUpdate.
    PhasingUpdate(PhasingUpdate),
    /// MC_GearInMultiMaster (§4.12.4, Enable-type).
    GearInMultiMaster(GearInMultiMaster),
    /// MC_ExtSetPointGenEnable (§4.6.1).
    ExtSetPointGenEnable(ExtSetPointGenEnable),
    /// MC_ExtSetPointGenDisable (§4.6.2).
    ExtSetPointGenDisable(ExtSetPointGenDisable),
    /// MC_ExtSetPointGenFeed (§4.6.3, FUNCTION).
    ExtSetPointGenFeed(ExtSetPointGenFeed),
    /// MC_ExtSetPointGenFeedWithTorque (§4.6.4, FUNCTION).
    ExtSetPointGenFeedWithTorque(ExtSetPointGenFeedWithTorque),
    /// MC_ReadDriveOperationMode (§4.7.1).
    ReadDriveOperationMode(ReadDriveOperationMode),
    /// MC_WriteDriveOperationMode (§4.7.1).
    WriteDriveOperationMode(WriteDriveOperationMode),
    /// MC_BacklashCompensation (§4.7.2, Enable-type).
    BacklashCompensation(BacklashCompensation),
    /// MC_PositionCorrectionLimiter (§4.7.5, Enable-type).
    PositionCorrectionLimiter(PositionCorrectionLimiter),
    /// MC_ReadDriveAddress (§4.7.6).
    ReadDriveAddress(ReadDriveAddress),
    /// MC_SelectControlLoop (§4.7.7).
    SelectControlLoop(SelectControlLoop),
    /// MC_SetAcceptBlockedDriveSignal (§4.7.8, FUNCTION).
    SetAcceptBlockedDriveSignal(SetAcceptBlockedDriveSignal),
    /// MC_SetEncoderScalingFactor (§4.7.9).
    SetEncoderScalingFactor(SetEncoderScalingFactor),
    /// MC_WriteNcIoOutput (§4.7.11).
    WriteNcIoOutput(WriteNcIoOutput),
    /// MC_TableBasedPositionCompensation (§4.7.12, Enable-type).
    TableBasedPositionCompensation(TableBasedPositionCompensation),
    /// MC_ConvertIncPosToPos (§4.7.13).
    ConvertIncPosToPos(ConvertIncPosToPos),
    /// MC_ConvertPosToIncPos (§4.7.13).
    ConvertPosToIncPos(ConvertPosToIncPos),
    /// MC_ReadParameterSet (§4.4.6).
    ReadParameterSet(ReadParameterSet),
    /// MC_ReadAxisComponents (§4.4.3).
    ReadAxisComponents(ReadAxisComponents),
    /// MC_WriteParameterPersistent (§4.4.9).
    WriteParameterPersistent(WriteParameter),
    /// MC_WriteBoolParameterPersistent (§4.4.9).
    WriteBoolParameterPersistent(WriteBoolParameter),
    /// A collision-avoidance group block (collision_avoidance.md; [`crate::ca`]).
    Ca(crate::ca::CaCommand),
}

// The outputs of one FB instance ([`AxisCommand::ReadFbOutputs`]).
pub use single_axis::InstanceOutputs;

/// A value returned at once by read-type FBs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ReplyValue {
    /// No value (motion and write commands).
    None,
    /// An LREAL value.
    Real(f64),
    /// A BOOL value.
    Bool(bool),
    /// A DWORD value (e.g. the axis error id).
    DWord(u32),
    /// MC_ReadStatus.
    Status(Box<AxisStatus>),
    /// [`AxisCommand::ReadFbOutputs`].
    Outputs(Box<InstanceOutputs>),
    /// Group read FBs (and [`AxisCommand::ReadFbOutputs`] of a group instance).
    Group(crate::group::GroupReply),
    /// Platform reads.
    Platform(isg_platform::PlatformReply),
    /// Structured values of the §4.7 / §4.4.3 / §4.4.6 read FBs.
    Extension(Box<ExtensionValue>),
    /// Values of the CA read/enable blocks ([`crate::ca::CaValue`]).
    Ca(Box<crate::ca::CaValue>),
}

/// The answer to an accepted command.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AxisReply {
    /// Identity of the FB instance started by this call.
    pub id: CmdId,
    /// Value of read-type FBs.
    pub value: ReplyValue,
    /// True when the id names a tracked FB instance whose outputs follow as events
    /// (false for MC_Power, read FBs and other calls without a lifetime).
    pub tracked: bool,
}

impl From<single_axis::FbValue> for ReplyValue {
    fn from(v: single_axis::FbValue) -> Self {
        use single_axis::FbValue as V;
        match v {
            V::None => ReplyValue::None,
            V::Real(x) => ReplyValue::Real(x),
            V::Bool(x) => ReplyValue::Bool(x),
            V::DWord(x) => ReplyValue::DWord(x),
            V::Status(x) => ReplyValue::Status(x),
            V::Outputs(x) => ReplyValue::Outputs(x),
            V::Extension(x) => ReplyValue::Extension(x),
        }
    }
}

impl From<crate::ca::CaReply> for AxisReply {
    fn from(r: crate::ca::CaReply) -> Self {
        AxisReply {
            id: r.id,
            value: r
                .value
                .map_or(ReplyValue::None, |v| ReplyValue::Ca(Box::new(v))),
            tracked: r.tracked,
        }
    }
}

impl AxisCommand {
    /// The manual's FB name of a single-axis call ([`isg_platform::SIM`] for the simulation inputs; empty
    /// for calls that are not single-axis FBs).
    pub fn fb_name(&self) -> &'static str {
        use AxisCommand::*;
        match self {
            Power(_) => "MC_Power",
            Reset(_) => "MC_Reset",
            MoveAbsolute(_) => "MC_MoveAbsolute",
            MoveRelative(_) => "MC_MoveRelative",
            MoveAdditive(_) => "MC_MoveAdditive",
            MoveModulo(_) => "MC_MoveModulo",
            MoveVelocity(_) => "MC_MoveVelocity",
            MoveContinuousAbsolute(_) => "MC_MoveContinuousAbsolute",
            MoveContinuousRelative(_) => "MC_MoveContinuousRelative",
            Halt(_) => "MC_Halt",
            Stop(_) => "MC_Stop",
            SetPosition(_) => "MC_SetPosition",
            ReadParameter(_) => "MC_ReadParameter",
            ReadBoolParameter(_) => "MC_ReadBoolParameter",
            WriteParameter(_) => "MC_WriteParameter",
            WriteBoolParameter(_) => "MC_WriteBoolParameter",
            ReadStatus(_) => "MC_ReadStatus",
            ReadActualPosition(_) => "MC_ReadActualPosition",
            ReadActualVelocity(_) => "MC_ReadActualVelocity",
            ReadAxisError(_) => "MC_ReadAxisError",
            Sim(_) => isg_platform::SIM,
            Home(_) => "MC_Home",
            Jog(_) => "MC_Jog",
            SetOverride(_) => "MC_SetOverride",
            GearIn(_) => "MC_GearIn",
            GearOut(_) => "MC_GearOut",
            GearInDyn(_) => "MC_GearInDyn",
            TorqueControl(_) => "MC_TorqueControl",
            MoveSuperImposed(_) => "MC_MoveSuperImposed",
            AbortSuperposition(_) => "MC_AbortSuperposition",
            TouchProbe(_) => "MC_TouchProbe",
            AbortTrigger(_) => "MC_AbortTrigger",
            PhasingAbsolute(_) | PhasingUpdate(_) => "MC_PhasingAbsolute",
            PhasingRelative(_) => "MC_PhasingRelative",
            HaltPhasing(_) => "MC_HaltPhasing",
            GearInMultiMaster(_) => "MC_GearInMultiMaster",
            ExtSetPointGenEnable(_) => "MC_ExtSetPointGenEnable",
            ExtSetPointGenDisable(_) => "MC_ExtSetPointGenDisable",
            ExtSetPointGenFeed(_) => "MC_ExtSetPointGenFeed",
            ExtSetPointGenFeedWithTorque(_) => "MC_ExtSetPointGenFeedWithTorque",
            ReadDriveOperationMode(_) => "MC_ReadDriveOperationMode",
            WriteDriveOperationMode(_) => "MC_WriteDriveOperationMode",
            BacklashCompensation(_) => "MC_BacklashCompensation",
            PositionCorrectionLimiter(_) => "MC_PositionCorrectionLimiter",
            ReadDriveAddress(_) => "MC_ReadDriveAddress",
            SelectControlLoop(_) => "MC_SelectControlLoop",
            SetAcceptBlockedDriveSignal(_) => "MC_SetAcceptBlockedDriveSignal",
            SetEncoderScalingFactor(_) => "MC_SetEncoderScalingFactor",
            WriteNcIoOutput(_) => "MC_WriteNcIoOutput",
            TableBasedPositionCompensation(_) => "MC_TableBasedPositionCompensation",
            ConvertIncPosToPos(_) => "MC_ConvertIncPosToPos",
            ConvertPosToIncPos(_) => "MC_ConvertPosToIncPos",
            ReadParameterSet(_) => "MC_ReadParameterSet",
            ReadAxisComponents(_) => "MC_ReadAxisComponents",
            WriteParameterPersistent(_) => "MC_WriteParameterPersistent",
            WriteBoolParameterPersistent(_) => "MC_WriteBoolParameterPersistent",
            SetExecute { .. }
            | HomeCalibrationCam { .. }
            | TorqueControlUpdate { .. }
            | TouchProbePlcEvent { .. }
            | ReadFbOutputs { .. }
            | Group(_)
            | Platform(_)
            | Ca(_) => "",
        }
    }

    /// The manual's name of a single-axis motion FB (MC_MoveAbsolute ... MC_SetPosition), None
    /// for every other command: the commands that groups and the platform's safety rules
    /// screen on their axes.
    pub fn motion_fb_name(&self) -> Option<&'static str> {
        use AxisCommand::*;
        matches!(
            self,
            MoveAbsolute(_)
                | MoveRelative(_)
                | MoveAdditive(_)
                | MoveModulo(_)
                | MoveVelocity(_)
                | MoveContinuousAbsolute(_)
                | MoveContinuousRelative(_)
                | Halt(_)
                | Stop(_)
                | Home(_)
                | Jog(_)
                | GearIn(_)
                | GearInDyn(_)
                | GearOut(_)
                | TorqueControl(_)
                | MoveSuperImposed(_)
                | SetPosition(_)
        )
        .then(|| self.fb_name())
    }

    /// An FB added to Tc2_MC2 after the first release (phasing, multi-master gearing,
    /// external set-point generator, §4.7 extensions): not in the ISG catalogue.
    pub fn is_extension(&self) -> bool {
        use AxisCommand as C;
        matches!(
            self,
            C::PhasingAbsolute(_)
                | C::PhasingRelative(_)
                | C::HaltPhasing(_)
                | C::PhasingUpdate(_)
                | C::GearInMultiMaster(_)
                | C::ExtSetPointGenEnable(_)
                | C::ExtSetPointGenDisable(_)
                | C::ExtSetPointGenFeed(_)
                | C::ExtSetPointGenFeedWithTorque(_)
                | C::ReadDriveOperationMode(_)
                | C::WriteDriveOperationMode(_)
                | C::BacklashCompensation(_)
                | C::PositionCorrectionLimiter(_)
                | C::ReadDriveAddress(_)
                | C::SelectControlLoop(_)
                | C::SetAcceptBlockedDriveSignal(_)
                | C::SetEncoderScalingFactor(_)
                | C::WriteNcIoOutput(_)
                | C::TableBasedPositionCompensation(_)
                | C::ConvertIncPosToPos(_)
                | C::ConvertPosToIncPos(_)
                | C::ReadParameterSet(_)
                | C::ReadAxisComponents(_)
                | C::WriteParameterPersistent(_)
                | C::WriteBoolParameterPersistent(_)
        )
    }

    /// A plain single-axis motion command: refused on a member of an enabled CA group
    /// (collision_avoidance.md §4.2); MC_GearOut is not one there.
    pub fn is_plain_motion(&self) -> bool {
        self.motion_fb_name().is_some() && !matches!(self, AxisCommand::GearOut(_))
    }

    /// The axis the command addresses (None for `SetExecute`).
    pub fn axis(&self) -> Option<&str> {
        use AxisCommand::*;
        Some(match self {
            Power(c) => &c.axis,
            Reset(c) => &c.axis,
            MoveAbsolute(c) => &c.axis,
            MoveRelative(c) => &c.axis,
            MoveAdditive(c) => &c.axis,
            MoveModulo(c) => &c.axis,
            MoveVelocity(c) => &c.axis,
            Halt(c) => &c.axis,
            MoveContinuousAbsolute(c) => &c.axis,
            MoveContinuousRelative(c) => &c.axis,
            Stop(c) => &c.axis,
            SetPosition(c) => &c.axis,
            ReadParameter(c) => &c.axis,
            ReadBoolParameter(c) => &c.axis,
            WriteParameter(c) => &c.axis,
            WriteBoolParameter(c) => &c.axis,
            ReadStatus(c) => &c.axis,
            ReadActualPosition(c) => &c.axis,
            ReadActualVelocity(c) => &c.axis,
            ReadAxisError(c) => &c.axis,
            Home(c) => &c.axis,
            Jog(c) => &c.axis,
            SetOverride(c) => &c.axis,
            GearIn(c) => &c.slave,
            GearOut(c) => &c.slave,
            GearInDyn(c) => &c.slave,
            TorqueControl(c) => &c.axis,
            MoveSuperImposed(c) => &c.axis,
            AbortSuperposition(c) => &c.axis,
            TouchProbe(c) => &c.axis,
            AbortTrigger(c) => &c.axis,
            PhasingAbsolute(c) => &c.slave,
            PhasingRelative(c) => &c.slave,
            HaltPhasing(c) => &c.slave,
            GearInMultiMaster(c) => &c.slave,
            ExtSetPointGenEnable(c) => &c.axis,
            ExtSetPointGenDisable(c) => &c.axis,
            ExtSetPointGenFeed(c) => &c.axis,
            ExtSetPointGenFeedWithTorque(c) => &c.axis,
            ReadDriveOperationMode(c) => &c.axis,
            WriteDriveOperationMode(c) => &c.axis,
            BacklashCompensation(c) => &c.axis,
            PositionCorrectionLimiter(c) => &c.axis,
            ReadDriveAddress(c) => &c.axis,
            SelectControlLoop(c) => &c.axis,
            SetAcceptBlockedDriveSignal(c) => &c.axis,
            SetEncoderScalingFactor(c) => &c.axis,
            WriteNcIoOutput(c) => &c.axis,
            TableBasedPositionCompensation(c) => &c.axis,
            ConvertIncPosToPos(c) => &c.axis,
            ConvertPosToIncPos(c) => &c.axis,
            ReadParameterSet(c) => &c.axis,
            ReadAxisComponents(c) => &c.axis,
            WriteParameterPersistent(c) => &c.axis,
            WriteBoolParameterPersistent(c) => &c.axis,
            PhasingUpdate(_) => return None,
            SetExecute { .. }
            | HomeCalibrationCam { .. }
            | TorqueControlUpdate { .. }
            | TouchProbePlcEvent { .. }
            | ReadFbOutputs { .. }
            | Group(_)
            | Platform(_)
            | Ca(_) => return None,
            Sim(s) => match s {
                self::Sim::InjectAxisError { axis, .. }
                | self::Sim::DriveFault { axis, .. }
                | self::Sim::SetFollowingOffset { axis, .. }
                | self::Sim::ProbeInput { axis, .. } => axis,
            },
        })
    }
}

// ---- Inputs of the added FBs (single_axis::added_inputs) and of the §4.7 extensions
pub use crate::extension_inputs::*;
pub use single_axis::added_inputs::*;
pub use single_axis::handshake::ExtraOutputs;
