//! W10 — gearing (§8, §4.12.1, §4.12.3, §2.5) and the transition rows T8, T9, T10, T10b.
use axis_engine::*;
use motion_core::{CmdId, CommandState, Engine, ErrorId, ExecuteOutputs, Rejection, Tick};

const DT: f64 = 0.002;

struct Two {
    e: AxisEngine,
    tick: u64,
    ev: Vec<motion_core::CommandEvent>,
}

impl Two {
    fn new(slave_cfg: AxisConfig) -> Self {
        let mut e = AxisEngine::new(vec![
            ("m".into(), AxisConfig::default()),
            ("s".into(), slave_cfg),
        ])
        .unwrap();
        for n in ["m", "s"] {
            e.command(AxisCommand::Power(Power {
                axis: n.into(),
                enable: true,
                enable_positive: true,
                enable_negative: true,
                override_percent: 100.0,
                buffer_mode: BufferMode::Aborting,
            }))
            .unwrap();
        }
        let mut t = Two {
            e,
            tick: 0,
            ev: vec![],
        };
        t.step();
        t
    }
    fn step(&mut self) {
        self.e.step(
            Tick {
                index: self.tick,
                dt: DT,
            },
            &mut self.ev,
        );
        self.tick += 1;
    }
    fn steps(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }
    fn st(&self, n: &str) -> AxisStatus {
        self.e.status(n).unwrap()
    }
    fn out(&self, id: CmdId) -> ExecuteOutputs {
        self.e.outputs(id).unwrap()
    }
    fn gear_in(&mut self, num: f64, den: u32) -> Result<AxisReply, Rejection> {
        self.e.command(AxisCommand::GearIn(GearIn {
            master: "m".into(),
            slave: "s".into(),
            ratio_numerator: num,
            ratio_denominator: den,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
        }))
    }
    fn mv(&mut self, axis: &str, position: f64, bm: BufferMode) -> Result<AxisReply, Rejection> {
        self.e.command(AxisCommand::MoveAbsolute(MoveAbsolute {
            axis: axis.into(),
            position,
            velocity: 100.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: bm,
            options: MoveOptions::default(),
        }))
    }
    fn vel(&mut self, axis: &str, v: f64) -> CmdId {
        self.e
            .command(AxisCommand::MoveVelocity(MoveVelocity {
                axis: axis.into(),
                velocity: v,
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
                direction: Direction::Positive,
                buffer_mode: BufferMode::Aborting,
                options: MoveOptions::default(),
            }))
            .unwrap()
            .id
    }
    fn until(&mut self, max: usize, f: impl Fn(&Two) -> bool) {
        for _ in 0..max {
            if f(self) {
                return;
            }
            self.step();
        }
        panic!("not reached");
    }
}

fn master_plus_100(num: f64, den: u32) -> f64 {
    let mut t = Two::new(AxisConfig::default());
    let g = t.gear_in(num, den).unwrap().id;
    assert_eq!(
        t.st("s").motion_state,
        MotionState::SynchronizedMotion,
        "T9"
    );
    t.step();
    assert!(t.out(g).done, "InGear the cycle after the edge");
    assert!(!t.out(g).busy && !t.out(g).active);
    let id = t.mv("m", 100.0, BufferMode::Aborting).unwrap().id;
    t.until(10000, |t| t.out(id).done);
    assert_eq!(t.st("s").motion_state, MotionState::SynchronizedMotion);
    assert_eq!(t.st("s").couple_state, 3);
    assert_eq!(t.st("m").couple_state, 1);
    assert!(t.st("s").bit(snapshot::bits::PROTECTED));
    t.st("s").set_pos
}

#[test]
fn ratios() {
    assert!((master_plus_100(1.0, 4) - 25.0).abs() < 1e-9);
    assert!((master_plus_100(0.25, 1) - 25.0).abs() < 1e-9);
    assert!((master_plus_100(-0.25, 1) + 25.0).abs() < 1e-9);
    assert!((master_plus_100(3.0, 2) - 150.0).abs() < 1e-9);
}

#[test]
fn slave_velocity_follows_in_the_same_cycle() {
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(3.0, 2).unwrap();
    t.vel("m", 100.0);
    t.steps(500);
    let (m, s) = (t.st("m"), t.st("s"));
    assert!((m.set_velo - 100.0).abs() < 1e-9);
    assert!((s.set_velo - 150.0).abs() < 1e-9);
    assert!(
        (s.set_pos - 1.5 * m.set_pos).abs() < 1e-9,
        "no one-cycle lag"
    );
}

#[test]
fn denominator_zero_and_moving_master_are_rejected() {
    let mut t = Two::new(AxisConfig::default());
    assert_eq!(t.gear_in(1.0, 0).unwrap_err().error_id, ErrorId(0x4B06));
    t.vel("m", 100.0);
    t.steps(10);
    let e = t.gear_in(1.0, 1).unwrap_err();
    assert_eq!(e.error_id, ErrorId(0x4B05), "{}", e.message);
    assert_eq!(t.st("s").motion_state, MotionState::Standstill);
}

#[test]
fn t10_gear_out_while_moving_keeps_the_velocity_for_ever() {
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(1.5, 1).unwrap();
    t.vel("m", 100.0);
    t.steps(500);
    let g =
        t.e.command(AxisCommand::GearOut(GearOut { slave: "s".into() }))
            .unwrap()
            .id;
    assert_eq!(t.st("s").motion_state, MotionState::ContinuousMotion, "T10");
    t.step();
    assert!(t.out(g).done);
    // The master stops; the slave does not care.
    t.e.command(AxisCommand::Halt(Halt {
        axis: "m".into(),
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }))
    .unwrap();
    t.steps(1000);
    assert_eq!(t.st("m").set_velo, 0.0);
    assert!((t.st("s").set_velo - 150.0).abs() < 1e-9);
    assert_eq!(t.st("s").couple_state, 0);
    let h =
        t.e.command(AxisCommand::Halt(Halt {
            axis: "s".into(),
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }))
        .unwrap()
        .id;
    t.until(5000, |t| t.out(h).done);
}

#[test]
fn t10b_gear_out_at_rest_gives_standstill_and_not_coupled_is_an_error() {
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(1.0, 1).unwrap();
    t.step();
    t.e.command(AxisCommand::GearOut(GearOut { slave: "s".into() }))
        .unwrap();
    assert_eq!(t.st("s").motion_state, MotionState::Standstill);
    let e =
        t.e.command(AxisCommand::GearOut(GearOut { slave: "s".into() }))
            .unwrap_err();
    assert_eq!(e.error_id, ErrorId(0x4B05));
}

#[test]
fn t8_motion_command_on_a_slave() {
    // Parameter FALSE: rejected with 0x4B01, the coupling stays.
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(1.0, 1).unwrap();
    t.step();
    assert_eq!(
        t.mv("s", 50.0, BufferMode::Aborting).unwrap_err().error_id,
        ErrorId(0x4B01)
    );
    assert_eq!(t.st("s").motion_state, MotionState::SynchronizedMotion);
    // Parameter TRUE: only Aborting (else 0x4B05); the slave is decoupled first.
    let mut t = Two::new(AxisConfig {
        allow_motion_cmd_to_slave_axis: true,
        ..Default::default()
    });
    t.gear_in(1.0, 1).unwrap();
    t.step();
    assert_eq!(
        t.mv("s", 50.0, BufferMode::Buffered).unwrap_err().error_id,
        ErrorId(0x4B05)
    );
    let id = t.mv("s", 50.0, BufferMode::Aborting).unwrap().id;
    assert_eq!(t.st("s").motion_state, MotionState::DiscreteMotion, "T8");
    assert_eq!(t.st("s").couple_state, 0);
    t.until(10000, |t| t.out(id).done);
    assert_eq!(t.st("s").set_pos, 50.0);
}

#[test]
fn errors_master_and_slave() {
    // A slave error decouples the slave; the master is unaffected.
    let mut t = Two::new(AxisConfig::default());
    let g = t.gear_in(1.0, 1).unwrap().id;
    let mid = t.vel("m", 100.0);
    t.steps(200);
    t.e.command(AxisCommand::Sim(Sim::InjectAxisError {
        axis: "s".into(),
        error_id: 0x4550,
    }))
    .unwrap();
    assert_eq!(t.st("s").motion_state, MotionState::ErrorStop);
    assert_eq!(t.st("s").couple_state, 0);
    assert!(t.out(mid).active);
    t.until(2000, |t| t.st("s").set_velo == 0.0);
    assert!(t.out(g).done, "InGear result stays until Execute falls");
    // A master error stops the master; its slave keeps following.
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(2.0, 1).unwrap();
    t.vel("m", 100.0);
    t.steps(200);
    t.e.command(AxisCommand::Sim(Sim::InjectAxisError {
        axis: "m".into(),
        error_id: 0x4550,
    }))
    .unwrap();
    t.until(2000, |t| t.st("m").set_velo == 0.0);
    let (m, s) = (t.st("m"), t.st("s"));
    assert_eq!(s.motion_state, MotionState::SynchronizedMotion);
    assert!((s.set_pos - 2.0 * m.set_pos).abs() < 1e-9);
    assert_eq!(s.set_velo, 0.0);
}

#[test]
fn stop_and_reset_on_a_slave() {
    let mut t = Two::new(AxisConfig {
        allow_motion_cmd_to_slave_axis: true,
        ..Default::default()
    });
    t.gear_in(1.0, 1).unwrap();
    t.vel("m", 100.0);
    t.steps(200);
    let s =
        t.e.command(AxisCommand::Stop(Stop {
            axis: "s".into(),
            deceleration: 0.0,
            jerk: 0.0,
            options: MoveOptions::default(),
        }))
        .unwrap()
        .id;
    assert_eq!(t.st("s").motion_state, MotionState::Stopping);
    t.until(2000, |t| t.out(s).done);
    assert_eq!(t.st("s").set_velo, 0.0);
    assert!((t.st("m").set_velo - 100.0).abs() < 1e-9);
    // Reset decouples (slave parameter not needed).
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(1.0, 1).unwrap();
    t.vel("m", 100.0);
    t.steps(200);
    let r =
        t.e.command(AxisCommand::Reset(Reset { axis: "s".into() }))
            .unwrap()
            .id;
    t.until(2000, |t| t.out(r).done);
    assert_eq!(t.st("s").motion_state, MotionState::Standstill);
    assert!(matches!(
        t.ev.iter().rev().find(|e| e.id == r).map(|e| e.state),
        Some(CommandState::Done)
    ));
}

#[test]
fn gearing_bad_inputs() {
    let mut t = Two::new(AxisConfig::default());
    let before = t.st("s");
    assert_eq!(
        t.gear_in(f64::NAN, 1).unwrap_err().error_id,
        ErrorId::NOT_FINITE
    );
    let e =
        t.e.command(AxisCommand::GearIn(GearIn {
            master: "nope".into(),
            slave: "s".into(),
            ratio_numerator: 1.0,
            ratio_denominator: 1,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .unwrap_err();
    assert_eq!(e.error_id, ErrorId::UNKNOWN_OBJECT);
    assert_eq!(t.st("s"), before);
    // No loops.
    t.gear_in(1.0, 1).unwrap();
    t.step();
    let e =
        t.e.command(AxisCommand::GearIn(GearIn {
            master: "s".into(),
            slave: "m".into(),
            ratio_numerator: 1.0,
            ratio_denominator: 1,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .unwrap_err();
    assert_eq!(e.error_id, ErrorId(0x4B06), "{}", e.message);
}

#[test]
fn set_position_on_the_master_does_not_move_the_slave() {
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(2.0, 1).unwrap();
    t.step();
    t.e.command(AxisCommand::SetPosition(SetPosition {
        axis: "m".into(),
        position: 500.0,
        mode: false,
        options: Default::default(),
    }))
    .unwrap();
    t.steps(5);
    assert_eq!(t.st("m").set_pos, 500.0);
    assert_eq!(t.st("s").set_pos, 0.0);
    let id = t.mv("m", 510.0, BufferMode::Aborting).unwrap().id;
    t.until(5000, |t| t.out(id).done);
    assert!((t.st("s").set_pos - 20.0).abs() < 1e-9);
}

fn gear_in_dyn(t: &mut Two, enable: bool, ratio: f64, acc: f64) -> Result<AxisReply, Rejection> {
    t.e.command(AxisCommand::GearInDyn(GearInDyn {
        master: "m".into(),
        slave: "s".into(),
        enable,
        gear_ratio: ratio,
        acceleration: acc,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
    }))
}

/// W10: GearInDyn, master max velocity 2000, Acceleration 1000: a ratio jump 1 → 2 is slewed
/// at 0.5 ratio/s (2 s); the slave acceleration during the slew is 1000 at master velocity
/// 2000 and 250 at 500.
#[test]
fn gear_in_dyn_ratio_slew() {
    for (vm, want_acc) in [(2000.0, 1000.0), (500.0, 250.0)] {
        let mut t = Two::new(AxisConfig::default());
        let g = gear_in_dyn(&mut t, true, 1.0, 1000.0).unwrap().id;
        assert_eq!(t.st("s").motion_state, MotionState::SynchronizedMotion);
        assert!(t.e.fb_outputs(g).unwrap().in_gear);
        t.vel("m", vm);
        t.steps(3000);
        assert!((t.st("s").set_velo - vm).abs() < 1e-6);
        let again = gear_in_dyn(&mut t, true, 2.0, 1000.0).unwrap().id;
        assert_eq!(again, g, "a cyclic update of the same instance");
        t.step();
        assert!(!t.e.fb_outputs(g).unwrap().in_gear, "slewing");
        assert!(
            (t.st("s").set_acc - want_acc).abs() < 1e-6,
            "slave acceleration {}",
            t.st("s").set_acc
        );
        let t0 = t.tick;
        t.until(5000, |t| t.e.fb_outputs(g).unwrap().in_gear);
        let slew = (t.tick - t0 + 1) as f64 * DT;
        assert!((slew - 2.0).abs() <= 2.0 * DT, "slew time {slew}");
        assert!((t.st("s").set_velo - 2.0 * vm).abs() < 1e-6);
        // Enable↓: the command ends (outputs FALSE), the coupling stays with the frozen ratio.
        gear_in_dyn(&mut t, false, 2.0, 1000.0).unwrap();
        assert_eq!(t.out(g), ExecuteOutputs::default());
        assert_eq!(t.st("s").motion_state, MotionState::SynchronizedMotion);
        t.steps(10);
        assert!((t.st("s").set_velo - 2.0 * vm).abs() < 1e-6);
    }
}

#[test]
fn gear_out_while_gear_in_dyn_is_enabled_recouples() {
    let mut t = Two::new(AxisConfig::default());
    let g = gear_in_dyn(&mut t, true, 1.0, 0.0).unwrap().id;
    t.vel("m", 100.0);
    t.steps(300);
    let o =
        t.e.command(AxisCommand::GearOut(GearOut { slave: "s".into() }))
            .unwrap()
            .id;
    t.step();
    assert!(t.out(o).done);
    assert_eq!(t.st("s").motion_state, MotionState::SynchronizedMotion);
    assert!(t.out(g).active);
}

/// AxisGearRatio (3000) reads the coupling ratio while the axis is a coupled slave (§6),
/// and is refused on an uncoupled axis.
#[test]
fn gear_ratio_parameter_on_a_coupled_slave() {
    let mut t = Two::new(AxisConfig::default());
    let read = |t: &mut Two| {
        t.e.command(AxisCommand::ReadParameter(ReadParameter {
            axis: "s".into(),
            parameter_number: 3000,
        }))
    };
    assert!(read(&mut t).is_err(), "not coupled yet");
    t.gear_in(3.0, 2).unwrap();
    t.step();
    match read(&mut t).unwrap().value {
        ReplyValue::Real(r) => assert!((r - 1.5).abs() < 1e-12, "{r}"),
        v => panic!("{v:?}"),
    }
}

/// AxisGearRatio (3000) on a coupled slave (§4.4.8): read gives the ratio; a write applies at
/// once without a jump of the slave (the coupling is re-anchored at the master's current
/// value), the slave then follows with the new ratio; uncoupled, 0 or NaN → refused.
#[test]
fn axis_gear_ratio_written_on_a_coupled_slave() {
    let mut t = Two::new(AxisConfig::default());
    let rw = |t: &mut Two, value: Option<f64>| {
        let c = match value {
            None => AxisCommand::ReadParameter(ReadParameter {
                axis: "s".into(),
                parameter_number: 3000,
            }),
            Some(value) => AxisCommand::WriteParameter(WriteParameter {
                axis: "s".into(),
                parameter_number: 3000,
                value,
            }),
        };
        t.e.command(c)
    };
    // Uncoupled: read and write refused with 0x4B05.
    assert_eq!(rw(&mut t, None).unwrap_err().error_id, ErrorId(0x4B05));
    assert_eq!(rw(&mut t, Some(2.0)).unwrap_err().error_id, ErrorId(0x4B05));
    t.gear_in(1.0, 1).unwrap();
    t.step();
    t.vel("m", 100.0);
    t.until(5000, |t| (t.st("m").set_velo - 100.0).abs() < 1e-9);
    t.steps(10);
    assert!(matches!(rw(&mut t, None).unwrap().value, ReplyValue::Real(r) if r == 1.0));
    let before = t.st("s").set_pos;
    let w = rw(&mut t, Some(2.0)).unwrap().id;
    t.step();
    assert!(t.out(w).done);
    let after = t.st("s").set_pos;
    // One cycle at the new ratio: 2 · 100 · DT, no jump.
    assert!(
        (after - before - 2.0 * 100.0 * DT).abs() < 1e-9,
        "{before} -> {after}"
    );
    t.steps(10);
    assert!((t.st("s").set_velo - 200.0).abs() < 1e-9);
    assert!(matches!(rw(&mut t, None).unwrap().value, ReplyValue::Real(r) if r == 2.0));
    for bad in [0.0, f64::NAN] {
        assert!(rw(&mut t, Some(bad)).is_err(), "{bad}");
    }
    assert!(matches!(rw(&mut t, None).unwrap().value, ReplyValue::Real(r) if r == 2.0));
}

/// Issue 15 item 10: MC_ReadStatus reports the same CoupleState as the state topic (one
/// source): 1 for the gear master, 3 for the slave, in the same cycle.
#[test]
fn read_status_and_the_snapshot_agree_on_couple_state() {
    let mut t = Two::new(AxisConfig::default());
    t.gear_in(1.5, 1).unwrap();
    for _ in 0..5 {
        t.step();
    }
    for (axis, want) in [("m", 1), ("s", 3)] {
        let r =
            t.e.command(AxisCommand::ReadStatus(ReadStatus { axis: axis.into() }))
                .unwrap();
        let ReplyValue::Status(s) = r.value else {
            panic!("{:?}", r.value)
        };
        assert_eq!(s.couple_state, want, "read_status of {axis}");
        assert_eq!(t.st(axis).couple_state, want, "snapshot of {axis}");
    }
}
