//! The FB calls on an [`AxisSet`] without any composition above it (issue 16: the single axis
//! has its own tests): MC_Power + MC_MoveAbsolute reach the target and report Done
//! (single_axis.md §4.1, §4.8.1, §3.1), bad input is refused with the spec's ids, and a
//! profile changes a single axis only through [`AxisProfile`].

use motion_core::{CmdId, CommandState, ErrorId};
use single_axis::axis::Axis;
use single_axis::error_ids::PARAMETER_NOT_CORRECT;
use single_axis::set::{BufferMode, MoveAbsolute, MoveOptions, Power};
use single_axis::{AxisConfig, AxisProfile, AxisSet, MotionState};

const DT: f64 = 0.001;

fn set_with(profile: Option<Box<dyn AxisProfile>>) -> AxisSet {
    let mut s = AxisSet::new(vec![("x".into(), AxisConfig::default())]).unwrap();
    if let Some(p) = profile {
        s.set_profile(p);
    }
    s.power(
        0,
        Power {
            axis: "x".into(),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        },
    )
    .unwrap();
    step(&mut s, 2);
    s
}

fn step(s: &mut AxisSet, n: usize) -> Vec<motion_core::CommandEvent> {
    let mut events = Vec::new();
    for _ in 0..n {
        s.begin_cycle();
        s.step_axes(DT);
        s.end_cycle();
        events.append(&mut s.fbs.events);
    }
    events
}

fn move_to(position: f64, velocity: f64) -> MoveAbsolute {
    MoveAbsolute {
        axis: "x".into(),
        position,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }
}

#[test]
fn move_absolute_reaches_its_target_and_reports_done() {
    let mut s = set_with(None);
    assert_eq!(s.axes[0].state(), MotionState::Standstill);
    let id = s.move_absolute(0, move_to(10.0, 100.0)).unwrap().id;
    assert_eq!(s.axes[0].state(), MotionState::DiscreteMotion);
    let events = step(&mut s, 2000);
    assert!(events
        .iter()
        .any(|e| e.id == id && e.state == CommandState::Done));
    let st = s.axis_status(0, false);
    assert!((st.set_pos - 10.0).abs() < 1e-9, "SetPos {}", st.set_pos);
    assert_eq!(st.motion_state, MotionState::Standstill);
}

#[test]
fn bad_inputs_are_refused_with_the_spec_ids() {
    let mut s = set_with(None);
    let r = s.move_absolute(0, move_to(10.0, f64::NAN)).unwrap_err();
    assert_eq!(r.error_id, ErrorId::NOT_FINITE);
    let r = s.move_absolute(0, move_to(10.0, -1.0)).unwrap_err();
    assert_eq!(r.error_id, PARAMETER_NOT_CORRECT);
    let r = s.axis_index("nope").unwrap_err();
    assert_eq!(r.error_id, ErrorId::UNKNOWN_OBJECT);
    let r = s.set_execute(CmdId(9999), false).unwrap_err();
    assert_eq!(r.error_id, ErrorId::UNKNOWN_OBJECT);
}

/// A profile that latches final outputs until Execute falls and shows every axis error as 1.
#[derive(Debug)]
struct Latching;

impl AxisProfile for Latching {
    fn latch_done(&self) -> bool {
        true
    }
    fn shown_error_id(&self, _axis: &Axis, _id: ErrorId) -> ErrorId {
        ErrorId(1)
    }
}

/// §3.1: an instance whose Execute fell before it finished shows Done for one cycle in
/// Tc2_MC2; a latching profile (ISG R-HS-2) keeps it. Its error ids are the profile's too.
#[test]
fn the_profile_decides_how_long_done_shows() {
    for (profile, latched) in [(None, false), (Some(Box::new(Latching) as _), true)] {
        let mut s = set_with(profile);
        let id = s.move_absolute(0, move_to(1.0, 100.0)).unwrap().id;
        s.set_execute(id, false).unwrap();
        let events = step(&mut s, 500);
        assert!(events
            .iter()
            .any(|e| e.id == id && e.state == CommandState::Done));
        assert_eq!(s.fb_outputs(id).unwrap().standard.done, latched);
        // An axis error shows in the running instance's ErrorID as the profile shows it.
        let id = s.move_absolute(0, move_to(2.0, 100.0)).unwrap().id;
        s.sim(
            0,
            single_axis::set::Sim::InjectAxisError {
                axis: "x".into(),
                error_id: 0x4550,
            },
        )
        .unwrap();
        step(&mut s, 1);
        let o = s.fb_outputs(id).unwrap().standard;
        assert!(o.error);
        assert_eq!(
            o.error_id,
            if latched { ErrorId(1) } else { ErrorId(0x4550) }
        );
    }
}
