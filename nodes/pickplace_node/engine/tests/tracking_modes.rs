//! pick_and_place.md §11 tracking modes 0 … 4 and the contour cases of §15.4 (static → belt,
//! belt → static, belt → belt on the same belt, belt 1 → belt 2).
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{CellEvent, GripperEvent, PickPlaceCommand, TmState};

fn feed(c: &mut Cell, belt: u8, x: f64, y: f64) {
    c.cmd(PickPlaceCommand::DetectWorkpiece {
        belt,
        position: [x, y, 0.0, 0.0, 0.0, 0.0],
        valid_delay_cycles: 1,
    });
}

fn pulses(ev: &[CellEvent]) -> Vec<GripperEvent> {
    ev.iter()
        .filter_map(|e| match e {
            CellEvent::GripperPulse { kind, .. } => Some(*kind),
            _ => None,
        })
        .collect()
}

fn run_mode(mode: u8, feeds: &[(u8, f64)], cycles: usize) -> (Cell, Vec<CellEvent>) {
    let mut c = two_belt_cell(100.0, 80.0);
    c.set_par(|p| {
        p.tracking_mode = mode;
        p.target_pos = [0.0, 0.0, 120.0, 180.0, 0.0, 180.0, 0.0];
        p.z_target_dist = 30.0;
        p.z_start_dist = 30.0;
        p.gripper_closing_time = 0.05;
        p.gripper_open_time = 0.05;
    });
    for &(b, x) in feeds {
        feed(&mut c, b, x, 0.0);
        c.steps(3);
    }
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(cycles);
    let ev = c.eng.drain_events();
    (c, ev)
}

fn check_hits(c: &Cell, min: usize) {
    let hits = belt_hits(c);
    assert!(hits.len() >= min, "only {} belt hits: {hits:?}", hits.len());
    for (i, n, d) in hits {
        assert!(d <= 0.1, "belt {n} target missed by {d} at trace index {i}");
    }
}

#[test]
fn mode1_static_to_cv1_endless() {
    let (c, ev) = run_mode(1, &[(1, 250.0), (1, 150.0), (1, 50.0)], 6000);
    assert_eq!(c.last().state, TmState::MovePp, "endless");
    let p = pulses(&ev);
    assert!(p.len() >= 4, "{p:?}");
    for (k, kind) in p.iter().enumerate() {
        assert_eq!(
            *kind,
            if k % 2 == 0 {
                GripperEvent::Close
            } else {
                GripperEvent::Open
            },
            "pulse {k}"
        );
    }
    check_hits(&c, 2);
    // Every place leg ends on CV1 (eSetTargetOut 1), every pick leg at the static position.
    assert!(c.trace.iter().any(|s| s.outputs.set_target_out == 1));
    assert!(c.trace.iter().any(|s| s.tcp[0].abs() < 1e-9
        && s.tcp[1].abs() < 1e-9
        && (s.tcp[2] - 120.0).abs() < 1e-9));
}

#[test]
fn mode2_cv1_to_static() {
    let (c, ev) = run_mode(2, &[(1, 250.0), (1, 100.0)], 5000);
    let p = pulses(&ev);
    assert!(
        p.len() >= 3 && p[0] == GripperEvent::Close && p[1] == GripperEvent::Open,
        "{p:?}"
    );
    check_hits(&c, 2);
    let picked = ev
        .iter()
        .filter(|e| {
            matches!(
                e,
                CellEvent::Workpiece {
                    kind: pickplace_engine::belt::WorkpieceEventKind::Picked,
                    ..
                }
            )
        })
        .count();
    assert_eq!(picked, 2);
}

#[test]
fn mode3_cv1_to_cv2() {
    let (c, ev) = run_mode(3, &[(1, 250.0), (2, 300.0), (1, 100.0), (2, 150.0)], 9000);
    check_hits(&c, 3);
    let hits = belt_hits(&c);
    assert_eq!(hits[0].1, 1, "pick on CV1 first");
    assert_eq!(hits[1].1, 2, "place on CV2");
    let placed = ev
        .iter()
        .filter(|e| {
            matches!(
                e,
                CellEvent::Workpiece {
                    belt: 2,
                    kind: pickplace_engine::belt::WorkpieceEventKind::Placed,
                    ..
                }
            )
        })
        .count();
    assert!(placed >= 1);
}

#[test]
fn mode4_cv2_to_cv1() {
    let (c, _) = run_mode(4, &[(2, 300.0), (1, 250.0), (2, 100.0)], 9000);
    let hits = belt_hits(&c);
    check_hits(&c, 3);
    assert_eq!(hits[0].1, 2, "pick on CV2 first");
    assert_eq!(hits[1].1, 1, "place on CV1");
}

#[test]
fn abort_ends_the_endless_mode_after_the_current_leg() {
    let mut c = two_belt_cell(100.0, 80.0);
    c.set_par(|p| {
        p.tracking_mode = 2;
        p.target_pos = [0.0, 0.0, 120.0, 180.0, 0.0, 180.0, 0.0];
        p.gripper_closing_time = 0.05;
        p.gripper_open_time = 0.05;
    });
    feed(&mut c, 1, 250.0, 0.0);
    c.steps(3);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(200);
    assert_eq!(c.last().state, TmState::MovePp);
    c.cmd(PickPlaceCommand::Abort);
    c.until(5000, |s| s.state == TmState::Ready);
    assert!(c.last().outputs.done);
    // The pick leg was completed (with its gripper pulse) before READY.
    let ev = c.eng.drain_events();
    assert_eq!(pulses(&ev), vec![GripperEvent::Close]);
    assert_eq!(belt_hits(&c).len(), 1);
}

#[test]
fn halt_ends_the_endless_mode_immediately() {
    let mut c = two_belt_cell(100.0, 80.0);
    c.set_par(|p| {
        p.tracking_mode = 1;
        p.target_pos = [0.0, 0.0, 120.0, 180.0, 0.0, 180.0, 0.0];
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(20);
    c.cmd(PickPlaceCommand::SetStopInputs(
        pickplace_engine::StopInputs {
            path_halt: Some(true),
            ..Default::default()
        },
    ));
    c.until(2000, |s| s.state == TmState::Stop && !s.outputs.busy);
    assert!(c.last().outputs.path_hold);
}

#[test]
fn mode0_belt_to_belt_same_belt_resynchronises() {
    // §15.4 case 3: two appended belt targets on CV1.
    let mut c = two_belt_cell(100.0, 80.0);
    feed(&mut c, 1, 300.0, -20.0);
    c.steps(3);
    feed(&mut c, 1, 220.0, 20.0);
    c.steps(3);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.steps(50);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    let hits = belt_hits(&c);
    assert_eq!(hits.len(), 2, "{hits:?}");
    for (_, _, d) in &hits {
        assert!(*d <= 0.1, "{hits:?}");
    }
    // Between the two hits the TCP rises to lrZDistBelt above the belt level (110 + 50).
    let top = c.trace[hits[0].0..hits[1].0]
        .iter()
        .map(|s| s.tcp[2])
        .fold(f64::MIN, f64::max);
    assert!(top > 140.0 && top <= 160.0 + 1e-6, "top {top}");
}

#[test]
fn mode0_belt1_to_belt2() {
    // §15.4 case 4: synchronised with CV1, then re-synchronise to CV2.
    let mut c = two_belt_cell(100.0, 60.0);
    feed(&mut c, 1, 260.0, 0.0);
    feed(&mut c, 2, 320.0, 0.0);
    c.steps(3);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.steps(50);
    c.cmd(PickPlaceCommand::Execute { set_target: 2 });
    c.until(6000, |s| s.state == TmState::Ready && s.outputs.done);
    let hits = belt_hits(&c);
    assert_eq!(hits.iter().map(|h| h.1).collect::<Vec<_>>(), vec![1, 2]);
    for (_, _, d) in &hits {
        assert!(*d <= 0.1, "{hits:?}");
    }
    // After the CV2 hit the TCP runs with CV2 (−60 units/s in X).
    let i = hits[1].0 + 5;
    assert_close("vX with CV2", c.trace[i].tcp_velocity[0], -60.0, 0.5);
    assert!(c.trace[hits[0].0..hits[1].0]
        .iter()
        .any(|s| s.outputs.acc_dec_sync));
}

#[test]
fn cv1_to_cv2_with_target_before_lower_limit_waits_at_cv2_park() {
    let mut c = two_belt_cell(100.0, 100.0);
    feed(&mut c, 1, 260.0, 0.0);
    feed(&mut c, 2, 0.0, 0.0);
    c.steps(3);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.steps(50);
    c.cmd(PickPlaceCommand::Execute { set_target: 2 });
    c.until(6000, |s| s.outputs.in_park_pos);
    let s = c.last();
    assert_close("park CV2 X", s.tcp[0], -400.0, 1e-6);
    assert_close("park CV2 Y", s.tcp[1], -500.0, 1e-6);
    assert_eq!(s.state, TmState::MovePp);
    c.until(6000, |s| s.state == TmState::Ready && s.outputs.done);
    let hits = belt_hits(&c);
    assert_eq!(hits.len(), 2);
    for (_, _, d) in &hits {
        assert!(*d <= 0.1, "{hits:?}");
    }
}

#[test]
fn sync_limit_exceeded_lifts_to_park_with_warning_90013() {
    let mut c = two_belt_cell(300.0, 0.0);
    feed(&mut c, 1, 250.0, 0.0);
    c.steps(2);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    assert!(c.last().outputs.synchronised);
    c.until(3000, |s| s.outputs.error_id == 90013);
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.in_park_pos);
    assert_close("park X", c.last().tcp[0], -400.0, 1e-6);
    assert!(c.last().outputs.warning);
}

#[test]
fn stop_all_while_synchronised_is_error_90012() {
    let mut c = two_belt_cell(100.0, 0.0);
    feed(&mut c, 1, 260.0, 0.0);
    c.steps(2);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(3000, |s| s.outputs.in_target);
    c.cmd(PickPlaceCommand::SetStopInputs(
        pickplace_engine::StopInputs {
            stop_all: Some(true),
            ..Default::default()
        },
    ));
    c.until(2000, |s| s.state == TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90012);
    assert_eq!(c.last().tcp_velocity[0], 0.0, "at standstill");
}

#[test]
fn path_stop_while_coupled_ramps_out_and_resume_replans() {
    let mut c = two_belt_cell(100.0, 0.0);
    feed(&mut c, 1, 260.0, 0.0);
    c.steps(2);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(3000, |s| s.outputs.acc_dec_sync);
    c.cmd(PickPlaceCommand::SetStopInputs(
        pickplace_engine::StopInputs {
            path_stop: Some(true),
            ..Default::default()
        },
    ));
    c.until(2000, |s| s.state == TmState::Stop && !s.outputs.busy);
    c.steps(50);
    let v = c.last().tcp_velocity;
    assert!(
        v.iter().all(|x| x.abs() < 1e-9),
        "TCP at rest in MCS: {v:?}"
    );
    c.cmd(PickPlaceCommand::SetStopInputs(
        pickplace_engine::StopInputs {
            path_stop: Some(false),
            ..Default::default()
        },
    ));
    c.step();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    let hits = belt_hits(&c);
    assert_eq!(hits.len(), 1);
    assert!(hits[0].2 <= 0.1, "{hits:?}");
}

#[test]
fn ellipse_with_rotated_belt_falls_back_to_linear_90007() {
    let mut c = two_belt_cell(0.0, 0.0);
    let mut bp = w8_belt();
    bp.conveyor_belt_origin[3] = 5.0;
    c.cmd(PickPlaceCommand::SetBeltParams {
        belt: 1,
        params: bp,
    });
    c.set_par(|p| {
        p.path_mode = 1;
        p.z_dist_elliptical = 50.0;
    });
    feed(&mut c, 1, 300.0, 0.0);
    c.steps(3);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(3000, |s| s.outputs.in_target);
    assert_eq!(c.last().outputs.error_id, 90007);
    assert!(c.last().outputs.warning && !c.last().outputs.error);
}

#[test]
fn close_pulse_at_the_workpiece_attaches_it() {
    // Lead 0: the close pulse comes when the TCP reaches the workpiece on CV1 (mode 2).
    let mut c = two_belt_cell(100.0, 0.0);
    c.set_par(|p| {
        p.tracking_mode = 2;
        p.target_pos = [0.0, 0.0, 120.0, 180.0, 0.0, 180.0, 0.0];
        p.gripper_closing_time = 1e-9;
        p.gripper_open_time = 1e-9;
    });
    feed(&mut c, 1, 250.0, 0.0);
    c.steps(3);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.outputs.pulse_gripper);
    let id = c.trace[c.trace.len() - 2].belts[0].workpieces[0].id;
    assert!(c.last().gripper_closed);
    assert_eq!(c.last().held_workpiece, Some(id));
    c.until(5000, |s| s.outputs.pulse_gripper);
    assert!(!c.last().gripper_closed);
    assert_eq!(
        c.last().held_workpiece,
        None,
        "released at the static place position"
    );
}

#[test]
fn endless_mode_command_completes_only_when_the_loop_ends() {
    use motion_core::CommandState;
    let mut c = two_belt_cell(100.0, 0.0);
    c.set_par(|p| {
        p.tracking_mode = 2;
        p.target_pos = [0.0, 0.0, 120.0, 180.0, 0.0, 180.0, 0.0];
    });
    feed(&mut c, 1, 250.0, 0.0);
    c.steps(3);
    let id = c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.outputs.in_target);
    c.steps(1500);
    assert!(
        !c.events.iter().any(|e| e.id == id && e.state.is_final()),
        "still running after the first legs"
    );
    c.cmd(PickPlaceCommand::Abort);
    c.until(8000, |s| s.state == TmState::Ready);
    let states: Vec<CommandState> = c
        .events
        .iter()
        .filter(|e| e.id == id)
        .map(|e| e.state)
        .collect();
    assert_eq!(
        states,
        vec![CommandState::Busy, CommandState::Active, CommandState::Done]
    );
}
