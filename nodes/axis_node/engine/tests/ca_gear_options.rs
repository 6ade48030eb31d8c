//! MC_GearInPosCA options (collision_avoidance.md §5.5.2) and the Late start point (§5.5.3):
//! DirectionReversalAllowed, MinimalSlavePosition, MasterVelocityUndershoot/OvershootAllowed,
//! SlaveSyncPositionReferenceSystem, DynamicsReferenceSystem, MasterSignalCorrection; Late
//! starts at the latest point of the 1 mm master grid and arrives in sync within its dynamics.
//! Setting as §10.9: master "MA" outside the group cruising at 500 mm/s, at 0 when the
//! command is issued, MasterSyncPosition 1000 (t = 2.0 s); sync V 1500, A = D 10000, J 100000.

mod ca_common;
use axis_engine::ca::geometry::*;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::{CmdId, CommandState, Engine};

const TPL: u32 = 0x0101_0010;

fn rig_on(cfg: CaGroupConfig, slave: f64) -> CaRig {
    gear_rig(cfg, slave)
}

fn rig() -> CaRig {
    rig_on(open(100000.0), 0.0)
}

/// A ring with the §3.4 starter-kit geometry and one template (y = 100).
fn ring_with_template() -> CaGroupConfig {
    CaGroupConfig {
        geometry: CaGeometry {
            mover_templates: vec![MoverTemplate {
                oid: TPL,
                y_shift: 100.0,
                active: true,
            }],
            ..Default::default()
        },
        ..ring(3000.0)
    }
}

/// MC_GearInPosCA to `s* = ssp + (m − 1000)`.
fn base(ssp: f64, strategy: SyncStrategy) -> GearInPosCa {
    GearInPosCa {
        master: "MA".into(),
        slave: "S".into(),
        ratio_denumerator: 1,
        master_sync_position: McLreal::Value(1000.0),
        slave_sync_position: McLreal::Value(ssp),
        sync_strategy: strategy,
        velocity: McLreal::Value(1500.0),
        acceleration: McLreal::Value(10000.0),
        deceleration: McLreal::Value(10000.0),
        jerk: McLreal::Value(100000.0),
        ..Default::default()
    }
}

/// What the slave did during the sync phase (until the first InSync or `cycles`).
#[derive(Debug, Default)]
struct Trace {
    min_v: f64,
    max_v: f64,
    min_x: f64,
    /// Lowest velocity after the slave first reached 500 mm/s.
    min_v_after_500: f64,
    max_abs_a: f64,
    max_jerk: f64,
    start_sync: Option<usize>,
    in_sync: Option<usize>,
    master_at_start: f64,
}

fn trace(r: &mut CaRig, id: CmdId, cycles: usize) -> Trace {
    let mut t = Trace {
        min_v_after_500: f64::INFINITY,
        min_x: f64::INFINITY,
        ..Default::default()
    };
    let mut reached = false;
    let mut prev_a = r.axis("S").acceleration;
    for k in 1..=cycles {
        r.step();
        let Some(o) = r.e.ca_groups().gear_outputs(id) else {
            break;
        };
        let a = r.axis("S");
        if o.start_sync && t.start_sync.is_none() {
            t.start_sync = Some(k);
            t.master_at_start = r.e.status("MA").unwrap().set_pos;
        }
        if o.in_sync {
            t.in_sync = Some(k);
            break;
        }
        t.min_v = t.min_v.min(a.velocity);
        t.max_v = t.max_v.max(a.velocity);
        t.min_x = t.min_x.min(a.position);
        reached |= a.velocity >= 500.0 - 1e-9;
        if reached {
            t.min_v_after_500 = t.min_v_after_500.min(a.velocity);
        }
        t.max_abs_a = t.max_abs_a.max(a.acceleration.abs());
        t.max_jerk = t.max_jerk.max((a.acceleration - prev_a).abs() / T);
        prev_a = a.acceleration;
    }
    t
}

fn coupled_error(r: &CaRig, ssp: f64) -> f64 {
    let m = r.e.status("MA").unwrap().set_pos;
    r.pos("S") - (ssp + m - 1000.0)
}

#[test]
fn direction_reversal_forbidden_keeps_the_slave_moving_forward() {
    // Slave at 0, s* = m − 200 starts 200 mm behind it: Early lets the slave back up first.
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(base(800.0, SyncStrategy::Early)));
    let free = trace(&mut r, id, 3000);
    assert!(
        free.min_v < -1.0,
        "reference: Early reverses ({})",
        free.min_v
    );
    assert!(free.in_sync.is_some());

    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        forbid_direction_reversal: true,
        ..base(800.0, SyncStrategy::Early)
    }));
    let t = trace(&mut r, id, 3000);
    assert!(t.min_v >= -1e-9, "never backward: {}", t.min_v);
    assert!(t.in_sync.is_some(), "still synchronises: {t:?}");
    assert!(coupled_error(&r, 800.0).abs() < 1e-6);
    assert!(t.max_jerk <= 100000.0 * (1.0 + 1e-6), "{t:?}");
}

#[test]
fn minimal_slave_position_bounds_the_sync_phase() {
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(base(800.0, SyncStrategy::Early)));
    let free = trace(&mut r, id, 3000);
    assert!(
        free.min_x < -20.0,
        "reference: Early backs up to {}",
        free.min_x
    );

    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        minimal_slave_position: McLreal::Value(-20.0),
        ..base(800.0, SyncStrategy::Early)
    }));
    let t = trace(&mut r, id, 3000);
    assert!(t.min_x >= -20.0 - 1e-6, "never below −20: {}", t.min_x);
    assert!(t.min_x < -19.0, "uses the room down to −20: {}", t.min_x);
    assert!(t.in_sync.is_some(), "still synchronises: {t:?}");
    assert!(coupled_error(&r, 800.0).abs() < 1e-6);
    assert!(t.max_jerk <= 100000.0 * (1.0 + 1e-6), "{t:?}");
    assert!(t.max_abs_a <= 10000.0 * (1.0 + 1e-6), "{t:?}");
}

#[test]
fn undershoot_forbidden_never_drops_below_the_sync_velocity_once_reached() {
    // The slave is ahead of s* = m − 200: it could only sync by running slower than the
    // master. With undershoot forbidden Early keeps trying (no error, never InSync).
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        forbid_master_velocity_undershoot: true,
        ..base(800.0, SyncStrategy::Early)
    }));
    let t = trace(&mut r, id, 3000);
    assert!(
        t.min_v >= -1e-9,
        "a slower slave accelerates first: {}",
        t.min_v
    );
    assert!(
        t.min_v_after_500 >= 500.0 - 1e-6,
        "not below 500 once reached: {t:?}"
    );
    assert_eq!(t.in_sync, None);
    assert_eq!(r.cmd_state(id), CommandState::Active, "Early never errors");
    // Behind its target (s* = m + 400) the slave may overtake as usual and syncs.
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        forbid_master_velocity_undershoot: true,
        ..base(1400.0, SyncStrategy::Early)
    }));
    let t = trace(&mut r, id, 3000);
    assert!(t.in_sync.is_some());
    assert!(t.min_v_after_500 >= 500.0 - 1e-6, "{t:?}");
}

#[test]
fn overshoot_forbidden_never_exceeds_the_sync_velocity() {
    // Ahead of its target the slave syncs from the front, never faster than the master.
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        forbid_master_velocity_overshoot: true,
        ..base(800.0, SyncStrategy::Early)
    }));
    let t = trace(&mut r, id, 3000);
    assert!(t.max_v <= 500.0 + 1e-6, "{t:?}");
    assert!(t.in_sync.is_some(), "{t:?}");
    assert!(coupled_error(&r, 800.0).abs() < 1e-6);
    // Behind it (s* = m + 400) it can never catch up: Early keeps trying.
    let mut r = rig();
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        forbid_master_velocity_overshoot: true,
        ..base(1400.0, SyncStrategy::Early)
    }));
    let t = trace(&mut r, id, 3000);
    assert!(t.max_v <= 500.0 + 1e-6, "{t:?}");
    assert_eq!(t.in_sync, None);
    assert_eq!(r.cmd_state(id), CommandState::Active);
}

#[test]
fn restrictions_that_make_a_cam_impossible_are_slave_cannot_sync() {
    // s* = m + 400: 1400 mm in 1000 mm of master travel needs more than the master's velocity.
    for strategy in [SyncStrategy::Slow, SyncStrategy::Late] {
        let mut r = rig();
        let id = r.ok(CaCommand::GearInPos(GearInPosCa {
            forbid_master_velocity_overshoot: true,
            ..base(1400.0, strategy)
        }));
        r.until(3000, |r| r.cmd_state(id) != CommandState::Active);
        assert_eq!(
            r.cmd_state(id),
            CommandState::Error(SLAVE_CANNOT_SYNC),
            "{strategy:?}"
        );
        // MinimalSlavePosition above the current position.
        let mut r = rig();
        let id = r.ok(CaCommand::GearInPos(GearInPosCa {
            minimal_slave_position: McLreal::Value(10.0),
            ..base(1400.0, strategy)
        }));
        r.until(3000, |r| r.cmd_state(id) != CommandState::Active);
        assert_eq!(
            r.cmd_state(id),
            CommandState::Error(SLAVE_CANNOT_SYNC),
            "{strategy:?}: MinimalSlavePosition 10 with the slave at 0"
        );
    }
    // The same restrictions a cam can keep: Slow and Late sync at t = 2.0 s.
    for strategy in [SyncStrategy::Slow, SyncStrategy::Late] {
        let mut r = rig();
        let id = r.ok(CaCommand::GearInPos(GearInPosCa {
            forbid_direction_reversal: true,
            forbid_master_velocity_undershoot: true,
            minimal_slave_position: McLreal::Value(0.0),
            ..base(1400.0, strategy)
        }));
        let t = trace(&mut r, id, 3000);
        assert!(t.min_v >= -1e-9 && t.min_x >= -1e-6, "{strategy:?}: {t:?}");
        assert!(t.min_v_after_500 >= 500.0 - 1e-6, "{strategy:?}: {t:?}");
        let at = t.in_sync.expect("InSync") as f64 * T;
        assert!((at - 2.0).abs() <= 0.0035, "{strategy:?}: InSync at {at}");
    }
}

#[test]
fn late_starts_at_the_latest_grid_point_and_arrives_in_sync_within_its_dynamics() {
    let mut r = rig();
    let m_cmd = r.e.status("MA").unwrap().set_pos;
    let id = r.ok(CaCommand::GearInPos(base(1400.0, SyncStrategy::Late)));
    let t = trace(&mut r, id, 3000);
    let k_start = t.start_sync.expect("StartSync");
    let k_sync = t.in_sync.expect("InSync");
    // Arrival: the cycle in which the master passes 1000, on the coupled law.
    let m = r.e.status("MA").unwrap().set_pos;
    assert!(
        (1000.0..1000.5 + 1e-9).contains(&m),
        "InSync as the master passes 1000: {m}"
    );
    assert!(coupled_error(&r, 1400.0).abs() < 1e-6);
    assert!(((k_sync as f64) * T - (1000.0 - m_cmd) / 500.0).abs() <= 1.5 * T);
    // Within the sync dynamics (§8.2 tolerances) ...
    assert!(t.max_v <= 1500.0 * (1.0 + 1e-5), "{t:?}");
    assert!(t.max_abs_a <= 10000.0 * (1.0 + 1e-6), "{t:?}");
    assert!(t.max_jerk <= 100000.0 * (1.0 + 1e-6), "{t:?}");
    // ... and as late as possible: one grid step (1 mm) later would exceed a limit, so the
    // profile uses a limit nearly to the full.
    let used = (t.max_v / 1500.0)
        .max(t.max_abs_a / 10000.0)
        .max(t.max_jerk / 100000.0);
    assert!(used > 0.99, "a limit is nearly exhausted: {used} ({t:?})");
    // The start point lies on the grid 1000 − k mm, passed in the StartSync cycle.
    let before = t.master_at_start - 0.5;
    let k = (1000.0 - before).floor();
    assert!(
        1000.0 - k > before - 1e-9 && 1000.0 - k <= t.master_at_start + 1e-9,
        "grid point {} passed in the StartSync cycle (master {})",
        1000.0 - k,
        t.master_at_start
    );
    assert!(k_start > 2, "Late does not start at once");
}

#[test]
fn option_validation() {
    let mut r = rig_on(ring_with_template(), 0.0);
    for bad in [
        McLreal::Value(f64::NAN),
        McLreal::Value(f64::INFINITY),
        McLreal::Default,
        McLreal::Maximum,
    ] {
        let c = GearInPosCa {
            minimal_slave_position: bad,
            ..base(1400.0, SyncStrategy::Early)
        };
        assert_eq!(
            r.err(CaCommand::GearInPos(c)),
            INVALID_SYNC_OPTIONS,
            "{bad:?}"
        );
    }
    // Template OIDs must be registered for the slave (§7.2 COMPENSATION_ERROR).
    for c in [
        GearInPosCa {
            slave_sync_position_reference_system: TPL,
            ..base(1400.0, SyncStrategy::Early)
        },
        GearInPosCa {
            dynamics_reference_system: TPL,
            ..base(1400.0, SyncStrategy::Early)
        },
        GearInPosCa {
            dynamics_reference_system: 0x4711,
            ..base(1400.0, SyncStrategy::Early)
        },
    ] {
        assert_eq!(r.err(CaCommand::GearInPos(c)), COMPENSATION_ERROR);
    }
    assert_eq!(
        MasterSignalCorrection::from_raw(2).unwrap_err().error_id,
        INVALID_MODE
    );
    // A modulo SlaveSyncPosition on the offset path must lie within one offset lap.
    r.ok(CaCommand::RegisterCompensation {
        axis: "S".into(),
        compensation_type: 1,
        compensation_id: TPL,
    });
    let c = GearInPosCa {
        slave_sync_position_reference_system: TPL,
        sync_mode: SyncMode::Positive,
        ..base(3700.0, SyncStrategy::Early)
    };
    assert_eq!(r.err(CaCommand::GearInPos(c)), INVALID_TARGET_POSITION);
}

#[test]
fn master_signal_correction_none_behaves_like_auto() {
    let run = |msc| {
        let mut r = rig();
        let id = r.ok(CaCommand::GearInPos(GearInPosCa {
            master_signal_correction: msc,
            ..base(1400.0, SyncStrategy::Late)
        }));
        (0..2500)
            .map(|_| {
                r.step();
                (r.pos("S"), r.e.ca_groups().gear_outputs(id))
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(
        run(MasterSignalCorrection::Auto),
        run(MasterSignalCorrection::None)
    );
}

fn registered(slave: f64) -> CaRig {
    let mut r = rig_on(ring_with_template(), slave);
    r.ok(CaCommand::RegisterCompensation {
        axis: "S".into(),
        compensation_type: 1,
        compensation_id: TPL,
    });
    r
}

#[test]
fn slave_sync_position_on_the_offset_path() {
    // §10.8: offset 1407.080 is motor 1250, so s* = 1250 + (m − 1000) on the motor path.
    let mut r = registered(0.0);
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        slave_sync_position_reference_system: TPL,
        ..base(1407.080, SyncStrategy::Early)
    }));
    r.until(3000, |r| r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
    assert!(
        coupled_error(&r, 1250.0).abs() < 1e-3,
        "{}",
        coupled_error(&r, 1250.0)
    );
    // Modulo: the next occurrence of offset 1407.080 (motor 1250) in positive direction.
    let mut r = registered(1300.0);
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        slave_sync_position_reference_system: TPL,
        sync_mode: SyncMode::Positive,
        ..base(1407.080, SyncStrategy::Early)
    }));
    r.until(3000, |r| r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
    assert!(
        coupled_error(&r, 4250.0).abs() < 1e-3,
        "{}",
        coupled_error(&r, 4250.0)
    );
}

#[test]
fn dynamics_reference_system_couples_on_the_offset_path() {
    // s*_offset = Σ(1400) + (m − 1000): in the curve [1000, 1500) the TCP runs with the
    // master (500 mm/s), the motor slower by the curve slope.
    let geo = ring_with_template().geometry;
    let off = |x: f64| geo.to_offset(3000.0, 100.0, x);
    let slope = (500.0 + std::f64::consts::PI * 100.0) / 500.0;
    let mut r = registered(0.0);
    let id = r.ok(CaCommand::GearInPos(GearInPosCa {
        dynamics_reference_system: TPL,
        ..base(1400.0, SyncStrategy::Early)
    }));
    r.until(3000, |r| r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
    let (mut straight, mut curve) = (false, false);
    for _ in 0..3000 {
        r.step();
        assert!(r.e.ca_groups().gear_outputs(id).unwrap().in_sync);
        let m = r.e.status("MA").unwrap().set_pos;
        let a = r.axis("S");
        assert!(
            (off(a.position) - (off(1400.0) + m - 1000.0)).abs() < 1e-6,
            "coupled on the offset path at {}",
            a.position
        );
        if (1050.0..1450.0).contains(&a.position) {
            assert!((a.velocity - 500.0 / slope).abs() < 1e-6, "{}", a.velocity);
            curve = true;
        }
        if (1550.0..2450.0).contains(&a.position) {
            assert!((a.velocity - 500.0).abs() < 1e-6, "{}", a.velocity);
            straight = true;
        }
    }
    assert!(straight && curve);
}

/// Early with a master that changes its velocity during the sync phase (§5.5.3: Early works
/// "on any master"; the restrictions of §5.5.2 refer to the master's current velocity): the
/// master ramps from 500 to 900 mm/s at 300 mm/s² right after the command. Undershoot
/// forbidden: once the slave has reached the master's velocity it never falls below the
/// master's current velocity; overshoot forbidden (slave ahead of s*): never faster than the
/// master. Both synchronise, within the sync dynamics.
#[test]
fn restrictions_follow_an_accelerating_master() {
    let speed_up = |r: &mut CaRig| {
        r.e.command(master_velocity(900.0, 300.0)).unwrap();
    };
    for (ssp, undershoot) in [(1400.0, true), (800.0, false)] {
        let mut r = rig();
        let id = r.ok(CaCommand::GearInPos(GearInPosCa {
            forbid_master_velocity_undershoot: undershoot,
            forbid_master_velocity_overshoot: !undershoot,
            ..base(ssp, SyncStrategy::Early)
        }));
        speed_up(&mut r);
        let mut reached = false;
        let mut synced = None;
        let mut prev_a = r.axis("S").acceleration;
        for k in 1..=6000 {
            r.step();
            let o = r.e.ca_groups().gear_outputs(id).expect("coupling");
            let a = r.axis("S");
            let mv = r.e.status("MA").unwrap().set_velo;
            if undershoot {
                reached |= a.velocity >= mv - 1e-9;
                if reached {
                    assert!(
                        a.velocity >= mv - 1e-6,
                        "cycle {k}: slave {} < master {mv}",
                        a.velocity
                    );
                }
            } else {
                assert!(
                    a.velocity <= mv + 1e-6,
                    "cycle {k}: slave {} > master {mv}",
                    a.velocity
                );
            }
            assert!(
                a.acceleration.abs() <= 10000.0 * (1.0 + 1e-6),
                "cycle {k}: {a:?}"
            );
            assert!(
                (a.acceleration - prev_a).abs() / T <= 100000.0 * (1.0 + 1e-6),
                "cycle {k}: jerk {} -> {} (master v {mv}, in_sync {}, start {})",
                prev_a,
                a.acceleration,
                o.in_sync,
                o.start_sync
            );
            prev_a = a.acceleration;
            if o.in_sync {
                synced = Some(k);
                break;
            }
        }
        assert!(synced.is_some(), "ssp {ssp}: never InSync");
        assert!(coupled_error(&r, ssp).abs() < 1e-3, "ssp {ssp}");
        let mv = r.e.status("MA").unwrap().set_velo;
        assert!(
            mv > 500.0,
            "the master was still accelerating or faster: {mv}"
        );
    }
}
