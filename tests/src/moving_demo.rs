//! The demo machine moving by itself: `launch-configs/demo.yaml` with a command script per node
//! (`script:` in its entry), so tests see motion without a client: the live view test and the
//! replay-determinism test.

use axis_engine::Power;
use axis_engine::{AxisCommand, BufferMode, Direction, MoveAbsolute, MoveOptions, MoveVelocity};
use planar_engine::{DynamicConstraint, MoveToPositionOptions, PlanarCommand, PositionXYC};
use serde_yaml::{Mapping, Value};

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
        .map(|a| {
            step(
                0.0,
                AxisCommand::Power(Power {
                    axis: a.to_string(),
                    enable: true,
                    enable_positive: true,
                    enable_negative: true,
                    override_percent: 100.0,
                    buffer_mode: BufferMode::Aborting,
                }),
            )
        })
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
/// row at 40 mm/s (a leg every 5 s, so it never rests), for `seconds`.
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
                    velocity: 40.0,
                    ..Default::default()
                },
                options: MoveToPositionOptions::default(),
            },
        ));
        t += 5.0;
        k += 1;
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
