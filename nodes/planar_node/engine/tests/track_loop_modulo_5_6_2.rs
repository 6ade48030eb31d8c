//! §5.6.2 – closed loops: unwrapped coordinate, SetPosModulo, every direction mode with
//! additional turns and modulo tolerance (manual 6.1.9 rule), option checks; §5.9 dependent C
//! follows the heading continuously over laps.
//!
//! Loop L: circle of length 2000 mm (r = 2000/2π) starting at (r, 0), counter-clockwise;
//! mover M joins at s = 0 with use_orientation (heading 90°).

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;
use Direction::*;

const L: f64 = 2000.0;

fn setup() -> Sim {
    let r = L / std::f64::consts::TAU;
    let mut s = Sim::new(cfg(&[("M", r, 0.0)], &["L"]));
    circle_loop(&mut s, r);
    assert!(close(track(&s, "L").length, L, 1e-9));
    assert!(track(&s, "L").closed_loop);
    s.enable("M");
    join_wait(&mut s, "M", "L", true);
    assert!(close(on_track(&s, "M").set_pos, 0.0, 1e-6));
    s
}

/// (name, target, options, expected unwrapped SetPos afterwards) in sequence.
const CASES: &[(&str, f64, Direction, u32, f64, f64)] = &[
    (
        "NonModulo forward over a lap",
        2500.0,
        NonModulo,
        0,
        0.0,
        2500.0,
    ),
    (
        "NonModulo backward below zero",
        -300.0,
        NonModulo,
        0,
        0.0,
        -300.0,
    ),
    ("Positive to the next ≡100", 100.0, Positive, 0, 0.0, 100.0),
    (
        "Positive with one extra lap",
        100.0,
        Positive,
        1,
        0.0,
        2100.0,
    ),
    (
        "Positive: target behind → almost a lap",
        50.0,
        Positive,
        0,
        0.0,
        4050.0,
    ),
    ("Negative to ≡1900", 1900.0, Negative, 0, 0.0, 3900.0),
    (
        "Negative, equal target, no turn: no motion",
        1900.0,
        Negative,
        0,
        0.0,
        3900.0,
    ),
    (
        "Negative, equal target, one turn",
        1900.0,
        Negative,
        1,
        0.0,
        1900.0,
    ),
    (
        "ShortestWay forward (200 < 1800)",
        100.0,
        ShortestWay,
        0,
        0.0,
        2100.0,
    ),
    (
        "ShortestWay backward (600 < 1400)",
        1500.0,
        ShortestWay,
        0,
        0.0,
        1500.0,
    ),
    (
        "Positive within tolerance goes back",
        1490.0,
        Positive,
        0,
        20.0,
        1490.0,
    ),
    (
        "Positive outside tolerance goes a lap",
        1480.0,
        Positive,
        0,
        5.0,
        3480.0,
    ),
    (
        "Negative within tolerance goes forward",
        1500.0,
        Negative,
        0,
        30.0,
        3500.0,
    ),
    (
        "Negative within tolerance plus one turn",
        1490.0,
        Negative,
        1,
        30.0,
        1490.0,
    ),
    (
        "target value reduced mod L",
        4100.0 + 2000.0,
        Positive,
        0,
        0.0,
        2100.0,
    ),
];

#[test]
fn loop_modulo_cases() {
    let mut s = setup();
    let r = L / std::f64::consts::TAU;
    for &(name, target, dir, turns, tol, expect) in CASES {
        let id = s.ok(mot_opt("M", "", target, dir_opt(dir, turns, tol)));
        assert_eq!(s.wait_final(id, 60.0), CommandState::Done, "{name}");
        let o = on_track(&s, "M");
        assert!(
            close(o.set_pos, expect, POS_TOL),
            "{name}: SetPos {} expected {expect}",
            o.set_pos
        );
        let m = expect.rem_euclid(L);
        assert!(
            close(o.set_pos_modulo, m, POS_TOL) && (0.0..L).contains(&o.set_pos_modulo),
            "{name}: SetPosModulo {} expected {m}",
            o.set_pos_modulo
        );
        // Dependent C: heading at s plus the laps driven (continuous, unwrapped).
        let c = 90.0 + (expect / r).to_degrees();
        assert!(
            close(s.mover("M").set_pos.c, c, 1e-6 + ANG_TOL),
            "{name}: c {} expected {c}",
            s.mover("M").set_pos.c
        );
        let q = position_at(&mut s, "L", expect);
        assert_pos(&s.mover("M"), q.x, q.y);
    }
}

/// The motion goes only in the requested direction (no backward step for Positive).
#[test]
fn positive_never_moves_backward() {
    let mut s = setup();
    let id = s.ok(mot_opt("M", "", 10.0, dir_opt(Positive, 2, 0.0)));
    let mut last = on_track(&s, "M").set_pos;
    while s.state(id) != Some(CommandState::Done) {
        s.step();
        let now = on_track(&s, "M").set_pos;
        assert!(now >= last - 1e-9, "moved backward: {last} -> {now}");
        last = now;
    }
    assert!(close(last, 2.0 * L + 10.0, POS_TOL));
}

#[test]
fn option_checks() {
    let mut s = setup();
    for (name, dir, turns, tol) in [
        ("turns with NonModulo", NonModulo, 1, 0.0),
        ("turns with ShortestWay", ShortestWay, 1, 0.0),
        ("tolerance with NonModulo", NonModulo, 0, 5.0),
        ("negative tolerance", Positive, 0, -1.0),
    ] {
        let e = s.err(mot_opt("M", "", 10.0, dir_opt(dir, turns, tol)));
        assert_eq!(e.error_id, E_INVALID_PARAMETER, "{name}");
    }
    let e = s.err(mot_opt(
        "M",
        "",
        10.0,
        MoveOnTrackOptions {
            gap: -1.0,
            ..Default::default()
        },
    ));
    assert_eq!(e.error_id, E_INVALID_PARAMETER, "negative gap");
    let e = s.err(mot("M", "", f64::NAN));
    assert_eq!(e.error_id, motion_core::ErrorId::NOT_FINITE);
    let e = s.err(mot("M", "nope", 10.0));
    assert_eq!(e.error_id, motion_core::ErrorId::UNKNOWN_OBJECT);
}
