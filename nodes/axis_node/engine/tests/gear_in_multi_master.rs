//! §4.12.4 MC_GearInMultiMaster: superposition of up to four masters, Enable-type calls,
//! AdvancedSlaveDynamics with VELOSYNC / POSSYNC1 / POSSYNC2, T9 and T9b (§2.2), phasing on
//! ASD couplings, bad input. The spec has no worked example for this FB; the numbers follow
//! from its model (`v_slave = Σ GearRatio_i·v_master_i`).
mod rig3;
use axis_engine::*;
use motion_core::ErrorId;
use rig3::*;

fn three() -> Axes {
    Axes::new(&["m1", "m2", "s"], AxisConfig::default())
}

#[test]
fn slave_is_the_superposition_of_the_masters() {
    let mut t = three();
    let id = t.id(AxisCommand::GearInMultiMaster(multi(
        "s",
        ["m1", "m2", "", ""],
        [1.0, 0.5, 0.0, 0.0],
        false,
    )));
    assert_eq!(
        t.st("s").motion_state,
        MotionState::SynchronizedMotion,
        "T9"
    );
    assert!(t.fb(id).in_gear && t.out(id).busy && t.out(id).active);
    assert_eq!(t.st("m1").couple_state, 1);
    assert_eq!(t.st("m2").couple_state, 1);
    assert_eq!(t.st("s").couple_state, 3);
    assert_eq!(t.ext("s").masters, vec!["m1".to_string(), "m2".to_string()]);
    let a = t.mv("m1", 100.0, 100.0);
    let b = t.mv("m2", 40.0, 100.0);
    t.steps(300);
    // Same cycle: velocities add up.
    let v = t.st("m1").set_velo + 0.5 * t.st("m2").set_velo;
    assert!((t.st("s").set_velo - v).abs() < 1e-9);
    t.until(10000, |t| t.out(a).done && t.out(b).done);
    assert!(
        (t.st("s").set_pos - 120.0).abs() < 1e-9,
        "{}",
        t.st("s").set_pos
    );
}

#[test]
fn enable_false_freezes_the_ratios_and_keeps_the_coupling() {
    let mut t = three();
    let mut c = multi("s", ["m1", "", "", ""], [2.0, 0.0, 0.0, 0.0], false);
    let id = t.id(AxisCommand::GearInMultiMaster(c.clone()));
    // Cyclic ratio change: slewed at Acceleration / master max velocity = 1000/2000 = 0.5/s.
    c.gear_ratio1 = 3.0;
    assert_eq!(
        t.id(AxisCommand::GearInMultiMaster(c.clone())),
        id,
        "same instance"
    );
    t.step();
    assert!(!t.fb(id).in_gear, "ratio still slewing");
    t.steps(1000); // 2 s
    assert!(t.fb(id).in_gear);
    c.enable = false;
    t.id(AxisCommand::GearInMultiMaster(c));
    let o = t.out(id);
    assert!(!o.busy && !o.active, "{o:?}");
    assert_eq!(
        t.st("s").motion_state,
        MotionState::SynchronizedMotion,
        "stays coupled"
    );
    let m = t.mv("m1", 10.0, 100.0);
    t.until(5000, |t| t.out(m).done);
    assert!((t.st("s").set_pos - 30.0).abs() < 1e-9, "frozen ratio 3");
    // GearOut now decouples for good.
    let g = t.gear_out("s");
    t.step();
    assert!(t.out(g).done);
    assert_eq!(t.st("s").motion_state, MotionState::Standstill);
}

#[test]
fn gear_out_while_enabled_only_decouples_briefly() {
    let mut t = three();
    let id = t.id(AxisCommand::GearInMultiMaster(multi(
        "s",
        ["m1", "", "", ""],
        [1.0, 0.0, 0.0, 0.0],
        false,
    )));
    let g = t.gear_out("s");
    t.step();
    assert!(t.out(g).done);
    assert_eq!(t.st("s").motion_state, MotionState::SynchronizedMotion);
    assert!(t.out(id).busy);
}

#[test]
fn without_asd_moving_masters_and_moving_slaves_are_rejected() {
    let mut t = three();
    t.vel("m2", 50.0);
    t.step();
    t.rejects(
        AxisCommand::GearInMultiMaster(multi(
            "s",
            ["m1", "m2", "", ""],
            [1.0, 1.0, 0.0, 0.0],
            false,
        )),
        0x4B05,
    );
    let mut u = three();
    u.vel("s", 50.0);
    u.step();
    u.rejects(
        AxisCommand::GearInMultiMaster(multi("s", ["m1", "", "", ""], [1.0, 0.0, 0.0, 0.0], false)),
        0x4B01,
    );
}

#[test]
fn t9b_asd_velosync_couples_a_moving_slave_onto_moving_masters() {
    let mut t = three();
    t.vel("m1", 100.0);
    t.vel("m2", 100.0);
    t.vel("s", 20.0);
    t.steps(500);
    assert_eq!(t.st("s").motion_state, MotionState::ContinuousMotion);
    let id = t.id(AxisCommand::GearInMultiMaster(multi(
        "s",
        ["m1", "m2", "", ""],
        [1.0, 0.5, 0.0, 0.0],
        true,
    )));
    assert_eq!(
        t.st("s").motion_state,
        MotionState::SynchronizedMotion,
        "T9b"
    );
    assert!(!t.fb(id).in_gear);
    let n = t.until(5000, |t| t.fb(id).in_gear);
    assert!(n > 10, "synchronizing takes time with AxisAcc 1000");
    let mut prev = t.st("s").set_velo;
    for _ in 0..100 {
        t.step();
        let v = t.st("s").set_velo;
        assert!((v - prev).abs() <= 1000.0 * DT + 1e-9);
        prev = v;
    }
    assert!((t.st("s").set_velo - 150.0).abs() < 1e-6);
}

#[test]
fn possync2_catches_up_the_position() {
    let mut t = three();
    t.vel("m1", 100.0);
    t.steps(500);
    let m0 = t.st("m1").set_pos;
    let s0 = t.st("s").set_pos;
    let mut c = multi("s", ["m1", "", "", ""], [1.0, 0.0, 0.0, 0.0], true);
    c.options.sync_mode = GearInMultiMasterSyncMode::PosSync2;
    let id = t.id(AxisCommand::GearInMultiMaster(c));
    t.until(20000, |t| t.fb(id).in_gear);
    let (m, s) = (t.st("m1"), t.st("s"));
    assert!(
        (s.set_pos - (s0 + (m.set_pos - m0))).abs() < 1e-6,
        "position-synchronous"
    );
    assert!((s.set_velo - 100.0).abs() < 1e-6);
    // The master speeds up within the slave's limits: the slave stays exact all along.
    t.vel("m1", 300.0);
    for _ in 0..500 {
        t.step();
        let (m, s) = (t.st("m1"), t.st("s"));
        assert!((s.set_pos - (s0 + (m.set_pos - m0))).abs() < 1e-6);
        assert!(t.fb(id).in_gear);
    }
}

#[test]
fn possync1_syncs_velocity_then_position() {
    let mut t = three();
    t.vel("m1", 100.0);
    t.steps(500);
    let mut c = multi("s", ["m1", "", "", ""], [1.0, 0.0, 0.0, 0.0], true);
    c.options.sync_mode = GearInMultiMasterSyncMode::PosSync1;
    let id = t.id(AxisCommand::GearInMultiMaster(c));
    t.until(20000, |t| t.fb(id).in_gear);
    // Once synchronous, the slave keeps the master's motion exactly.
    let d0 = t.st("s").set_pos - t.st("m1").set_pos;
    t.steps(500);
    let d1 = t.st("s").set_pos - t.st("m1").set_pos;
    assert!((d1 - d0).abs() < 1e-6);
}

#[test]
fn phasing_needs_asd() {
    let mut t = three();
    t.id(AxisCommand::GearInMultiMaster(multi(
        "s",
        ["m1", "", "", ""],
        [1.0, 0.0, 0.0, 0.0],
        false,
    )));
    t.rejects(
        AxisCommand::PhasingAbsolute(phasing_abs("m1", "s", 1.0, 10.0)),
        0x4B05,
    );
    let mut u = three();
    let mut c = multi("s", ["m1", "m2", "", ""], [1.0, 1.0, 0.0, 0.0], true);
    c.options.sync_mode = GearInMultiMasterSyncMode::PosSync2;
    u.id(AxisCommand::GearInMultiMaster(c));
    u.vel("m1", 100.0);
    u.steps(200);
    let p = u.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m2", "s", 5.0, 20.0,
    )));
    u.until(5000, |u| u.out(p).done);
    u.steps(2000);
    let want = u.st("m1").set_pos + u.st("m2").set_pos + 5.0;
    assert!(
        (u.st("s").set_pos - want).abs() < 1e-6,
        "{} vs {want}",
        u.st("s").set_pos
    );
}

#[test]
fn slave_error_ends_the_instance_with_the_axis_error() {
    let mut t = three();
    let id = t.id(AxisCommand::GearInMultiMaster(multi(
        "s",
        ["m1", "", "", ""],
        [1.0, 0.0, 0.0, 0.0],
        false,
    )));
    t.cmd(AxisCommand::Sim(Sim::InjectAxisError {
        axis: "s".into(),
        error_id: 0,
    }))
    .unwrap();
    assert_eq!(t.st("s").motion_state, MotionState::ErrorStop);
    t.step();
    let o = t.out(id);
    assert!(o.error && o.error_id == ErrorId(0x4550), "{o:?}");
}

#[test]
fn bad_input() {
    let mut t = three();
    let ok = multi("s", ["m1", "", "", ""], [1.0, 0.0, 0.0, 0.0], false);
    let with = |f: &dyn Fn(&mut GearInMultiMaster)| {
        let mut c = ok.clone();
        f(&mut c);
        AxisCommand::GearInMultiMaster(c)
    };
    t.rejects(with(&|c| c.slave = "nope".into()), 0x7F01);
    t.rejects(with(&|c| c.master2 = "nope".into()), 0x7F01);
    t.rejects(with(&|c| c.master1 = String::new()), 0x4B06);
    t.rejects(with(&|c| c.master1 = "s".into()), 0x4B06);
    t.rejects(with(&|c| c.master2 = "m1".into()), 0x4B06);
    for bad in [f64::NAN, f64::INFINITY] {
        t.rejects(with(&|c| c.gear_ratio3 = bad), 0x7F02);
        t.rejects(with(&|c| c.jerk = bad), 0x7F02);
    }
    t.rejects(with(&|c| c.acceleration = -1.0), 0x4B06);
    t.rejects(with(&|c| c.deceleration = -1.0), 0x4B06);
    assert_eq!(
        GearInMultiMasterSyncMode::from_raw(3).unwrap_err().error_id,
        ErrorId::ENUM_OUT_OF_RANGE
    );
    // Loop: m1 follows s, so s cannot follow m1.
    t.gear_in("s", "m1", 1.0).unwrap();
    t.rejects(with(&|_| {}), 0x4B06);
    // Disabled slave.
    let mut u = three();
    u.cmd(AxisCommand::Power(Power {
        axis: "s".into(),
        enable: false,
        enable_positive: true,
        enable_negative: true,
        override_percent: 100.0,
        buffer_mode: BufferMode::Aborting,
    }))
    .unwrap();
    u.rejects(AxisCommand::GearInMultiMaster(ok.clone()), 0x4B01);
    // Enable FALSE without a running instance: nothing happens.
    let r = t
        .cmd(AxisCommand::GearInMultiMaster(GearInMultiMaster {
            enable: false,
            ..ok
        }))
        .unwrap();
    assert!(!r.tracked);
}
