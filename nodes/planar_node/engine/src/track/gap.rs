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
pub const GAP_EPS: f64 = 1e-7;

/// Absolute reach interval of a state (`r`, `v`, `a`) stopping with (`d`, `j`).
pub fn reach(r: f64, v: f64, a: f64, d: f64, j: f64) -> (f64, f64) {
    let (lo, hi) = stop_range(v, a, d, j);
    (r + lo, r + hi)
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
    fn growing_into_the_front_is_refused() {
        assert!(step_ok((0.0, 10.0), (1.0, 12.0), 20.0, -100.0));
        assert!(!step_ok((0.0, 10.0), (1.0, 21.0), 20.0, -100.0));
        // Already too close but not growing: allowed.
        assert!(step_ok((0.0, 30.0), (1.0, 30.0), 20.0, -100.0));
    }
}
