//! The PLCopen function-block handshake shared by all engines (single_axis.md §3).
//!
//! One service/action call is one rising Execute edge of a fresh FB instance: the engine
//! admits it (returning a [`CmdId`]) or rejects it at once with a [`Rejection`]. Afterwards
//! the instance's outputs change only inside `step`, reported as [`CommandEvent`]s.

use crate::error_id::ErrorId;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Identity of one admitted FB instance (one Execute edge). Unique per engine.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub struct CmdId(pub u64);

/// The mutually exclusive phase of an Execute-type FB (single_axis.md §3.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum CommandState {
    /// Admitted and queued (buffered behind another command): Busy, not yet Active.
    Busy,
    /// In control of the object: Busy and Active.
    Active,
    /// Finished as commanded (Done). Final.
    Done,
    /// Taken over by another command or a stop (CommandAborted). Final.
    Aborted,
    /// Ended with an error (Error + ErrorID). Final.
    Error(ErrorId),
    /// Ended without Done, CommandAborted or Error: all outputs FALSE (XPlanar external
    /// set-point generation: "when ESG ends, Busy becomes FALSE without Done", xplanar.md
    /// §6.1). Final.
    Ended,
}

impl CommandState {
    /// Done, Aborted and Error end an instance; Busy and Active do not.
    pub fn is_final(self) -> bool {
        matches!(
            self,
            CommandState::Done
                | CommandState::Aborted
                | CommandState::Error(_)
                | CommandState::Ended
        )
    }
}

/// The standard outputs of an Execute-type FB, derived from its state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ExecuteOutputs {
    /// Done output.
    pub done: bool,
    /// Busy output.
    pub busy: bool,
    /// Active output.
    pub active: bool,
    /// CommandAborted output.
    pub command_aborted: bool,
    /// Error output.
    pub error: bool,
    /// ErrorID output (0 unless `error`).
    pub error_id: ErrorId,
}

impl From<CommandState> for ExecuteOutputs {
    fn from(s: CommandState) -> Self {
        let mut o = ExecuteOutputs::default();
        match s {
            CommandState::Busy => o.busy = true,
            CommandState::Active => {
                o.busy = true;
                o.active = true
            }
            CommandState::Done => o.done = true,
            CommandState::Aborted => o.command_aborted = true,
            CommandState::Ended => {}
            CommandState::Error(id) => {
                o.error = true;
                o.error_id = id
            }
        }
        o
    }
}

/// A status change of an admitted command, reported by `Engine::step`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CommandEvent {
    /// The command instance.
    pub id: CmdId,
    /// Its new state.
    pub state: CommandState,
}

/// Longest message text a reply carries [bytes]; longer texts end in [`TRUNCATED`].
pub const MAX_MESSAGE_LEN: usize = 1024;

/// The tail of a capped message.
pub const TRUNCATED: &str = " ... (truncated)";

/// Caps `text` at [`MAX_MESSAGE_LEN`] bytes (on a character boundary), marking the cut with
/// [`TRUNCATED`]: echoed input (a bad YAML text, a value) must never make a reply unbounded.
fn cap_message(mut text: String) -> String {
    if text.len() > MAX_MESSAGE_LEN {
        let mut cut = MAX_MESSAGE_LEN - TRUNCATED.len();
        while !text.is_char_boundary(cut) {
            cut -= 1;
        }
        text.truncate(cut);
        text.push_str(TRUNCATED);
    }
    text
}

/// Why a command was refused at its Execute edge (it never became Busy).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rejection {
    /// The manual's error id.
    pub error_id: ErrorId,
    /// Human-readable: names the object, field and value where there is one.
    pub message: String,
    /// The object the error names, where the manual reports one (XPlanar `objectInfo` of
    /// E_COLLISION: the blocking object's type and id).
    #[serde(default)]
    pub object: Option<ObjectRef>,
}

/// An object reference in an error: the manual's object type number and the object's id.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ObjectRef {
    /// Object type (e.g. EPlanarObjectType: 302 mover, 303 track, 304 environment).
    pub kind: u16,
    /// Object id (OID).
    pub id: u32,
}

impl Rejection {
    /// A rejection with an id and a message.
    /// The message is capped at [`MAX_MESSAGE_LEN`] bytes: it may quote the request (a bad
    /// YAML text, a value), and a reply must never grow with its input.
    pub fn new(error_id: ErrorId, message: impl Into<String>) -> Self {
        Rejection {
            error_id,
            message: cap_message(message.into()),
            object: None,
        }
    }

    /// The same rejection naming `object`.
    pub fn with_object(mut self, object: ObjectRef) -> Self {
        self.object = Some(object);
        self
    }

    /// A NaN/infinite field.
    pub fn not_finite(object: &str, field: &str, value: f64) -> Self {
        Rejection::new(
            ErrorId::NOT_FINITE,
            format!("{object}: {field} = {value} is not finite"),
        )
    }

    /// An unknown object name.
    pub fn unknown_object(kind: &str, name: &str) -> Self {
        Rejection::new(ErrorId::UNKNOWN_OBJECT, format!("unknown {kind} '{name}'"))
    }
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "error {}: {}", self.error_id, self.message)
    }
}

impl std::error::Error for Rejection {}

#[cfg(test)]
mod message_cap_tests {
    use super::*;

    #[test]
    fn long_messages_are_capped_on_a_char_boundary() {
        let long = "ä".repeat(MAX_MESSAGE_LEN); // 2 bytes each
        let r = Rejection::new(ErrorId(1), long);
        assert!(r.message.len() <= MAX_MESSAGE_LEN, "{}", r.message.len());
        assert!(r.message.ends_with(TRUNCATED));
        let short = Rejection::new(ErrorId(1), "x = NaN");
        assert_eq!(short.message, "x = NaN");
        let exact = "a".repeat(MAX_MESSAGE_LEN);
        assert_eq!(Rejection::new(ErrorId(1), exact.clone()).message, exact);
    }
}
