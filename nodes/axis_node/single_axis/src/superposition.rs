//! MC_MoveSuperImposed / MC_AbortSuperposition (single_axis.md §4.9, W9).
//!
//! The overlay is a trapezoidal velocity-difference profile Δv(τ) in *profile time* τ, which
//! advances with the base motion: `Δτ = |Δs_base| / VelocityProcess` per cycle. The overlay
//! offset `sign(D)·dir·∫Δv dτ` is added to the set position *and* to the running job's
//! coordinate offset, so a discrete base command's end position moves with it (§4.9.1
//! rule 8) and the MoveAbsolute still reports Done.

use crate::error_ids::SUPERPOSITION_INCOMPLETE;
use motion_core::{CmdId, ErrorId};

/// The planned trapezoid in profile time: peak `dv`, ramps `a`/`d`, total time `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayPlan {
    /// Peak velocity difference Δv \[u/s\].
    pub dv: f64,
    /// Acceleration of the overlay a' \[u/s²\].
    pub a: f64,
    /// Deceleration of the overlay d' \[u/s²\].
    pub d: f64,
    /// Duration in profile time \[s\].
    pub t: f64,
    /// Area = distance overlaid (≥ 0) \[u\].
    pub area: f64,
    /// The overlay cannot be completed as requested (WarningID 0x4243).
    pub warning: bool,
    /// Available profile time T \[s\] (for ActualLength).
    pub t_available: f64,
}

impl OverlayPlan {
    fn ta(&self) -> f64 {
        if self.dv > 0.0 {
            self.dv / self.a
        } else {
            0.0
        }
    }
    fn td(&self) -> f64 {
        if self.dv > 0.0 {
            self.dv / self.d
        } else {
            0.0
        }
    }

    /// Δv at profile time τ.
    pub fn vel(&self, tau: f64) -> f64 {
        let (ta, td) = (self.ta(), self.td());
        if tau <= 0.0 || tau >= self.t {
            0.0
        } else if tau < ta {
            self.a * tau
        } else if tau > self.t - td {
            self.d * (self.t - tau)
        } else {
            self.dv
        }
    }

    /// ∫₀^τ Δv.
    pub fn area_at(&self, tau: f64) -> f64 {
        let tau = tau.clamp(0.0, self.t);
        let (ta, td) = (self.ta(), self.td());
        let tc_end = self.t - td;
        if tau <= ta {
            0.5 * self.a * tau * tau
        } else if tau <= tc_end {
            0.5 * self.a * ta * ta + self.dv * (tau - ta)
        } else {
            let r = self.t - tau;
            self.area - 0.5 * self.d * r * r
        }
    }
}

/// `E_SuperpositionMode` values 1..6.
pub fn plan(
    mode: u32,
    distance: f64,
    v_max: f64,
    a: f64,
    d: f64,
    vp: f64,
    length: f64,
) -> OverlayPlan {
    let dd = distance.abs();
    let additive = matches!(mode, 1 | 3 | 5);
    let t_avail = if additive {
        length / vp
    } else {
        (length - distance) / vp
    };
    let k = 1.0 / (2.0 * a) + 1.0 / (2.0 * d);
    let empty = |warning| OverlayPlan {
        dv: 0.0,
        a,
        d,
        t: 0.0,
        area: 0.0,
        warning,
        t_available: t_avail.max(0.0),
    };
    if dd == 0.0 {
        return empty(false);
    }
    if t_avail <= 0.0 {
        return empty(true);
    }
    // Largest area possible in T with peak ≤ V (rule 3 fallback).
    let largest = |a: f64, d: f64| {
        let k = 1.0 / (2.0 * a) + 1.0 / (2.0 * d);
        let dv = v_max.min(t_avail / (2.0 * k));
        OverlayPlan {
            dv,
            a,
            d,
            t: t_avail,
            area: dv * t_avail - k * dv * dv,
            warning: true,
            t_available: t_avail,
        }
    };
    let trapezoid = |dv: f64, t: f64| OverlayPlan {
        dv,
        a,
        d,
        t,
        area: dd,
        warning: false,
        t_available: t_avail,
    };
    match mode {
        1 | 2 => {
            let disc = t_avail * t_avail - 4.0 * k * dd;
            if disc < 0.0 {
                return largest(a, d);
            }
            let dv = (t_avail - disc.sqrt()) / (2.0 * k);
            if dv > v_max {
                largest(a, d)
            } else {
                trapezoid(dv, t_avail)
            }
        }
        3 | 4 => {
            let (dv, t) = if dd >= k * v_max * v_max {
                (v_max, dd / v_max + k * v_max)
            } else {
                let dv = (dd / k).sqrt();
                (dv, 2.0 * k * dv)
            };
            if t > t_avail + 1e-12 {
                largest(a, d)
            } else {
                trapezoid(dv, t)
            }
        }
        _ => {
            // ACCREDUCTION: scale a and d by λ ≤ 1 so that the area in T equals |D|.
            let tri_peak = 2.0 * dd / t_avail;
            let lambda = if tri_peak <= v_max {
                4.0 * k * dd / (t_avail * t_avail)
            } else if v_max * t_avail > dd {
                k * v_max * v_max / (v_max * t_avail - dd)
            } else {
                f64::INFINITY
            };
            if lambda > 1.0 {
                return largest(a, d);
            }
            let (a2, d2) = (a * lambda, d * lambda);
            let dv = if tri_peak <= v_max { tri_peak } else { v_max };
            OverlayPlan {
                dv,
                a: a2,
                d: d2,
                t: t_avail,
                area: dd,
                warning: false,
                t_available: t_avail,
            }
        }
    }
}

pub use crate::handshake::SuperImposedOutputs;

/// A running overlay.
#[derive(Clone, Copy, Debug)]
pub struct Overlay {
    /// The MC_MoveSuperImposed instance.
    pub owner: CmdId,
    /// The planned overlay (velocity difference over the base travel).
    pub plan: OverlayPlan,
    /// Progress along the plan, in base travel divided by `vp` \[s\].
    pub tau: f64,
    /// sign(D)·dir: the direction in which the offset grows.
    pub sign: f64,
    /// Base travel direction at the start.
    pub dir: f64,
    /// VelocityProcess: the base velocity the plan was made for \[u/s\].
    pub vp: f64,
    /// E_SuperpositionAbortOption.
    pub abort_option: u32,
    /// MC_AbortSuperposition ramp: (instance, τ at the start, Δv at the start).
    pub abort: Option<(CmdId, f64, f64)>,
    /// Covered area so far (≥ 0).
    pub covered: f64,
}

/// WarningID for an incomplete overlay.
pub fn warning_id(p: &OverlayPlan) -> ErrorId {
    if p.warning {
        SUPERPOSITION_INCOMPLETE
    } else {
        ErrorId::NONE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn w9_numbers() {
        // Conveyor gap: mode 2, D 300, L 1000, V 500, Vp 500, a = d = 1000.
        let p = plan(2, 300.0, 500.0, 1000.0, 1000.0, 500.0, 1000.0);
        assert!((p.t - 1.4).abs() < 1e-12 && (p.dv - 264.1).abs() < 0.05 && !p.warning);
        assert!((p.area_at(p.t) - 300.0).abs() < 1e-9);
        let p = plan(2, -300.0, 500.0, 1000.0, 1000.0, 500.0, 1000.0);
        assert!((p.t - 2.6).abs() < 1e-12 && (p.dv - 121.0).abs() < 0.05);
        // Print roller fast (mode 4) and slow (mode 2).
        let p = plan(4, 7.1, 30.0, 100.0, 100.0, 90.0, 360.0);
        assert!((p.dv - 26.65).abs() < 0.005 && (p.t - 0.533).abs() < 0.001);
        let p = plan(2, 7.1, 30.0, 100.0, 100.0, 90.0, 360.0);
        assert!((p.dv - 1.82).abs() < 0.005 && (p.t - 3.921).abs() < 0.001);
        // Drilling fast (3) and slow (1).
        let p = plan(3, 250.0, 500.0, 2000.0, 2000.0, 200.0, 400.0);
        assert!((p.dv - 500.0).abs() < 1e-9 && (p.t - 0.75).abs() < 1e-12);
        let p = plan(1, 250.0, 500.0, 2000.0, 2000.0, 200.0, 400.0);
        assert!((p.dv - 129.2).abs() < 0.05 && (p.t - 2.0).abs() < 1e-12);
        // Test form.
        let p = plan(3, 50.0, 50.0, 500.0, 500.0, 100.0, 1000.0);
        assert!((p.dv - 50.0).abs() < 1e-12 && (p.t - 1.1).abs() < 1e-12);
        let p = plan(1, 250.0, 500.0, 500.0, 500.0, 100.0, 400.0);
        assert!((p.dv - 64.6).abs() < 0.05 && (p.t - 4.0).abs() < 1e-12);
        let p = plan(1, 250.0, 50.0, 500.0, 500.0, 100.0, 100.0);
        assert!(p.warning && (p.area - 45.0).abs() < 1e-9 && (p.dv - 50.0).abs() < 1e-12);
    }

    #[test]
    fn accreduction_scales_the_ramps() {
        // T = 4 s, D 100, V 100: triangle peak 50 ≤ 100 → λ = 4k·100/16.
        let p = plan(5, 100.0, 100.0, 100.0, 100.0, 100.0, 400.0);
        assert!(!p.warning && (p.area_at(p.t) - 100.0).abs() < 1e-9, "{p:?}");
        assert!((p.t - 4.0).abs() < 1e-12 && p.a <= 100.0);
    }
}
