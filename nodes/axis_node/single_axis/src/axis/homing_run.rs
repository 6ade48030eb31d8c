//! The homing run of the axis (§4.10): its phases cycle by cycle. The run's data and the
//! reference modes are described in [`crate::homing`].

use super::{Axis, Job, JobKind};
use crate::error_ids;
use crate::handshake::Handshake;
use crate::homing::*;
use motion_core::Limits;

impl Axis {
    /// Raw (uncalibrated) actual position (§1.5).
    pub fn raw_act(&self) -> f64 {
        self.act_pos - self.coord_offset
    }

    /// Level of the simulated reference cam at raw position `raw` (§1.5).
    pub fn virtual_cam(&self, raw: f64) -> bool {
        self.cfg
            .home_cam
            .is_some_and(|[lo, hi]| raw >= lo && raw <= hi)
    }

    fn homing_limits(&self, velocity: f64) -> Limits {
        Limits {
            velocity,
            acceleration: self.cfg.acceleration,
            deceleration: self.cfg.deceleration,
            jerk: self.cfg.jerk,
        }
    }

    /// Starts an endless homing motion (no FB owner: the MC_Home instance owns the run).
    fn homing_move(&mut self, dir: f64, velocity: f64) {
        let l = self.homing_limits(velocity);
        if let Some(profile) = self.plan_velocity_free(dir, &l) {
            let mut job = Job::internal(JobKind::Velocity, profile, f64::NAN, l);
            job.dir = dir;
            self.start_job(job);
        }
    }

    fn homing_stop(&mut self) {
        let l = self.homing_limits(self.cfg.max_velocity);
        let profile = self.plan_stop(&l);
        let stop = profile.end().pos;
        self.start_job(Job::internal(JobKind::Halt, profile, stop, l));
    }

    /// Starts the run (phase 1, or 3 when the cam is already active).
    pub fn start_homing(&mut self, mut h: Homing) {
        let raw = self.raw_act();
        h.prev_raw = raw;
        h.start_raw = raw;
        let cam = h.cam_input || self.virtual_cam(raw);
        h.prev_cam = cam;
        h.homed_before = self.homed;
        self.homed = false;
        if cam {
            h.phase = 3;
        } else {
            h.phase = 1;
            self.homing_move(h.search_dir, h.search_velocity);
        }
        self.last_target = None;
        self.homing = Some(h);
    }

    /// One cycle of the homing run, after the setpoint generator and actual values.
    pub fn homing_step(&mut self, fbs: &mut Handshake) {
        let Some(mut h) = self.homing else { return };
        let raw = self.raw_act();
        let cam = h.cam_input || self.virtual_cam(raw);
        let at_rest = self.job.is_none() && !self.moving();
        // Edge position: the virtual cam boundary crossed, else this cycle's position.
        let edge = |rising: bool, dir: f64| -> f64 {
            if let Some([lo, hi]) = self.cfg.home_cam {
                let b = if (dir > 0.0) == rising { lo } else { hi };
                if (b - h.prev_raw) * (raw - b) >= 0.0 {
                    return b;
                }
            }
            raw
        };
        match h.phase {
            1 | 2 => {
                h.phase = 2;
                if cam && !h.prev_cam {
                    self.homing_stop();
                    h.phase = 3;
                }
            }
            3 if at_rest => {
                if !cam {
                    // The cam must still be active at standstill (§4.10 phase 3).
                    self.end_homing(fbs, Some(error_ids::HOMING_NOT_FOUND), h);
                    return;
                }
                self.homing_move(h.sync_dir, h.sync_velocity);
                h.phase = 4;
            }
            4 if !cam && h.prev_cam => {
                let e = edge(false, h.sync_dir);
                if h.mode == 1 {
                    h.ref_raw = e;
                    self.homing_stop();
                    h.phase = 6;
                } else if matches!(h.mode, 3 | 4 | 6 | 7) {
                    // Arm the latch on probe input 1 (phase 5).
                    h.phase = 5;
                } else {
                    let p = self.cfg.sync_pulse_period;
                    h.pulse = if h.sync_dir > 0.0 {
                        (e / p).floor() * p + p
                    } else {
                        (e / p).ceil() * p - p
                    };
                    h.phase = 5;
                }
            }
            5 if matches!(h.mode, 3 | 4 | 6 | 7) => {
                let level = self.probe_level[0];
                let prev = self.probe_prev[0];
                let rising = matches!(h.mode, 3 | 6);
                let mark = if rising {
                    self.cfg.probe_marks.iter().copied().find(|&m| {
                        (m - h.prev_raw) * (raw - m) >= 0.0 && (raw - h.prev_raw).abs() > 0.0
                    })
                } else {
                    None
                };
                let edge = if rising {
                    level && !prev
                } else {
                    !level && prev
                };
                if let Some(at) = mark.or(edge.then_some(h.prev_raw)) {
                    h.ref_raw = at;
                    self.homing_stop();
                    h.phase = 6;
                }
            }
            5 if (raw - h.pulse) * h.sync_dir >= 0.0 => {
                h.ref_raw = h.pulse;
                self.homing_stop();
                h.phase = 6;
            }
            6 if at_rest => {
                // ActPos := reference position + distance travelled since the reference point.
                let new_act = h.position + (raw - h.ref_raw);
                let delta = new_act - self.act_pos;
                crate::axis::shift_coordinates(self, delta);
                self.set_position_offset = 0.0;
                self.homed = true;
                self.homing = None;
                fbs.done(h.owner);
                return;
            }
            _ => {}
        }
        if (raw - h.start_raw).abs() > self.cfg.homing_search_limit {
            self.homing_stop();
            self.end_homing(fbs, Some(error_ids::HOMING_NOT_FOUND), h);
            return;
        }
        h.prev_cam = cam;
        h.prev_raw = raw;
        self.homing = Some(h);
    }

    /// Ends the run with an error (axis stopped) or aborted (`None`); Homed as before.
    pub fn end_homing(
        &mut self,
        fbs: &mut Handshake,
        error: Option<motion_core::ErrorId>,
        h: Homing,
    ) {
        self.homing = None;
        self.homed = h.homed_before;
        match error {
            Some(e) => fbs.error(h.owner, e),
            None => fbs.aborted(h.owner),
        }
    }
}
