//! pick_and_place.md §7.8 (2): the AXIS_REF maxima of the group configuration at the
//! interpolation stage. During a belt pick the belt superposition of §15.1 is added to the path,
//! which planning (§7.8 (1)) does not see; the path is slowed so that no axis exceeds its
//! maximum velocity, acceleration or jerk, the TCP stays on the planned (belt-coupled) geometry
//! and still meets the workpiece (§15.1: ±0.05). An axis that cannot follow at all (belt faster
//! than its maximum) is clamped and, past its `following_error_limit`, raises 90011 (§16).
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{AxisConfig, PickPlaceCommand, PickPlaceSnapshot, TmState};

/// Start pose downstream of the workpiece (the TCP moves +X against the belt, as in W8).
const DOWNSTREAM: [f64; 7] = [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0];
/// Start pose upstream (the TCP moves −X with the belt, so path and belt velocity add up).
const UPSTREAM: [f64; 7] = [450.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0];

fn x_max(vel: f64, acc: f64, jerk: f64) -> AxisConfig {
    AxisConfig {
        max_vel: vel,
        max_acc: acc,
        max_jerk: jerk,
        ..AxisConfig::default()
    }
}

struct Pick {
    cell: Cell,
    /// Largest distance of the TCP from the running leg's belt-coupled path (§15.1).
    deviation: f64,
}

/// W8's pick (workpiece at belt X 210, receive + valid + execute in one cycle) with the TCP at
/// `tcp`, stepped until READY; the path deviation is measured in every cycle of a path phase.
fn pick(velocity: f64, tcp: [f64; 7], axes: &[(&str, AxisConfig)]) -> Pick {
    let mut c = belt_cell_with_axes(velocity, tcp, axes);
    c.cmd(PickPlaceCommand::BeltInput {
        belt: 1,
        receive: true,
        valid_pos: true,
        initial_object_position: [210.0, -50.0, 10.0, 0.0, 0.0, 0.0],
        aux1_target_pos: 0.0,
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    let mut deviation: f64 = 0.0;
    for _ in 0..10_000 {
        let s = c.step().clone();
        let path = c.eng.active_path(4000);
        if path.len() > 1 {
            deviation = deviation.max(distance_to_polyline(&s.tcp, &path));
        }
        if s.state != TmState::MovePp && s.outputs.done || s.state == TmState::Error {
            break;
        }
    }
    Pick { cell: c, deviation }
}

fn distance_to_polyline(p: &[f64; 7], path: &[[f64; 3]]) -> f64 {
    let mut best = f64::MAX;
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
        let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
        let t = if l2 > 0.0 {
            ((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (0..3)
            .map(|i| (ap[i] - t * ab[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        best = best.min(d);
    }
    best
}

/// Largest |v|, |a|, |j| of pose axis `q` over the trace (finite differences of the set-points,
/// what the drive receives).
fn axis_peaks(trace: &[PickPlaceSnapshot], q: usize) -> (f64, f64, f64) {
    let (mut v, mut a, mut j) = (0.0f64, 0.0f64, 0.0f64);
    let x: Vec<f64> = trace.iter().map(|s| s.tcp[q]).collect();
    for i in 3..x.len() {
        let d = |k: usize| (x[k] - x[k - 1]) / TS;
        let dd = |k: usize| (d(k) - d(k - 1)) / TS;
        v = v.max(d(i).abs());
        a = a.max(dd(i).abs());
        j = j.max(((dd(i) - dd(i - 1)) / TS).abs());
    }
    (v, a, j)
}

fn assert_within_maxima(trace: &[PickPlaceSnapshot], q: usize, m: &AxisConfig) {
    let (v, a, j) = axis_peaks(trace, q);
    // Velocity with the spec's tolerance (W5: never above max + 0.05); acceleration and jerk
    // up to the round-off of the finite differences.
    assert!(
        v <= m.max_vel + 0.05,
        "axis {q}: peak velocity {v} > {}",
        m.max_vel
    );
    assert!(
        a <= m.max_acc * (1.0 + 1e-6) + 1e-3,
        "axis {q}: peak acceleration {a} > {}",
        m.max_acc
    );
    assert!(
        j <= m.max_jerk * (1.0 + 1e-6) + 1.0,
        "axis {q}: peak jerk {j} > {}",
        m.max_jerk
    );
}

fn assert_meets_workpiece(c: &Cell) {
    let hits = belt_hits(c);
    assert_eq!(hits.len(), 1, "one belt target reached");
    let (_, belt, d) = hits[0];
    assert_eq!(belt, 1);
    // §15.1: at the end of the lowering |P − X_wp| ≤ 0.05 (noise-free simulation).
    assert!(d <= 0.05, "TCP {d} from the workpiece at xInTarget");
}

#[test]
fn belt_plus_path_speed_above_the_x_maximum_is_slowed_not_exceeded() {
    // Acceleration and jerk maxima high enough for the blend at IP2 (r = 10): slowing the path
    // alone keeps every maximum.
    let m = x_max(450.0, 30_000.0, 1e7);
    for velocity in [100.0, 200.0] {
        // Without the AXIS_REF maxima the sum of path and belt velocity exceeds 450 on X.
        let free = pick(velocity, UPSTREAM, &[]);
        let (v_free, _, _) = axis_peaks(&free.cell.trace, 0);
        assert!(
            v_free > 470.0,
            "belt {velocity}: scenario must need the clamp ({v_free})"
        );
        let limited = pick(velocity, UPSTREAM, &[("x", m)]);
        let c = &limited.cell;
        assert_eq!(c.last().state, TmState::Ready, "belt {velocity}");
        assert!(c.last().outputs.done);
        assert_within_maxima(&c.trace, 0, &m);
        // The geometry is kept: the TCP stays on the belt-coupled path of the leg.
        assert!(
            limited.deviation < 0.01,
            "belt {velocity}: TCP {} off the path",
            limited.deviation
        );
        assert_meets_workpiece(c);
        // Slower than the free run: the path parameter was slowed down.
        let in_target = |c: &Cell| c.trace.iter().position(|s| s.outputs.in_target).unwrap();
        assert!(in_target(c) > in_target(&free.cell), "belt {velocity}");
    }
}

#[test]
fn all_axes_limited_against_the_belt_too() {
    // Downstream start (W8): the coupling blend adds to the +X approach; all Cartesian axes
    // and the real axes A1 … A3 carry maxima (the stricter one applies).
    let m = x_max(420.0, 40_000.0, 2e7);
    let real = x_max(400.0, 30_000.0, 1e7);
    let axes = [("x", m), ("y", m), ("z", m), ("a1", real), ("a3", real)];
    let eff = x_max(400.0, 30_000.0, 1e7);
    for velocity in [50.0, 150.0, 250.0] {
        let p = pick(velocity, DOWNSTREAM, &axes);
        let c = &p.cell;
        assert_eq!(c.last().state, TmState::Ready, "belt {velocity}");
        for q in 0..3 {
            assert_within_maxima(&c.trace, q, &eff);
        }
        assert!(p.deviation < 0.01, "belt {velocity}: {}", p.deviation);
        assert_meets_workpiece(c);
    }
}

#[test]
fn no_clamp_needed_gives_bit_identical_set_points() {
    // Generous maxima that are never reached: the same set-points as without any maximum.
    let generous = x_max(1e4, 1e6, 1e9);
    let axes = [("x", generous), ("y", generous), ("z", generous)];
    for velocity in [0.0, 100.0, 300.0] {
        let free = pick(velocity, DOWNSTREAM, &[]);
        let limited = pick(velocity, DOWNSTREAM, &axes);
        assert_eq!(free.cell.trace.len(), limited.cell.trace.len());
        for (a, b) in free.cell.trace.iter().zip(&limited.cell.trace) {
            assert_eq!(a.tcp, b.tcp, "cycle {}", a.cycle);
            assert_eq!(a.outputs, b.outputs, "cycle {}", a.cycle);
        }
    }
}

#[test]
fn maxima_folded_into_planning_never_clamp_a_static_profile() {
    // W5 with the limits given as AXIS_REF maxima instead of lrXMaxVel/lrYMaxVel: planning
    // (§7.8 (1)) already keeps them, so the set-points equal the TM-parameter run bit for bit.
    let run = |axis_ref: bool| {
        let mut cfg = common_config();
        if axis_ref {
            cfg.axes.insert("x".into(), x_max(20.0, 0.0, 0.0));
            cfg.axes.insert("y".into(), x_max(20.0, 0.0, 0.0));
        }
        let mut c = Cell::ready(cfg);
        c.set_par(|p| {
            p.path_vel = 50.0;
            p.path_acc = 500.0;
            p.path_dec = 500.0;
            p.z_start_dist = 0.0;
            p.z_target_dist = 0.0;
            p.target_pos[0] = 60.0;
            p.target_pos[1] = 80.0;
            p.target_pos[2] = 100.0;
            if !axis_ref {
                p.max_vel[0] = 20.0;
                p.max_vel[1] = 20.0;
            }
        });
        c.cmd(PickPlaceCommand::Execute { set_target: 0 });
        c.until(10_000, |s| s.state == TmState::Ready && s.outputs.done);
        c
    };
    let (tm, ax) = (run(false), run(true));
    assert_eq!(tm.trace.len(), ax.trace.len());
    for (a, b) in tm.trace.iter().zip(&ax.trace) {
        assert_eq!(a.tcp, b.tcp, "cycle {}", a.cycle);
    }
    let (vy, _, _) = axis_peaks(&ax.trace, 1);
    assert_close("peak |vY| (W5)", vy, 20.0, 0.05);
}

#[test]
fn an_axis_slower_than_the_belt_is_clamped_and_reports_90011() {
    // Belt at 500 units/s along −X, X may only do 450: after the coupling the TCP cannot follow
    // the workpiece. The axis is interpolated at its maximum (never above it) …
    let m = x_max(450.0, 8000.0, 2e6);
    let p = pick(500.0, DOWNSTREAM, &[("x", m)]);
    assert_within_maxima(&p.cell.trace, 0, &m);
    // … and with a following-error limit the lost axis is an error (90011 on axis 1, §16).
    let lim = AxisConfig {
        following_error_limit: 1.0,
        ..m
    };
    let p = pick(500.0, DOWNSTREAM, &[("x", lim)]);
    let s = p.cell.last();
    assert_eq!(s.state, TmState::Error);
    assert_eq!(s.outputs.error_id, 90011);
    assert!(s.outputs.error_info[0].error);
    assert_eq!(s.outputs.error_info[0].error_id, 90011);
    // The ERROR stop is the per-axis stop of §16 (alrStopDec), not the AXIS_REF clamp.
    assert!(p
        .cell
        .trace
        .iter()
        .all(|s| s.tcp.iter().all(|x| x.is_finite())));
}

#[test]
fn a_deceleration_the_path_cannot_give_is_clamped_within_the_maxima() {
    // X near its 450 units/s maximum reaches a blend whose curvature asks for more deceleration
    // than X may do: slowing the path cannot help once there (§7.7 plans no curvature
    // slow-down), so X is interpolated at its maximum (§7.8 (2)), leaves the path for a moment
    // and catches up on a braking curve. The maxima hold every cycle, the deviation stays
    // bounded, and the TCP still meets the workpiece (§15.1, ±0.05) and stays on it.
    for (velocity, m, bound) in [
        (100.0, x_max(450.0, 8000.0, 2e6), 10.0),
        (300.0, x_max(450.0, 30_000.0, 1e7), 0.1),
    ] {
        let p = pick(velocity, UPSTREAM, &[("x", m)]);
        let c = &p.cell;
        assert_eq!(c.last().state, TmState::Ready, "belt {velocity}");
        assert_within_maxima(&c.trace, 0, &m);
        assert!(
            p.deviation > 0.01,
            "belt {velocity}: clamp needed ({})",
            p.deviation
        );
        assert!(
            p.deviation < bound,
            "belt {velocity}: deviation {}",
            p.deviation
        );
        assert_meets_workpiece(c);
        let done = c.trace.iter().position(|s| s.outputs.done).unwrap();
        let d = distance_to_workpiece(c, done - 1);
        assert!(
            d <= 0.05,
            "belt {velocity}: {d} from the workpiece at the dwell end"
        );
    }
}

/// Distance of the TCP at trace index `i` from the nearest workpiece on belt 1 (as `belt_hits`).
fn distance_to_workpiece(c: &Cell, i: usize) -> f64 {
    let (a, b) = (&c.trace[i - 1], &c.trace[i]);
    let ds = b.belts[0].position - a.belts[0].position;
    a.belts[0]
        .workpieces
        .iter()
        .map(|w| {
            let p = [w.mcs_position[0] - ds, w.mcs_position[1], w.mcs_position[2]];
            (0..3)
                .map(|k| (p[k] - b.tcp[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(f64::MAX, f64::min)
}
