//! Error ids as the manuals number them (TwinCAT NC ids are hex, e.g. 0x4B01).

use serde::{Deserialize, Serialize};
use std::fmt;

/// A manual's error number. `ErrorId::NONE` (0) means no error.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub struct ErrorId(pub u32);

impl ErrorId {
    /// No error.
    pub const NONE: ErrorId = ErrorId(0);

    // Ids of the shell and runtime, shared by all nodes (proposal: the manuals do not cover
    // the transport). Kept in the 0x7F00 range, which no manual of this suite uses.
    /// The named object (axis, mover, group, belt, ...) is not configured.
    pub const UNKNOWN_OBJECT: ErrorId = ErrorId(0x7F01);
    /// A request field is NaN or infinite.
    pub const NOT_FINITE: ErrorId = ErrorId(0x7F02);
    /// An enum field is out of range.
    pub const ENUM_OUT_OF_RANGE: ErrorId = ErrorId(0x7F03);
    /// The cycle's command queue is full; the command was not queued.
    pub const QUEUE_FULL: ErrorId = ErrorId(0x7F04);
    /// The node is shutting down or its cycle is not running.
    pub const NOT_RUNNING: ErrorId = ErrorId(0x7F05);
    /// A request field is outside its allowed range (e.g. a negative limit).
    pub const VALUE_OUT_OF_RANGE: ErrorId = ErrorId(0x7F06);
    /// The command is not implemented by this engine yet.
    pub const NOT_IMPLEMENTED: ErrorId = ErrorId(0x7F07);

    /// True for `NONE`.
    pub fn is_none(self) -> bool {
        self.0 == 0
    }
}

impl fmt::Display for ErrorId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:04X}", self.0)
    }
}
