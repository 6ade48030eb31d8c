//! Gap control (xplanar.md §5.6.3): reach intervals and the admissibility of one step.
//!
//! Every on-track mover has a *reach interval*: the positions it passes while stopping now
//! with the dynamics it was last verified with (closed form, [`stop_range`]). A step is
//! admissible if the new interval does not grow into `[front_reach_lo - gap, ...)` nor
//! `(..., back_reach_hi + gap]`. Because a mover following a committed stop only shrinks its
//! interval, and every other step is checked against the neighbours' latest intervals, the
//! arc-length distance never falls below the gap, also when the leader stops hard.

use crate::motion::stop_range;

/// Numerical slack of the checks \[mm\].
pub const GAP_EPS: f64 = 1e-9;
/// Gap-limited plans aim this far inside their limit, so rounding never reaches it \[mm\].
pub const AIM_INSIDE: f64 = 1e-6;

/// Absolute reach interval of a state (`r`, `v`, `a`) stopping with (`d`, `j`).
pub fn reach(r: f64, v: f64, a: f64, d: f64, j: f64) -> (f64, f64) {
    let (lo, hi) = stop_interval(v, a, d, j);
    (r + lo, r + hi)
}

/// Positions passed (relative) by the time-optimal stop from (`v`, `a`). Monotone stops are
/// [`stop_range`]; a stop that must reverse (braking so hard that the velocity changes sign
/// before the acceleration is back to zero, as at the end of every positioning profile) is
/// computed exactly: jerk +j up to the peak `a_p = √((a² − 2jv)/2)`, then −j to rest.
pub fn stop_interval(v: f64, a: f64, d: f64, j: f64) -> (f64, f64) {
    let sign = if v > 0.0 || (v == 0.0 && a > 0.0) {
        1.0
    } else {
        -1.0
    };
    let (vn, an) = (v * sign, a * sign);
    if an >= 0.0 || vn >= an * an / (2.0 * j) {
        return stop_range(v, a, d, j);
    }
    let ap = ((an * an - 2.0 * j * vn) / 2.0).max(0.0).sqrt();
    let t1 = (ap - an) / j;
    let p1 = vn * t1 + an * t1 * t1 / 2.0 + j * t1 * t1 * t1 / 6.0;
    let v1 = vn + an * t1 + j * t1 * t1 / 2.0;
    let t2 = ap / j;
    let p_end = p1 + v1 * t2 + ap * t2 * t2 / 2.0 - j * t2 * t2 * t2 / 6.0;
    // Forward excursion until the velocity first reaches zero (phase 1).
    let disc = (an * an - 2.0 * j * vn).max(0.0);
    let ts = ((-an - disc.sqrt()) / j).clamp(0.0, t1);
    let xp = vn * ts + an * ts * ts / 2.0 + j * ts * ts * ts / 6.0;
    let (lo, hi) = (p_end.min(0.0), xp.max(0.0));
    if sign > 0.0 {
        (lo, hi)
    } else {
        (-hi, -lo)
    }
}

/// True if the step from interval `old` to `new` is allowed with the limits
/// (`fwd`: the forward reach may not exceed it, `bwd`: the backward reach may not go below).
/// A side that does not grow is always allowed (no deadlock when a join left a short gap).
pub fn step_ok(old: (f64, f64), new: (f64, f64), fwd: f64, bwd: f64) -> bool {
    let fwd_ok = new.1 <= fwd + GAP_EPS || new.1 <= old.1 + GAP_EPS;
    let bwd_ok = new.0 >= bwd - GAP_EPS || new.0 >= old.0 - GAP_EPS;
    fwd_ok && bwd_ok
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reversing_stop_matches_the_profile() {
        use motion_core::trajectory::{Limits, Profile1, State1};
        let lim = Limits {
            velocity: 1000.0,
            acceleration: 10000.0,
            deceleration: 10000.0,
            jerk: 100000.0,
        };
        for &(v, a) in &[
            (0.24, -364.0),
            (-0.24, 364.0),
            (1.0, -2000.0),
            (5.0, -900.0),
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
            let (lo, hi) = stop_interval(v, a, 10000.0, 100000.0);
            let n = 2000;
            let (mut mn, mut mx) = (0.0f64, 0.0f64);
            for k in 0..=n {
                let x = p.at(p.duration() * k as f64 / n as f64).pos;
                mn = mn.min(x);
                mx = mx.max(x);
            }
            assert!(
                mn >= lo - 1e-9 && mx <= hi + 1e-9,
                "v {v} a {a}: [{mn}, {mx}] not in [{lo}, {hi}]"
            );
            let e = p.end().pos;
            assert!(
                (e - lo).abs() < 1e-9 || (e - hi).abs() < 1e-9,
                "v {v} a {a}: end {e} is not an end of [{lo}, {hi}]"
            );
        }
    }

    #[test]
    fn growing_into_the_front_is_refused() {
        assert!(step_ok((0.0, 10.0), (1.0, 12.0), 20.0, -100.0));
        assert!(!step_ok((0.0, 10.0), (1.0, 21.0), 20.0, -100.0));
        // Already too close but not growing: allowed.
        assert!(step_ok((0.0, 30.0), (1.0, 30.0), 20.0, -100.0));
    }
}
