//! collision_avoidance.md §10.4 "Modulo positioning table" (M = 100, tolerance window 1) and
//! the additional-turns example (M = 360), through `ca::modulo::target` (§5.2.3).

use axis_engine::ca::modulo::target;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::CaDirection::{self, *};
use motion_core::ErrorId;

/// (direction, start, target, turns, expected relative move or error id).
type Row = (CaDirection, f64, f64, u32, Result<f64, ErrorId>);
const CASES: &[Row] = &[
    (Positive, 110.0, 10.0, 0, Ok(0.0)),
    (Positive, 110.9, 10.0, 0, Ok(-0.9)),
    (Positive, 112.0, 10.0, 0, Ok(98.0)),
    (Positive, 95.0, 10.0, 0, Ok(15.0)),
    (Positive, 110.0, 110.0, 0, Err(INVALID_TARGET_POSITION)),
    (Positive, 110.0, 10.0, 3, Ok(300.0)),
    (Positive, 110.9, 10.0, 3, Ok(299.1)),
    (Positive, 112.0, 10.0, 3, Ok(398.0)),
    (Positive, 95.0, 10.0, 3, Ok(315.0)),
    (Positive, 110.0, 110.0, 3, Err(INVALID_TARGET_POSITION)),
    (Negative, 110.0, 10.0, 0, Ok(0.0)),
    (Negative, 109.9, 10.0, 0, Ok(0.1)),
    (Negative, 108.0, 10.0, 0, Ok(-98.0)),
    (Negative, 95.0, 10.0, 0, Ok(-85.0)),
    (Negative, 110.0, 110.0, 0, Err(INVALID_TARGET_POSITION)),
    (Negative, 410.0, 10.0, 3, Ok(-300.0)),
    (Negative, 409.9, 10.0, 3, Ok(-299.9)),
    (Negative, 408.0, 10.0, 3, Ok(-398.0)),
    (Negative, 495.0, 10.0, 3, Ok(-385.0)),
    (Negative, 410.0, 110.0, 3, Err(INVALID_TARGET_POSITION)),
    (ShortestWay, 440.0, 50.0, 0, Ok(10.0)),
    (ShortestWay, 440.0, 10.0, 0, Ok(-30.0)),
    (ShortestWay, 440.0, 50.0, 1, Err(INVALID_ADDITIONAL_TURNS)),
];

#[test]
fn table_rows() {
    for (row, &(dir, start, p, turns, want)) in CASES.iter().enumerate() {
        let got = target(start, 100.0, 1.0, p, dir, turns, true);
        match (want, got) {
            (Ok(rel), Ok(end)) => {
                assert!(
                    (end - (start + rel)).abs() < 1e-9,
                    "row {}: {dir:?} {start} → {p} turns {turns}: end {end}, want {}",
                    row + 1,
                    start + rel
                );
                assert!(
                    (end.rem_euclid(100.0) - p).abs() < 1e-9,
                    "row {}: modulo end {}",
                    row + 1,
                    end.rem_euclid(100.0)
                );
            }
            (Err(id), Err(r)) => assert_eq!(r.error_id, id, "row {}", row + 1),
            (w, g) => panic!("row {}: want {w:?}, got {g:?}", row + 1),
        }
    }
}

#[test]
fn additional_turns_example_360() {
    let end = target(5.0, 360.0, 1.0, 10.0, Positive, 2, true).unwrap();
    assert!((end - 730.0).abs() < 1e-9, "relative 725, end 730: {end}");
}

#[test]
fn non_modulo_turns_and_open_rail() {
    assert_eq!(
        target(5.0, 360.0, 1.0, 10.0, NonModulo, 1, true)
            .unwrap_err()
            .error_id,
        INVALID_ADDITIONAL_TURNS
    );
    assert_eq!(
        target(5.0, 360.0, 1.0, 10.0, Positive, 0, false)
            .unwrap_err()
            .error_id,
        MODULO_ON_OPEN_RAIL
    );
    assert_eq!(
        target(5.0, 360.0, 1.0, 1234.5, NonModulo, 0, false).unwrap(),
        1234.5
    );
    // p = M is treated as 0.
    let e = target(5.0, 360.0, 1.0, 360.0, Positive, 0, true).unwrap();
    assert!((e - 360.0).abs() < 1e-9);
}
