//! `Engine::snapshot_into` of the pick-and-place engine (issue 14, lockstep speed): a snapshot
//! refilled in place equals a fresh one, whatever it held before (more belts, more
//! workpieces, a running profile), so a lockstep stream may reuse its snapshots.
mod common;
use common::*;
use motion_core::Engine;
use pickplace_engine::{PickPlaceCommand, PickPlaceSnapshot, TmState};

fn belt(velocity: f64) -> pickplace_engine::BeltConfig {
    pickplace_engine::BeltConfig {
        params: w8_belt(),
        initial_velocity: velocity,
        initial_position: 0.0,
    }
}

fn detect(c: &mut Cell, belt: u8, n: usize) {
    for _ in 0..n {
        c.cmd(PickPlaceCommand::DetectWorkpiece {
            belt,
            position: [10.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            valid_delay_cycles: 0,
        });
        c.steps(2);
    }
}

/// Refills `old` from the cell's engine and checks it against a fresh snapshot.
fn refill_equals_fresh(c: &Cell, mut old: PickPlaceSnapshot, what: &str) {
    c.eng.snapshot_into(&mut old);
    assert_eq!(old, c.eng.snapshot(), "refilled from {what}");
}

#[test]
fn a_refilled_snapshot_equals_a_fresh_one() {
    // Another cell with two belts, 12 and 5 workpieces, moving along a linear profile.
    let mut cfg = common_config();
    cfg.belts.insert("1".into(), belt(10.0));
    cfg.belts.insert("2".into(), belt(20.0));
    let mut other = Cell::ready(cfg);
    detect(&mut other, 1, 12);
    detect(&mut other, 2, 5);
    other.set_par(|p| {
        p.target_pos[0] = 200.0;
        p.target_pos[2] = 50.0;
        p.z_start_dist = 50.0;
        p.z_target_dist = 30.0;
    });
    other.cmd(PickPlaceCommand::Execute { set_target: 0 });
    other.until(2000, |s| s.active_profile.is_some());
    other.steps(100);
    let busy = other.last().clone();
    assert!(busy.active_profile.is_some() && busy.state != TmState::Ready);
    assert_eq!(busy.belts[1].workpieces.len(), 5);

    // This cell: one belt, 3 workpieces, idle.
    let mut cfg = common_config();
    cfg.belts.insert("1".into(), belt(0.0));
    let mut c = Cell::ready(cfg);
    detect(&mut c, 1, 3);
    let fresh = c.eng.snapshot();
    assert_eq!(fresh.belts[0].workpieces.len(), 3);
    assert!(fresh.active_profile.is_none());

    refill_equals_fresh(&c, busy.clone(), "a busy cell's snapshot with more belts");
    refill_equals_fresh(&c, PickPlaceSnapshot::default(), "an empty snapshot");
    // And the other way: the busy cell refilling the idle one's snapshot.
    refill_equals_fresh(
        &other,
        fresh,
        "an idle cell's snapshot with fewer workpieces",
    );
}
