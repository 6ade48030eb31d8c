//! FB instance bookkeeping: the Execute-type handshake of single_axis.md §3.1–§3.3.
//!
//! Every admitted command is one FB instance with a [`CmdId`]. Its phase is a
//! [`CommandState`] (so Busy/Done/Error/CommandAborted are exclusive by construction, §3.2);
//! the outputs add the Execute rules on top: a falling Execute resets the outputs of a finished
//! instance (rule 5); a result that arrives while Execute is already FALSE is shown for exactly
//! one cycle (rule 6). MC_Stop's exception (Done together with Busy/Active while the axis is
//! locked) and MC_MoveVelocity's InVelocity are extra flags.

use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, ExecuteOutputs};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Which FB an instance belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum FbKind {
    /// MC_Power (Enable-type; one instance per axis, read with its command id).
    Power,
    /// MC_Reset.
    Reset,
    /// MC_MoveAbsolute.
    MoveAbsolute,
    /// MC_MoveRelative.
    MoveRelative,
    /// MC_MoveAdditive.
    MoveAdditive,
    /// MC_MoveModulo.
    MoveModulo,
    /// MC_MoveVelocity.
    MoveVelocity,
    /// MC_MoveContinuousAbsolute.
    MoveContinuousAbsolute,
    /// MC_MoveContinuousRelative.
    MoveContinuousRelative,
    /// MC_Halt.
    Halt,
    /// MC_Stop.
    Stop,
    /// MC_SetPosition.
    SetPosition,
    /// MC_WriteParameter / MC_WriteBoolParameter.
    WriteParameter,
    /// MC_Home.
    Home,
    /// MC_Jog.
    Jog,
    /// MC_GearIn (Done = InGear).
    GearIn,
    /// MC_GearOut.
    GearOut,
    /// MC_GearInDyn (Enable-type; InGear while r_eff = GearRatio).
    GearInDyn,
    /// MC_TorqueControl.
    TorqueControl,
    /// MC_MoveSuperImposed.
    MoveSuperImposed,
    /// MC_AbortSuperposition.
    AbortSuperposition,
    /// MC_TouchProbe.
    TouchProbe,
    /// MC_AbortTrigger.
    AbortTrigger,
    // ---- set/phasing.rs, multi_master.rs, ext_setpoint.rs, extensions.rs
    /// MC_PhasingAbsolute.
    PhasingAbsolute,
    /// MC_PhasingRelative.
    PhasingRelative,
    /// MC_HaltPhasing.
    HaltPhasing,
    /// MC_GearInMultiMaster (Enable-type; InGear while synchronous).
    GearInMultiMaster,
    /// MC_ExtSetPointGenEnable.
    ExtSetPointGenEnable,
    /// MC_ExtSetPointGenDisable.
    ExtSetPointGenDisable,
    /// MC_ReadDriveOperationMode.
    ReadDriveOperationMode,
    /// MC_WriteDriveOperationMode.
    WriteDriveOperationMode,
    /// MC_BacklashCompensation (Enable-type).
    BacklashCompensation,
    /// MC_PositionCorrectionLimiter (Enable-type).
    PositionCorrectionLimiter,
    /// MC_TableBasedPositionCompensation (Enable-type).
    TableBasedPositionCompensation,
    /// MC_ReadDriveAddress.
    ReadDriveAddress,
    /// MC_SelectControlLoop.
    SelectControlLoop,
    /// MC_SetEncoderScalingFactor.
    SetEncoderScalingFactor,
    /// MC_WriteNcIoOutput.
    WriteNcIoOutput,
    /// MC_ReadParameterSet.
    ReadParameterSet,
    /// MC_ReadAxisComponents.
    ReadAxisComponents,
    /// MC_WriteParameterPersistent / MC_WriteBoolParameterPersistent.
    WriteParameterPersistent,
}

impl FbKind {
    /// The manual's FB name (`MC_` + the variant).
    pub fn fb_name(self) -> &'static str {
        match self {
            FbKind::Power => "MC_Power",
            FbKind::Reset => "MC_Reset",
            FbKind::MoveAbsolute => "MC_MoveAbsolute",
            FbKind::MoveRelative => "MC_MoveRelative",
            FbKind::MoveAdditive => "MC_MoveAdditive",
            FbKind::MoveModulo => "MC_MoveModulo",
            FbKind::MoveVelocity => "MC_MoveVelocity",
            FbKind::MoveContinuousAbsolute => "MC_MoveContinuousAbsolute",
            FbKind::MoveContinuousRelative => "MC_MoveContinuousRelative",
            FbKind::Halt => "MC_Halt",
            FbKind::Stop => "MC_Stop",
            FbKind::SetPosition => "MC_SetPosition",
            FbKind::WriteParameter => "MC_WriteParameter",
            FbKind::Home => "MC_Home",
            FbKind::Jog => "MC_Jog",
            FbKind::GearIn => "MC_GearIn",
            FbKind::GearOut => "MC_GearOut",
            FbKind::GearInDyn => "MC_GearInDyn",
            FbKind::TorqueControl => "MC_TorqueControl",
            FbKind::MoveSuperImposed => "MC_MoveSuperImposed",
            FbKind::AbortSuperposition => "MC_AbortSuperposition",
            FbKind::TouchProbe => "MC_TouchProbe",
            FbKind::AbortTrigger => "MC_AbortTrigger",
            FbKind::PhasingAbsolute => "MC_PhasingAbsolute",
            FbKind::PhasingRelative => "MC_PhasingRelative",
            FbKind::HaltPhasing => "MC_HaltPhasing",
            FbKind::GearInMultiMaster => "MC_GearInMultiMaster",
            FbKind::ExtSetPointGenEnable => "MC_ExtSetPointGenEnable",
            FbKind::ExtSetPointGenDisable => "MC_ExtSetPointGenDisable",
            FbKind::ReadDriveOperationMode => "MC_ReadDriveOperationMode",
            FbKind::WriteDriveOperationMode => "MC_WriteDriveOperationMode",
            FbKind::BacklashCompensation => "MC_BacklashCompensation",
            FbKind::PositionCorrectionLimiter => "MC_PositionCorrectionLimiter",
            FbKind::TableBasedPositionCompensation => "MC_TableBasedPositionCompensation",
            FbKind::ReadDriveAddress => "MC_ReadDriveAddress",
            FbKind::SelectControlLoop => "MC_SelectControlLoop",
            FbKind::SetEncoderScalingFactor => "MC_SetEncoderScalingFactor",
            FbKind::WriteNcIoOutput => "MC_WriteNcIoOutput",
            FbKind::ReadParameterSet => "MC_ReadParameterSet",
            FbKind::ReadAxisComponents => "MC_ReadAxisComponents",
            FbKind::WriteParameterPersistent => "MC_WriteParameterPersistent",
        }
    }
}

/// All outputs of an Execute-type instance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FbOutputs {
    /// The standard outputs (Done, Busy, Active, CommandAborted, Error, ErrorID).
    pub standard: ExecuteOutputs,
    /// MC_MoveVelocity.InVelocity.
    pub in_velocity: bool,
    /// MC_MoveContinuousAbsolute/Relative.InEndVelocity.
    pub in_end_velocity: bool,
    /// MC_TorqueControl.InTorque.
    pub in_torque: bool,
    /// MC_GearIn / MC_GearInDyn.InGear.
    pub in_gear: bool,
}

#[derive(Clone, Copy, Debug)]
/// One admitted FB instance and its outputs (§3).
pub struct Instance {
    /// The axis (index) the instance commands.
    pub axis: usize,
    /// Which FB.
    pub kind: FbKind,
    /// Its state: Busy/Active, or final (Done, CommandAborted, Error).
    pub state: CommandState,
    /// Its Execute input as last called.
    pub execute: bool,
    /// Cycle in which the final state became visible.
    pub ended_cycle: u64,
    /// Outputs reset by a falling Execute edge.
    pub cleared: bool,
    /// InVelocity / InGear-type output of the instance.
    pub in_velocity: bool,
    /// MC_Stop: Done while the axis is still locked (Busy and Active stay TRUE).
    pub locked: bool,
}

/// Instances above this count are pruned (finished ones first) when a new one is admitted.
const PRUNE_ABOVE: usize = 4096;

/// The instance table and the event queue.
#[derive(Debug, Default)]
pub struct Handshake {
    instances: HashMap<CmdId, Instance>,
    next_id: u64,
    /// Events not yet handed out by `Engine::step`.
    pub events: Vec<CommandEvent>,
    /// Number of steps started so far (the current cycle while `in_step`).
    pub cycle: u64,
    /// True while `step` runs (final states then show in this cycle, else in the next).
    pub in_step: bool,
    /// Recorded data of MC_TouchProbe instances.
    pub probes: HashMap<CmdId, ProbeOutputs>,
    /// Extra outputs of MC_MoveSuperImposed instances.
    pub superimposed: HashMap<CmdId, SuperImposedOutputs>,
    /// Extra outputs of the phasing / position-correction FBs (single_axis::set).
    pub extra: HashMap<CmdId, ExtraOutputs>,
}

impl Handshake {
    /// No instances; ids start at 1.
    pub fn new() -> Self {
        Handshake {
            instances: HashMap::with_capacity(256),
            next_id: 1,
            events: Vec::with_capacity(256),
            cycle: 0,
            in_step: false,
            superimposed: HashMap::new(),
            probes: HashMap::new(),
            extra: HashMap::new(),
        }
    }

    /// A fresh id for calls that do not create a tracked instance (reads, MC_Power).
    pub fn untracked_id(&mut self) -> CmdId {
        let id = CmdId(self.next_id);
        self.next_id += 1;
        id
    }

    /// Admits a new instance in `state` (Busy = buffered, Active = in control).
    pub fn admit(&mut self, axis: usize, kind: FbKind, state: CommandState) -> CmdId {
        if self.instances.len() > PRUNE_ABOVE {
            let cycle = self.cycle;
            self.instances.retain(|_, i| {
                !(i.state.is_final() && (!i.execute || i.ended_cycle + 1000 < cycle))
            });
            let live = &self.instances;
            self.superimposed.retain(|id, _| live.contains_key(id));
            self.probes.retain(|id, _| live.contains_key(id));
            self.extra.retain(|id, _| live.contains_key(id));
        }
        let id = self.untracked_id();
        self.instances.insert(
            id,
            Instance {
                axis,
                kind,
                state,
                execute: true,
                ended_cycle: 0,
                cleared: false,
                in_velocity: false,
                locked: false,
            },
        );
        // The admission is the instance's first status (Busy, or Active when it takes over
        // at once): reported like every later change, so watchers see Active from the start.
        if !state.is_final() {
            self.events.push(CommandEvent { id, state });
        }
        id
    }

    /// The instance with this id.
    pub fn get(&self, id: CmdId) -> Option<&Instance> {
        self.instances.get(&id)
    }

    /// The instance with this id, to change its outputs.
    pub fn get_mut(&mut self, id: CmdId) -> Option<&mut Instance> {
        self.instances.get_mut(&id)
    }

    /// Moves an instance to `state` and queues the event. Final states never change again.
    pub fn set(&mut self, id: CmdId, state: CommandState) {
        let visible = if self.in_step {
            self.cycle
        } else {
            self.cycle + 1
        };
        if let Some(i) = self.instances.get_mut(&id) {
            if i.state.is_final() || i.state == state {
                return;
            }
            i.state = state;
            if state.is_final() {
                i.ended_cycle = visible;
                i.in_velocity = false;
            }
            self.events.push(CommandEvent { id, state });
        }
    }

    /// Shorthands.
    pub fn done(&mut self, id: CmdId) {
        self.set(id, CommandState::Done)
    }
    /// Ends the instance with CommandAborted.
    pub fn aborted(&mut self, id: CmdId) {
        self.set(id, CommandState::Aborted)
    }
    /// Ends the instance with Error and this ErrorID.
    pub fn error(&mut self, id: CmdId, e: ErrorId) {
        self.set(id, CommandState::Error(e))
    }
    /// The instance takes control (Active), e.g. a buffered command starting.
    pub fn active(&mut self, id: CmdId) {
        self.set(id, CommandState::Active)
    }

    /// Sets the Execute level (§3.1 rules 5 and 6). Returns the instance (for MC_Stop unlock).
    pub fn set_execute(&mut self, id: CmdId, execute: bool) -> Option<Instance> {
        let i = self.instances.get_mut(&id)?;
        if i.execute && !execute && i.state.is_final() && !i.locked {
            // Falling edge on a finished instance: outputs reset at once.
            i.cleared = true;
        }
        i.execute = execute;
        Some(*i)
    }

    /// The outputs as the FB would show them now.
    /// `latch` (isg_mcp, plcopen_platform.md R-HS-2): a final result stays
    /// until Execute falls instead of showing for one cycle.
    pub fn outputs_with(&self, id: CmdId, latch: bool) -> Option<FbOutputs> {
        let i = self.instances.get(&id)?;
        if i.state.is_final()
            && !i.execute
            && !i.locked
            && (i.cleared || (!latch && self.cycle > i.ended_cycle))
        {
            return Some(FbOutputs::default());
        }
        let mut standard = ExecuteOutputs::from(i.state);
        if i.locked {
            standard.busy = true;
            standard.active = true;
        }
        let flag = i.in_velocity && !i.state.is_final();
        let continuous = matches!(
            i.kind,
            FbKind::MoveContinuousAbsolute | FbKind::MoveContinuousRelative
        );
        Some(FbOutputs {
            standard,
            in_velocity: flag && i.kind == FbKind::MoveVelocity,
            in_end_velocity: flag && continuous,
            in_torque: flag && i.kind == FbKind::TorqueControl,
            // MC_GearIn: InGear is its Done (the command is complete once coupled).
            in_gear: (flag && matches!(i.kind, FbKind::GearInDyn | FbKind::GearInMultiMaster))
                || (i.kind == FbKind::GearIn && standard.done),
        })
    }
}

/// Outputs of the added FBs beyond the standard ones (the engine's `InstanceOutputs::extra`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum ExtraOutputs {
    /// MC_Power: Status (axis ready for operation) and Valid (outputs valid: called with
    /// Enable and no FB error).
    Power {
        /// Status.
        status: bool,
        /// Valid.
        valid: bool,
    },
    /// MC_PhasingAbsolute.AbsolutePhaseShift / MC_PhasingRelative.CoveredPhaseShift \[u\].
    Phasing {
        /// AbsolutePhaseShift (MC_PhasingAbsolute).
        absolute_phase_shift: Option<f64>,
        /// CoveredPhaseShift (MC_PhasingRelative).
        covered_phase_shift: Option<f64>,
    },
    /// MC_ExtSetPointGenEnable/Disable.Enabled: the generator's current state.
    ExtSetPointGen {
        /// Enabled.
        enabled: bool,
    },
    /// MC_BacklashCompensation.
    Backlash {
        /// Enabled.
        enabled: bool,
        /// CurrentBacklash \[u\].
        current_backlash: f64,
        /// Limiting: the correction is still ramping.
        limiting: bool,
    },
    /// MC_PositionCorrectionLimiter.
    CorrectionLimiter {
        /// Limiting: the requested value is not yet fully applied.
        limiting: bool,
    },
    /// MC_TableBasedPositionCompensation.
    TableCompensation {
        /// Enabled.
        enabled: bool,
        /// CurrentCorrection \[u\].
        current_correction: f64,
        /// Limiting.
        limiting: bool,
    },
}

/// `MC_TouchProbeRecordedData` plus RecordedPosition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ProbeOutputs {
    /// RecordedPosition (absolute or modulo per `ModuloPositions`).
    pub recorded_position: f64,
    /// RecordedData.Counter: valid edges in the last cycle with an edge.
    pub counter: f64,
    /// RecordedData.AbsolutePosition.
    pub absolute_position: f64,
    /// RecordedData.ModuloPosition.
    pub modulo_position: f64,
    /// CONTINOUS mode: cycle number of the last accepted edge (Done pulses in that cycle).
    pub edge_cycle: u64,
}

/// Outputs of an MC_MoveSuperImposed instance besides the standard ones (§4.9.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SuperImposedOutputs {
    /// Warning.
    pub warning: bool,
    /// WarningID (0x4243 = 16963).
    pub warning_id: ErrorId,
    /// ActualVelocityDiff.
    pub actual_velocity_diff: f64,
    /// ActualDistance (signed; the covered part if aborted).
    pub actual_distance: f64,
    /// ActualLength.
    pub actual_length: f64,
    /// ActualAcceleration.
    pub actual_acceleration: f64,
    /// ActualDeceleration.
    pub actual_deceleration: f64,
}
