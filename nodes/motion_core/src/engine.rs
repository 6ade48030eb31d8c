//! The contract between an engine and the cycle that drives it.

use crate::error_id::ErrorId;
use crate::fb::{CmdId, CommandEvent, Rejection};

/// One cycle handed to an engine. Time never comes from a clock inside an engine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tick {
    /// Cycle counter since start (0 for the first cycle).
    pub index: u64,
    /// Nominal cycle time [s]; always the configured period, also after a late wake-up.
    pub dt: f64,
}

impl Tick {
    /// Simulated time at the start of this cycle [s].
    pub fn time(&self) -> f64 {
        self.index as f64 * self.dt
    }
}

/// A pure, deterministic engine: commands in, `step(dt)`, state out.
///
/// The runtime calls, in every cycle: `command` for each queued command (arrival order),
/// then `step` once, then `snapshot` when a state publication is due.
pub trait Engine: Send + 'static {
    /// A decoded, screened command (one FB call / Execute edge).
    type Command: Send + 'static;
    /// What an accepted command answers at once (usually its [`CmdId`] and a payload).
    type Reply: Send + 'static;
    /// A copy of the engine state, cheap enough to take at the state-topic rate.
    type Snapshot: Clone + Send + Sync + 'static;

    /// Applies one command. `Ok` = accepted (the command may still end in an error later,
    /// reported as a [`CommandEvent`]); `Err` = rejected at once with an error id.
    fn command(&mut self, cmd: Self::Command) -> Result<Self::Reply, Rejection>;

    /// Advances by one cycle. Status changes of commands are appended to `events`
    /// (the vector is reused by the caller: no allocation in steady state).
    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>);

    /// The state as published on the state topics.
    fn snapshot(&self) -> Self::Snapshot;

    /// [`Engine::snapshot`] into an earlier snapshot, reusing its memory (a lockstep state
    /// stream takes one every cycle). Default: a fresh one.
    fn snapshot_into(&self, out: &mut Self::Snapshot) {
        *out = self.snapshot();
    }

    /// Called when the ROS side gave up on a command (e.g. an action goal was cancelled):
    /// the engine applies the manual's halt semantics for it. Default: nothing to do.
    fn cancel(&mut self, _id: CmdId) -> Result<(), Rejection> {
        Ok(())
    }

    /// The command id inside an accepted reply when the command has a lifetime (its
    /// [`CommandEvent`]s follow); `None` for instantaneous commands. The ROS shell routes
    /// events to the caller (action goal) with it.
    fn reply_id(_reply: &Self::Reply) -> Option<CmdId> {
        None
    }

    /// Fail-safe (README "Operating it"): the node's ROS side is lost, so every moving object
    /// is brought to a controlled stop with the manual's stop dynamics (axes: MC_Stop with
    /// the fast deceleration and jerk; movers: Halt; the pick-and-place group: xPathStop).
    /// The runtime calls it once, then keeps cycling until [`Engine::at_rest`].
    /// Default: nothing to stop.
    fn fail_safe_stop(&mut self) {}

    /// True when nothing moves (the fail-safe stop has ended). Default: true.
    fn at_rest(&self) -> bool {
        true
    }

    /// A short text for an error id that arises during execution (after the Execute edge),
    /// published with the command status.
    fn error_text(id: ErrorId) -> String {
        format!("error {id}")
    }
}
