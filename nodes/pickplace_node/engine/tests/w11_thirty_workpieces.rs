//! pick_and_place.md §19 W11 — "30 workpieces".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, TmState};

#[test]
fn w11_warning_17918_with_the_30th_workpiece() {
    let mut cfg = common_config();
    cfg.belts.insert(
        "1".into(),
        pickplace_engine::BeltConfig {
            params: w8_belt(),
            initial_velocity: 10.0,
            initial_position: 0.0,
        },
    );
    let mut c = Cell::ready(cfg);
    for k in 1..=31 {
        c.cmd(PickPlaceCommand::DetectWorkpiece {
            belt: 1,
            position: [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            valid_delay_cycles: 0,
        });
        c.steps(2);
        let s = c.last();
        assert_eq!(s.state, TmState::Ready, "state unchanged");
        if k < 30 {
            assert!(!s.outputs.warning, "no warning after {k}");
        } else {
            assert!(s.outputs.warning, "warning after {k}");
            assert_eq!(s.outputs.error_id, 17918, "after {k}");
        }
        assert_eq!(s.belts[0].workpieces.len(), k.min(30));
    }
    c.steps(10);
    assert_eq!(c.last().belts[0].workpieces.len(), 30);
    assert_eq!(c.last().outputs.error_id, 17918);
    // Latched until xResetError.
    c.cmd(PickPlaceCommand::ResetError);
    c.steps(2);
    assert!(!c.last().outputs.warning);
    assert_eq!(c.last().outputs.error_id, 0);
}

#[test]
fn pending_and_visible_fifo() {
    let mut cfg = common_config();
    cfg.belts.insert(
        "1".into(),
        pickplace_engine::BeltConfig {
            params: w8_belt(),
            initial_velocity: 0.0,
            initial_position: 0.0,
        },
    );
    let mut c = Cell::ready(cfg);
    let rx = |c: &mut Cell, recv: bool, valid: bool, x: f64| {
        c.cmd(PickPlaceCommand::BeltInput {
            belt: 1,
            receive: recv,
            valid_pos: valid,
            initial_object_position: [x, 0.0, 0.0, 0.0, 0.0, 0.0],
            aux1_target_pos: 0.0,
        });
        c.step();
    };
    rx(&mut c, true, false, 0.0);
    rx(&mut c, false, false, 0.0);
    rx(&mut c, true, false, 0.0);
    rx(&mut c, false, false, 0.0);
    let w = &c.last().belts[0].workpieces;
    assert_eq!(w.len(), 2);
    assert!(!w[0].visible && !w[1].visible);
    // The valid edge completes the oldest pending entry.
    rx(&mut c, false, true, 321.0);
    let w = &c.last().belts[0].workpieces;
    assert!(w[0].visible && !w[1].visible);
    assert_eq!(w[0].belt_position[0], 321.0);
}

#[test]
fn workpiece_beyond_the_upper_limit_is_deleted() {
    let mut cfg = common_config();
    cfg.belts.insert(
        "1".into(),
        pickplace_engine::BeltConfig {
            params: w8_belt(),
            initial_velocity: 1000.0,
            initial_position: 0.0,
        },
    );
    let mut c = Cell::ready(cfg);
    c.cmd(PickPlaceCommand::DetectWorkpiece {
        belt: 1,
        position: [700.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        valid_delay_cycles: 0,
    });
    c.steps(2);
    assert_eq!(c.last().belts[0].workpieces.len(), 1);
    c.steps(100);
    assert_eq!(
        c.last().belts[0].workpieces.len(),
        0,
        "missed workpiece deleted"
    );
    let ev = c.eng.drain_events();
    assert!(ev.iter().any(|e| matches!(
        e,
        pickplace_engine::CellEvent::Workpiece {
            kind: pickplace_engine::belt::WorkpieceEventKind::Missed,
            ..
        }
    )));
    assert!(
        !c.last().outputs.warning,
        "no warning for a missed workpiece"
    );
}
