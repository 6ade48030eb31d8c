//! Time-optimal, jerk-limited 1-DOF trajectories shared by all engines (single_axis.md §1.1).
//!
//! A [`Profile1`] is planned once (with the `rsruckig` port of Ruckig) and then evaluated with
//! [`Profile1::at`] every cycle: the plan is stored as at most [`MAX_SEGMENTS`] constant-jerk
//! segments in a fixed array, so evaluation is allocation-free and costs one short search and
//! one cubic polynomial.
//!
//! Limits are direction-aware as the manual wants them: `acceleration` bounds |a| while |v|
//! grows, `deceleration` while |v| shrinks. Ruckig only knows signed bounds (`max_acceleration`,
//! `min_acceleration`), so each planned piece is monotonic in its direction of travel and the
//! signed bounds are mapped from that direction. A move whose target lies behind the stopping
//! point (direction reversal) is planned as "stop, then move back" (two pieces), as the spec
//! requires. `jerk = f64::INFINITY` gives trapezoidal (acceleration-limited) profiles; Ruckig
//! supports infinite jerk natively (second-order profiles).

mod plan;

use std::fmt;

pub use plan::MAX_SEGMENTS;

/// Kinematic limits of a move. All must be > 0; `jerk` may be `f64::INFINITY` (trapezoid).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Maximum |velocity| \[u/s\].
    pub velocity: f64,
    /// Maximum |acceleration| while |velocity| increases \[u/s²\].
    pub acceleration: f64,
    /// Maximum |acceleration| while |velocity| decreases \[u/s²\].
    pub deceleration: f64,
    /// Maximum |jerk| \[u/s³\]; `f64::INFINITY` = no jerk limit.
    pub jerk: f64,
}

impl Limits {
    /// Checks that every limit is a positive finite number (jerk may be +∞).
    pub fn validate(&self) -> Result<(), TrajectoryError> {
        let check = |name: &'static str, value: f64, inf_ok: bool| {
            if value.is_nan() || value <= 0.0 || (!inf_ok && value.is_infinite()) {
                Err(TrajectoryError::InvalidLimit { name, value })
            } else {
                Ok(())
            }
        };
        check("velocity", self.velocity, false)?;
        check("acceleration", self.acceleration, false)?;
        check("deceleration", self.deceleration, false)?;
        check("jerk", self.jerk, true)
    }
}

/// Position, velocity and acceleration of one degree of freedom.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct State1 {
    /// Position \[u\].
    pub pos: f64,
    /// Velocity \[u/s\].
    pub vel: f64,
    /// Acceleration \[u/s²\].
    pub acc: f64,
}

impl State1 {
    /// At rest at `pos`.
    pub fn at_rest(pos: f64) -> Self {
        State1 {
            pos,
            vel: 0.0,
            acc: 0.0,
        }
    }

    fn check_finite(&self, what: &'static str) -> Result<(), TrajectoryError> {
        for (field, value) in [("pos", self.pos), ("vel", self.vel), ("acc", self.acc)] {
            if !value.is_finite() {
                return Err(TrajectoryError::NotFinite { what, field, value });
            }
        }
        Ok(())
    }
}

/// Why a profile could not be planned.
#[derive(Clone, Debug, PartialEq)]
pub enum TrajectoryError {
    /// A limit is NaN, ≤ 0 or (except jerk) infinite.
    InvalidLimit {
        /// Name of the limit field.
        name: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A start or target value is NaN or infinite.
    NotFinite {
        /// "start" or "target".
        what: &'static str,
        /// Field name.
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// The target velocity exceeds the velocity limit.
    TargetVelocityAboveLimit {
        /// Requested |target velocity|.
        target: f64,
        /// Velocity limit.
        limit: f64,
    },
    /// Ruckig found no solution (should not happen for valid input).
    Calculation(String),
}

impl fmt::Display for TrajectoryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TrajectoryError::InvalidLimit { name, value } => {
                write!(f, "limit {name} = {value} must be a positive number")
            }
            TrajectoryError::NotFinite { what, field, value } => {
                write!(f, "{what}.{field} = {value} is not finite")
            }
            TrajectoryError::TargetVelocityAboveLimit { target, limit } => {
                write!(
                    f,
                    "target velocity {target} exceeds the velocity limit {limit}"
                )
            }
            TrajectoryError::Calculation(m) => write!(f, "trajectory calculation failed: {m}"),
        }
    }
}

impl std::error::Error for TrajectoryError {}

/// One constant-jerk piece of a profile, starting at time `t0` in state `(p, v, a)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Segment {
    pub t0: f64,
    pub p: f64,
    pub v: f64,
    pub a: f64,
    pub j: f64,
}

/// A planned time-optimal 1-DOF profile (positions or velocity target), cheap to evaluate.
#[derive(Clone, Copy, Debug)]
pub struct Profile1 {
    seg: [Segment; MAX_SEGMENTS],
    n: usize,
    duration: f64,
    end: State1,
    /// Velocity targets keep moving at the end velocity after `duration`.
    continues: bool,
}

impl Profile1 {
    /// Fastest profile from `start` to `target_pos`, arriving with `target_vel` (and zero
    /// acceleration). A target behind the stopping point is reached by stopping first.
    pub fn to_position(
        start: State1,
        target_pos: f64,
        target_vel: f64,
        limits: &Limits,
    ) -> Result<Profile1, TrajectoryError> {
        limits.validate()?;
        start.check_finite("start")?;
        State1 {
            pos: target_pos,
            vel: target_vel,
            acc: 0.0,
        }
        .check_finite("target")?;
        if target_vel.abs() > limits.velocity {
            return Err(TrajectoryError::TargetVelocityAboveLimit {
                target: target_vel.abs(),
                limit: limits.velocity,
            });
        }
        plan::to_position(start, target_pos, target_vel, limits)
    }

    /// Fastest profile from `start` to the constant velocity `target_vel` (zero acceleration).
    /// The position is free. A sign change of the velocity stops first, then accelerates.
    pub fn to_velocity(
        start: State1,
        target_vel: f64,
        limits: &Limits,
    ) -> Result<Profile1, TrajectoryError> {
        limits.validate()?;
        start.check_finite("start")?;
        if !target_vel.is_finite() {
            return Err(TrajectoryError::NotFinite {
                what: "target",
                field: "vel",
                value: target_vel,
            });
        }
        // A velocity target above the limit is clamped: the limit wins (e.g. override).
        let v = target_vel.clamp(-limits.velocity, limits.velocity);
        plan::to_velocity(start, v, limits)
    }

    /// Fastest jerk-limited stop from `start` (uses `deceleration` and `jerk`).
    pub fn stopping(start: State1, limits: &Limits) -> Result<Profile1, TrajectoryError> {
        Profile1::to_velocity(start, 0.0, limits)
    }

    /// A profile that stays at `state` (constant velocity continues linearly) for ever;
    /// `duration() = 0`, `at(t)` = `state` for every `t` ≥ 0 (acceleration dropped).
    pub fn hold(state: State1) -> Profile1 {
        let s = State1 {
            pos: state.pos,
            vel: state.vel,
            acc: 0.0,
        };
        let mut p = Profile1 {
            seg: [Segment::default(); MAX_SEGMENTS],
            n: 1,
            duration: 0.0,
            end: s,
            continues: true,
        };
        p.seg[0] = Segment {
            t0: 0.0,
            p: s.pos,
            v: s.vel,
            a: 0.0,
            j: 0.0,
        };
        p
    }

    /// The same motion seen from a frame that starts at `pos` and moves at the constant
    /// velocity `vel`: every state gains `pos + vel·t` (and `vel`). A plan relative to a
    /// moving target (gear-in chase) becomes an absolute plan this way; with `vel = 0` it is a
    /// plain position offset. A moving frame keeps the end moving after `duration`.
    pub fn moved_by(&self, pos: f64, vel: f64) -> Profile1 {
        let mut p = *self;
        for s in &mut p.seg[..p.n] {
            s.p += pos + vel * s.t0;
            s.v += vel;
        }
        p.end.pos += pos + vel * p.duration;
        p.end.vel += vel;
        p.continues |= vel != 0.0;
        p
    }

    /// True if the motion goes on at the end velocity after `duration` (velocity targets,
    /// [`Profile1::hold`], moving frames); false if it rests at the end.
    pub fn continues(&self) -> bool {
        self.continues
    }

    /// Total duration \[s\].
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The state at the end (exactly the requested target).
    pub fn end(&self) -> State1 {
        self.end
    }

    /// The state at the start.
    pub fn start(&self) -> State1 {
        let s = &self.seg[0];
        State1 {
            pos: s.p,
            vel: s.v,
            acc: s.a,
        }
    }

    /// The state at time `t` \[s\] after the start. `t` is clamped to `[0, duration]` for
    /// position targets (`at(duration())` is exactly the target); after `duration` a velocity
    /// target continues at its velocity (position = end + v·(t − duration)), which keeps
    /// endless motions exact.
    #[inline]
    pub fn at(&self, t: f64) -> State1 {
        if t >= self.duration {
            if !self.continues {
                return self.end;
            }
            let dt = t - self.duration;
            return State1 {
                pos: self.end.pos + self.end.vel * dt,
                vel: self.end.vel,
                acc: 0.0,
            };
        }
        let t = t.max(0.0);
        // Few segments: a linear scan from the back beats a binary search here.
        let mut i = self.n - 1;
        while i > 0 && self.seg[i].t0 > t {
            i -= 1;
        }
        let s = &self.seg[i];
        let dt = t - s.t0;
        State1 {
            pos: s.p + dt * (s.v + dt * (s.a / 2.0 + dt * s.j / 6.0)),
            vel: s.v + dt * (s.a + dt * s.j / 2.0),
            acc: s.a + dt * s.j,
        }
    }

    /// True if the velocity takes both signs (beyond 1e-7) somewhere in the profile, i.e. the
    /// motion reverses its direction (e.g. a stop-then-move-back plan).
    pub fn reverses(&self) -> bool {
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for k in 0..self.n {
            let s = &self.seg[k];
            let end = if k + 1 < self.n {
                self.seg[k + 1].t0
            } else {
                self.duration
            };
            let len = (end - s.t0).max(0.0);
            let v_end = s.v + len * (s.a + len * s.j / 2.0);
            lo = lo.min(s.v).min(v_end);
            hi = hi.max(s.v).max(v_end);
            if s.j != 0.0 {
                let te = -s.a / s.j;
                if te > 0.0 && te < len {
                    let ve = s.v + te * (s.a + te * s.j / 2.0);
                    lo = lo.min(ve);
                    hi = hi.max(ve);
                }
            }
        }
        lo < -1e-7 && hi > 1e-7
    }

    /// The jerk at time `t` (0 outside the profile).
    pub fn jerk_at(&self, t: f64) -> f64 {
        if t >= self.duration || t < 0.0 {
            return 0.0;
        }
        let mut i = self.n - 1;
        while i > 0 && self.seg[i].t0 > t {
            i -= 1;
        }
        self.seg[i].j
    }

    /// Earliest time at which the profile passes `pos` (searched on the stored segments),
    /// or `None` if it never does. Used for blending positions.
    pub fn time_at_position(&self, pos: f64) -> Option<f64> {
        for k in 0..self.n {
            let s = &self.seg[k];
            let t_end = if k + 1 < self.n {
                self.seg[k + 1].t0
            } else {
                self.duration
            };
            let len = t_end - s.t0;
            let p_end = self.at(t_end).pos;
            if (s.p - pos).abs() < 1e-12 {
                return Some(s.t0);
            }
            if (s.p - pos) * (p_end - pos) <= 0.0 && len > 0.0 {
                // Bisection: the segment's position is monotonic inside one piece of
                // a monotonic profile.
                let (mut lo, mut hi) = (0.0, len);
                let f = |dt: f64| s.p + dt * (s.v + dt * (s.a / 2.0 + dt * s.j / 6.0)) - pos;
                let f_lo = f(lo);
                for _ in 0..100 {
                    let mid = 0.5 * (lo + hi);
                    if (f(mid) > 0.0) == (f_lo > 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(s.t0 + 0.5 * (lo + hi));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests;
