//! W19 — touch probe windows (§8, §4.5.1) with the virtual probe marks of §1.5.
mod common;
use axis_engine::*;
use common::*;

fn probe(first: f64, last: f64, modulo: bool, window: bool, mode: TouchProbeMode) -> AxisCommand {
    AxisCommand::TouchProbe(TouchProbe {
        axis: AX.into(),
        trigger_input: TriggerRef {
            modulo_positions: modulo,
            mode,
            ..Default::default()
        },
        window_only: window,
        first_position: first,
        last_position: last,
    })
}

fn marks_rig(marks: Vec<f64>) -> Rig {
    Rig::powered_with(AxisConfig {
        probe_marks: marks,
        ..Default::default()
    })
}

#[test]
fn picture_a_window_90_to_180_each_turn() {
    let mut r = marks_rig(vec![45.0, 480.0]);
    let id = r.id(probe(90.0, 180.0, true, true, TouchProbeMode::Single));
    r.id(vel(200.0));
    r.until(5000, |r| r.st().set_pos > 50.0);
    assert!(r.out(id).busy, "edge at 45 discarded, latch re-armed");
    r.until(5000, |r| r.out(id).done);
    let o = r.e.probe_outputs(id).unwrap();
    assert!((o.recorded_position - 120.0).abs() < 1e-9, "{o:?}");
    assert!(
        (o.absolute_position - 480.0).abs() < 1e-9,
        "interpolated to the exact crossing"
    );
    assert!((o.modulo_position - 120.0).abs() < 1e-9);
}

#[test]
fn picture_b_window_across_the_period_end() {
    let mut r = marks_rig(vec![120.0, 330.0]);
    let id = r.id(probe(300.0, 60.0, true, true, TouchProbeMode::Single));
    r.id(vel(200.0));
    r.until(5000, |r| r.st().set_pos > 125.0);
    assert!(r.out(id).busy, "edge at 120 discarded");
    r.until(5000, |r| r.out(id).done);
    assert!((r.e.probe_outputs(id).unwrap().recorded_position - 330.0).abs() < 1e-9);
    // 0…60 belongs to the window as well.
    let mut r = marks_rig(vec![400.0]);
    let id = r.id(probe(300.0, 60.0, true, true, TouchProbeMode::Single));
    r.id(vel(200.0));
    r.until(5000, |r| r.out(id).done);
    assert!((r.e.probe_outputs(id).unwrap().recorded_position - 40.0).abs() < 1e-9);
}

#[test]
fn non_modulo_window_is_one_absolute_window() {
    let mut r = marks_rig(vec![45.0, 480.0]);
    let id = r.id(probe(90.0, 180.0, false, true, TouchProbeMode::Single));
    r.id(vel(200.0));
    r.until(10000, |r| r.st().set_pos > 600.0);
    assert!(
        r.out(id).busy && !r.out(id).done,
        "480 is outside the absolute window"
    );
    let ab = r.id(AxisCommand::AbortTrigger(AbortTrigger {
        axis: AX.into(),
        trigger_input: TriggerRef::default(),
    }));
    assert!(r.out(id).command_aborted);
    r.step();
    assert!(r.out(ab).done);
}

#[test]
fn client_level_and_plc_event_and_continuous_mode() {
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.steps(100);
    let id = r.id(probe(0.0, 0.0, false, false, TouchProbeMode::Single));
    r.steps(10);
    r.cmd(AxisCommand::Sim(Sim::ProbeInput {
        axis: AX.into(),
        unit: 1,
        level: true,
    }))
    .unwrap();
    r.step();
    assert!(r.out(id).done);
    let o = r.e.probe_outputs(id).unwrap();
    assert!((o.recorded_position - r.st().act_pos).abs() < 1e-9);
    // PlcEvent: rising edge of TriggerInput.PlcEvent.
    let t = TriggerRef {
        touch_probe: TouchProbeUnit::PlcEvent,
        ..Default::default()
    };
    let p = r.id(AxisCommand::TouchProbe(TouchProbe {
        axis: AX.into(),
        trigger_input: t,
        window_only: false,
        first_position: 0.0,
        last_position: 0.0,
    }));
    r.steps(5);
    r.cmd(AxisCommand::TouchProbePlcEvent {
        id: p,
        plc_event: true,
    })
    .unwrap();
    r.step();
    assert!(r.out(p).done);
    // CONTINOUS on unit 2 with marks every 10 u: stays Busy, records each edge.
    let mut r = Rig::powered_with(AxisConfig {
        probe_marks_2: vec![10.0, 20.0, 30.0],
        ..Default::default()
    });
    let t = TriggerRef {
        touch_probe: TouchProbeUnit::TouchProbe2,
        mode: TouchProbeMode::Continous,
        ..Default::default()
    };
    let c = r.id(AxisCommand::TouchProbe(TouchProbe {
        axis: AX.into(),
        trigger_input: t,
        window_only: false,
        first_position: 0.0,
        last_position: 0.0,
    }));
    r.id(vel(100.0));
    r.until(5000, |r| r.st().set_pos > 35.0);
    assert!(r.out(c).busy);
    assert!((r.e.probe_outputs(c).unwrap().absolute_position - 30.0).abs() < 1e-9);
}

#[test]
fn probe_errors() {
    let mut r = Rig::powered();
    let t3 = TriggerRef {
        touch_probe: TouchProbeUnit::TouchProbe3,
        ..Default::default()
    };
    let e = r
        .cmd(AxisCommand::TouchProbe(TouchProbe {
            axis: AX.into(),
            trigger_input: t3,
            window_only: false,
            first_position: 0.0,
            last_position: 0.0,
        }))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B04));
    r.id(probe(0.0, 1.0, false, true, TouchProbeMode::Single));
    let e = r
        .cmd(probe(0.0, 1.0, false, true, TouchProbeMode::Single))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B05), "latch already armed");
    let e = r
        .cmd(probe(f64::NAN, 1.0, false, true, TouchProbeMode::Single))
        .unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::NOT_FINITE);
    let e = r
        .cmd(AxisCommand::Sim(Sim::ProbeInput {
            axis: AX.into(),
            unit: 3,
            level: true,
        }))
        .unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::VALUE_OUT_OF_RANGE);
}
