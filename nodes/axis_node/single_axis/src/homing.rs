//! MC_Home homing run (single_axis.md §4.10, W16): the HomingState phases 1→2→3→4→(5)→6→0
//! with the virtual cam of §1.5 ORed with `bCalibrationCam`.
//!
//! Reference modes: PLCCAM (1) = falling cam edge (phase 5 skipped); HARDWARESYNC (2) and
//! SOFTWARESYNC (5) = first sync pulse after the falling cam edge (pulses at raw positions
//! that are multiples of `sim.sync_pulse_period`). Latch modes (§4.10 simulator proposal):
//! HARDWARELATCHPOS (3) / SOFTDRIVELATCHPOS (6) = first rising edge of the virtual probe input
//! 1 after the falling cam edge (the level set with `sim.probe_input`, or a crossing of one of
//! `sim.probe_marks`, interpolated to the mark), HARDWARELATCHNEG (4) / SOFTDRIVELATCHNEG (7) =
//! first falling edge of that input. A level changed between two cycles is latched at the
//! position of the cycle boundary (the hardware latch of a real drive is exact; the virtual
//! input is only as fine as the command timing).

use motion_core::CmdId;

/// A running homing run.
#[derive(Clone, Copy, Debug)]
pub struct Homing {
    /// The MC_Home instance.
    pub owner: CmdId,
    /// NcToPlc.HomingState (1..6).
    pub phase: u32,
    /// Reference position assigned to the reference point.
    pub position: f64,
    /// Search direction (±1) towards the cam.
    pub search_dir: f64,
    /// Search velocity \[u/s\] (Options.SearchVelocity or the axis default).
    pub search_velocity: f64,
    /// Direction (±1) of the sync move off the cam.
    pub sync_dir: f64,
    /// Sync velocity \[u/s\] (Options.SyncVelocity or the axis default).
    pub sync_velocity: f64,
    /// E_EncoderReferenceMode actually used (1..7).
    pub mode: u32,
    /// bCalibrationCam level as last called.
    pub cam_input: bool,
    /// bCalibrationCam level of the previous cycle.
    pub prev_cam: bool,
    /// Raw position of the previous cycle (for edge interpolation).
    pub prev_raw: f64,
    /// Next sync pulse (phase 5), raw.
    pub pulse: f64,
    /// Raw position of the reference point.
    pub ref_raw: f64,
    /// Raw position at the start (search limit).
    pub start_raw: f64,
    /// Homed flag before the run (restored on abort).
    pub homed_before: bool,
}
