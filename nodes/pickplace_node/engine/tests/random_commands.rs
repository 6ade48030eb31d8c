//! Robustness: seeded random command sequences (including NaN, ∞, out-of-range enums and
//! unconfigured belts) never panic, keep every published value finite, and bad input is
//! rejected with an id instead of changing the state. `PICKPLACE_FUZZ_CASES` (default 20).
mod common;
use common::*;
use motion_core::Engine;
use pickplace_engine::{PickPlaceCommand, StopInputs};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

fn value(rng: &mut SmallRng) -> f64 {
    match rng.gen_range(0..12) {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1.0,
        3 => 0.0,
        _ => rng.gen_range(-300.0..600.0),
    }
}

#[test]
fn random_command_sequences_never_panic() {
    let cases: u64 = std::env::var("PICKPLACE_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20);
    for seed in 0..cases {
        let mut rng = SmallRng::seed_from_u64(seed);
        let mut c = two_belt_cell(rng.gen_range(0.0..300.0), rng.gen_range(0.0..300.0));
        for _ in 0..40 {
            let cmd = match rng.gen_range(0..16) {
                0 => PickPlaceCommand::Execute {
                    set_target: rng.gen_range(0..8),
                },
                1 => PickPlaceCommand::SetStopInputs(StopInputs {
                    path_stop: Some(rng.gen_bool(0.2)),
                    path_halt: Some(rng.gen_bool(0.2)),
                    stop_all: Some(rng.gen_bool(0.1)),
                    path_interrupt: Some(rng.gen_bool(0.2)),
                }),
                2 => PickPlaceCommand::Abort,
                3 => PickPlaceCommand::ResetError,
                4 => PickPlaceCommand::SetOverride(value(&mut rng)),
                5 => PickPlaceCommand::Jog {
                    select_axis: rng.gen_range(0..15),
                    jog_pos: rng.gen_bool(0.5),
                    jog_neg: rng.gen_bool(0.3),
                },
                6 => PickPlaceCommand::DetectWorkpiece {
                    belt: rng.gen_range(0..4),
                    position: [value(&mut rng), value(&mut rng), 0.0, 0.0, 0.0, 0.0],
                    valid_delay_cycles: rng.gen_range(0..5),
                },
                7 => {
                    let mut p = c.eng.params().clone();
                    p.target_pos[0] = value(&mut rng);
                    p.target_pos[2] = value(&mut rng);
                    p.path_mode = rng.gen_range(0..3);
                    p.z_dist_elliptical = value(&mut rng);
                    p.blending_radius = value(&mut rng);
                    p.tracking_mode = rng.gen_range(0..6);
                    p.target_coord_system = rng.gen_range(0..20);
                    PickPlaceCommand::SetParams(Box::new(p))
                }
                8 => PickPlaceCommand::SetEnable(rng.gen_bool(0.9)),
                9 => PickPlaceCommand::SetRegulatorOn(rng.gen_bool(0.9)),
                10 => PickPlaceCommand::GroupHome,
                11 => PickPlaceCommand::AckGripper,
                12 => PickPlaceCommand::SimSetBeltVelocity {
                    belt: rng.gen_range(0..4),
                    velocity: value(&mut rng),
                    acceleration: value(&mut rng),
                },
                13 => PickPlaceCommand::SimInjectFault {
                    axis: rng.gen_range(0..15),
                    kind: pickplace_engine::FaultKind::DriveFault,
                },
                14 => {
                    let mut bp = w8_belt();
                    bp.z_dist_belt = value(&mut rng);
                    bp.lower_sync_limit = value(&mut rng);
                    PickPlaceCommand::SetBeltParams {
                        belt: rng.gen_range(0..18),
                        params: bp,
                    }
                }
                _ => PickPlaceCommand::Execute { set_target: 0 },
            };
            let before = c.eng.snapshot().state;
            if let Err(r) = c.eng.command(cmd) {
                assert!(r.error_id.0 != 0 && !r.message.is_empty());
                assert_eq!(
                    c.eng.snapshot().state,
                    before,
                    "a rejection does not change the state"
                );
            }
            for _ in 0..rng.gen_range(1..400) {
                let s = c.step();
                assert!(
                    s.tcp
                        .iter()
                        .chain(s.tcp_velocity.iter())
                        .all(|x| x.is_finite()),
                    "seed {seed}: {:?}",
                    s.tcp
                );
                assert!(s.outputs.act_pos.iter().all(|x| x.is_finite()));
            }
        }
    }
}
