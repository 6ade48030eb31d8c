//! Seeded random command sequences: no panic, no NaN, outputs exclusive, velocity within the
//! axis maximum, state consistent with the status bits, every admitted command ends or stays
//! busy in a legal way.
mod common;
use axis_engine::*;
use common::*;
use rand::rngs::SmallRng;
use rand::{Rng as _, SeedableRng};

fn random_cmd(g: &mut SmallRng) -> AxisCommand {
    let bm = BufferMode::from_raw(g.gen_range(0..6)).unwrap();
    let v = g.gen_range(1.0..300.0);
    let (a, d, j) = (
        g.gen_range(0.0..3000.0),
        g.gen_range(0.0..3000.0),
        if g.gen_bool(0.2) {
            0.0
        } else {
            g.gen_range(100.0..1e5)
        },
    );
    let opts = if g.gen_bool(0.2) {
        MoveOptions {
            enable_blending_position: true,
            blending_position: g.gen_range(-200.0..200.0),
            ..Default::default()
        }
    } else {
        MoveOptions::default()
    };
    match g.gen_range(0..16) {
        0 | 1 => AxisCommand::MoveAbsolute(MoveAbsolute {
            axis: AX.into(),
            position: g.gen_range(-200.0..200.0),
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
            buffer_mode: bm,
            options: opts,
        }),
        2 => AxisCommand::MoveRelative(MoveRelative {
            axis: AX.into(),
            distance: g.gen_range(-50.0..50.0),
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
            buffer_mode: bm,
            options: opts,
        }),
        3 => AxisCommand::MoveAdditive(MoveAdditive {
            axis: AX.into(),
            distance: g.gen_range(-50.0..50.0),
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
            buffer_mode: bm,
            options: opts,
        }),
        4 => AxisCommand::MoveVelocity(MoveVelocity {
            axis: AX.into(),
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
            direction: if g.gen_bool(0.5) {
                Direction::Positive
            } else {
                Direction::Negative
            },
            buffer_mode: bm,
            options: opts,
        }),
        5 => AxisCommand::MoveModulo(MoveModulo {
            axis: AX.into(),
            position: g.gen_range(0.0..720.0),
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
            direction: Direction::from_raw(g.gen_range(1..4)).unwrap(),
            buffer_mode: bm,
            options: opts,
        }),
        6 => halt(g.gen_range(0.0..3000.0), 0.0, bm),
        7 => stop(g.gen_range(0.0..3000.0), 0.0),
        8 => reset(),
        9 => AxisCommand::Power(Power {
            axis: AX.into(),
            enable: g.gen_bool(0.9),
            enable_positive: g.gen_bool(0.9),
            enable_negative: g.gen_bool(0.9),
            override_percent: [0.0, 50.0, 100.0][g.gen_range(0..3)],
            buffer_mode: bm,
        }),
        10 => inject(0x4550),
        12 => AxisCommand::MoveContinuousAbsolute(MoveContinuousAbsolute {
            axis: AX.into(),
            position: g.gen_range(-200.0..200.0),
            velocity: v,
            end_velocity: g.gen_range(0.0..100.0),
            acceleration: a,
            deceleration: d,
            jerk: j,
            buffer_mode: bm,
            options: opts,
        }),
        13 => AxisCommand::SetOverride(SetOverride {
            axis: AX.into(),
            enable: g.gen_bool(0.5),
            vel_factor: g.gen_range(0.0..1.0),
            acc_factor: 1.0,
            jerk_factor: 1.0,
        }),
        14 => AxisCommand::MoveSuperImposed(MoveSuperImposed {
            axis: AX.into(),
            mode: SuperpositionMode::from_raw(g.gen_range(1..7)).unwrap(),
            distance: g.gen_range(-50.0..50.0),
            velocity_diff: g.gen_range(1.0..100.0),
            acceleration: a,
            deceleration: d,
            jerk: 0.0,
            velocity_process: g.gen_range(1.0..200.0),
            length: g.gen_range(0.0..500.0),
            abort_option: SuperpositionAbortOption::from_raw(g.gen_range(0..3)).unwrap(),
        }),
        15 => AxisCommand::TorqueControl(TorqueControl {
            axis: AX.into(),
            continuous_update: false,
            relative: g.gen_bool(0.3),
            torque: g.gen_range(-50.0..50.0),
            torque_ramp: g.gen_range(1.0..100.0),
            velocity_limit_high: g.gen_range(0.0..300.0),
            velocity_limit_low: g.gen_range(-300.0..0.0),
            buffer_mode: BufferMode::Aborting,
            options: TorqueControlOptions::default(),
        }),
        _ => AxisCommand::Jog(Jog {
            axis: AX.into(),
            jog_forward: g.gen_bool(0.5),
            jog_backwards: true,
            mode: JogMode::from_raw(g.gen_range(0..5)).unwrap(),
            position: g.gen_range(0.1..20.0),
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
        }),
    }
}

#[test]
fn random_sequences_keep_the_invariants() {
    for seed in 0..40u64 {
        let mut g = SmallRng::seed_from_u64(seed);
        let mut r = Rig::powered();
        let mut ids = vec![];
        for step in 0..3000 {
            if g.gen_bool(0.02) {
                if let Ok(rep) = r.cmd(random_cmd(&mut g)) {
                    ids.push(rep.id);
                }
            }
            if g.gen_bool(0.01) && !ids.is_empty() {
                let id = ids[g.gen_range(0..ids.len())];
                let _ = r.cmd(execute(id, false));
            }
            r.step();
            let st = r.st();
            for x in [
                st.set_pos,
                st.set_velo,
                st.set_acc,
                st.act_pos,
                st.target_pos,
            ] {
                assert!(x.is_finite(), "seed {seed} step {step}: {st:?}");
            }
            assert!(
                st.set_velo.abs() <= 2000.0 + 1e-6,
                "seed {seed} step {step}: {}",
                st.set_velo
            );
            assert_eq!(st.has_job, st.bit(snapshot::bits::HAS_JOB));
            if st.motion_state == MotionState::Standstill {
                assert!(
                    !st.has_job,
                    "seed {seed} step {step}: Standstill with a job"
                );
            }
            if st.motion_state == MotionState::Disabled {
                assert_eq!(st.set_velo, 0.0);
            }
            for &id in &ids {
                if let Some(o) = r.e.outputs(id) {
                    let is_stop = matches!(r.e.instance(id), Some((_, FbKind::Stop)));
                    assert_exclusive(&o, is_stop);
                }
            }
        }
    }
}
