//! Interpolation-stage axis limits (pick_and_place.md §7.8 (2)): the AXIS_REF maxima of the group
//! configuration applied to the commanded set-points of each cycle.
//!
//! The planning stage (§7.8 (1)) already folds these maxima into the path limits, so a static
//! profile never needs this. What planning cannot see is the belt superposition of §15.1 (belt
//! velocity and the coupling blend added to the path), and curvature in blends. Here every cycle
//! gets, per axis, the set-point interval that keeps its velocity, acceleration and jerk (the
//! finite differences of consecutive set-points, as a drive sees them) within the maxima, with
//! a braking look-ahead so the velocity limit is always approached at the jerk limit and never
//! overshot. The engine first slows the path parameter so that all axes fit (the geometry is
//! kept, proposal), and clamps an axis only if no path speed fits.

use crate::config::PickPlaceConfig;

/// AXIS_REF maxima of one pose axis; `f64::INFINITY` = no limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisMax {
    /// Max velocity [units/s].
    pub vel: f64,
    /// Max acceleration/deceleration [units/s²].
    pub acc: f64,
    /// Max jerk [units/s³].
    pub jerk: f64,
}

impl AxisMax {
    /// No limit at all.
    pub const NONE: AxisMax = AxisMax {
        vel: f64::INFINITY,
        acc: f64::INFINITY,
        jerk: f64::INFINITY,
    };

    /// True when none of the three maxima is set.
    pub fn is_none(&self) -> bool {
        *self == Self::NONE
    }
}

/// The AXIS_REF maxima per pose axis X, Y, Z, A, B, C, Aux1 (§2.1: 0 = none). With the identity
/// kinematics A1 … A6 move like X … C, so the stricter of the two applies to the pose axis.
pub fn pose_axis_max(cfg: &PickPlaceConfig) -> [AxisMax; 7] {
    let set = |v: f64| if v > 0.0 { v } else { f64::INFINITY };
    let mut out = [AxisMax::NONE; 7];
    for (q, m) in out.iter_mut().enumerate() {
        let cartesian = if q < 6 { q + 1 } else { 13 };
        let joint = if q < 6 { q + 7 } else { 13 };
        for i in [cartesian, joint] {
            let a = cfg.axis(i);
            m.vel = m.vel.min(set(a.max_vel));
            m.acc = m.acc.min(set(a.max_acc));
            m.jerk = m.jerk.min(set(a.max_jerk));
        }
    }
    out
}

/// Commanded state of one axis after the last cycle: set-point and its finite differences.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisState {
    /// Set-point [units].
    pub pos: f64,
    /// (pos − previous pos) / dt.
    pub vel: f64,
    /// (vel − previous vel) / dt.
    pub acc: f64,
}

/// Largest acceleration `a ≥ 0` with `margin − a·dt − a²/(2j) ≥ 0`: the velocity still reachable
/// this cycle such that ramping the acceleration down at jerk `j` does not pass the limit
/// (`margin` = velocity limit − velocity). Negative margin: the velocity must come back at once.
fn braking_acc(margin: f64, dt: f64, j: f64) -> f64 {
    if margin < 0.0 {
        margin / dt
    } else {
        // Root of a²/(2j) + a·dt − margin, in the cancellation-free form (j = ∞ gives margin/dt).
        2.0 * margin / (dt + (dt * dt + 2.0 * margin / j).sqrt())
    }
}

/// The set-point interval `[lo, hi]` of the next cycle for which the axis keeps its maxima.
///
/// Acceleration and jerk are exact; the velocity bound includes the braking look-ahead, which
/// keeps itself feasible from cycle to cycle (after the largest admissible acceleration, one
/// step of −j·dt stays admissible). If the state already violates a maximum (an earlier stop
/// with `alrStopDec`), the interval brings the axis back at the jerk limit.
pub fn admissible(s: &AxisState, m: &AxisMax, dt: f64) -> (f64, f64) {
    if m.is_none() {
        return (f64::NEG_INFINITY, f64::INFINITY);
    }
    let jd = m.jerk * dt;
    let (mut a_lo, mut a_hi) = ((s.acc - jd).max(-m.acc), (s.acc + jd).min(m.acc));
    if a_lo > a_hi {
        // |acc| above the maximum: reduce it at the jerk limit.
        if s.acc > 0.0 {
            a_hi = a_lo;
        } else {
            a_lo = a_hi;
        }
    }
    if m.vel.is_finite() {
        let v_hi = braking_acc(m.vel - s.vel, dt, m.jerk);
        let v_lo = -braking_acc(m.vel + s.vel, dt, m.jerk);
        // Acceleration and jerk win over the look-ahead if they cannot both be met.
        let lo = v_lo.max(a_lo).min(a_hi);
        let hi = v_hi.min(a_hi).max(a_lo);
        (a_lo, a_hi) = if lo <= hi { (lo, hi) } else { (hi, hi) };
    }
    let at = |a: f64| s.pos + dt * (s.vel + a * dt);
    (at(a_lo), at(a_hi))
}

/// The set-point of an axis that cannot take the path's set-point `target` (outside its
/// admissible interval): it closes the gap to the target moving at `target_vel` along a braking
/// curve (at half the maximum deceleration, leaving room for the jerk), within the interval,
/// so it converges instead of overshooting back and forth at the limits.
pub fn catch_up(s: &AxisState, m: &AxisMax, dt: f64, target: f64, target_vel: f64) -> f64 {
    let (lo, hi) = admissible(s, m, dt);
    // Gap after this cycle if the axis kept its velocity; its rate of change.
    let r = s.pos + s.vel * dt - target;
    let r_dot = s.vel - target_vel;
    let brake = 0.5 * m.acc.min(f64::MAX);
    // Time constant of the velocity loop: the time to build up the braking deceleration.
    let tau = (brake / m.jerk).max(dt);
    let closing = (2.0 * brake * r.abs()).sqrt().min(r.abs() / (2.0 * tau));
    let a = (-r.signum() * closing - r_dot) / tau;
    (s.pos + dt * (s.vel + a * dt)).clamp(lo, hi)
}

/// Slack of the admissibility test against round-off of the finite differences [units].
pub fn slack(pos: f64) -> f64 {
    1e-10 * (1.0 + pos.abs())
}

/// True when `p` lies in `[lo, hi]` up to round-off.
pub fn inside(p: f64, (lo, hi): (f64, f64)) -> bool {
    let e = slack(p);
    p >= lo - e && p <= hi + e
}

/// The largest `λ ∈ [0, 1]` for which the linear blend `p0 + λ·(p1 − p0)` lies in every axis's
/// interval; if no λ fits, the one nearest to fitting (the middle of the crossed bounds).
pub fn largest_fraction(p0: &[f64; 7], p1: &[f64; 7], iv: &[(f64, f64); 7]) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for q in 0..7 {
        let (a, b) = iv[q];
        let d = p1[q] - p0[q];
        if d.abs() <= slack(p0[q]) {
            continue; // this axis hardly moves with λ: λ cannot help it
        }
        let (x, y) = ((a - p0[q]) / d, (b - p0[q]) / d);
        lo = lo.max(x.min(y));
        hi = hi.min(x.max(y));
    }
    if lo <= hi {
        hi
    } else {
        (0.5 * (lo + hi)).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 0.001;

    /// Drives one axis towards an unreachable target velocity through the interval: the finite
    /// differences never exceed the maxima and the velocity settles at the limit.
    #[test]
    fn pushing_against_the_limits_keeps_v_a_j() {
        let m = AxisMax {
            vel: 100.0,
            acc: 2000.0,
            jerk: 1e5,
        };
        let mut s = AxisState {
            pos: 0.0,
            vel: 0.0,
            acc: 0.0,
        };
        for k in 0..2000 {
            let (_, hi) = admissible(&s, &m, DT);
            let vel = (hi - s.pos) / DT;
            let acc = (vel - s.vel) / DT;
            let jerk = (acc - s.acc) / DT;
            assert!(vel <= 100.0 + 1e-9, "cycle {k}: v {vel}");
            assert!(acc.abs() <= 2000.0 + 1e-6, "cycle {k}: a {acc}");
            assert!(jerk.abs() <= 1e5 * (1.0 + 1e-6), "cycle {k}: j {jerk}");
            s = AxisState { pos: hi, vel, acc };
        }
        assert!(
            (s.vel - 100.0).abs() < 1e-6,
            "settles at the limit: {}",
            s.vel
        );
        // And braking to the negative limit from there.
        for k in 0..2000 {
            let (lo, _) = admissible(&s, &m, DT);
            let vel = (lo - s.pos) / DT;
            let acc = (vel - s.vel) / DT;
            let jerk = (acc - s.acc) / DT;
            assert!(vel >= -100.0 - 1e-9, "cycle {k}: v {vel}");
            assert!(acc.abs() <= 2000.0 + 1e-6, "cycle {k}: a {acc}");
            assert!(jerk.abs() <= 1e5 * (1.0 + 1e-6), "cycle {k}: j {jerk}");
            s = AxisState { pos: lo, vel, acc };
        }
        assert!((s.vel + 100.0).abs() < 1e-6);
    }

    #[test]
    fn no_limit_is_the_whole_line_and_over_limit_states_come_back() {
        let s = AxisState {
            pos: 5.0,
            vel: 300.0,
            acc: 5000.0,
        };
        assert_eq!(
            admissible(&s, &AxisMax::NONE, DT),
            (f64::NEG_INFINITY, f64::INFINITY)
        );
        let m = AxisMax {
            vel: 100.0,
            acc: 2000.0,
            jerk: 1e5,
        };
        // Acceleration above the maximum: reduced at the jerk limit (one point).
        let (lo, hi) = admissible(&s, &m, DT);
        assert_eq!(lo, hi);
        let acc = ((hi - s.pos) / DT - s.vel) / DT;
        assert!((acc - (5000.0 - 100.0)).abs() < 1e-6, "{acc}");
    }

    /// An axis 5 units behind a target moving at 100 units/s converges onto it within the
    /// maxima and stays on it (no oscillation at the limits).
    #[test]
    fn catch_up_converges_onto_a_moving_target() {
        let m = AxisMax {
            vel: 450.0,
            acc: 8000.0,
            jerk: 2e6,
        };
        let mut s = AxisState {
            pos: -5.0,
            vel: 100.0,
            acc: 0.0,
        };
        let mut err = f64::MAX;
        for k in 1..=300 {
            let target = 100.0 * k as f64 * DT;
            let p = catch_up(&s, &m, DT, target, 100.0);
            let vel = (p - s.pos) / DT;
            let acc = (vel - s.vel) / DT;
            assert!(
                vel.abs() <= 450.0 + 1e-9 && acc.abs() <= 8000.0 + 1e-6,
                "cycle {k}"
            );
            assert!(
                ((acc - s.acc) / DT).abs() <= 2e6 * (1.0 + 1e-6),
                "cycle {k}"
            );
            s = AxisState { pos: p, vel, acc };
            err = (p - target).abs();
        }
        assert!(err < 1e-3, "still {err} behind after 0.3 s");
    }

    #[test]
    fn largest_fraction_of_a_linear_blend() {
        let p0 = [0.0; 7];
        let mut p1 = [0.0; 7];
        p1[0] = 2.0;
        p1[1] = -4.0;
        let mut iv = [(f64::NEG_INFINITY, f64::INFINITY); 7];
        iv[0] = (-1.0, 1.0);
        assert_eq!(largest_fraction(&p0, &p1, &iv), 0.5);
        iv[1] = (-1.0, 1.0);
        assert_eq!(largest_fraction(&p0, &p1, &iv), 0.25);
        // Crossed bounds: X needs λ ≥ 0.75, Y allows at most 0.25.
        iv[0] = (1.5, 3.0);
        assert_eq!(largest_fraction(&p0, &p1, &iv), 0.5);
    }
}
