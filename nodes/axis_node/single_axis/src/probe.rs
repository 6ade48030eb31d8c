//! MC_TouchProbe / MC_AbortTrigger (single_axis.md §4.5, W19) with the virtual probe inputs
//! of §1.5: a level per unit set by the client and `sim.probe_marks` (raw positions where a
//! rising edge occurs when the axis crosses them; the latched position is interpolated to the
//! exact crossing). `PlcEvent` latches the ActPos of the cycle with the rising edge.

use crate::inputs::{SignalEdge, TouchProbeMode};
use motion_core::CmdId;

pub use crate::handshake::ProbeOutputs;

/// An armed latch.
#[derive(Clone, Copy, Debug)]
pub struct Probe {
    /// The MC_TouchProbe instance.
    pub owner: CmdId,
    /// Which edge latches.
    pub edge: SignalEdge,
    /// Single or continuous latching.
    pub mode: TouchProbeMode,
    /// Only edges inside the window [first, last] latch.
    pub window_only: bool,
    /// Window start \[u\].
    pub first: f64,
    /// Window end \[u\].
    pub last: f64,
    /// The window and the recorded position are modulo positions.
    pub modulo_positions: bool,
    /// PlcEvent level (slot 2 only).
    pub plc_event: bool,
    /// PlcEvent level of the previous cycle.
    pub plc_prev: bool,
}
