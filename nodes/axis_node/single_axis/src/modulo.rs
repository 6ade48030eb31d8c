//! Modulo target computation for MC_MoveModulo (single_axis.md §4.8.4, §4.8.5, W1–W4).

use crate::inputs::Direction;

/// `x mod p` in `[0, p)`.
pub fn modulo(x: f64, p: f64) -> f64 {
    let r = x.rem_euclid(p);
    // rem_euclid may return p for tiny negative x because of rounding.
    if r >= p {
        0.0
    } else {
        r
    }
}

/// Modulo turns `floor(x / p)`.
pub fn turns(x: f64, p: f64) -> i32 {
    (x / p).floor() as i32
}

/// Signed distance from the set position `s_abs` for a start from standstill (or
/// Buffered), per the algorithm of §4.8.4. `period` > 0, `tol` = AxisModuloToleranceWindow,
/// `position` ≥ 0 (checked by the caller). Returns `None` for MC_Shortest_Way with
/// `position ≥ period`, and for directions that are not allowed from standstill.
pub fn standstill_distance(
    s_abs: f64,
    position: f64,
    period: f64,
    tol: f64,
    dir: Direction,
) -> Option<f64> {
    let s = modulo(s_abs, period);
    let base = modulo(position, period);
    let n_turns = (position / period).floor();
    // Signed shortest difference in (−P/2, +P/2]; a tie (exactly P/2) goes positive.
    let mut delta = modulo(base - s, period);
    if delta > period / 2.0 {
        delta -= period;
    }
    match dir {
        Direction::ShortestWay => {
            if position >= period {
                None
            } else {
                Some(delta)
            }
        }
        Direction::Positive => Some(if delta.abs() <= tol {
            delta + n_turns * period
        } else {
            modulo(base - s, period) + n_turns * period
        }),
        Direction::Negative => Some(if delta.abs() <= tol {
            delta - n_turns * period
        } else {
            -(modulo(s - base, period) + n_turns * period)
        }),
        Direction::Current | Direction::Undefined => None,
    }
}

/// Target for a start on a moving axis (§4.8.4 "Start while the axis is moving"): the first
/// absolute position at or beyond `stop_point` in the travel direction `dir_sign` (±1) whose
/// modulo value equals `position mod period`.
pub fn moving_target(stop_point: f64, position: f64, period: f64, dir_sign: f64) -> f64 {
    let base = modulo(position, period);
    let s = modulo(stop_point, period);
    if dir_sign >= 0.0 {
        stop_point + modulo(base - s, period)
    } else {
        stop_point - modulo(s - base, period)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modulo_is_in_range() {
        assert_eq!(modulo(-1e-18, 360.0), 0.0);
        assert_eq!(modulo(-90.0, 360.0), 270.0);
        assert_eq!(turns(-90.0, 360.0), -1);
    }

    #[test]
    fn moving_target_goes_forward() {
        assert_eq!(moving_target(100.0, 90.0, 360.0, 1.0), 450.0);
        assert_eq!(moving_target(100.0, 90.0, 360.0, -1.0), 90.0);
        assert_eq!(moving_target(90.0, 90.0, 360.0, 1.0), 90.0);
    }
}
