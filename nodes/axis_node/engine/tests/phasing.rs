//! §4.13 phasing: MC_PhasingAbsolute, MC_PhasingRelative, MC_HaltPhasing on an MC_GearIn
//! slave (ratio 1, master running at 100 u/s), the admission rules (§2.4 row "Phasing",
//! §3.6 rule 10) and the bad-input screening.
mod rig3;
use axis_engine::*;
use motion_core::{Engine, ErrorId};
use rig3::*;

/// Master "m" at 100 u/s, slave "s" coupled 1:1 at standstill before.
fn running() -> Axes {
    let mut t = Axes::new(&["m", "s"], AxisConfig::default());
    t.gear_in("m", "s", 1.0).unwrap();
    t.vel("m", 100.0);
    t.steps(1000);
    assert!((t.st("s").set_velo - 100.0).abs() < 1e-9);
    t
}

fn lead(t: &Axes) -> f64 {
    t.st("s").set_pos - t.st("m").set_pos
}

#[test]
fn phasing_absolute_establishes_the_shift_jerk_limited() {
    let mut t = running();
    assert!(lead(&t).abs() < 1e-9);
    let id = t.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m", "s", 10.0, 20.0,
    )));
    assert!(t.out(id).busy && t.out(id).active);
    assert_eq!(
        t.st("s").motion_state,
        MotionState::SynchronizedMotion,
        "no state change"
    );
    let mut max_dv: f64 = 0.0;
    let mut prev_v = t.st("s").set_velo;
    let mut saw_active = false;
    while !t.out(id).done {
        t.step();
        let s = t.st("s");
        saw_active |= s.state_dword & (1 << 15) != 0;
        // Phasing velocity ≤ Velocity on top of the master's.
        assert!(s.set_velo - 100.0 <= 20.0 + 1e-9, "{}", s.set_velo);
        max_dv = max_dv.max((s.set_velo - prev_v).abs());
        prev_v = s.set_velo;
        assert!(t.tick < 5000);
    }
    assert!(saw_active, "Status.PhasingActive (bit 15) while phasing");
    // No velocity step: |Δv| per cycle ≤ AxisAcc·dt.
    assert!(max_dv <= 1000.0 * DT + 1e-9, "{max_dv}");
    assert!((lead(&t) - 10.0).abs() < 1e-9, "lead {}", lead(&t));
    assert!((t.ext("s").abs_phasing_pos - 10.0).abs() < 1e-12);
    assert_eq!(t.st("s").state_dword & (1 << 15), 0, "PhasingActive off");
    assert!(!t.out(id).busy);
    match t.extra(id) {
        Some(ExtraOutputs::Phasing {
            absolute_phase_shift: Some(p),
            ..
        }) => assert!((p - 10.0).abs() < 1e-12),
        o => panic!("{o:?}"),
    }
    // The shift stays while the master runs on.
    t.steps(500);
    assert!((lead(&t) - 10.0).abs() < 1e-9);
    assert!((t.st("s").set_velo - 100.0).abs() < 1e-9);
}

#[test]
fn phasing_relative_adds_and_reports_the_covered_part() {
    let mut t = running();
    let a = t.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m", "s", 10.0, 50.0,
    )));
    t.until(5000, |t| t.out(a).done);
    let r = t.id(AxisCommand::PhasingRelative(phasing_rel(
        "m", "s", -4.0, 50.0,
    )));
    t.until(5000, |t| t.out(r).done);
    assert!((lead(&t) - 6.0).abs() < 1e-9);
    match t.extra(r) {
        Some(ExtraOutputs::Phasing {
            covered_phase_shift: Some(c),
            absolute_phase_shift: None,
        }) => assert!((c + 4.0).abs() < 1e-12, "{c}"),
        o => panic!("{o:?}"),
    }
}

#[test]
fn halt_phasing_stops_the_phasing_motion_and_keeps_the_shift() {
    let mut t = running();
    let a = t.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m", "s", 100.0, 50.0,
    )));
    t.steps(200);
    let h = t.id(AxisCommand::HaltPhasing(halt_phasing("m", "s")));
    assert!(t.out(a).command_aborted, "the phasing FB is aborted");
    t.until(5000, |t| t.out(h).done);
    let phi = t.ext("s").abs_phasing_pos;
    assert!(phi > 0.0 && phi < 100.0, "{phi}");
    t.steps(300);
    assert!(
        (t.ext("s").abs_phasing_pos - phi).abs() < 1e-12,
        "shift remains"
    );
    assert!((lead(&t) - phi).abs() < 1e-9);
    assert!(
        (t.st("s").set_velo - 100.0).abs() < 1e-9,
        "phasing velocity 0"
    );
}

#[test]
fn continuous_update_follows_new_inputs_until_execute_falls() {
    let mut t = running();
    let mut c = phasing_abs("m", "s", 5.0, 50.0);
    c.continuous_update = true;
    let id = t.id(AxisCommand::PhasingAbsolute(c));
    t.until(5000, |t| t.out(id).done);
    let o = t.out(id);
    assert!(
        o.done && o.busy && o.active,
        "Done with Busy/Active (§4.13.1): {o:?}"
    );
    t.id(AxisCommand::PhasingUpdate(PhasingUpdate {
        id,
        phase_shift: 8.0,
        velocity: 50.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
    }));
    t.step();
    assert!(t.ext("s").phasing_active, "moving again after the update");
    t.until(5000, |t| (lead(t) - 8.0).abs() < 1e-9);
    t.step();
    assert!(!t.ext("s").phasing_active);
    let o = t.out(id);
    assert!(o.done && o.busy, "{o:?}");
    t.cmd(AxisCommand::SetExecute { id, execute: false })
        .unwrap();
    let o = t.out(id);
    assert!(!o.busy && !o.active && !o.done, "outputs reset: {o:?}");
    // Further updates are ignored.
    t.id(AxisCommand::PhasingUpdate(PhasingUpdate {
        id,
        phase_shift: 20.0,
        velocity: 50.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
    }));
    t.steps(500);
    assert!((lead(&t) - 8.0).abs() < 1e-9);
}

#[test]
fn decoupling_aborts_the_phasing_command() {
    let mut t = running();
    let a = t.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m", "s", 100.0, 50.0,
    )));
    t.steps(10);
    t.gear_out("s");
    t.step();
    assert!(t.out(a).command_aborted);
    assert_eq!(t.ext("s").abs_phasing_pos, 0.0);
    // A new coupling starts without phase offset.
    let h = t.id(AxisCommand::Halt(Halt {
        axis: "s".into(),
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }));
    t.until(10000, |t| t.out(h).done);
}

#[test]
fn axis_error_ends_the_phasing_with_the_axis_error() {
    let mut t = running();
    let a = t.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m", "s", 100.0, 50.0,
    )));
    t.steps(10);
    t.cmd(AxisCommand::Sim(Sim::InjectAxisError {
        axis: "s".into(),
        error_id: 0x4550,
    }))
    .unwrap();
    t.step();
    let o = t.out(a);
    assert!(o.error && o.error_id == ErrorId(0x4550), "{o:?}");
}

#[test]
fn admission_and_bad_input() {
    let mut t = Axes::new(&["m", "s", "d"], AxisConfig::default());
    // Not coupled: Standstill → 0x4B05.
    t.rejects(
        AxisCommand::PhasingAbsolute(phasing_abs("m", "s", 1.0, 10.0)),
        0x4B05,
    );
    t.rejects(AxisCommand::HaltPhasing(halt_phasing("m", "s")), 0x4B05);
    // Moving, not coupled → 0x4B05.
    t.vel("d", 10.0);
    t.step();
    t.rejects(
        AxisCommand::PhasingRelative(phasing_rel("m", "d", 1.0, 10.0)),
        0x4B05,
    );
    // Disabled → 0x4B01.
    let mut u = Axes::new(&["m", "s"], AxisConfig::default());
    u.cmd(AxisCommand::Power(Power {
        axis: "s".into(),
        enable: false,
        enable_positive: true,
        enable_negative: true,
        override_percent: 100.0,
        buffer_mode: BufferMode::Aborting,
    }))
    .unwrap();
    u.step();
    u.rejects(
        AxisCommand::PhasingAbsolute(phasing_abs("m", "s", 1.0, 10.0)),
        0x4B01,
    );

    t.gear_in("m", "s", 1.0).unwrap();
    t.step();
    let ok = phasing_abs("m", "s", 1.0, 10.0);
    // Unknown axes.
    t.rejects(
        AxisCommand::PhasingAbsolute(PhasingAbsolute {
            master: "nope".into(),
            ..ok.clone()
        }),
        0x7F01,
    );
    t.rejects(
        AxisCommand::PhasingAbsolute(PhasingAbsolute {
            slave: "nope".into(),
            ..ok.clone()
        }),
        0x7F01,
    );
    // Wrong master.
    t.rejects(
        AxisCommand::PhasingAbsolute(PhasingAbsolute {
            master: "d".into(),
            ..ok.clone()
        }),
        0x4B05,
    );
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        t.rejects(
            AxisCommand::PhasingAbsolute(PhasingAbsolute {
                phase_shift: bad,
                ..ok.clone()
            }),
            0x7F02,
        );
        t.rejects(
            AxisCommand::PhasingRelative(PhasingRelative {
                jerk: bad,
                ..phasing_rel("m", "s", 1.0, 10.0)
            }),
            0x7F02,
        );
        t.rejects(
            AxisCommand::HaltPhasing(HaltPhasing {
                deceleration: bad,
                ..halt_phasing("m", "s")
            }),
            0x7F02,
        );
    }
    for v in [0.0, 0.009, -1.0, 2000.1] {
        t.rejects(
            AxisCommand::PhasingAbsolute(PhasingAbsolute {
                velocity: v,
                ..ok.clone()
            }),
            0x4B06,
        );
    }
    t.rejects(
        AxisCommand::PhasingAbsolute(PhasingAbsolute {
            acceleration: -1.0,
            ..ok.clone()
        }),
        0x4B06,
    );
    t.rejects(
        AxisCommand::HaltPhasing(HaltPhasing {
            jerk: -1.0,
            ..halt_phasing("m", "s")
        }),
        0x4B06,
    );
    // Only MC_Aborting (§3.6 rule 10).
    for bm in [BufferMode::Buffered, BufferMode::BlendingHigh] {
        t.rejects(
            AxisCommand::PhasingAbsolute(PhasingAbsolute {
                buffer_mode: bm,
                ..ok.clone()
            }),
            0x4B04,
        );
        t.rejects(
            AxisCommand::HaltPhasing(HaltPhasing {
                buffer_mode: bm,
                ..halt_phasing("m", "s")
            }),
            0x4B04,
        );
    }
    // Velocity 0.01 is the smallest allowed.
    assert!(t
        .cmd(AxisCommand::PhasingAbsolute(PhasingAbsolute {
            velocity: 0.01,
            ..ok
        }))
        .is_ok());
    // Updates of unknown / non-phasing instances.
    let upd = |id| {
        AxisCommand::PhasingUpdate(PhasingUpdate {
            id,
            phase_shift: 1.0,
            velocity: 10.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
        })
    };
    t.rejects(upd(motion_core::CmdId(999_999)), 0x7F01);
    let m = t.mv("d", 5.0, 10.0);
    t.rejects(upd(m), 0x4B05);
}

#[test]
fn not_on_gear_in_dyn_couplings() {
    let mut t = Axes::new(&["m", "s"], AxisConfig::default());
    t.id(AxisCommand::GearInDyn(GearInDyn {
        master: "m".into(),
        slave: "s".into(),
        enable: true,
        gear_ratio: 1.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
    }));
    t.step();
    t.rejects(
        AxisCommand::PhasingAbsolute(phasing_abs("m", "s", 1.0, 10.0)),
        0x4B05,
    );
}

#[test]
fn cancel_halts_the_phasing() {
    let mut t = running();
    let a = t.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m", "s", 100.0, 50.0,
    )));
    t.steps(200);
    t.e.cancel(a).unwrap();
    assert!(t.out(a).command_aborted);
    t.steps(200);
    let phi = t.ext("s").abs_phasing_pos;
    assert!(phi > 0.0 && phi < 100.0, "{phi}");
    assert!(!t.ext("s").phasing_active);
    assert!((t.st("s").set_velo - 100.0).abs() < 1e-9);
}

#[test]
fn execute_falling_while_an_update_moves_ends_the_instance_at_the_target() {
    let mut t = running();
    let mut c = phasing_abs("m", "s", 5.0, 50.0);
    c.continuous_update = true;
    let id = t.id(AxisCommand::PhasingAbsolute(c));
    t.until(5000, |t| t.out(id).done);
    t.id(AxisCommand::PhasingUpdate(PhasingUpdate {
        id,
        phase_shift: 20.0,
        velocity: 50.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
    }));
    t.step();
    t.cmd(AxisCommand::SetExecute { id, execute: false })
        .unwrap();
    t.until(5000, |t| !t.ext("s").phasing_active);
    t.steps(2);
    let o = t.out(id);
    assert!(!o.busy && !o.active && !o.done, "{o:?}");
    assert!((lead(&t) - 20.0).abs() < 1e-9);
}

#[test]
fn a_phasing_left_by_a_vanished_coupling_ends_even_if_a_new_one_starts_in_the_same_cycle() {
    let mut t = Axes::new(&["m", "s"], AxisConfig::default());
    t.gear_in("m", "s", 1.0).unwrap();
    t.step();
    let old = t.id(AxisCommand::PhasingAbsolute(phasing_abs(
        "m", "s", 100.0, 10.0,
    )));
    t.steps(300);
    // Decouple (the slave keeps the phasing velocity), re-couple (T9b) and phase again,
    // all before the next cycle.
    t.gear_out("s");
    assert_eq!(t.st("s").motion_state, MotionState::ContinuousMotion);
    let mut mm = multi("s", ["m", "", "", ""], [1.0, 0.0, 0.0, 0.0], true);
    mm.options.sync_mode = GearInMultiMasterSyncMode::PosSync2;
    t.id(AxisCommand::GearInMultiMaster(mm));
    let new = t.id(AxisCommand::PhasingRelative(phasing_rel(
        "m", "s", 1.0, 10.0,
    )));
    assert!(t.out(old).command_aborted, "{:?}", t.out(old));
    t.until(5000, |t| t.out(new).done);
    assert!(t.out(old).command_aborted || !t.out(old).busy);
}
