//! W5 – External set points across parts (manual 6.1.7), layout of W2, stream of W4.
//! CS OID and 0 are valid everywhere, Part L while on Part L; crossing x = 240 needs the
//! switch to Part R with x − 240 in the same cycle, else E_INVALID_REFERENCE_ID.

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

/// Streams W4's profile from the mover's position with `refsys`; `local` maps CS x to the
/// (x, ref) sent. Returns the session id.
fn stream(s: &mut Sim, j: f64, a: f64, local: impl Fn(f64) -> (f64, u32)) -> motion_core::CmdId {
    let start = s.ok(PlanarCommand::StartExternalSetpointGeneration {
        mover: "M".into(),
        options: Default::default(),
    });
    let base = s.mover("M").set_pos;
    for (p, v, acc) in jerk_stream(base.x, j, a, 0.001) {
        let (x, r) = local(p);
        let (sp, sv, sa) = sp_x(x, v, acc, base);
        s.cmd(PlanarCommand::SetExternalSetpointReferenceId {
            mover: "M".into(),
            set_position: sp,
            set_velocity: sv,
            set_acceleration: sa,
            reference_system_oid: r,
        })
        .ok();
        s.step();
        if s.state(start).is_some_and(|st| st.is_final()) {
            break;
        }
    }
    start
}

#[test]
fn w05_reference_variants_on_part_l() {
    for r in [CS, 0, PART_L] {
        let mut s = Sim::new(two_parts());
        s.enable("M");
        let start = stream(&mut s, 10000.0, 2000.0, |x| (x, r));
        assert_eq!(
            s.state(start),
            Some(CommandState::Active),
            "ref 0x{r:08X} accepted"
        );
        assert!(close(s.mover("M").set_pos.x, 200.0, 0.5));
        assert_eq!(s.mover("M").part_oid, PART_L, "stays on the first part");
        let stop = s.ok(PlanarCommand::StopExternalSetpointGeneration { mover: "M".into() });
        assert_eq!(s.wait_final(stop, 1.0), CommandState::Done);
    }
}

#[test]
fn w05_border_crossing_with_switch() {
    let mut s = Sim::new(two_parts());
    s.enable("M");
    let start = stream(&mut s, 10000.0, 3000.0, |x| {
        if x <= 240.0 {
            (x, PART_L)
        } else {
            (x - 240.0, PART_R)
        }
    });
    assert_eq!(s.state(start), Some(CommandState::Active));
    assert!(
        close(s.mover("M").set_pos.x, 390.0, 0.5),
        "270 mm profile: {}",
        s.mover("M").set_pos.x
    );
    let stop = s.ok(PlanarCommand::StopExternalSetpointGeneration { mover: "M".into() });
    assert_eq!(s.wait_final(stop, 1.0), CommandState::Done);
    let m = s.mover("M");
    assert_eq!(m.part_oid, PART_R);
    assert!(m.set_pos.x < 480.0);
}

#[test]
fn w05_border_crossing_without_switch_fails() {
    let mut s = Sim::new(two_parts());
    s.enable("M");
    let start = stream(&mut s, 10000.0, 3000.0, |x| (x, PART_L));
    assert_eq!(
        s.state(start),
        Some(CommandState::Error(errors::E_INVALID_REFERENCE_ID))
    );
    let m = s.mover("M");
    // The stale point was not applied; the QuickStop has run one cycle (< v·dt = 0.9 mm).
    assert!(m.set_pos.x < 241.0, "x = {}", m.set_pos.x);
    assert_eq!(
        m.state,
        PlanarState::ErrorPending,
        "ESG violation → object error (QuickStop)"
    );
}
