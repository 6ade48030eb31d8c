//! collision_avoidance.md §8.2 G1/G2 under random traffic: 10 movers on a 3000 mm ring,
//! random targets and dynamics, random hard halts (MC_HaltCA with MAXIMUM deceleration and the
//! maximum jerk) of the leader M1, 10 000 cycles. Seeded (CA_STRESS_SEED, default 1..=3;
//! CA_STRESS_RUNS adds more seeds): deterministic.
//!
//! Asserts every cycle: no pair gap below its effective gap − 1e-6 (all start ≥ gap),
//! |v| ≤ V_max (1 + 1e-5), |a| ≤ A/D_max (1 + 1e-6), |Δa| ≤ J_max·T (1 + 1e-6) for every axis.
//! The Fast runs with unequal axis maxima (every axis its own V/A/D/J maxima) exercise the
//! Fast precondition of §8.6: the follower's deceleration capped by its predecessor's maximum
//! and the sampled C4 when it already brakes harder.

mod ca_common;
use axis_engine::ca::*;
use ca_common::*;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

const VMAX: f64 = 2000.0;
const AMAX: f64 = 20000.0;
const JMAX: f64 = 200000.0;

fn mcl(v: f64) -> McLreal {
    McLreal::Value(v)
}

/// Axis maxima (velocity, acceleration, deceleration, jerk).
type Maxima = (f64, f64, f64, f64);

fn run(seed: u64, mode: DefaultGapControlMode, direction: GapControlDirection) {
    run_with(seed, mode, direction, false)
}

/// `unequal`: every axis gets its own random maxima (V 1000..2000, A and D 5000..20000,
/// J 50 000..200 000); commands and halts ask for up to the common maxima and are clamped.
fn run_with(seed: u64, mode: DefaultGapControlMode, direction: GapControlDirection, unequal: bool) {
    let mut rng = StdRng::seed_from_u64(seed);
    let names: Vec<String> = (1..=10).map(|i| format!("M{i}")).collect();
    let maxima: Vec<Maxima> = (0..10)
        .map(|_| {
            if unequal {
                (
                    rng.gen_range(1000.0..VMAX),
                    rng.gen_range(5000.0..AMAX),
                    rng.gen_range(5000.0..AMAX),
                    rng.gen_range(50000.0..JMAX),
                )
            } else {
                (VMAX, AMAX, AMAX, JMAX)
            }
        })
        .collect();
    let axes: Vec<(String, axis_engine::AxisConfig)> = names
        .iter()
        .zip(&maxima)
        .enumerate()
        .map(|(i, (n, &(v, a, d, j)))| {
            let mut c = axis_engine::ca_bench::ca_axis_config(2700.0 - i as f64 * 300.0);
            c.max_velocity = v;
            c.fast_acceleration = a;
            c.fast_deceleration = d;
            c.fast_jerk = j;
            (n.clone(), c)
        })
        .collect();
    let cfg = CaGroupConfig {
        default_gap_control_mode: mode,
        gap_control_direction: direction,
        ..ring(3000.0)
    };
    let mut r = CaRig::with_axes(&axes, cfg);
    let max_of = |name: &str| maxima[names.iter().position(|n| n == name).unwrap()];
    let mut prev_a = [0.0; 10];
    // G1 floor per CA position: the effective gap, or (after an increase of the effective gap
    // of an axis below it) the previous value until regained or stopped, then never
    // decreasing (§8.2 G1).
    let mut floor = [100.0f64; 10];
    let mut tgt_prev = [100.0f64; 10];
    let mut catching = [false; 10];
    let mut worst = f64::INFINITY;
    let mut moved = 0.0;
    let mut halts = 0;
    let mut reversals = 0;
    let mut unprotected = [false; 10];
    let mut stop_at: Option<usize> = None;
    for cycle in 0..10_000 {
        // Random traffic: on average a new command every 20 cycles, a leader halt every 400.
        if rng.gen_bool(0.05) && stop_at.is_none() {
            let i = rng.gen_range(0..10);
            let jerk = rng.gen_range(1000.0..JMAX);
            let acc = rng.gen_range(100.0..AMAX);
            let dec = rng.gen_range(100.0..AMAX);
            let v = rng.gen_range(50.0..VMAX);
            let gap = if rng.gen_bool(0.5) {
                McLreal::Unset
            } else {
                mcl(rng.gen_range(100.0..140.0))
            };
            let mode = GapControlMode::from_raw(rng.gen_range(0..3)).unwrap();
            let backward = direction == GapControlDirection::Both && rng.gen_bool(0.3);
            // In direction Positive a reverse move is unprotected (§1.5): forward targets lie
            // beyond the axis' stop point with the new command's braking.
            let st = r.axis(&names[i]);
            let reach = planner::stop_point(
                planner::Kin {
                    x: 0.0,
                    v: st.velocity.max(0.0),
                    a: st.acceleration,
                },
                dec.min(maxima[i].2).max(-st.acceleration),
                jerk.min(maxima[i].3),
            ) + 1.0;
            let d = rng.gen_range(reach..reach + 2000.0);
            let d = if backward {
                -rng.gen_range(0.0..2000.0)
            } else {
                d
            };
            let res = if rng.gen_bool(0.5) {
                let target = st.position + d;
                let (position, dir) = if rng.gen_bool(0.5) || backward {
                    (target, CaDirection::NonModulo)
                } else {
                    (target.rem_euclid(3000.0), CaDirection::Positive)
                };
                r.ca(CaCommand::MoveAbsolute(MoveAbsoluteCa {
                    axis: names[i].clone(),
                    position: mcl(position),
                    velocity: mcl(v),
                    acceleration: mcl(acc),
                    deceleration: mcl(dec),
                    jerk: mcl(jerk),
                    gap,
                    direction: dir,
                    gap_control_mode: mode,
                    ..Default::default()
                }))
            } else {
                r.ca(CaCommand::MoveRelative(MoveRelativeCa {
                    axis: names[i].clone(),
                    distance: mcl(d),
                    velocity: mcl(v),
                    acceleration: mcl(acc),
                    deceleration: mcl(dec),
                    jerk: mcl(jerk),
                    gap,
                    gap_control_mode: mode,
                    ..Default::default()
                }))
            };
            res.unwrap_or_else(|e| panic!("seed {seed} cycle {cycle}: rejected {e}"));
        }
        // Group-wide stops now and then: MC_GroupHalt (not locking) and MC_GroupStop (locking,
        // released once the group stands).
        if stop_at.is_none() && rng.gen_bool(0.0008) {
            r.ca(CaCommand::GroupHalt {
                group: G.into(),
                deceleration: McLreal::Unset,
                jerk: McLreal::Unset,
            })
            .unwrap();
        }
        if stop_at.is_none() && rng.gen_bool(0.0004) {
            stop_at = Some(cycle);
            r.ca(CaCommand::GroupStop {
                group: G.into(),
                execute: true,
                deceleration: McLreal::Maximum,
                jerk: McLreal::Unset,
            })
            .unwrap();
        }
        if stop_at.is_some_and(|c| cycle > c + 50) && r.group().all_axes_standing {
            stop_at = None;
            r.ca(CaCommand::GroupStop {
                group: G.into(),
                execute: false,
                deceleration: McLreal::Unset,
                jerk: McLreal::Unset,
            })
            .unwrap();
            r.step();
            assert_eq!(
                r.state(),
                GroupState::GroupStandby,
                "released after the stop"
            );
        }
        if rng.gen_bool(0.0025) && stop_at.is_none() {
            halts += 1;
            r.ca(CaCommand::Halt(HaltCa {
                axis: "M1".into(),
                deceleration: McLreal::Maximum,
                jerk: mcl(JMAX),
                ..Default::default()
            }))
            .unwrap();
        }
        r.step();
        let g = r.group();
        for (k, a) in g.axes.iter().enumerate() {
            let (vmax, amax, dmax, jmax) = max_of(&a.name);
            if a.gap_target < tgt_prev[k] {
                floor[k] = floor[k].min(a.gap_target);
            }
            // Direction Positive: a predecessor moving backward is not limited by this axis
            // (§1.5); the gap is unprotected until this axis, which planned with the old
            // position, has come to rest; afterwards G1 applies from the value then. (Forward
            // targets lie beyond the stop point, but an axis whose deceleration the Fast rule
            // caps at its predecessor's maximum (§8.6) can overshoot its target and return.)
            let p = &g.axes[(k + 9) % 10];
            if direction == GapControlDirection::Positive
                && (p.velocity < 0.0 || (p.velocity == 0.0 && p.acceleration < 0.0))
            {
                reversals += 1;
                unprotected[k] = true;
            }
            if unprotected[k] {
                floor[k] = floor[k].min(a.gap_actual);
                unprotected[k] = a.velocity != 0.0 || a.acceleration != 0.0;
            }
            worst = worst.min(a.gap_actual - floor[k]);
            assert!(
                a.gap_actual >= floor[k] - 1e-6,
                "seed {seed} cycle {cycle}: {} gap {} < {} (target {})",
                a.name,
                a.gap_actual,
                floor[k],
                a.gap_target
            );
            let (gap, tgt) = (a.gap_actual, a.gap_target);
            // The pair is at rest: this axis and its predecessor (reverse motion in Both).
            let p = &g.axes[(k + 9) % 10];
            let standing = a.velocity == 0.0
                && a.acceleration == 0.0
                && p.velocity == 0.0
                && p.acceleration == 0.0;
            if tgt > tgt_prev[k] && (gap < tgt || !standing) {
                // Increase on a moving axis: the previous value stays guaranteed until it stops.
                catching[k] = true;
                floor[k] = floor[k].min(tgt_prev[k]);
            }
            if catching[k] {
                if standing {
                    catching[k] = false;
                    floor[k] = tgt.min(gap);
                }
            } else if gap >= tgt - 1e-6 {
                floor[k] = tgt;
            } else {
                floor[k] = tgt.min(floor[k].max(gap));
            }
            tgt_prev[k] = tgt;
            assert!(
                a.velocity.abs() <= vmax * (1.0 + 1e-5),
                "seed {seed} cycle {cycle}: {} v {} > {vmax}",
                a.name,
                a.velocity
            );
            // Acceleration in the direction of travel, deceleration against it.
            let braking = a.acceleration * a.velocity < 0.0;
            let alim = if braking { dmax } else { amax.max(dmax) };
            assert!(
                a.acceleration.abs() <= alim * (1.0 + 1e-6),
                "seed {seed} cycle {cycle}: {} a {} (v {}) > {alim}",
                a.name,
                a.acceleration,
                a.velocity
            );
            let da = (a.acceleration - prev_a[k]).abs();
            assert!(
                da <= jmax * T * (1.0 + 1e-6),
                "seed {seed} cycle {cycle}: {} jerk {} > {}",
                a.name,
                da / T,
                jmax
            );
            prev_a[k] = a.acceleration;
            moved += a.velocity.abs() * T;
        }
    }
    eprintln!(
        "seed {seed} {mode:?} {direction:?} unequal {unequal}: moved {moved:.0} mm, {halts} leader halts, {reversals} cycles with an unprotected reverse predecessor"
    );
    if !unequal {
        assert_eq!(reversals, 0, "no reverse moves in direction Positive");
    }
    assert!(
        moved > 10_000.0,
        "the traffic really moved the train: {moved} mm"
    );
    assert!(halts > 5, "the leader was halted {halts} times");
    assert!(worst.is_finite());
}

fn seeds() -> Vec<u64> {
    let runs: u64 = std::env::var("CA_STRESS_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    match std::env::var("CA_STRESS_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        Some(s) => vec![s],
        None => (1..=runs).collect(),
    }
}

#[test]
fn standard_positive_random_traffic_never_violates_a_gap() {
    for s in seeds() {
        run(
            s,
            DefaultGapControlMode::Standard,
            GapControlDirection::Positive,
        );
    }
}

#[test]
fn fast_positive_random_traffic_never_violates_a_gap() {
    for s in seeds() {
        run(
            s,
            DefaultGapControlMode::Fast,
            GapControlDirection::Positive,
        );
    }
}

#[test]
fn standard_both_random_traffic_with_reverse_moves_never_violates_a_gap() {
    for s in seeds() {
        run(
            s,
            DefaultGapControlMode::Standard,
            GapControlDirection::Both,
        );
    }
}

#[test]
fn fast_both_random_traffic_with_reverse_moves_never_violates_a_gap() {
    for s in seeds() {
        run(s, DefaultGapControlMode::Fast, GapControlDirection::Both);
    }
}

#[test]
fn fast_both_random_traffic_with_unequal_axis_maxima_never_violates_a_gap() {
    for s in seeds() {
        run_with(
            s,
            DefaultGapControlMode::Fast,
            GapControlDirection::Both,
            true,
        );
    }
}

#[test]
fn fast_positive_random_traffic_with_unequal_axis_maxima_never_violates_a_gap() {
    for s in seeds() {
        run_with(
            s,
            DefaultGapControlMode::Fast,
            GapControlDirection::Positive,
            true,
        );
    }
}
