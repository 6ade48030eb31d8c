//! `L_TT1P_States` (`eTMState`, pick_and_place.md §3.6, §4.1).

use serde::{Deserialize, Serialize};

/// State of the technology module; numbers as the spec's proposal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum TmState {
    /// `xEnable = FALSE`: block not executed.
    #[default]
    Disabled = 0,
    /// Waiting for commands (may hold a stopped path).
    Ready = 1,
    /// Error present, axes stopped.
    Error = 2,
    /// A stop input is active or the axes decelerate due to one.
    Stop = 3,
    /// A `scCtrlAGBC` request is served.
    Service = 4,
    /// Jogging +.
    JogPos = 5,
    /// Jogging −.
    JogNeg = 6,
    /// Homing sequence running.
    Homing = 7,
    /// Path preparation (≤ 25 cycles).
    PreparingPath = 8,
    /// Pick & place path running (incl. park waiting and synchronous dwell).
    MovePp = 9,
    /// Path held by `xPathInterrupt`.
    PathInterrupt = 10,
}

impl TmState {
    /// `xBusy` (§3.3 proposal), except STOP, which is busy only while not at standstill.
    pub fn is_busy_state(self) -> bool {
        matches!(
            self,
            TmState::PreparingPath
                | TmState::MovePp
                | TmState::PathInterrupt
                | TmState::Homing
                | TmState::JogPos
                | TmState::JogNeg
                | TmState::Service
        )
    }
}
