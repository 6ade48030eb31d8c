//! Where a platform profile changes single-axis behaviour: a small trait the profile's crate
//! implements. [`Tc2Mc2`] (every default) is the behaviour of the manual itself.

use crate::axis::Axis;
use motion_core::{ErrorId, Limits};

/// The single-axis rules a platform profile may change.
pub trait AxisProfile: std::fmt::Debug + Send {
    /// The target of a discrete motion (MC_MoveAbsolute/Relative, not buffered) started on
    /// axis `ax` while it moves; default unchanged.
    fn target_while_moving(&self, ax: usize, axis: &Axis, target: f64, limits: &Limits) -> f64 {
        let _ = (ax, axis, limits);
        target
    }

    /// Whether a final result (Done/CommandAborted/Error) stays until Execute falls instead of
    /// showing for one cycle (§3.1); default no.
    fn latch_done(&self) -> bool {
        false
    }

    /// The ErrorID an instance of `axis` shows for `id`; default `id`.
    fn shown_error_id(&self, axis: &Axis, id: ErrorId) -> ErrorId {
        let _ = axis;
        id
    }
}

/// Tc2_MC2 as the manual describes it: no profile changes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tc2Mc2;

impl AxisProfile for Tc2Mc2 {}
