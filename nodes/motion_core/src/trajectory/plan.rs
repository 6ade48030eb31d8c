//! Planning with Ruckig and conversion of its profiles into fixed segment arrays.

use super::{Limits, Profile1, Segment, State1, TrajectoryError};
use rsruckig::prelude::*;

/// Capacity of a [`Profile1`]: two Ruckig profiles (brake pre-phase 2 + 7 phases each).
pub const MAX_SEGMENTS: usize = 18;

/// Velocities below this count as "at rest" when deciding directions \[u/s\].
const V_EPS: f64 = 1e-9;

struct Builder {
    seg: [Segment; MAX_SEGMENTS],
    n: usize,
    t: f64,
}

impl Builder {
    fn new() -> Self {
        Builder {
            seg: [Segment::default(); MAX_SEGMENTS],
            n: 0,
            t: 0.0,
        }
    }

    fn push(&mut self, dur: f64, p: f64, v: f64, a: f64, j: f64) {
        if dur <= 0.0 {
            return;
        }
        debug_assert!(self.n < MAX_SEGMENTS);
        self.seg[self.n] = Segment {
            t0: self.t,
            p,
            v,
            a,
            j,
        };
        self.n += 1;
        self.t += dur;
    }

    fn push_ruckig(&mut self, pr: &Profile) {
        if pr.brake.duration > 0.0 {
            for i in 0..2 {
                self.push(
                    pr.brake.t[i],
                    pr.brake.p[i],
                    pr.brake.v[i],
                    pr.brake.a[i],
                    pr.brake.j[i],
                );
            }
        }
        for i in 0..7 {
            self.push(pr.t[i], pr.p[i], pr.v[i], pr.a[i], pr.j[i]);
        }
    }

    fn append(&mut self, other: &Profile1) {
        for k in 0..other.n {
            let s = other.seg[k];
            if other.duration <= 0.0 {
                break;
            }
            let end = if k + 1 < other.n {
                other.seg[k + 1].t0
            } else {
                other.duration
            };
            self.push(end - s.t0, s.p, s.v, s.a, s.j);
        }
    }

    fn finish(self, end: State1, continues: bool) -> Profile1 {
        let mut b = self;
        if b.n == 0 {
            // Zero-length profile: one segment that holds the end state.
            b.seg[0] = Segment {
                t0: 0.0,
                p: end.pos,
                v: end.vel,
                a: 0.0,
                j: 0.0,
            };
            b.n = 1;
        }
        Profile1 {
            seg: b.seg,
            n: b.n,
            duration: b.t,
            end,
            continues,
        }
    }
}

/// Signed acceleration bounds (max, min) for travel in direction `dir` (±1): accelerating
/// along the travel direction is bounded by `acceleration`, against it by `deceleration`.
fn signed_acc(dir: f64, l: &Limits) -> (f64, f64) {
    if dir >= 0.0 {
        (l.acceleration, -l.deceleration)
    } else {
        (l.deceleration, -l.acceleration)
    }
}

fn sign_or(x: f64, eps: f64, fallback: f64) -> f64 {
    if x > eps {
        1.0
    } else if x < -eps {
        -1.0
    } else {
        fallback
    }
}

fn ruckig(
    start: State1,
    target: Option<f64>,
    target_vel: f64,
    dir: f64,
    l: &Limits,
) -> Result<Profile, TrajectoryError> {
    match ruckig_once(start, target, target_vel, dir, l) {
        Ok(p) => Ok(p),
        Err(e) => {
            // The Rust port fails on some exactly-degenerate inputs (e.g. 0 -> 20.000000000000018
            // with v 100, a 1000, j 1e4, where the velocity limit is reached exactly at the end
            // of the jerk phase). Slightly tighter limits avoid the degenerate case and never
            // exceed the requested ones.
            for k in [1e-9, 1e-7, 1e-5] {
                for (dv, da, dj) in [(k, 0.0, 0.0), (0.0, k, 0.0), (0.0, 0.0, k), (k, k, k)] {
                    let tight = Limits {
                        velocity: l.velocity * (1.0 - dv),
                        acceleration: l.acceleration * (1.0 - da),
                        deceleration: l.deceleration * (1.0 - da),
                        jerk: l.jerk * (1.0 - dj),
                    };
                    if let Ok(p) = ruckig_once(
                        start,
                        target,
                        target_vel.clamp(-tight.velocity, tight.velocity),
                        dir,
                        &tight,
                    ) {
                        return Ok(p);
                    }
                }
            }
            Err(e)
        }
    }
}

fn ruckig_once(
    start: State1,
    target: Option<f64>,
    target_vel: f64,
    dir: f64,
    l: &Limits,
) -> Result<Profile, TrajectoryError> {
    let mut otg = Ruckig::<1, ThrowErrorHandler>::new(None, 0.001);
    let mut input = InputParameter::<1>::new(None);
    let mut traj = Trajectory::<1>::new(None);
    let (a_max, a_min) = signed_acc(dir, l);
    input.control_interface = match target {
        Some(_) => ControlInterface::Position,
        None => ControlInterface::Velocity,
    };
    input.current_position[0] = start.pos;
    input.current_velocity[0] = start.vel;
    input.current_acceleration[0] = start.acc;
    input.target_position[0] = target.unwrap_or(0.0);
    input.target_velocity[0] = target_vel;
    input.target_acceleration[0] = 0.0;
    input.max_velocity[0] = l.velocity;
    input.max_acceleration[0] = a_max;
    input.min_acceleration = Some(daov_stack![a_min]);
    input.max_jerk[0] = l.jerk;
    otg.calculate(&input, &mut traj).map_err(|e| {
        TrajectoryError::Calculation(format!("{e:?} for {start:?} -> {target:?}/{target_vel}"))
    })?;
    Ok(traj.profiles[0][0])
}

/// True if the velocity never points against `dir` (beyond a small tolerance).
fn monotonic(p: &Profile1, dir: f64) -> bool {
    for k in 0..p.n {
        let s = p.seg[k];
        let end = if k + 1 < p.n {
            p.seg[k + 1].t0
        } else {
            p.duration
        };
        let len = end - s.t0;
        let v_end = s.v + len * (s.a + len * s.j / 2.0);
        let mut vmin = (s.v * dir).min(v_end * dir);
        if s.j != 0.0 {
            let te = -s.a / s.j;
            if te > 0.0 && te < len {
                vmin = vmin.min((s.v + te * (s.a + te * s.j / 2.0)) * dir);
            }
        }
        if vmin < -1e-7 {
            return false;
        }
    }
    true
}

fn single(
    start: State1,
    target: Option<f64>,
    target_vel: f64,
    dir: f64,
    l: &Limits,
) -> Result<Builder, TrajectoryError> {
    let pr = ruckig(start, target, target_vel, dir, l)?;
    let mut b = Builder::new();
    b.push_ruckig(&pr);
    Ok(b)
}

/// Stop from `start`; bounds mapped from the current travel direction.
fn stop_piece(start: State1, l: &Limits) -> Result<Profile1, TrajectoryError> {
    let dir = sign_or(start.vel, V_EPS, sign_or(start.acc, 0.0, 1.0));
    let mut p = single(start, None, 0.0, dir, l)?.finish(State1::at_rest(start.pos), false);
    if p.duration > 0.0 {
        p.end = State1::at_rest(p.at_raw_end());
    }
    Ok(p)
}

impl Profile1 {
    /// Position reached at the end of the last stored segment (before snapping to `end`).
    fn at_raw_end(&self) -> f64 {
        let s = &self.seg[self.n - 1];
        let dt = self.duration - s.t0;
        s.p + dt * (s.v + dt * (s.a / 2.0 + dt * s.j / 6.0))
    }
}

pub(super) fn to_position(
    start: State1,
    target_pos: f64,
    target_vel: f64,
    l: &Limits,
) -> Result<Profile1, TrajectoryError> {
    let end = State1 {
        pos: target_pos,
        vel: target_vel,
        acc: 0.0,
    };
    let d = target_pos - start.pos;
    let at_rest = start.vel.abs() <= V_EPS && start.acc.abs() <= V_EPS;
    if d.abs() <= 1e-12 && at_rest && target_vel == 0.0 {
        return Ok(Builder::new().finish(end, false));
    }
    let dir = sign_or(
        d,
        1e-12,
        sign_or(target_vel, 0.0, sign_or(start.vel, 0.0, 1.0)),
    );
    // Moving away from the target: stop first, then move back (spec §1.1).
    if start.vel * dir < -V_EPS {
        return stop_then_move(start, target_pos, target_vel, l);
    }
    let b = single(start, Some(target_pos), target_vel, dir, l)?;
    let p = b.finish(end, false);
    if monotonic(&p, dir) {
        Ok(p)
    } else if at_rest {
        // From rest a reversal can only come from numerical noise; keep Ruckig's answer.
        Ok(p)
    } else {
        stop_then_move(start, target_pos, target_vel, l)
    }
}

fn stop_then_move(
    start: State1,
    target_pos: f64,
    target_vel: f64,
    l: &Limits,
) -> Result<Profile1, TrajectoryError> {
    let stop = stop_piece(start, l)?;
    let rest = State1::at_rest(stop.end.pos);
    let d = target_pos - rest.pos;
    let dir = sign_or(d, 1e-12, sign_or(target_vel, 0.0, 1.0));
    let mut b = Builder::new();
    b.append(&stop);
    if d.abs() > 1e-12 || target_vel != 0.0 {
        let mv =
            single(rest, Some(target_pos), target_vel, dir, l)?.finish(State1::default(), false);
        b.append(&mv);
    }
    Ok(b.finish(
        State1 {
            pos: target_pos,
            vel: target_vel,
            acc: 0.0,
        },
        false,
    ))
}

pub(super) fn to_velocity(
    start: State1,
    target_vel: f64,
    l: &Limits,
) -> Result<Profile1, TrajectoryError> {
    let v0 = start.vel;
    if v0 * target_vel < 0.0 && v0.abs() > V_EPS {
        // Sign change: stop with the deceleration bound, then accelerate the other way.
        let stop = stop_piece(start, l)?;
        let rest = State1::at_rest(stop.end.pos);
        let dir = sign_or(target_vel, 0.0, 1.0);
        let acc = single(rest, None, target_vel, dir, l)?.finish(State1::default(), false);
        let mut b = Builder::new();
        b.append(&stop);
        b.append(&acc);
        let end_pos = if acc.duration > 0.0 {
            acc.at_raw_end()
        } else {
            rest.pos
        };
        return Ok(b.finish(
            State1 {
                pos: end_pos,
                vel: target_vel,
                acc: 0.0,
            },
            true,
        ));
    }
    let dir = sign_or(
        target_vel,
        V_EPS,
        sign_or(v0, 0.0, sign_or(start.acc, 0.0, 1.0)),
    );
    let b = single(start, None, target_vel, dir, l)?;
    let tmp = b.finish(State1::default(), true);
    let end_pos = if tmp.duration > 0.0 {
        tmp.at_raw_end()
    } else {
        start.pos
    };
    let mut p = tmp;
    p.end = State1 {
        pos: end_pos,
        vel: target_vel,
        acc: 0.0,
    };
    if p.duration <= 0.0 {
        return Ok(Profile1::hold(State1 {
            pos: start.pos,
            vel: target_vel,
            acc: 0.0,
        }));
    }
    Ok(p)
}
