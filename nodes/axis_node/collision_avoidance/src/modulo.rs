//! Modulo target computation of MC_MoveAbsoluteCA (collision_avoidance.md §5.2.3, §10.4).

use super::types::{errors as err, CaDirection};
use motion_core::Rejection;

/// Absolute target for a start position `x0` (absolute), modulo factor `m`, tolerance window
/// `w`, target `p`, direction and additional turns `turns` on a rail (`ring`).
pub fn target(
    x0: f64,
    m: f64,
    w: f64,
    p: f64,
    dir: CaDirection,
    turns: u32,
    ring: bool,
) -> Result<f64, Rejection> {
    let bad_turns = || {
        Rejection::new(
            err::INVALID_ADDITIONAL_TURNS,
            format!("AdditionalTurns = {turns} not allowed with Direction {dir:?}"),
        )
    };
    if dir == CaDirection::NonModulo {
        return if turns != 0 { Err(bad_turns()) } else { Ok(p) };
    }
    if !ring {
        return Err(Rejection::new(
            err::MODULO_ON_OPEN_RAIL,
            format!("Direction {dir:?} needs a ring rail"),
        ));
    }
    if !(0.0..=m).contains(&p) {
        return Err(Rejection::new(
            err::INVALID_TARGET_POSITION,
            format!("modulo target {p} outside [0, {m}]"),
        ));
    }
    let p = if p == m { 0.0 } else { p };
    let s = x0.rem_euclid(m);
    let df = (p - s).rem_euclid(m);
    let db = (s - p).rem_euclid(m);
    let c = df.min(db);
    let sigma = if df <= m / 2.0 { df } else { df - m };
    let n = turns as f64 * m;
    let r = match dir {
        CaDirection::ShortestWay => {
            if turns != 0 {
                return Err(bad_turns());
            }
            sigma
        }
        CaDirection::Positive => {
            if c <= w {
                sigma + n
            } else {
                df + n
            }
        }
        CaDirection::Negative => {
            if c <= w {
                sigma - n
            } else {
                -db - n
            }
        }
        CaDirection::NonModulo => p - x0,
    };
    Ok(x0 + r)
}
