//! The demo machine moving by itself: `launch-configs/demo.yaml` with a command script per node
//! (`script:` in its entry), so tests see motion without a client: the live view test, the
//! replay-determinism test and the plot test.

use axis_engine::Power;
use axis_engine::{AxisCommand, BufferMode, Direction, MoveAbsolute, MoveOptions, MoveVelocity};
use planar_engine::{DynamicConstraint, MoveToPositionOptions, PlanarCommand, PositionXYC};
use serde_yaml::{Mapping, Value};

/// MC_Power of `axis` with Enable, both directions and 100 % override (the suite's benches and
/// scripts switch axes on this way).
pub fn power(axis: &str) -> AxisCommand {
    AxisCommand::Power(Power {
        axis: axis.to_string(),
        enable: true,
        enable_positive: true,
        enable_negative: true,
        override_percent: 100.0,
        buffer_mode: BufferMode::Aborting,
    })
}

/// One script step of an engine command at `at` seconds.
fn step<C: serde::Serialize>(at: f64, command: C) -> Value {
    let mut m = Mapping::new();
    m.insert("at".into(), at.into());
    // The map form users write: {MoveAbsolute: {axis: x, ...}}.
    let command = serde_yaml::with::singleton_map_recursive::serialize(
        &command,
        serde_yaml::value::Serializer,
    )
    .expect("command as YAML");
    m.insert("command".into(), command);
    Value::Mapping(m)
}

/// The axes: powered at once; `table` turns at 90 deg/s; `x` goes between 0 and 200 mm, a
/// leg every 2 s, for `seconds`.
fn axis_script(seconds: f64) -> Vec<Value> {
    let mut s: Vec<Value> = ["x", "y", "table"]
        .iter()
        .map(|a| step(0.0, power(a)))
        .collect();
    s.push(step(
        0.01,
        AxisCommand::MoveVelocity(MoveVelocity {
            axis: "table".into(),
            velocity: 90.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            direction: Direction::Positive,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }),
    ));
    let mut t = 0.01;
    let mut k = 0;
    while t < seconds {
        s.push(step(
            t,
            AxisCommand::MoveAbsolute(MoveAbsolute {
                axis: "x".into(),
                position: if k % 2 == 0 { 200.0 } else { 0.0 },
                velocity: 150.0,
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
                buffer_mode: BufferMode::Aborting,
                options: MoveOptions::default(),
            }),
        ));
        t += 2.0;
        k += 1;
    }
    s
}

/// The movers: m2 and m4 enabled at once; m2 shuttles between x = 240 and 480 mm in the top
/// row at 12 mm/s, a leg every 25 s from 1 s (each takes about 20 s: within a test's first 20 s
/// m2 is always under way in one direction, never turning), for `seconds`.
fn planar_script(seconds: f64) -> Vec<Value> {
    let mut s: Vec<Value> = ["m2", "m4"]
        .iter()
        .map(|m| {
            step(
                0.0,
                PlanarCommand::MoverEnable {
                    mover: m.to_string(),
                },
            )
        })
        .collect();
    let mut t = 1.0;
    let mut k = 0;
    while t < seconds {
        s.push(step(
            t,
            PlanarCommand::MoveToPosition {
                mover: "m2".into(),
                target_position: PositionXYC::new(
                    if k % 2 == 0 { 480.0 } else { 240.0 },
                    630.0,
                    0.0,
                ),
                constraint: DynamicConstraint {
                    velocity: 12.0,
                    ..Default::default()
                },
                options: MoveToPositionOptions::default(),
            },
        ));
        t += 25.0;
        k += 1;
    }
    s
}

/// The pick-and-place cell: on, regulator on, its endless tracking mode (eSetTarget 0) at
/// 0.5 s, and a workpiece detected on belt 1 every 2 s from 0.6 s (as the demo's driver does).
fn pickplace_script(seconds: f64) -> Vec<Value> {
    use pickplace_engine::PickPlaceCommand as P;
    let mut s = vec![
        step(0.0, P::SetEnable(true)),
        step(0.0, P::SetRegulatorOn(true)),
        step(0.5, P::Execute { set_target: 0 }),
    ];
    let mut t = 0.6;
    while t < seconds {
        s.push(step(
            t,
            P::DetectWorkpiece {
                belt: 1,
                position: [0.0; 6],
                valid_delay_cycles: 0,
            },
        ));
        t += 2.0;
    }
    s
}

/// The demo config as YAML text with the scripts for `seconds` of motion; `live` = the
/// config's `live` key (None: no feed); `lockstep`: every node in simulated time.
pub fn config(seconds: f64, live: Option<Value>, lockstep: bool) -> String {
    let text = std::fs::read_to_string(crate::workspace().join("launch-configs/demo.yaml"))
        .expect("demo.yaml");
    let mut root: Value = serde_yaml::from_str(&text).expect("demo.yaml parses");
    let map = root.as_mapping_mut().expect("mapping");
    match live {
        Some(v) => map.insert("live".into(), v),
        None => map.remove("live"),
    };
    let nodes = map
        .get_mut("nodes")
        .and_then(Value::as_sequence_mut)
        .expect("nodes");
    for n in nodes {
        let n = n.as_mapping_mut().expect("node entry");
        let script = match n.get("kind").and_then(Value::as_str) {
            Some("axis_node") => axis_script(seconds),
            Some("planar_node") => planar_script(seconds),
            Some("pickplace_node") => pickplace_script(seconds),
            _ => Vec::new(),
        };
        if !script.is_empty() {
            n.insert("script".into(), Value::Sequence(script));
        }
        if lockstep {
            n.insert("lockstep".into(), true.into());
        }
    }
    serde_yaml::to_string(&root).expect("YAML")
}

/// `launch-configs/ca_ring.yaml` in lockstep with a script: the three movers powered and
/// grouped (m1 front, m3 rear), the group enabled; m1 drives to 1500 mm and m3 to 1400 mm at
/// 500 mm/s (gap control keeps m3 and m2, which stands at 500 mm, 100 mm apart), so the
/// gaps change and one is held at its target.
pub fn ca_ring_config() -> String {
    use axis_engine::ca::{CaCommand, IdentInGroup, McLreal, MoveAbsoluteCa};
    let text = std::fs::read_to_string(crate::workspace().join("launch-configs/ca_ring.yaml"))
        .expect("ca_ring.yaml");
    let mut root: Value = serde_yaml::from_str(&text).expect("ca_ring.yaml parses");
    let mut script = Vec::new();
    for (i, m) in ["m1", "m2", "m3"].iter().enumerate() {
        script.push(step(0.0, power(m)));
        script.push(step(
            0.005,
            AxisCommand::Ca(CaCommand::AddAxisToGroup {
                group: "ring".into(),
                axis: m.to_string(),
                ident_in_group: IdentInGroup(i as u32 + 1),
            }),
        ));
    }
    script.push(step(
        0.01,
        AxisCommand::Ca(CaCommand::GroupEnable {
            group: "ring".into(),
        }),
    ));
    for (m, to) in [("m1", 1500.0), ("m3", 1400.0)] {
        script.push(step(
            0.1,
            AxisCommand::Ca(CaCommand::MoveAbsolute(MoveAbsoluteCa {
                axis: m.into(),
                position: McLreal::Value(to),
                velocity: McLreal::Value(500.0),
                gap: McLreal::Default,
                ..Default::default()
            })),
        ));
    }
    let node = root
        .get_mut("nodes")
        .and_then(Value::as_sequence_mut)
        .and_then(|n| n.first_mut())
        .and_then(Value::as_mapping_mut)
        .expect("the axis node");
    node.insert("script".into(), Value::Sequence(script));
    node.insert("lockstep".into(), true.into());
    serde_yaml::to_string(&root).expect("YAML")
}
