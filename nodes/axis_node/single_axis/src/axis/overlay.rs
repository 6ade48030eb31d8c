//! The running superposition overlay of the axis (§4.9) each cycle, its end and abort. The
//! overlay plan and data are in [`crate::superposition`].

use super::Axis;
use crate::handshake::Handshake;
use crate::superposition::*;

impl Axis {
    /// Advances the overlay after the base setpoint of this cycle (`prev_pos` = set position
    /// at the end of the previous cycle).
    pub fn overlay_step(&mut self, prev_pos: f64, dt: f64, fbs: &mut Handshake) {
        let Some(mut o) = self.overlay else { return };
        let ds = self.set.pos - prev_pos;
        let paused = self.job.is_some_and(|j| j.paused);
        let base_active = self.job.is_some() || self.coupling.is_some() || self.torque.is_some();
        if o.abort.is_none() {
            let standstill = ds.abs() < 1e-12;
            let reversed = ds * o.dir < 0.0;
            let end = if !base_active && standstill {
                // Case 4: target reached or stopped: aborted unless RESUMEAFTERMOTIONSTOP.
                o.abort_option != 2
            } else if standstill && !paused {
                // Case 2: temporary standstill of the main motion.
                o.abort_option == 0
            } else {
                // Case 3: reversal of the main motion.
                reversed && o.abort_option == 0
            };
            if end {
                self.end_overlay(o, fbs, true);
                return;
            }
        }
        let dtau = ds.abs() / o.vp;
        let (da, v_now, finished) = match o.abort {
            None => {
                let tau = (o.tau + dtau).min(o.plan.t);
                let da = o.plan.area_at(tau) - o.plan.area_at(o.tau);
                o.tau = tau;
                (da, o.plan.vel(tau), tau >= o.plan.t)
            }
            Some((_, tau0, v0)) => {
                // Ramp Δv to 0 with the overlay's deceleration (MC_AbortSuperposition).
                let t_stop = if o.plan.d > 0.0 { v0 / o.plan.d } else { 0.0 };
                let area = |t: f64| {
                    let t = t.clamp(0.0, t_stop);
                    v0 * t - 0.5 * o.plan.d * t * t
                };
                let t_old = o.tau - tau0;
                let t_new = (t_old + dtau).min(t_stop);
                o.tau = tau0 + t_new;
                (
                    area(t_new) - area(t_old),
                    (v0 - o.plan.d * t_new).max(0.0),
                    t_new >= t_stop,
                )
            }
        };
        if da != 0.0 {
            let delta = o.sign * da;
            o.covered += da;
            self.set.pos += delta;
            self.target_pos += delta;
            if let Some(j) = self.job.as_mut() {
                j.offset += delta;
            }
            if let Some(c) = self.coupling.as_mut() {
                c.s0 += delta;
            }
            // The overlay velocity (torque mode integrates its own velocity).
            if dt > 0.0 && self.torque.is_none() {
                self.set.vel += o.sign * v_now * dtau / dt;
            }
        }
        if finished {
            self.end_overlay(o, fbs, false);
        } else {
            self.overlay = Some(o);
        }
    }

    /// Ends the overlay: Done (`aborted` = false, or the AbortSuperposition ramp finished) or
    /// CommandAborted with the covered distance as ActualDistance.
    pub fn end_overlay(&mut self, o: Overlay, fbs: &mut Handshake, aborted: bool) {
        self.overlay = None;
        // sign(D) = sign·dir (dir = ±1).
        let covered = o.sign * o.dir * o.covered;
        if let Some((abort_id, _, _)) = o.abort {
            if let Some(out) = fbs.superimposed.get_mut(&o.owner) {
                out.actual_distance = covered;
            }
            fbs.done(abort_id);
            return;
        }
        if aborted {
            if let Some(out) = fbs.superimposed.get_mut(&o.owner) {
                out.actual_distance = covered;
            }
            fbs.aborted(o.owner);
        } else {
            fbs.done(o.owner);
        }
    }

    /// MC_AbortSuperposition / a new overlay / reset: the overlay's FB ends with
    /// CommandAborted, the offset covered so far stays.
    pub fn abort_overlay(&mut self, fbs: &mut Handshake) {
        if let Some(o) = self.overlay.take() {
            if o.abort.is_none() {
                self.end_overlay(o, fbs, true);
            } else if let Some((id, _, _)) = o.abort {
                fbs.aborted(id);
            }
        }
    }
}
