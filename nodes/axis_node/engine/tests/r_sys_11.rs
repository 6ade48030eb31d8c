//! plcopen_platform.md §11 in `isg_mcp` (linear axis 0 of §13, µm units, 1 ms):
//! R-SYS-1 — an enabled software limit is a travel limit monitored every cycle (not on modulo
//! axes): crossing it raises MC error 91001 (reaction class 2) and the axis brakes with the
//! limit deceleration `a_limit` (not the standard one), so it overshoots the limit by the
//! braking distance v²/(2a) + v·a/(2j) (from constant velocity, jerk = fast jerk).
//! R-SYS-2 — a discrete motion (MC_MoveRelative) aborting fast continuous motion: a modulo
//! axis keeps the target noted at the abort and brakes over as many revolutions as needed,
//! then positions on it modulo (never reversing); a linear axis overshoots by the full
//! braking distance and travels back.
mod p4rig;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;
use std::collections::BTreeMap;

const LIMIT: f64 = 100_000.0;

fn platform(modulo: bool, a_limit: f64, kind: AxisKind) -> PlatformConfig {
    let mut axes = BTreeMap::new();
    axes.insert(
        A0.to_string(),
        AxisPlatformConfig {
            modulo,
            a_limit,
            kind,
            vb_monitor: 1e7,
            ..AxisPlatformConfig::default()
        },
    );
    PlatformConfig {
        axes,
        ..PlatformConfig::default()
    }
}

/// `isg_mcp`, axis 0 with its max software limit enabled at `limit`, powered.
fn rig_at(pc: PlatformConfig, modulo_value: f64, limit: f64) -> P4 {
    let cfg = EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        platform: pc,
        ..EngineConfig::default()
    };
    let axis = AxisConfig {
        en_max_soft_pos_limit: true,
        max_soft_pos_limit: limit,
        modulo_value,
        ..a0_cfg()
    };
    let mut r = P4::build(vec![(A0.into(), axis)], cfg);
    r.steps(10);
    r.power(A0, true).unwrap();
    r.step();
    r
}

/// `rig_at` with the limit at 100 mm.
fn rig(pc: PlatformConfig, modulo_value: f64) -> P4 {
    rig_at(pc, modulo_value, LIMIT)
}

/// Runs MoveVelocity 200 mm/s into the limit; returns (set position when 91001 was raised,
/// final position at rest, braking cycles).
fn run_into_the_limit(r: &mut P4) -> (f64, f64, u64) {
    let id = r.id(vel(A0, 200_000.0));
    r.until(2000, |r| r.a0().error_code != 0);
    let p1 = r.a0().set_pos;
    let t1 = r.tick;
    assert_eq!(r.a0().error_code, 91001);
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    // The FB of the axis ends with ErrorID 1 (§7.2).
    assert!(r.out(id).error);
    assert_eq!(r.out(id).error_id, ErrorId(1));
    let m = &r.messages(A0)[0];
    assert_eq!((m.error_id, m.reaktions_klasse), (91001, 2));
    r.until(1000, |r| r.a0().set_velo == 0.0);
    (p1, r.a0().set_pos, r.tick - t1)
}

#[test]
fn r_sys_1_crossing_the_limit_brakes_with_a_limit_and_raises_91001() {
    let mut r = rig(platform(false, 2e6, AxisKind::Linear), 360.0);
    let (p1, end, n) = run_into_the_limit(&mut r);
    // Detected in the first cycle beyond the limit (200 µm per cycle at speed).
    assert!(p1 > LIMIT && p1 <= LIMIT + 200.0 + 1e-6, "{p1}");
    // Braking from 200 000 µm/s with a_limit = 2e6 and the fast jerk 1e9 of axis 0.
    let (v, a, j) = (200_000.0, 2e6, 1e9);
    let d = v * v / (2.0 * a) + v * a / (2.0 * j);
    assert!((end - (p1 + d)).abs() < 1e-3, "end {end} vs {}", p1 + d);
    assert!((d - 10_200.0).abs() < 1e-9);
    // Duration v/a + a/j = 0.102 s.
    assert!((n as f64 * DT - 0.102).abs() <= 0.002, "{n} cycles");
}

#[test]
fn r_sys_1_default_limit_deceleration_is_the_fast_deceleration() {
    // a_limit 0 → fast_deceleration (5e6 for axis 0): 4000 + 500 µm.
    let mut r = rig(platform(false, 0.0, AxisKind::Linear), 360.0);
    let (p1, end, _) = run_into_the_limit(&mut r);
    assert!((end - (p1 + 4500.0)).abs() < 1e-3, "{}", end - p1);
}

#[test]
fn r_sys_1_after_reset_only_motion_back_inside_is_possible() {
    let mut r = rig(platform(false, 2e6, AxisKind::Linear), 360.0);
    let (_, end, _) = run_into_the_limit(&mut r);
    assert!(end > LIMIT);
    let reset = r.id(AxisCommand::Reset(Reset { axis: A0.into() }));
    r.steps(5);
    assert!(r.out(reset).done);
    assert_eq!(r.a0().motion_state, MotionState::Standstill);
    // Further out: the target is refused (outside the limits).
    assert!(r.cmd(abs(A0, end + 1000.0, 10_000.0)).is_err());
    // Back inside: fine, no error on the way.
    let back = r.id(abs(A0, 50_000.0, 100_000.0));
    r.until(3000, |r| r.out(back).done);
    assert_eq!(r.a0().error_code, 0);
    assert_eq!(r.a0().set_pos, 50_000.0);
}

#[test]
fn r_sys_1_is_not_effective_on_modulo_axes_nor_in_tc2_mc2() {
    // Modulo axis: runs through the limit (not monitored, not planned), and a target beyond
    // it is accepted.
    let mut r = rig(platform(true, 2e6, AxisKind::Rotary), 360_000.0);
    r.id(vel(A0, 200_000.0));
    r.steps(800);
    assert!(r.a0().set_pos > LIMIT + 10_000.0);
    assert_eq!(r.a0().error_code, 0);
    assert!(r.cmd(abs(A0, 3.0 * LIMIT, 100_000.0)).is_ok());
    // tc2_mc2: the endless motion is planned to stop exactly at the limit (§1.3, 0x4D02).
    let axis = AxisConfig {
        en_max_soft_pos_limit: true,
        max_soft_pos_limit: LIMIT,
        ..a0_cfg()
    };
    let mut r = P4::build(vec![(A0.into(), axis)], EngineConfig::default());
    r.power(A0, true).unwrap();
    r.step();
    let id = r.id(vel(A0, 200_000.0));
    r.until(3000, |r| r.out(id).error);
    r.until(1000, |r| r.a0().set_velo == 0.0);
    assert_eq!(r.a0().set_pos, LIMIT);
    assert_eq!(r.out(id).error_id, ErrorId(0x4D02));
}

/// MoveVelocity at `v`, then MoveRelative(`dist`) with deceleration 1e6 and jerk 1e8;
/// returns (position at the abort, highest position, lowest velocity, final position).
fn abort_fast_motion(r: &mut P4, v: f64, dist: f64) -> (f64, f64, f64, f64) {
    r.id(vel(A0, v));
    r.until(3000, |r| (r.a0().set_velo - v).abs() < 1e-6);
    r.steps(5);
    let p0 = r.a0().set_pos;
    let id = r.id(rel_full(A0, dist, v, 1e6, 1e6, 1e8));
    let (mut hi, mut vmin) = (p0, f64::INFINITY);
    r.until(20_000, |r| {
        let s = r.a0();
        hi = hi.max(s.set_pos);
        vmin = vmin.min(s.set_velo);
        r.out(id).done
    });
    assert_eq!(r.a0().error_code, 0);
    (p0, hi, vmin, r.a0().set_pos)
}

#[test]
fn r_sys_2_modulo_axis_brakes_over_revolutions_onto_the_target() {
    // Rotary modulo axis, period 360 000 u (360° at 1000 u/°), 1 000 000 u/s: the braking
    // distance 1e6²/(2·1e6) + 1e6·1e6/(2·1e8) = 505 000 u is more than one revolution.
    let period = 360_000.0;
    let mut r = rig(platform(true, 0.0, AxisKind::Rotary), period);
    let (p0, _, vmin, end) = abort_fast_motion(&mut r, 1e6, 90_000.0);
    let target = p0 + 90_000.0;
    let brake = 505_000.0;
    let k = ((brake - 90_000.0) / period).ceil();
    assert_eq!(k, 2.0);
    assert!((end - (target + k * period)).abs() < 1e-3, "end {end}");
    assert!(
        ((end - target) / period - k).abs() < 1e-9,
        "on the target modulo"
    );
    assert!(vmin >= -1e-9, "never reverses: {vmin}");
}

#[test]
fn r_sys_2_linear_axis_overshoots_and_travels_back() {
    // 200 000 µm/s; braking distance 20 000 + 1 000 µm; target 5 000 µm ahead.
    let mut r = rig_at(platform(false, 0.0, AxisKind::Linear), 360.0, 1e9);
    let (p0, hi, vmin, end) = abort_fast_motion(&mut r, 200_000.0, 5_000.0);
    assert!((hi - (p0 + 21_000.0)).abs() < 1.0, "overshoot {}", hi - p0);
    assert!(vmin < 0.0, "travels back");
    assert!((end - (p0 + 5_000.0)).abs() < 1e-6, "end {}", end - p0);
}
