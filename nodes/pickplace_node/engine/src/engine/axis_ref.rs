//! The interpolation stage of the AXIS_REF limits (§7.8 (2)): the path parameter is slowed so
//! that every axis keeps its maximum velocity, acceleration and jerk (geometry kept, proposal);
//! an axis that still cannot follow is clamped to its maximum. Deterministic and allocation
//! free; inactive (bit-identical set-points) when no AXIS_REF maximum is configured or none is
//! reached.

use super::*;
use crate::axis_limits::{admissible, catch_up, inside, largest_fraction, AxisState};
use crate::path_run::PathRun;

/// Secant refinements of the path fraction against the exact (curved, coupled) set-points.
const REFINEMENTS: usize = 4;

impl PickPlaceEngine {
    /// Admissible set-point interval of each pose axis for this cycle.
    fn axis_intervals(&self, dt: f64) -> [(f64, f64); 7] {
        let mut iv = [(f64::NEG_INFINITY, f64::INFINITY); 7];
        for q in 0..7 {
            let s = AxisState {
                pos: self.prev_pose[q],
                vel: self.vel[q],
                acc: self.acc[q],
            };
            iv[q] = admissible(&s, &self.axis_max[q], dt);
        }
        iv
    }

    /// Advances `run` by one cycle, slowed if the set-points would exceed an AXIS_REF maximum.
    /// Returns true when the path was slowed (the planned timing no longer holds).
    pub(super) fn advance_path(&self, run: &mut PathRun, dt: f64) -> bool {
        if !self.axis_limited {
            run.advance(dt);
            return false;
        }
        let start = run.cursor();
        let s_of = |b: usize| self.belts[b - 1].axis.position;
        run.advance(dt);
        let p1 = run.pose(&s_of);
        let iv = self.axis_intervals(dt);
        if (0..7).all(|q| inside(p1[q], iv[q])) {
            return false;
        }
        // The set-points of a shorter advance λ·dt: λ = 0 holds σ (the belts still move).
        let sigma0 = start_sigma(run, start);
        let p0 = run.pose(&s_of);
        let (mut lam, mut p_lam) = (1.0, p1);
        for _ in 0..REFINEMENTS {
            // Linear in λ between σ and the last try; the exact set-points then check it.
            let next = lam * largest_fraction(&p0, &p_lam, &iv);
            run.restore(start);
            run.advance(next * dt);
            lam = next;
            p_lam = run.pose(&s_of);
            if (0..7).all(|q| inside(p_lam[q], iv[q])) {
                break;
            }
        }
        // The path velocity actually commanded (for lrSetPathVelOut and a later stop).
        run.sigma.vel = (run.sigma.pos - sigma0) / dt;
        true
    }

    /// Clamps each pose axis into its admissible interval (the final guarantee of §7.8 (2)): a
    /// clamp that moves an axis further than its `following_error_limit` from the path set-point
    /// raises 90011 (the axis cannot follow, §16). Returns true when an axis was clamped.
    pub(super) fn clamp_to_axis_max(&mut self, dt: f64, events: &mut Vec<CommandEvent>) -> bool {
        if !self.axis_limited {
            return false;
        }
        let iv = self.axis_intervals(dt);
        let nominal = self.pose;
        let mut clamped = false;
        let mut lost: Option<usize> = None;
        for q in 0..7 {
            let p = self.pose[q];
            if inside(p, iv[q]) {
                continue;
            }
            let s = AxisState {
                pos: self.prev_pose[q],
                vel: self.vel[q],
                acc: self.acc[q],
            };
            let target_vel = (p - self.prev_nominal[q]) / dt;
            let c = catch_up(&s, &self.axis_max[q], dt, p, target_vel);
            self.pose[q] = c;
            clamped = true;
            let idx = pose_axis_index(q);
            let lim = self.cfg.axis(idx).following_error_limit;
            if lim > 0.0 && (p - c).abs() > lim && lost.is_none() {
                lost = Some(idx);
            }
        }
        self.prev_nominal = nominal;
        if let Some(idx) = lost {
            self.raise_error(ids::FOLLOWING_ERROR, Some(idx), events);
        }
        clamped
    }
}

/// σ at `start` (the run is left there).
fn start_sigma(run: &mut PathRun, start: crate::path_run::Cursor) -> f64 {
    run.restore(start);
    run.sigma.pos
}
