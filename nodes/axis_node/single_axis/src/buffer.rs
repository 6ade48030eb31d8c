//! BufferMode arithmetic (single_axis.md §3.6): the velocity at the transition point and the
//! caps of rule 5.

use crate::inputs::BufferMode;

/// Transition velocity magnitude per the §3.6 table. `v2 = None` for MC_Halt (rule 9:
/// BlendingLow/Next → 0, BlendingPrevious/High → v1).
pub fn transition_velocity(mode: BufferMode, v1: f64, v2: Option<f64>) -> f64 {
    match (mode, v2) {
        (BufferMode::Aborting | BufferMode::Buffered, _) => 0.0,
        (BufferMode::BlendingLow | BufferMode::BlendingNext, None) => 0.0,
        (BufferMode::BlendingPrevious | BufferMode::BlendingHigh, None) => v1,
        (BufferMode::BlendingLow, Some(v2)) => v1.min(v2),
        (BufferMode::BlendingPrevious, Some(_)) => v1,
        (BufferMode::BlendingNext, Some(v2)) => v2,
        (BufferMode::BlendingHigh, Some(v2)) => v1.max(v2),
    }
}

/// Distance a jerk-limited stop from velocity `v` (acceleration 0) needs.
pub fn stopping_distance(v: f64, dec: f64, jerk: f64) -> f64 {
    if !jerk.is_finite() {
        return v * v / (2.0 * dec);
    }
    if v >= dec * dec / jerk {
        v * v / (2.0 * dec) + v * dec / (2.0 * jerk)
    } else {
        // Deceleration limit not reached: two jerk phases of sqrt(v/j) each.
        v * (v / jerk).sqrt()
    }
}

/// The highest velocity from which a stop fits into `distance` (rule 5: the transition
/// velocity is capped so that the next command can still stop at its target).
pub fn stop_capable_velocity(distance: f64, dec: f64, jerk: f64) -> f64 {
    if distance <= 0.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    while stopping_distance(hi, dec, jerk) < distance {
        hi *= 2.0;
    }
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if stopping_distance(mid, dec, jerk) <= distance {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_of_w5() {
        use BufferMode::*;
        let modes = [
            Buffered,
            BlendingLow,
            BlendingPrevious,
            BlendingNext,
            BlendingHigh,
        ];
        let a: Vec<f64> = modes
            .iter()
            .map(|&m| transition_velocity(m, 50.0, Some(100.0)))
            .collect();
        assert_eq!(a, vec![0.0, 50.0, 50.0, 100.0, 100.0]);
        let b: Vec<f64> = modes
            .iter()
            .map(|&m| transition_velocity(m, 100.0, Some(50.0)))
            .collect();
        assert_eq!(b, vec![0.0, 50.0, 100.0, 50.0, 100.0]);
    }

    #[test]
    fn stopping_distance_w18() {
        assert!((stopping_distance(100.0, 1000.0, 1e5) - 5.5).abs() < 1e-12);
        assert!((stopping_distance(100.0, 500.0, 1e5) - 10.25).abs() < 1e-12);
        let v = stop_capable_velocity(5.5, 1000.0, 1e5);
        assert!((v - 100.0).abs() < 1e-9);
    }
}
