//! Set-point generation of one mover (xplanar.md §5.1–§5.3, §5.7).
//!
//! XY moves are one time-optimal jerk-limited profile along the path parameter `s` of a
//! straight line (the shared [`Profile1`]); a velocity across the new line (re-planning
//! while moving, §5.2) is brought back to the line by a second profile `q`. C follows `s`
//! linearly when the XY command controls it, so XY and C arrive together. Z, A, B and an
//! independent C are plain 1-D profiles.

use crate::geometry::V2;
use crate::types::Dynamics;
use motion_core::trajectory::{Profile1, State1, TrajectoryError};

/// Lengths below this are "no XY motion" \[mm\].
pub const LEN_EPS: f64 = 1e-9;

/// One auxiliary axis (z, a, b or an independent c) with its running plan.
#[derive(Clone, Debug, Default)]
pub(crate) struct Axis1 {
    pub pos: f64,
    pub vel: f64,
    pub acc: f64,
    plan: Option<(Profile1, f64)>,
}

impl Axis1 {
    pub fn at(pos: f64) -> Self {
        Axis1 {
            pos,
            ..Default::default()
        }
    }

    pub fn state(&self) -> State1 {
        State1 {
            pos: self.pos,
            vel: self.vel,
            acc: self.acc,
        }
    }

    pub fn moving(&self) -> bool {
        self.plan.is_some() || self.vel != 0.0 || self.acc != 0.0
    }

    /// The axis's motion as a profile and the time in it of the current state: its plan, or
    /// a hold at the current state (constant velocity) without one.
    pub fn motion(&self) -> (Profile1, f64) {
        match &self.plan {
            Some((p, t)) => (*p, *t),
            None => (Profile1::hold(self.state()), 0.0),
        }
    }

    /// Forgets the plan but keeps the current state (another command takes the axis over).
    pub fn drop_plan(&mut self) {
        self.plan = None;
    }

    pub fn start(&mut self, p: Profile1) {
        self.plan = Some((p, 0.0));
    }

    /// Plans to `target` from the current state.
    pub fn plan_to(&self, target: f64, d: &Dynamics) -> Result<Profile1, TrajectoryError> {
        Profile1::to_position(self.state(), target, 0.0, &d.limits())
    }

    /// Fastest stop with `d`.
    pub fn plan_stop(&self, d: &Dynamics) -> Result<Profile1, TrajectoryError> {
        Profile1::stopping(self.state(), &d.limits())
    }

    /// Drops the plan and freezes the axis (Abort reaction).
    pub fn freeze(&mut self) {
        self.plan = None;
        self.vel = 0.0;
        self.acc = 0.0;
    }

    /// The state one cycle ahead (not applied).
    pub fn peek(&self, dt: f64) -> State1 {
        match &self.plan {
            Some((p, t)) => p.at(t + dt),
            None => self.state(),
        }
    }

    /// Advances one cycle; true when the plan just finished (state exactly at its end).
    pub fn advance(&mut self, dt: f64) -> bool {
        let Some((p, t)) = &mut self.plan else {
            return false;
        };
        *t += dt;
        let done = *t >= p.duration() - 1e-12;
        let s = if done { p.end() } else { p.at(*t) };
        self.pos = s.pos;
        self.vel = s.vel;
        self.acc = s.acc;
        if done {
            self.plan = None;
            self.vel = 0.0;
            self.acc = 0.0;
        }
        done
    }
}

/// XY kinematic state of a mover.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Kin2 {
    pub pos: V2,
    pub vel: V2,
    pub acc: V2,
}

impl Kin2 {
    pub fn at_rest(pos: V2) -> Self {
        Kin2 {
            pos,
            vel: V2::zeros(),
            acc: V2::zeros(),
        }
    }

    pub fn moving(&self) -> bool {
        self.vel.norm_squared() > 0.0 || self.acc.norm_squared() > 0.0
    }
}

/// A straight-line XY plan (optionally carrying C).
#[derive(Clone, Debug)]
pub(crate) struct PathPlan {
    origin: V2,
    /// Unit direction of the line (zero for a pure rotation).
    u: V2,
    /// Unit normal used by `q`.
    n: V2,
    c0: f64,
    /// dc/ds when the plan carries C (0 otherwise).
    c_per_s: f64,
    /// C rides on `s` in degrees (pure rotation: `u` = 0).
    pub controls_c: bool,
    s: Profile1,
    q: Profile1,
    t: f64,
    end: Option<(V2, f64)>,
}

/// Output of one path evaluation.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathState {
    pub xy: Kin2,
    /// C state when the plan carries C.
    pub c: Option<State1>,
}

fn frame_from(dir: V2, fallback: V2) -> (V2, V2) {
    let u = if dir.norm() > LEN_EPS {
        dir.normalize()
    } else if fallback.norm() > LEN_EPS {
        fallback.normalize()
    } else {
        V2::new(1.0, 0.0)
    };
    (u, V2::new(-u.y, u.x))
}

impl PathPlan {
    /// Move from `xy` to `target`; with `c` = Some((c_state, c_target, c_dyn)) C is carried
    /// along so that both arrive together (§3.2 MoveToPosition, §5.2).
    pub fn to_point(
        xy: Kin2,
        target: V2,
        dyn_xy: &Dynamics,
        c: Option<(State1, f64, &Dynamics)>,
    ) -> Result<PathPlan, TrajectoryError> {
        let d = target - xy.pos;
        let len = d.norm();
        let c_move = c.filter(|(cs, ct, _)| (ct - cs.pos).abs() > 1e-12);
        if let (true, Some((cs, ct, cd))) = (len <= LEN_EPS, c_move) {
            // Pure rotation: s measures degrees, q brings any XY velocity back to the point.
            let (n, _) = frame_from(xy.vel, xy.acc);
            let s0 = State1 {
                pos: 0.0,
                vel: cs.vel,
                acc: cs.acc,
            };
            let q0 = State1 {
                pos: 0.0,
                vel: xy.vel.dot(&n),
                acc: xy.acc.dot(&n),
            };
            let s = Profile1::to_position(s0, ct - cs.pos, 0.0, &cd.limits())?;
            let q = Profile1::to_position(q0, 0.0, 0.0, &dyn_xy.limits())?;
            return Ok(PathPlan {
                origin: xy.pos,
                u: V2::zeros(),
                n,
                c0: cs.pos,
                c_per_s: 1.0,
                controls_c: true,
                s,
                q,
                t: 0.0,
                end: Some((target, ct)),
            });
        }
        let (u, n) = frame_from(d, xy.vel);
        let mut lim = *dyn_xy;
        let (c0, c_per_s, c_end, controls_c) = match c {
            Some((cs, ct, cd)) => {
                let dc = ct - cs.pos;
                if len > LEN_EPS && dc.abs() > 1e-12 {
                    // C limits mapped onto the path parameter: dc/ds · v_s ≤ v_c, etc.
                    lim = lim.min(&cd.scaled(len / dc.abs()));
                }
                (cs.pos, if len > LEN_EPS { dc / len } else { 0.0 }, ct, true)
            }
            None => (0.0, 0.0, 0.0, false),
        };
        let s0 = State1 {
            pos: 0.0,
            vel: xy.vel.dot(&u),
            acc: xy.acc.dot(&u),
        };
        let q0 = State1 {
            pos: 0.0,
            vel: xy.vel.dot(&n),
            acc: xy.acc.dot(&n),
        };
        let s = Profile1::to_position(s0, len, 0.0, &lim.limits())?;
        let q = if q0.vel == 0.0 && q0.acc == 0.0 {
            Profile1::hold(State1::default())
        } else {
            Profile1::to_position(q0, 0.0, 0.0, &dyn_xy.limits())?
        };
        Ok(PathPlan {
            origin: xy.pos,
            u,
            n,
            c0,
            c_per_s,
            controls_c,
            s,
            q,
            t: 0.0,
            end: Some((target, c_end)),
        })
    }

    /// Fastest stop from `xy` with `d`; the path stays on the line of the current velocity
    /// (Halt, QuickStop). A carried C is stopped by the caller on the C axis.
    pub fn stop(xy: Kin2, d: &Dynamics) -> Result<PathPlan, TrajectoryError> {
        let (u, n) = frame_from(xy.vel, xy.acc);
        let s0 = State1 {
            pos: 0.0,
            vel: xy.vel.dot(&u),
            acc: xy.acc.dot(&u),
        };
        let q0 = State1 {
            pos: 0.0,
            vel: xy.vel.dot(&n),
            acc: xy.acc.dot(&n),
        };
        let s = Profile1::stopping(s0, &d.limits())?;
        let q = Profile1::stopping(q0, &d.limits())?;
        Ok(PathPlan {
            origin: xy.pos,
            u,
            n,
            c0: 0.0,
            c_per_s: 0.0,
            controls_c: false,
            s,
            q,
            t: 0.0,
            end: None,
        })
    }

    pub fn duration(&self) -> f64 {
        self.s.duration().max(self.q.duration())
    }

    fn eval(&self, t: f64) -> PathState {
        let s = self.s.at(t);
        let q = self.q.at(t);
        let pos = self.origin + self.u * s.pos + self.n * q.pos;
        let vel = self.u * s.vel + self.n * q.vel;
        let acc = self.u * s.acc + self.n * q.acc;
        let c = self.controls_c.then_some(State1 {
            pos: self.c0 + self.c_per_s * s.pos,
            vel: self.c_per_s * s.vel,
            acc: self.c_per_s * s.acc,
        });
        PathState {
            xy: Kin2 { pos, vel, acc },
            c,
        }
    }

    /// The state one cycle ahead, and whether the plan then ends.
    pub fn peek(&self, dt: f64) -> (PathState, bool) {
        let t = self.t + dt;
        if t >= self.duration() - 1e-12 {
            let mut st = self.eval(self.duration());
            st.xy.vel = V2::zeros();
            st.xy.acc = V2::zeros();
            if let Some((p, c)) = self.end {
                st.xy.pos = p;
                if let Some(cs) = &mut st.c {
                    cs.pos = c;
                }
            }
            if let Some(cs) = &mut st.c {
                cs.vel = 0.0;
                cs.acc = 0.0;
            }
            (st, true)
        } else {
            (self.eval(t), false)
        }
    }

    pub fn advance(&mut self, dt: f64) {
        self.t += dt;
    }
}

/// Positions [lo, hi] (relative to now) passed while stopping from (`v`, `a`) with
/// deceleration `d` and jerk `j` (time-optimal, closed form). Exact for monotone stops; a
/// stop that must reverse (only possible with foreign set points) gets a 1 mm margin.
pub(crate) fn stop_range(v: f64, a: f64, d: f64, j: f64) -> (f64, f64) {
    if v == 0.0 && a == 0.0 {
        return (0.0, 0.0);
    }
    let sign = if v > 0.0 || (v == 0.0 && a > 0.0) {
        1.0
    } else {
        -1.0
    };
    let (v, a) = (v * sign, (a * sign).max(-d));
    // Distance to stop from (w, 0).
    let from_zero_acc = |w: f64| -> f64 {
        if w <= 0.0 {
            0.0
        } else if w >= d * d / j {
            w * (w / d + d / j) / 2.0
        } else {
            w * (w / j).sqrt()
        }
    };
    let fwd_from_pos_acc = |v: f64, a: f64| -> f64 {
        let t1 = a / j;
        let v1 = v + a * a / (2.0 * j);
        v * t1 + a * t1 * t1 / 2.0 - j * t1 * t1 * t1 / 6.0 + from_zero_acc(v1)
    };
    let (lo, hi) = if a >= 0.0 {
        (0.0, fwd_from_pos_acc(v, a))
    } else if v >= a * a / (2.0 * j) {
        let vv = v + a * a / (2.0 * j);
        let t0 = -a / j;
        (
            0.0,
            (from_zero_acc(vv) - (vv * t0 - j * t0 * t0 * t0 / 6.0)).max(0.0),
        )
    } else {
        // Velocity reverses: forward excursion until v = 0, then a stop backwards.
        let disc = (a * a - 2.0 * j * v).max(0.0);
        let ts = (-a - disc.sqrt()) / j;
        let xp = v * ts + a * ts * ts / 2.0 + j * ts * ts * ts / 6.0;
        let back = fwd_from_pos_acc(0.0, disc.sqrt());
        ((xp - back).min(0.0) - 1.0, xp.max(0.0) + 1.0)
    };
    if sign > 0.0 {
        (lo, hi)
    } else {
        (-hi, -lo)
    }
}

/// True if `c` lies in one of the C windows [k·90 + c_min, k·90 + c_max] (§5.3).
pub fn in_c_window(c: f64, c_min: f64, c_max: f64) -> bool {
    window_index(c, c_min, c_max).is_some()
}

fn window_index(c: f64, c_min: f64, c_max: f64) -> Option<f64> {
    const TOL: f64 = 1e-9;
    let k = ((c - c_min + TOL) / 90.0).floor();
    let lo = k * 90.0 + c_min;
    let hi = k * 90.0 + c_max;
    (c >= lo - TOL && c <= hi + TOL).then_some(k)
}

/// True if the whole range between `c0` and `c1` lies inside a single C window (§5.3).
pub fn range_in_one_window(c0: f64, c1: f64, c_min: f64, c_max: f64) -> bool {
    let (lo, hi) = if c0 <= c1 { (c0, c1) } else { (c1, c0) };
    match (
        window_index(lo, c_min, c_max),
        window_index(hi, c_min, c_max),
    ) {
        (Some(a), Some(b)) => a == b,
        _ => false,
    }
}

/// Errors of the modulo target computation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ModuloError {
    /// additionalTurns ≠ 0 with NonModulo/ShortestWay.
    TurnsNotAllowed,
}

/// Absolute (unwrapped) C target of a modulo C command (§5.3).
pub(crate) fn modulo_target(
    requested: f64,
    now: f64,
    modulus: f64,
    tolerance: f64,
    direction: crate::types::Direction,
    turns: u32,
) -> Result<f64, ModuloError> {
    use crate::types::Direction::*;
    let m = modulus;
    let n = turns as f64;
    let wrap = |x: f64| {
        let r = x.rem_euclid(m);
        if m - r < 1e-9 {
            0.0
        } else {
            r
        }
    };
    match direction {
        NonModulo => {
            if turns != 0 {
                return Err(ModuloError::TurnsNotAllowed);
            }
            Ok(requested)
        }
        ShortestWay => {
            if turns != 0 {
                return Err(ModuloError::TurnsNotAllowed);
            }
            let f = wrap(requested - now);
            Ok(now + if f <= m / 2.0 { f } else { f - m })
        }
        Positive => {
            let f = wrap(requested - now);
            let base = if f.min(m - f) <= tolerance {
                if f <= m - f {
                    f
                } else {
                    f - m
                }
            } else {
                f
            };
            Ok(now + base + n * m)
        }
        Negative => {
            let b = wrap(now - requested);
            let base = if b.min(m - b) <= tolerance {
                if b <= m - b {
                    -b
                } else {
                    m - b
                }
            } else {
                -b
            };
            Ok(now + base - n * m)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::Direction;
    use motion_core::trajectory::Limits;

    #[test]
    fn stop_range_matches_profile() {
        let lim = Limits {
            velocity: 4000.0,
            acceleration: 30000.0,
            deceleration: 30000.0,
            jerk: 1e6,
        };
        for &(v, a) in &[
            (400.0, 0.0),
            (3000.0, 0.0),
            (1000.0, 5000.0),
            (1000.0, -8000.0),
            (-700.0, 2000.0),
            (0.0, 3000.0),
            (2000.0, -29000.0),
        ] {
            let p = Profile1::stopping(
                State1 {
                    pos: 0.0,
                    vel: v,
                    acc: a,
                },
                &lim,
            )
            .unwrap();
            let (lo, hi) = stop_range(v, a, 30000.0, 1e6);
            let end = p.end().pos;
            assert!(
                end >= lo - 1e-6 && end <= hi + 1e-6,
                "v {v} a {a}: end {end} not in [{lo}, {hi}]"
            );
            assert!(
                (end - if end >= 0.0 { hi } else { lo }).abs() < 1e-6,
                "v {v} a {a}: end {end} vs [{lo},{hi}]"
            );
        }
    }

    #[test]
    fn windows() {
        assert!(in_c_window(0.0, -15.0, 15.0));
        assert!(in_c_window(90.0, -15.0, 15.0));
        assert!(in_c_window(190.0, -15.0, 15.0));
        assert!(in_c_window(-80.0, -15.0, 15.0));
        assert!(!in_c_window(20.0, -15.0, 15.0));
        assert!(range_in_one_window(0.0, 3.0, -15.0, 15.0));
        assert!(!range_in_one_window(0.0, 20.0, -15.0, 15.0));
        assert!(!range_in_one_window(0.0, 90.0, -15.0, 15.0));
        assert!(range_in_one_window(80.0, 100.0, -15.0, 15.0));
    }

    #[test]
    fn modulo_targets() {
        use Direction::*;
        assert_eq!(
            modulo_target(0.0, 190.0, 360.0, 0.0, ShortestWay, 0),
            Ok(360.0)
        );
        assert_eq!(
            modulo_target(10.0, 350.0, 360.0, 0.0, Positive, 0),
            Ok(370.0)
        );
        assert_eq!(
            modulo_target(10.0, 350.0, 360.0, 0.0, Negative, 0),
            Ok(10.0)
        );
        assert_eq!(
            modulo_target(90.0, 90.0, 360.0, 0.0, Positive, 1),
            Ok(450.0)
        );
        assert_eq!(modulo_target(90.0, 90.0, 360.0, 0.0, Positive, 0), Ok(90.0));
        // Within the tolerance: shortest way back, no unintended full turn.
        assert_eq!(modulo_target(89.0, 90.0, 360.0, 2.0, Positive, 0), Ok(89.0));
        assert_eq!(
            modulo_target(89.0, 90.0, 360.0, 0.5, Positive, 0),
            Ok(449.0)
        );
        assert_eq!(
            modulo_target(30.0, 0.0, 360.0, 0.0, NonModulo, 1),
            Err(ModuloError::TurnsNotAllowed)
        );
        // Ties of ShortestWay go positive.
        assert_eq!(
            modulo_target(180.0, 0.0, 360.0, 0.0, ShortestWay, 0),
            Ok(180.0)
        );
    }
}
