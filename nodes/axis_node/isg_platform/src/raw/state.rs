//! State of the raw FB layer (plcopen_platform.md §12.2): the FB instances a PLC program
//! calls, their outputs and the acknowledgement queues. The behaviour is in [`super`].

use crate::RawWarning;
use motion_core::{CmdId, ErrorId};
use serde::{Deserialize, Serialize};
use std::collections::{HashMap, VecDeque};

/// One FB call of a PLC cycle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FbCall<C> {
    /// Instance name (the PLC's FB instance variable).
    pub instance: String,
    /// Execute input.
    pub execute: bool,
    /// The FB with its other inputs (including the axis = AXIS_REF).
    pub fb: C,
}

/// FB-internal state (R-FB-1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FbState {
    /// FB_IDLE.
    #[default]
    Idle,
    /// FB_ACTIVE: order(s) placed, collecting acknowledgements.
    Active,
    /// FB_ERROR: the last order attempt failed.
    Error,
}

/// Outputs of a called instance.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FbOut {
    /// Instance name.
    pub instance: String,
    /// Done.
    pub done: bool,
    /// Busy.
    pub busy: bool,
    /// Active.
    pub active: bool,
    /// CommandAborted.
    pub command_aborted: bool,
    /// Error.
    pub error: bool,
    /// ErrorID.
    pub error_id: ErrorId,
    /// InVelocity (MC_MoveVelocity).
    pub in_velocity: bool,
    /// Order number (0 = none yet).
    pub order_id: u32,
    /// Orders in flight under that number.
    pub in_flight: u32,
    /// FB-internal state.
    pub fb_state: FbState,
}

/// An acknowledgement posted by the MC (R-HS-5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum AckKind {
    /// The order was taken.
    Accepted,
    /// MC_MoveVelocity reached the velocity.
    InVelocity,
    /// Finished.
    Done,
    /// Aborted by a newer order.
    Aborted,
    /// Ended with an error.
    Error(ErrorId),
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Ack {
    pub(super) owner: usize,
    pub(super) kind: AckKind,
    pub(super) posted: u64,
    pub(super) order_id: u32,
}

#[derive(Clone, Debug)]
pub(super) struct Inst<C> {
    pub(super) name: String,
    pub(super) axis: usize,
    pub(super) state: FbState,
    pub(super) prev_execute: bool,
    pub(super) order_id: u32,
    pub(super) in_flight: u32,
    pub(super) engine: Vec<CmdId>,
    pub(super) out: FbOut,
    pub(super) in_velocity_acked: bool,
    /// FB_RETRY (§4.1): the order that found the slot occupied and the retries left
    /// (`MAX_RETRIALS`).
    pub(super) retry: Option<(C, u32)>,
    /// The inputs last sent, for Enable-type FBs with cyclic inputs (§6.2).
    pub(super) last_inputs: Option<C>,
}

/// The raw FB layer of one engine: its FB instances, the acknowledgement queues (one per
/// axis, then one per group channel) and the warnings so far.
#[derive(Clone, Debug)]
pub struct RawLayer<C> {
    pub(super) instances: Vec<Inst<C>>,
    pub(super) by_name: HashMap<String, usize>,
    pub(super) owner_of: HashMap<CmdId, usize>,
    pub(super) acks: Vec<VecDeque<Ack>>,
    pub(super) clog_warned: Vec<Option<(usize, u32)>>,
    pub(super) accepted: Vec<(usize, usize, u32)>,
    pub(super) cycle: u64,
    pub(super) warnings: Vec<RawWarning>,
}

impl<C> Inst<C> {
    pub(super) fn new(name: String) -> Self {
        Inst {
            name,
            axis: 0,
            state: FbState::Idle,
            prev_execute: false,
            order_id: 0,
            in_flight: 0,
            engine: Vec::new(),
            out: FbOut::default(),
            in_velocity_acked: false,
            retry: None,
            last_inputs: None,
        }
    }
}

impl<C> Default for RawLayer<C> {
    fn default() -> Self {
        RawLayer {
            instances: Vec::new(),
            by_name: HashMap::new(),
            owner_of: HashMap::new(),
            acks: Vec::new(),
            clog_warned: Vec::new(),
            accepted: Vec::new(),
            cycle: 0,
            warnings: Vec::new(),
        }
    }
}
