//! Torque mode of the axis (§4.14) each cycle. The job's data are in [`crate::torque`].

use super::Axis;
use crate::handshake::Handshake;
use motion_core::State1;

impl Axis {
    /// One cycle of torque mode (replaces the setpoint generator).
    pub fn torque_step(&mut self, dt: f64, fbs: &mut Handshake) {
        let Some(mut t) = self.torque else { return };
        let step = t.ramp * dt;
        let d = t.torque - self.set_torque;
        self.set_torque = if d.abs() <= step {
            t.torque
        } else {
            self.set_torque + step * d.signum()
        };
        let v0 = self.set.vel;
        let a = self.cfg.torque_gain * self.set_torque - self.cfg.viscous_damping * v0;
        let mut v = v0 + a * dt;
        t.clamped = false;
        if v > t.v_high {
            v = t.v_high;
            t.clamped = true;
        } else if v < t.v_low {
            v = t.v_low;
            t.clamped = true;
        }
        self.set = State1 {
            pos: self.set.pos + 0.5 * (v0 + v) * dt,
            vel: v,
            acc: (v - v0) / dt,
        };
        self.target_pos = self.set.pos;
        let in_torque = (self.set_torque - t.torque).abs() < 1e-9 && !t.clamped;
        if let Some(i) = fbs.get_mut(t.owner) {
            i.in_velocity = in_torque;
        }
        self.torque = Some(t);
    }
}
