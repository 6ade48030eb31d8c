//! W4 – External set points, absolute (manual 6.1.6, test values of §7): J = 10000 mm/s³,
//! A = 2000 mm/s²: 0.4 s, end velocity 400 mm/s, 80 mm. During ESG the mode is
//! ExternalSetpointGeneration and SetPos follows the stream (±1e-6 mm); after Stop the mover
//! brakes with maximum dynamics (+8 mm) → x ∈ [85, 95], FreeMovement.

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

#[test]
fn w04_external_setpoints_absolute() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let start = s.ok(PlanarCommand::StartExternalSetpointGeneration {
        mover: "M".into(),
        options: Default::default(),
    });
    let base = s.mover("M").set_pos;
    let stream = jerk_stream(0.0, 10000.0, 2000.0, 0.001);
    assert!(
        (stream.last().unwrap().0 - 80.0).abs() < 0.5
            && (stream.last().unwrap().1 - 400.0).abs() < 1.0
    );
    let mut stop = None;
    for (k, &(p, v, a)) in stream.iter().enumerate() {
        let (sp, sv, sa) = sp_x(p, v, a, base);
        let r = s
            .cmd(PlanarCommand::SetExternalSetpoint {
                mover: "M".into(),
                set_position: sp,
                set_velocity: sv,
                set_acceleration: sa,
            })
            .unwrap();
        assert_eq!(
            r.id, start,
            "set points report through the session feedback"
        );
        if k + 1 == stream.len() {
            // Stop after the last set point of the same cycle [manual]: that point still counts.
            stop = Some(s.ok(PlanarCommand::StopExternalSetpointGeneration { mover: "M".into() }));
        }
        s.step();
        let m = s.mover("M");
        assert_eq!(m.command_mode, CommandMode::ExternalSetpointGeneration);
        assert!(
            (m.set_pos.x - p).abs() <= 1e-6,
            "SetPos follows the stream: {} vs {p}",
            m.set_pos.x
        );
        assert_eq!(m.set_pos.y, 0.0);
    }
    let stop = stop.unwrap();
    assert_eq!(s.wait_final(stop, 2.0), CommandState::Done);
    let m = s.mover("M");
    assert_eq!(m.command_mode, CommandMode::FreeMovement);
    assert_eq!(m.set_velo.x, 0.0);
    assert!(
        m.set_pos.x >= 85.0 && m.set_pos.x <= 95.0,
        "final x {}",
        m.set_pos.x
    );
    assert!(
        (m.set_pos.x - 88.0).abs() < 0.6,
        "80 + 8 mm jerk-limited stop: {}",
        m.set_pos.x
    );
    // The ESG feedback never becomes Done nor Aborted: Busy falls without either (§6.1).
    assert_eq!(s.state(start), Some(CommandState::Ended));
}

/// §3.2: missing set points are extrapolated for `esg_timeout_cycles`, then
/// E_EXT_SETPOINT_MISSING with QuickStop; set points above the maximum dynamics →
/// E_DYNAMICS_VIOLATION.
#[test]
fn w04_external_setpoint_faults() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0), ("N", 0.0, 400.0)]);
    s.enable("M");
    let start = s.ok(PlanarCommand::StartExternalSetpointGeneration {
        mover: "M".into(),
        options: Default::default(),
    });
    s.steps(10);
    assert_eq!(
        s.mover("M").state,
        PlanarState::Enabled,
        "10 missing cycles tolerated"
    );
    s.step();
    assert_eq!(
        s.state(start),
        Some(CommandState::Error(errors::E_EXT_SETPOINT_MISSING))
    );
    assert_eq!(s.mover("M").state, PlanarState::ErrorPending);
    s.run_until(1.0, |p| p.mover("M").unwrap().state == PlanarState::Error);
    let r = s.ok(PlanarCommand::MoverReset { mover: "M".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(
        s.mover("M").state,
        PlanarState::Enabled,
        "QuickStop → reset ends Enabled (T10)"
    );

    s.enable("N");
    let start = s.ok(PlanarCommand::StartExternalSetpointGeneration {
        mover: "N".into(),
        options: Default::default(),
    });
    let base = s.mover("N").set_pos;
    let (sp, sv, sa) = sp_x(20.0, 0.0, 0.0, base);
    s.ok(PlanarCommand::SetExternalSetpoint {
        mover: "N".into(),
        set_position: sp,
        set_velocity: sv,
        set_acceleration: sa,
    });
    s.step();
    assert_eq!(
        s.state(start),
        Some(CommandState::Error(errors::E_DYNAMICS_VIOLATION)),
        "20 mm in 1 ms"
    );
    assert!(
        s.mover("N").set_pos.x.abs() < 1e-9,
        "the violating set point was not applied"
    );
}

/// §5.10 relative mode: offsets on top of internal set points, in parallel with a move;
/// Stop freezes the offsets.
#[test]
fn w04_relative_offsets() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let start = s.ok(PlanarCommand::StartExternalSetpointGeneration {
        mover: "M".into(),
        options: ExternalSetpointGenerationOptions {
            mode: ExternalSetpointMode::Relative,
        },
    });
    let mv = s.ok(mtp("M", 100.0, 0.0, 0.0));
    for k in 1..=100 {
        let y = 0.05 * k as f64;
        s.ok(PlanarCommand::SetExternalSetpoint {
            mover: "M".into(),
            set_position: MoverVector {
                y,
                ..Default::default()
            },
            set_velocity: MoverVector {
                y: 50.0,
                ..Default::default()
            },
            set_acceleration: MoverVector::default(),
        });
        s.step();
        let m = s.mover("M");
        assert_eq!(
            m.command_mode,
            CommandMode::FreeMovement,
            "relative mode keeps the mode"
        );
        assert!((m.set_pos.y - y).abs() < 1e-9);
    }
    let stop = s.ok(PlanarCommand::StopExternalSetpointGeneration { mover: "M".into() });
    assert_eq!(s.wait_final(stop, 1.0), CommandState::Done);
    assert_eq!(s.wait_final(mv, 5.0), CommandState::Done);
    assert!(s.state(start).is_some_and(|st| st != CommandState::Done));
    let m = s.mover("M");
    assert_pos(&m, 100.0, 5.0);
}
