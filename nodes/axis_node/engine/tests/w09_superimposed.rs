//! W9 — MC_MoveSuperImposed application examples (§8, §4.9).
mod common;
use axis_engine::*;
use common::*;
use motion_core::CommandState;

#[allow(clippy::too_many_arguments)]
fn sup(mode: u32, d: f64, v: f64, a: f64, dec: f64, vp: f64, length: f64) -> AxisCommand {
    AxisCommand::MoveSuperImposed(MoveSuperImposed {
        axis: AX.into(),
        mode: SuperpositionMode::from_raw(mode).unwrap(),
        distance: d,
        velocity_diff: v,
        acceleration: a,
        deceleration: dec,
        jerk: 0.0,
        velocity_process: vp,
        length,
        abort_option: SuperpositionAbortOption::AbortAtStandstill,
    })
}

/// MoveVelocity at `v` until constant; returns (instance, start position, start tick).
fn base_velocity(r: &mut Rig, v: f64) -> motion_core::CmdId {
    let id = r.id(vel(v));
    r.until(5000, |r| r.e.fb_outputs(id).unwrap().in_velocity);
    id
}

#[test]
fn test_form_length_reduction_additive() {
    let mut r = Rig::powered();
    let mv = base_velocity(&mut r, 100.0);
    let (p0, t0) = (r.st().set_pos, r.tick);
    let s = r.id(sup(3, 50.0, 50.0, 500.0, 500.0, 100.0, 1000.0));
    assert!(r.st().bit(snapshot::bits::COMPENSATING));
    let mut peak: f64 = 0.0;
    r.until(5000, |r| {
        peak = peak.max(r.st().set_velo);
        r.out(s).done
    });
    let t = (r.tick - t0) as f64 * DT;
    assert!((t - 1.1).abs() <= 2.0 * DT, "Done after {t} s");
    assert!((peak - 150.0).abs() < 1.0, "peak {peak}");
    let base = p0 + 100.0 * (r.tick - t0) as f64 * DT;
    assert!(
        (r.st().set_pos - base - 50.0).abs() < 1e-6,
        "lead {}",
        r.st().set_pos - base
    );
    let o = r.e.fb_outputs(mv).unwrap();
    assert!(
        o.in_velocity && o.standard.active,
        "MoveVelocity keeps InVelocity"
    );
    let out = r.e.superimposed_outputs(s).unwrap();
    assert!(!out.warning && out.actual_velocity_diff == 50.0 && out.actual_distance == 50.0);
}

#[test]
fn conveyor_gap_correction_limited_motion() {
    let mut r = Rig::powered();
    base_velocity(&mut r, 500.0);
    let (p0, t0) = (r.st().set_pos, r.tick);
    let s = r.id(sup(2, 300.0, 500.0, 1000.0, 1000.0, 500.0, 1000.0));
    r.until(5000, |r| r.out(s).done);
    let t = (r.tick - t0) as f64 * DT;
    assert!((t - 1.4).abs() <= 2.0 * DT, "Done after {t} s");
    let travelled = r.st().set_pos - p0;
    assert!(
        (travelled - 1000.0).abs() <= 500.0 * DT + 1e-6,
        "conveyor 1 travels Length: {travelled}"
    );
    let out = r.e.superimposed_outputs(s).unwrap();
    assert!((out.actual_velocity_diff - 264.1).abs() < 0.05);
    assert!((out.actual_length - 1000.0).abs() < 1e-9);
}

#[test]
fn not_achievable_gives_warning_and_the_largest_distance() {
    let mut r = Rig::powered();
    base_velocity(&mut r, 100.0);
    let (p0, t0) = (r.st().set_pos, r.tick);
    let s = r.id(sup(1, 250.0, 50.0, 500.0, 500.0, 100.0, 100.0));
    r.until(5000, |r| r.out(s).done);
    let out = r.e.superimposed_outputs(s).unwrap();
    assert!(out.warning && out.warning_id == err(0x4243));
    assert!((out.actual_distance - 45.0).abs() < 1e-9);
    let lead = r.st().set_pos - p0 - 100.0 * (r.tick - t0) as f64 * DT;
    assert!((lead - 45.0).abs() < 1e-6, "{lead}");
}

#[test]
fn target_shift_of_a_running_move_absolute() {
    let mut r = Rig::powered();
    let a = r.id(abs(1000.0, 100.0));
    r.steps(200);
    let s = r.id(sup(3, 250.0, 50.0, 500.0, 500.0, 100.0, 1000.0));
    r.until(20000, |r| r.out(a).done);
    assert_eq!(r.state_of(s), Some(CommandState::Done));
    assert!((r.st().set_pos - 1250.0).abs() < 1e-6, "{}", r.st().set_pos);
    assert_eq!(
        r.state_of(a),
        Some(CommandState::Done),
        "MoveAbsolute Done, not aborted"
    );
}

#[test]
fn overlay_aborted_when_the_base_motion_ends_first() {
    let mut r = Rig::powered();
    let a = r.id(abs(100.0, 100.0));
    r.steps(200);
    let s = r.id(sup(2, 50.0, 10.0, 500.0, 500.0, 100.0, 1000.0));
    r.until(20000, |r| r.out(a).done);
    assert!(r.out(s).command_aborted);
    let out = r.e.superimposed_outputs(s).unwrap();
    assert!(
        out.actual_distance > 0.0 && out.actual_distance < 50.0,
        "covered part: {}",
        out.actual_distance
    );
    assert!(
        (r.st().set_pos - 100.0 - out.actual_distance).abs() < 1e-6,
        "offset kept"
    );
}

#[test]
fn abort_superposition_ramps_down_and_keeps_the_offset() {
    let mut r = Rig::powered();
    base_velocity(&mut r, 100.0);
    let (p0, t0) = (r.st().set_pos, r.tick);
    let s = r.id(sup(3, 200.0, 50.0, 500.0, 500.0, 100.0, 10000.0));
    r.steps(500);
    let ab = r.id(AxisCommand::AbortSuperposition(AbortSuperposition {
        axis: AX.into(),
    }));
    assert!(r.out(s).command_aborted);
    assert!(r.out(ab).busy);
    r.until(1000, |r| r.out(ab).done);
    r.step();
    let lead = r.st().set_pos - p0 - 100.0 * (r.tick - t0) as f64 * DT;
    let out = r.e.superimposed_outputs(s).unwrap();
    assert!(
        lead > 0.0 && lead < 200.0 && (lead - out.actual_distance).abs() < 1e-6,
        "lead {lead} vs {}",
        out.actual_distance
    );
    assert!(!r.st().bit(snapshot::bits::COMPENSATING));
    // Nothing active: Done at once.
    let ab2 = r.id(AxisCommand::AbortSuperposition(AbortSuperposition {
        axis: AX.into(),
    }));
    r.step();
    assert!(r.out(ab2).done);
}

#[test]
fn standstill_and_bad_inputs() {
    let mut r = Rig::powered();
    assert_eq!(
        r.cmd(sup(3, 10.0, 50.0, 0.0, 0.0, 100.0, 100.0))
            .unwrap_err()
            .error_id,
        err(0x4B03)
    );
    base_velocity(&mut r, 100.0);
    let before_state = r.st().motion_state;
    assert_eq!(
        r.cmd(sup(3, 10.0, 0.0, 0.0, 0.0, 100.0, 100.0))
            .unwrap_err()
            .error_id,
        err(0x4B06)
    );
    assert_eq!(
        r.cmd(sup(3, 10.0, 5.0, 0.0, 0.0, 0.0, 100.0))
            .unwrap_err()
            .error_id,
        err(0x4B06)
    );
    assert_eq!(
        r.cmd(sup(3, f64::NAN, 5.0, 0.0, 0.0, 10.0, 100.0))
            .unwrap_err()
            .error_id,
        motion_core::ErrorId::NOT_FINITE
    );
    assert!(SuperpositionMode::from_raw(7).is_err() && SuperpositionMode::from_raw(0).is_err());
    assert_eq!(r.st().motion_state, before_state);
    // A new overlay aborts the running one.
    let s1 = r.id(sup(3, 100.0, 50.0, 0.0, 0.0, 100.0, 1000.0));
    r.steps(10);
    let s2 = r.id(sup(3, 10.0, 50.0, 0.0, 0.0, 100.0, 1000.0));
    assert!(r.out(s1).command_aborted);
    r.until(5000, |r| r.out(s2).done);
}
