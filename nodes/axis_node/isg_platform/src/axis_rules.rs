//! The `isg_mcp` profile's changes to the single axis, as the axis crate's
//! [`single_axis::AxisProfile`]: latched final outputs (R-HS-2), the axis error shown as
//! ERR_PLC_AX_MC (§7), and R-SYS-2 targets on moving modulo axes.

use super::ids::ERR_PLC_AX_MC;
use motion_core::{ErrorId, Limits};
use single_axis::axis::Axis;
use single_axis::AxisProfile;

/// The single-axis rules of `isg_mcp`; `modulo[ax]` = axis `ax` is a modulo axis of the
/// platform configuration.
#[derive(Clone, Debug, Default)]
pub struct IsgAxisRules {
    /// Per axis: configured as a modulo axis (`platform.axes.<name>.modulo`).
    pub modulo: Vec<bool>,
}

impl AxisProfile for IsgAxisRules {
    /// R-SYS-2: on a modulo axis that moves, a discrete motion's target lying behind the
    /// stopping point (with the new command's limits) is replaced by the first equivalent
    /// position (same value modulo the period) at or beyond it in the travel direction: the
    /// axis brakes over as many revolutions as needed. Otherwise unchanged.
    fn target_while_moving(&self, ax: usize, a: &Axis, target: f64, limits: &Limits) -> f64 {
        let v = a.set.vel;
        if !self.modulo.get(ax).copied().unwrap_or(false) || v.abs() <= 1e-9 {
            return target;
        }
        let period = a.cfg.modulo_value;
        let stop = a.plan_stop(limits).end().pos;
        let dir = v.signum();
        let behind = (stop - target) * dir;
        if behind <= 0.0 {
            return target;
        }
        target + dir * period * (behind / period).ceil()
    }

    /// R-HS-2: a final result stays until Execute falls.
    fn latch_done(&self) -> bool {
        true
    }

    /// §7.2: the axis' own error is reported as ERR_PLC_AX_MC, anything else unchanged.
    fn shown_error_id(&self, axis: &Axis, id: ErrorId) -> ErrorId {
        if !axis.error_id.is_none() && axis.error_id == id {
            ERR_PLC_AX_MC
        } else {
            id
        }
    }
}
