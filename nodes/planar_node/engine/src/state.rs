//! The planar state machine shared by movers, groups and parts (xplanar.md §2.1).
//!
//! Transitional states (Enabling, Disabling, Resetting, ErrorPending) last the configured
//! times; the owner decides when a phase may start counting (e.g. a mover first stops before
//! its disable time runs) through [`PlanarStateMachine::hold`].

use crate::errors::{reject, E_INVALID_STATE};
use crate::types::{ErrorReaction, PlanarState};
use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, Rejection};

/// Durations of the transitional states \[s\] (§1.12).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Enabling → Enabled.
    pub enable_time: f64,
    /// Disabling → Disabled.
    pub disable_time: f64,
    /// Resetting → Enabled/Disabled.
    pub reset_time: f64,
    /// ErrorPending → Error.
    pub error_pending_time: f64,
}

/// What a state-machine command did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Accepted {
    /// A transition started; the command completes later.
    Started,
    /// Nothing to do: the command is Done at once.
    AlreadyThere,
}

/// One object's planar state with its timers and the Enable/Disable/Reset commands waiting
/// for their end state.
#[derive(Clone, Debug, Default)]
pub(crate) struct PlanarStateMachine {
    pub state: PlanarState,
    /// Time left in the transitional state \[s\].
    timer: f64,
    /// Error reaction of the current/last error (§2.1).
    pub reaction: ErrorReaction,
    /// Error id of the current error (0 when none).
    pub error_id: ErrorId,
    enables: Vec<CmdId>,
    disables: Vec<CmdId>,
    resets: Vec<CmdId>,
}

fn finish(ids: &mut Vec<CmdId>, state: CommandState, events: &mut Vec<CommandEvent>) {
    for id in ids.drain(..) {
        events.push(CommandEvent { id, state });
    }
}

impl PlanarStateMachine {
    /// True in ErrorPending, Error and Resetting.
    pub fn in_error(&self) -> bool {
        matches!(
            self.state,
            PlanarState::ErrorPending | PlanarState::Error | PlanarState::Resetting
        )
    }

    /// Enable (T1, T6). `who` names the object for messages.
    pub fn enable(
        &mut self,
        id: CmdId,
        t: &Timing,
        who: &str,
        events: &mut Vec<CommandEvent>,
    ) -> Result<Accepted, Rejection> {
        match self.state {
            PlanarState::Enabled => return Ok(Accepted::AlreadyThere),
            PlanarState::Disabled => {
                self.state = PlanarState::Enabling;
                self.timer = t.enable_time;
            }
            PlanarState::Disabling => {
                // T6: aborts the running Disable.
                finish(&mut self.disables, CommandState::Aborted, events);
                self.state = PlanarState::Enabling;
                self.timer = t.enable_time;
            }
            PlanarState::Enabling => {}
            s => {
                return Err(reject(
                    E_INVALID_STATE,
                    format!("{who}: Enable not allowed in state {s:?}"),
                ));
            }
        }
        self.enables.push(id);
        Ok(Accepted::Started)
    }

    /// Disable (T3, T4, T12).
    pub fn disable(&mut self, id: CmdId, t: &Timing, events: &mut Vec<CommandEvent>) -> Accepted {
        match self.state {
            PlanarState::Disabled => return Accepted::AlreadyThere,
            PlanarState::Enabling | PlanarState::Enabled => {
                finish(&mut self.enables, CommandState::Aborted, events);
                self.state = PlanarState::Disabling;
                self.timer = t.disable_time;
            }
            PlanarState::Disabling => {}
            PlanarState::ErrorPending | PlanarState::Error | PlanarState::Resetting => {
                // T12: forces the Abort reaction; the later reset ends in Disabled.
                self.reaction = ErrorReaction::Abort;
                return Accepted::AlreadyThere;
            }
            PlanarState::Invalid => return Accepted::AlreadyThere,
        }
        self.disables.push(id);
        Accepted::Started
    }

    /// Reset (T9).
    pub fn reset(&mut self, id: CmdId, t: &Timing, who: &str) -> Result<Accepted, Rejection> {
        match self.state {
            PlanarState::Error => {
                self.state = PlanarState::Resetting;
                self.timer = t.reset_time;
            }
            PlanarState::Resetting => {}
            PlanarState::ErrorPending => {
                return Err(reject(
                    E_INVALID_STATE,
                    format!(
                        "{who}: Reset not allowed while the error reaction runs (ErrorPending)"
                    ),
                ));
            }
            _ => return Ok(Accepted::AlreadyThere),
        }
        self.resets.push(id);
        Ok(Accepted::Started)
    }

    /// An error occurs (T7, T14). Returns true if the state changed to ErrorPending.
    pub fn error(
        &mut self,
        id: ErrorId,
        reaction: ErrorReaction,
        t: &Timing,
        events: &mut Vec<CommandEvent>,
    ) -> bool {
        match self.state {
            PlanarState::Resetting => false,
            PlanarState::ErrorPending => {
                self.reaction = self.reaction.max(reaction);
                false
            }
            s => {
                // Never de-escalate while in Error (T14).
                self.reaction = if s == PlanarState::Error {
                    self.reaction.max(reaction)
                } else {
                    reaction
                };
                self.error_id = id;
                self.state = PlanarState::ErrorPending;
                self.timer = t.error_pending_time;
                finish(&mut self.enables, CommandState::Error(id), events);
                finish(&mut self.disables, CommandState::Error(id), events);
                true
            }
        }
    }

    /// Counts down the transitional timer; returns the state whose phase just ended.
    /// `may_finish` lets the owner delay the end (e.g. mover not yet at rest).
    pub fn advance(&mut self, dt: f64, may_finish: bool) -> Option<PlanarState> {
        if !matches!(
            self.state,
            PlanarState::Enabling
                | PlanarState::Disabling
                | PlanarState::Resetting
                | PlanarState::ErrorPending
        ) {
            return None;
        }
        self.timer -= dt;
        if self.timer <= 1e-9 && may_finish {
            Some(self.state)
        } else {
            None
        }
    }

    /// Keeps the timer from running out before a precondition holds.
    pub fn hold(&mut self, t: f64) {
        self.timer = self.timer.max(t);
    }

    /// Completes the current transitional phase (after `advance` reported it).
    pub fn complete(&mut self, events: &mut Vec<CommandEvent>) {
        match self.state {
            PlanarState::Enabling => {
                self.state = PlanarState::Enabled;
                finish(&mut self.enables, CommandState::Done, events);
            }
            PlanarState::Disabling => {
                self.state = PlanarState::Disabled;
                finish(&mut self.disables, CommandState::Done, events);
            }
            PlanarState::ErrorPending => self.state = PlanarState::Error,
            PlanarState::Resetting => {
                // T10 / T11: the reaction decides where the reset ends.
                self.state = if self.reaction == ErrorReaction::Abort {
                    PlanarState::Disabled
                } else {
                    PlanarState::Enabled
                };
                self.reaction = ErrorReaction::None;
                self.error_id = ErrorId::NONE;
                finish(&mut self.resets, CommandState::Done, events);
            }
            _ => {}
        }
    }
}

impl PlanarStateMachine {
    /// Drives an object without its own commands (a part following its movers, §2.6):
    /// starts enabling or disabling when the wish differs from the state.
    pub fn drive(&mut self, enable: bool, t: &Timing) {
        match (enable, self.state) {
            (true, PlanarState::Disabled | PlanarState::Disabling) => {
                self.state = PlanarState::Enabling;
                self.timer = t.enable_time;
            }
            (false, PlanarState::Enabled | PlanarState::Enabling) => {
                self.state = PlanarState::Disabling;
                self.timer = t.disable_time;
            }
            _ => {}
        }
    }
}

impl PlanarStateMachine {
    /// True once the transitional timer has run out (the phase may still be held).
    pub fn timer_elapsed(&self) -> bool {
        self.timer <= 1e-9
    }

    /// T13: the reset could not clear the cause; back to Error, the Reset commands fail.
    pub fn fail_reset(&mut self, id: ErrorId, events: &mut Vec<CommandEvent>) {
        if self.state == PlanarState::Resetting {
            self.state = PlanarState::Error;
            finish(&mut self.resets, CommandState::Error(id), events);
        }
    }
}
