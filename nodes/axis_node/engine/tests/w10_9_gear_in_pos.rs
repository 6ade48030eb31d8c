//! collision_avoidance.md §10.9 "Gear ratio and sync strategies" (MC_GearInPosCA, §5.5):
//! master cruising at 500 mm/s, at 0 when the command is issued, MasterSyncPosition 1000
//! (t = 2.0 s); slave at rest at 0, SlaveSyncPosition 1400, ratio 1 ⇒ s* = m + 400; sync
//! V 1500, A = D = 10000, J = 100000.

mod ca_common;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use axis_engine::AxisCommand;
use ca_common::*;
use motion_core::{CmdId, CommandState, Engine};

/// Master "MA" outside the group, slave "S" the only group axis (open rail).
fn rig() -> CaRig {
    rig_on(open(100000.0), 0.0)
}

fn rig_on(cfg: CaGroupConfig, slave: f64) -> CaRig {
    gear_rig(cfg, slave)
}

fn gear(r: &mut CaRig, strategy: SyncStrategy, ratio: f64) -> CmdId {
    r.ok(CaCommand::GearInPos(GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_numerator: McLreal::Value(ratio),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(1400.0),
        sync_strategy: strategy,
        velocity: McLreal::Value(1500.0),
        acceleration: McLreal::Value(10000.0),
        deceleration: McLreal::Value(10000.0),
        jerk: McLreal::Value(100000.0),
        ..Default::default()
    }))
}

/// (first StartSync [s], first InSync [s], peak |a| [mm/s²]); checks s = m + 400 after sync.
fn run(strategy: SyncStrategy) -> (f64, f64, f64) {
    let mut r = rig();
    let m_at_cmd = r.e.status("MA").unwrap().set_pos;
    let id = gear(&mut r, strategy, 1.0);
    let (mut start, mut sync, mut peak) = (None, None, 0.0f64);
    let (mut prev_a, mut max_jerk) = (0.0, 0.0f64);
    for k in 1..=3000 {
        r.step();
        let o = r.e.ca_groups().gear_outputs(id).unwrap();
        let t = k as f64 * T;
        if o.start_sync && start.is_none() {
            start = Some(t);
        }
        if o.in_sync && sync.is_none() {
            sync = Some(t);
        }
        peak = peak.max(r.axis("S").acceleration.abs());
        let a = r.axis("S").acceleration;
        max_jerk = max_jerk.max((a - prev_a).abs() / T);
        prev_a = a;
        if o.in_sync {
            let m = r.e.status("MA").unwrap().set_pos;
            assert!(
                (r.pos("S") - (m + 400.0)).abs() < 1e-6,
                "coupled: s = m + 400"
            );
        }
    }
    assert!(m_at_cmd.abs() < 0.5);
    eprintln!("{strategy:?}: max jerk {max_jerk:.0}, peak acc {peak:.0}");
    assert!(
        max_jerk <= 100000.0 * (1.0 + 1e-6),
        "{strategy:?}: sync jerk {max_jerk} > 100000"
    );
    assert_eq!(
        r.cmd_state(id),
        CommandState::Active,
        "no Done: the coupling lasts"
    );
    (
        start.unwrap_or(f64::NAN),
        sync.expect("InSync reached"),
        peak,
    )
}

#[test]
fn early_syncs_well_before_the_master_sync_position() {
    let (start, sync, _) = run(SyncStrategy::Early);
    assert!(start <= 2.0 * T, "StartSync at once: {start}");
    assert!(sync < 1.8, "InSync well before 2.0 s: {sync}");
}

#[test]
fn slow_and_late_sync_when_the_master_reaches_its_sync_position() {
    let (s_start, s_sync, s_peak) = run(SyncStrategy::Slow);
    let (l_start, l_sync, l_peak) = run(SyncStrategy::Late);
    assert!(s_start <= 2.0 * T, "Slow starts at once: {s_start}");
    assert!(
        (s_sync - 2.0).abs() <= 2.0 * T + 0.0015,
        "Slow InSync at 2.0 s: {s_sync}"
    );
    assert!(l_start > 2.0 * T, "Late starts later: {l_start}");
    assert!(
        (l_sync - 2.0).abs() <= 2.0 * T + 0.0015,
        "Late InSync at 2.0 s: {l_sync}"
    );
    assert!(
        s_peak < l_peak,
        "Slow has lower peak dynamics: {s_peak} vs {l_peak}"
    );
}

#[test]
fn ratio_0_8_slave_runs_at_0_8_master_velocity() {
    let mut r = rig();
    let id = gear(&mut r, SyncStrategy::Early, 0.8);
    r.until(3000, |r| r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
    r.steps(10);
    assert!(
        (r.axis("S").velocity - 400.0).abs() < 1e-6,
        "0.8 × 500: {}",
        r.axis("S").velocity
    );
}

#[test]
fn gear_validation() {
    let mut r = rig();
    let base = GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(1400.0),
        velocity: McLreal::Value(1500.0),
        ..Default::default()
    };
    let cases = [
        (
            GearInPosCa {
                ratio_denumerator: 0,
                ..base.clone()
            },
            PARAMETER_NOT_CORRECT,
        ),
        (
            GearInPosCa {
                master: "S".into(),
                ..base.clone()
            },
            PARAMETER_NOT_CORRECT,
        ),
        (
            GearInPosCa {
                master: "zz".into(),
                ..base.clone()
            },
            AXIS_NOT_IN_GROUP,
        ),
        (
            GearInPosCa {
                master_sync_position: McLreal::Unset,
                ..base.clone()
            },
            INVALID_TARGET_POSITION,
        ),
        (
            GearInPosCa {
                velocity: McLreal::Unset,
                ..base.clone()
            },
            INVALID_VELOCITY,
        ),
    ];
    for (c, id) in cases {
        assert_eq!(r.err(CaCommand::GearInPos(c)), id);
    }
    // Decoupled by another command with BufferMode Aborting.
    let g = r.ok(CaCommand::GearInPos(GearInPosCa {
        sync_strategy: SyncStrategy::Early,
        ..base
    }));
    r.steps(100);
    r.mv_rel("S", 10.0, 100.0);
    r.step();
    assert_eq!(r.cmd_state(g), CommandState::Aborted);
}

#[test]
fn master_start_distance_delays_the_start() {
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(1400.0),
        master_start_distance: McLreal::Value(500.0),
        sync_strategy: SyncStrategy::Early,
        velocity: McLreal::Value(1500.0),
        ..Default::default()
    }));
    let mut start = None;
    for k in 1..=3000 {
        r.step();
        if start.is_none() && r.e.ca_groups().gear_outputs(id).unwrap().start_sync {
            start = Some(k as f64 * T);
        }
    }
    let start = start.expect("started");
    assert!(
        (start - 1.0).abs() <= 3.0 * T,
        "starts when the master passes 500 (t = 1.0 s): {start}"
    );
    assert!(r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
}

#[test]
fn sync_options_and_sync_mode_validation() {
    let mut r = rig();
    let base = GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(1400.0),
        velocity: McLreal::Value(1500.0),
        ..Default::default()
    };
    let both = GearInPosCa {
        forbid_master_velocity_undershoot: true,
        forbid_master_velocity_overshoot: true,
        ..base.clone()
    };
    assert_eq!(r.err(CaCommand::GearInPos(both)), INVALID_SYNC_OPTIONS);
    let modulo = GearInPosCa {
        sync_mode: SyncMode::Positive,
        ..base.clone()
    };
    assert_eq!(
        r.err(CaCommand::GearInPos(modulo)),
        MODULO_ON_OPEN_RAIL,
        "open rail"
    );
    let bad = GearInPosCa {
        master_start_distance: McLreal::Value(f64::NAN),
        ..base
    };
    assert_eq!(r.err(CaCommand::GearInPos(bad)), PARAMETER_NOT_CORRECT);
    assert_eq!(SyncMode::from_raw(2).unwrap_err().error_id, INVALID_MODE);
    assert_eq!(
        SyncStrategy::from_raw(0).unwrap_err().error_id,
        INVALID_MODE
    );
}

#[test]
fn sync_mode_positive_takes_the_next_occurrence_on_a_ring() {
    let mut r = rig_on(ring(3000.0), 2900.0);
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(100.0),
        sync_mode: SyncMode::Positive,
        sync_strategy: SyncStrategy::Early,
        velocity: McLreal::Value(1500.0),
        ..Default::default()
    }));
    r.until(3000, |r| r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
    let m = r.e.status("MA").unwrap().set_pos;
    assert!(
        (r.pos("S") - (3100.0 + m - 1000.0)).abs() < 1e-6,
        "s* = 3100 + (m − 1000)"
    );
}

fn accelerate_master(r: &mut CaRig) {
    r.e.command(master_velocity(1500.0, 10000.0)).unwrap();
}

fn late(r: &mut CaRig, override_restrictions: bool) -> CmdId {
    r.ok(CaCommand::GearInPos(GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(1400.0),
        sync_strategy: SyncStrategy::Late,
        velocity: McLreal::Value(1500.0),
        acceleration: McLreal::Value(10000.0),
        deceleration: McLreal::Value(10000.0),
        jerk: McLreal::Value(100000.0),
        override_slave_dynamic_restrictions: override_restrictions,
        ..Default::default()
    }))
}

#[test]
fn late_master_accelerating_during_sync_is_slave_cannot_sync() {
    let mut r = rig();
    let id = late(&mut r, false);
    r.until(3000, |r| {
        r.e.ca_groups().gear_outputs(id).unwrap().start_sync
    });
    accelerate_master(&mut r);
    r.until(3000, |r| r.cmd_state(id) != CommandState::Active);
    assert_eq!(r.cmd_state(id), CommandState::Error(SLAVE_CANNOT_SYNC));
}

#[test]
fn late_with_override_slave_dynamic_restrictions_keeps_the_cam() {
    let mut r = rig();
    let id = late(&mut r, true);
    r.until(3000, |r| {
        r.e.ca_groups().gear_outputs(id).unwrap().start_sync
    });
    accelerate_master(&mut r);
    r.until(3000, |r| r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
    assert_eq!(r.cmd_state(id), CommandState::Active);
    let m = r.e.status("MA").unwrap().set_pos;
    assert!((r.pos("S") - (m + 400.0)).abs() < 1e-6);
}

#[test]
fn after_sync_velocity_limits_the_coupled_slave() {
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(1400.0),
        sync_strategy: SyncStrategy::Early,
        velocity: McLreal::Value(1500.0),
        after_sync_velocity: McLreal::Value(600.0),
        ..Default::default()
    }));
    r.until(3000, |r| r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
    accelerate_master(&mut r);
    let mut dropped = false;
    for _ in 0..1000 {
        r.step();
        let o = r.e.ca_groups().gear_outputs(id).unwrap();
        dropped |= !o.in_sync;
        // §8.2 G2: velocity within the limit, relative tolerance 1e-5.
        assert!(
            r.axis("S").velocity <= 600.0 * (1.0 + 1e-5),
            "v {}",
            r.axis("S").velocity
        );
    }
    assert!(
        dropped,
        "InSync drops when the master outruns the after-sync velocity"
    );
    assert_eq!(
        r.cmd_state(id),
        CommandState::Active,
        "keeps trying (no Done, no Error)"
    );
}

/// For the ROS shell (no direct engine access): `ReadFbOutputs` of a CA instance answers with
/// `CaValue::Outputs` (standard outputs + StartSync/InSync), and the group snapshot shows the
/// slave's StartSync/InSync; both agree with `gear_outputs`.
#[test]
fn read_fb_outputs_and_snapshot_show_start_sync_and_in_sync() {
    let mut r = rig();
    let id = gear(&mut r, SyncStrategy::Early, 1.0);
    let read = |r: &mut CaRig| match r.e.command(AxisCommand::ReadFbOutputs { id }) {
        Ok(axis_engine::AxisReply {
            value: axis_engine::ReplyValue::Ca(v),
            tracked: false,
            ..
        }) => match *v {
            CaValue::Outputs { outputs, gear } => (outputs, gear),
            other => panic!("unexpected value {other:?}"),
        },
        other => panic!("unexpected reply {other:?}"),
    };
    let (mut saw_start, mut saw_sync) = (false, false);
    for _ in 0..3000 {
        r.step();
        let (o, g) = read(&mut r);
        assert!(o.busy && o.active && !o.done);
        let g = g.expect("running coupling");
        assert_eq!(Some(g), r.e.ca_groups().gear_outputs(id));
        let s = r.axis("S");
        assert_eq!((s.start_sync, s.in_sync), (g.start_sync, g.in_sync));
        saw_start |= g.start_sync;
        saw_sync |= g.in_sync;
        if saw_sync {
            break;
        }
    }
    assert!(saw_start && saw_sync, "StartSync then InSync seen");
    // After the coupling ends: CommandAborted, no gear outputs, flags cleared.
    r.ok(CaCommand::Halt(HaltCa {
        axis: "S".into(),
        ..Default::default()
    }));
    r.step();
    let (o, g) = read(&mut r);
    assert!(o.command_aborted && !o.busy);
    assert_eq!(g, None);
    assert!(!r.axis("S").in_sync && !r.axis("S").start_sync);
}
