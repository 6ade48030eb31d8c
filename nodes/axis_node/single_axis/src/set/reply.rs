//! What an accepted single-axis FB call answers: the instance id, whether it is tracked, and
//! the value of read-type FBs. The composing engine widens [`FbValue`] into its own reply
//! type (which adds group, platform and collision-avoidance values).

use crate::extension_inputs::ExtensionValue;
use crate::handshake::{ExtraOutputs, FbKind, FbOutputs};
use crate::status::AxisStatus;
use motion_core::CmdId;
use serde::{Deserialize, Serialize};

/// A value returned at once by a read-type single-axis FB.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum FbValue {
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
    /// The outputs of an instance, as a PLC reads its FB instance.
    Outputs(Box<InstanceOutputs>),
    /// Structured values of the §4.7 / §4.4.3 / §4.4.6 read FBs.
    Extension(Box<ExtensionValue>),
}

/// The answer to an accepted single-axis FB call.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FbReply {
    /// Identity of the FB instance started by this call.
    pub id: CmdId,
    /// Value of read-type FBs.
    pub value: FbValue,
    /// True when the id names a tracked FB instance whose outputs follow as events
    /// (false for MC_Power, read FBs and other calls without a lifetime).
    pub tracked: bool,
}

/// The outputs of one FB instance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InstanceOutputs {
    /// Axis of the instance (the slave for gearing FBs).
    pub axis: String,
    /// The FB.
    pub kind: FbKind,
    /// Done/Busy/Active/CommandAborted/Error/ErrorID and the InVelocity-type flags.
    pub outputs: FbOutputs,
    /// MC_MoveSuperImposed: Warning, WarningID and the Actual* outputs.
    pub superimposed: Option<crate::superposition::SuperImposedOutputs>,
    /// MC_TouchProbe: RecordedPosition and RecordedData (after the first accepted edge).
    pub probe: Option<crate::probe::ProbeOutputs>,
    /// Extra outputs of the phasing, external-setpoint and position-correction FBs.
    pub extra: Option<ExtraOutputs>,
}
