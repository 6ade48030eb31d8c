//! §4.10 homing with the latch reference modes (simulator proposal): HARDWARELATCHPOS (3) /
//! SOFTDRIVELATCHPOS (6) = rising edge, HARDWARELATCHNEG (4) / SOFTDRIVELATCHNEG (7) = falling
//! edge of the virtual probe input 1 after the falling cam edge (phase 5), or a crossing of a
//! `sim.probe_marks` position (rising). The reference coordinate is exact; the axis stops one
//! braking distance later (ActPos = Position + distance travelled since the latch).
mod common;
use axis_engine::*;
use common::*;

fn home(mode: u32, position: f64) -> AxisCommand {
    AxisCommand::Home(Home {
        axis: AX.into(),
        position,
        use_default_position: false,
        homing_mode: HomingMode::DefaultHoming,
        buffer_mode: BufferMode::Aborting,
        options: HomingOptions {
            reference_mode: mode,
            ..Default::default()
        },
        calibration_cam: false,
    })
}

fn probe(level: bool) -> AxisCommand {
    AxisCommand::Sim(Sim::ProbeInput {
        axis: AX.into(),
        unit: 1,
        level,
    })
}

/// Runs the homing to phase 5 and `extra` cycles beyond, then toggles the probe input to
/// `level`; returns the raw position at the latch and the final raw position.
fn latch_run(mode: u32, start_level: bool, level: bool) -> (Rig, f64, f64, Vec<u32>) {
    let mut r = Rig::powered_with(AxisConfig {
        home_cam: Some([10.0, 20.0]),
        ..Default::default()
    });
    r.cmd(probe(start_level)).unwrap();
    r.step();
    let id = r.id(home(mode, 50.0));
    let mut phases = vec![r.st().homing_state];
    let note = |r: &Rig, phases: &mut Vec<u32>| {
        let p = r.st().homing_state;
        if *phases.last().unwrap() != p {
            phases.push(p);
        }
    };
    while r.st().homing_state != 5 {
        r.step();
        note(&r, &mut phases);
        assert!(r.tick < 100_000);
    }
    r.steps(50);
    assert_eq!(r.st().homing_state, 5, "waits for the latch");
    let at = r.st().raw_pos;
    r.cmd(probe(level)).unwrap();
    while !r.out(id).done {
        assert!(!r.out(id).error, "{:?}", r.out(id));
        r.step();
        note(&r, &mut phases);
        assert!(r.tick < 200_000);
    }
    let end = r.st().raw_pos;
    (r, at, end, phases)
}

#[test]
fn rising_edge_modes_3_and_6() {
    for mode in [3, 6] {
        let (r, at, end, phases) = latch_run(mode, false, true);
        assert_eq!(phases, vec![1, 2, 3, 4, 5, 6, 0], "mode {mode}");
        assert!(at > 20.0, "latched after the falling cam edge");
        assert!(
            (r.st().act_pos - (50.0 + (end - at))).abs() < 1e-9,
            "mode {mode}"
        );
        assert!(r.st().homed);
    }
}

#[test]
fn falling_edge_modes_4_and_7() {
    for mode in [4, 7] {
        let (r, at, end, phases) = latch_run(mode, true, false);
        assert_eq!(phases, vec![1, 2, 3, 4, 5, 6, 0], "mode {mode}");
        assert!(
            (r.st().act_pos - (50.0 + (end - at))).abs() < 1e-9,
            "mode {mode}"
        );
    }
}

#[test]
fn a_rising_level_does_not_latch_a_falling_mode() {
    let mut r = Rig::powered_with(AxisConfig {
        home_cam: Some([10.0, 20.0]),
        ..Default::default()
    });
    let id = r.id(home(4, 0.0));
    r.until(100_000, |r| r.st().homing_state == 5);
    r.cmd(probe(true)).unwrap();
    r.steps(100);
    assert_eq!(r.st().homing_state, 5);
    assert!(r.out(id).busy);
}

#[test]
fn probe_mark_gives_the_exact_reference() {
    let mut r = Rig::powered_with(AxisConfig {
        home_cam: Some([10.0, 20.0]),
        probe_marks: vec![25.0],
        ..Default::default()
    });
    let id = r.id(home(6, 100.0));
    r.until(200_000, |r| r.out(id).done);
    let end = r.st().raw_pos;
    assert!((r.st().act_pos - (100.0 + (end - 25.0))).abs() < 1e-9);
}
