//! The `ros2msg` definitions of [`motion_msgs::message_definition`] are what a recording's MCAP
//! schemas and a live feed's channels carry: a reader that knows nothing but the definition
//! must decode our CDR bytes to the values we encoded. The reader here is the PyPI package
//! `mcap-ros2-support` (the decoder of the `mcap` tools, as Foxglove's): every definition must
//! parse, and samples of our state topics must decode field by field.
//!
//! Needs a python3 with `mcap_ros2`: `$MOTION_MSGS_PYTHON`, else `python3` on PATH. Skipped with
//! a message when there is none (set `MOTION_MSGS_REQUIRE_MCAP=1` to fail instead; the README's
//! test command does).

use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus, KeyValue};
use motion_msgs::deps::geometry_msgs::msg::Point;
use motion_msgs::deps::sensor_msgs::msg::JointState;
use motion_msgs::deps::std_msgs::msg::Header;
use motion_msgs::deps::visualization_msgs::msg::{Marker, MarkerArray};
use motion_msgs::{message_definition, msg, RosType, MESSAGE_DEFINITIONS};
use ros2_client::dds::rustdds::serialization::to_writer_with_rep_id;
use ros2_client::dds::rustdds::RepresentationIdentifier;
use std::path::PathBuf;
use std::process::Command;

/// A message as it travels (and is recorded): the 4-byte encapsulation header (CDR_LE, no
/// options), then the CDR body.
fn cdr<T: serde::Serialize>(v: &T) -> Vec<u8> {
    let mut buf = vec![0x00, 0x01, 0x00, 0x00];
    to_writer_with_rep_id(&mut buf, v, RepresentationIdentifier::CDR_LE).expect("serialize");
    buf
}

/// Decodes each sample `i` (files `i.type`, `i.def`, `i.cdr`, `i.check`) with a decoder built
/// from the definition alone and evaluates the check expressions on it (`m` = the message);
/// then builds a decoder from every definition of the table (`all.tsv`).
const PY: &str = concat!(
    include_str!("feedback_names.py"),
    r#"
import os, sys
from mcap_ros2._dynamic import generate_dynamic
d = sys.argv[1]
n = 0
for f in sorted(os.listdir(d)):
    if not f.endswith('.type'):
        continue
    i = f[:-5]
    name = open(os.path.join(d, i + '.type')).read()
    text = open(os.path.join(d, i + '.def'), encoding='utf-8').read()
    data = open(os.path.join(d, i + '.cdr'), 'rb').read()
    name, text = parsable(name, text)
    m = generate_dynamic(name, text)[name](data)
    for line in open(os.path.join(d, i + '.check'), encoding='utf-8').read().splitlines():
        if not eval(line, {}, {'m': m}):
            raise SystemExit('%s: check failed: %s (decoded: %r)' % (name, line, m))
    n += 1
k = 0
for row in open(os.path.join(d, 'all.tsv'), encoding='utf-8').read().split('\x1e'):
    if not row:
        continue
    name, text = row.split('\x1f', 1)
    generate_dynamic(*parsable(name, text))
    k += 1
print('decoded', n, 'parsed', k)
"#
);

fn python() -> Option<String> {
    let candidates = std::env::var("MOTION_MSGS_PYTHON")
        .into_iter()
        .chain(["python3".to_string()]);
    candidates.into_iter().find(|p| {
        Command::new(p)
            .args(["-c", "import mcap_ros2._dynamic"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// `<pkg>/action/<Name>_FeedbackMessage` as an action server publishes it.
#[derive(serde::Serialize)]
struct FeedbackMessage<F> {
    goal_id: [u8; 16],
    feedback: F,
}

struct Sample {
    ty: &'static str,
    cdr: Vec<u8>,
    checks: Vec<String>,
}

fn sample<T: serde::Serialize + RosType>(v: &T, checks: &[&str]) -> Sample {
    Sample {
        ty: T::ROS_TYPE_NAME,
        cdr: cdr(v),
        checks: checks.iter().map(|s| s.to_string()).collect(),
    }
}

#[test]
fn the_table_is_sorted_and_holds_every_message_with_its_dependencies() {
    assert!(MESSAGE_DEFINITIONS.windows(2).all(|w| w[0].0 < w[1].0));
    let state = message_definition("motion_msgs/msg/AxisStateArray").expect("AxisStateArray");
    assert!(state.starts_with(include_str!("../msg/AxisStateArray.msg")));
    // Each type it uses once, after its separator; AxisState's own uses follow it.
    let sep = format!("{}\nMSG: ", "=".repeat(80));
    let used: Vec<&str> = state
        .split(sep.as_str())
        .skip(1)
        .map(|s| s.lines().next().unwrap_or(""))
        .collect();
    assert!(used.contains(&"builtin_interfaces/Time"), "{used:?}");
    assert!(used.contains(&"motion_msgs/AxisState"), "{used:?}");
    let mut sorted = used.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), used.len(), "a dependency twice: {used:?}");
    assert!(message_definition("motion_msgs/msg/NoSuchType").is_none());
    assert!(message_definition("sensor_msgs/msg/JointState").is_some());
    assert!(message_definition("visualization_msgs/msg/MarkerArray").is_some());
}

#[test]
fn a_reader_with_only_the_definition_decodes_our_messages() {
    let Some(py) = python() else {
        let msg = "no python3 with the mcap-ros2-support package (set MOTION_MSGS_PYTHON)";
        assert!(std::env::var("MOTION_MSGS_REQUIRE_MCAP").is_err(), "{msg}");
        eprintln!("SKIPPED: {msg}");
        return;
    };
    let stamp = Time {
        sec: 12,
        nanosec: 345,
    };
    let samples = [
        sample(
            &msg::AxisStateArray {
                header: Header {
                    stamp: stamp.clone(),
                    frame_id: String::new(),
                },
                axes: vec![
                    msg::AxisState {
                        name: "x".into(),
                        motion_state: 6,
                        set_pos: 1.25,
                        power_status: true,
                        cmd_no: 513,
                        ..Default::default()
                    },
                    msg::AxisState {
                        name: "yz".into(),
                        set_pos: -3.5,
                        ..Default::default()
                    },
                ],
            },
            &[
                "m.header.stamp.sec == 12 and m.header.stamp.nanosec == 345",
                "[a.name for a in m.axes] == ['x', 'yz']",
                "m.axes[0].motion_state == 6 and m.axes[0].set_pos == 1.25",
                "m.axes[0].power_status is True and m.axes[0].cmd_no == 513",
                "m.axes[1].set_pos == -3.5",
            ],
        ),
        sample(
            &JointState {
                header: Header {
                    stamp: stamp.clone(),
                    frame_id: "axes_base".into(),
                },
                name: vec!["x".into(), "y".into()],
                position: vec![0.5, -0.25],
                velocity: vec![1.0, 0.0],
                effort: vec![],
            },
            &[
                "m.header.frame_id == 'axes_base'",
                "list(m.name) == ['x', 'y']",
                "list(m.position) == [0.5, -0.25] and list(m.velocity) == [1.0, 0.0]",
                "len(m.effort) == 0",
            ],
        ),
        sample(
            &MarkerArray {
                markers: vec![Marker {
                    ns: "movers".into(),
                    id: 7,
                    text: "m1".into(),
                    points: vec![Point {
                        x: 1.0,
                        y: 2.0,
                        z: 3.0,
                    }],
                    ..Default::default()
                }],
            },
            &[
                "m.markers[0].ns == 'movers' and m.markers[0].id == 7",
                "m.markers[0].text == 'm1'",
                "(m.markers[0].points[0].x, m.markers[0].points[0].z) == (1.0, 3.0)",
            ],
        ),
        sample(
            &msg::PlanarState {
                header: Header {
                    stamp,
                    frame_id: String::new(),
                },
                movers: vec![msg::PlanarMoverState {
                    name: "m1".into(),
                    oid: 0x0106_0001,
                    state: 3,
                    ..Default::default()
                }],
                ..Default::default()
            },
            &[
                "m.movers[0].name == 'm1' and m.movers[0].oid == 0x01060001",
                "m.movers[0].state == 3 and len(m.tracks) == 0",
                "m.header.stamp.sec == 12 and m.header.frame_id == ''",
            ],
        ),
        sample(
            &DiagnosticArray {
                header: Header::default(),
                status: vec![DiagnosticStatus {
                    level: 1,
                    name: "axis_node: cycle".into(),
                    message: "overruns".into(),
                    hardware_id: "sim".into(),
                    values: vec![KeyValue {
                        key: "overruns".into(),
                        value: "3".into(),
                    }],
                }],
            },
            &[
                "m.status[0].name == 'axis_node: cycle'",
                "m.status[0].values[0].key == 'overruns' and m.status[0].values[0].value == '3'",
            ],
        ),
        // An action's feedback as its topic carries it: the goal's UUID, then the feedback.
        Sample {
            ty: "motion_msgs/action/MoveAbsolute_FeedbackMessage",
            cdr: cdr(&FeedbackMessage {
                goal_id: std::array::from_fn(|i| i as u8),
                feedback: motion_msgs::action::MoveAbsoluteFeedback {
                    busy: true,
                    active: true,
                    position: 12.5,
                    velocity: -3.0,
                    order_id: 7,
                    axis_state: 6,
                },
            }),
            checks: vec![
                "bytes(m.goal_id.uuid) == bytes(range(16))".into(),
                "m.feedback.busy and m.feedback.position == 12.5".into(),
                "m.feedback.velocity == -3.0 and m.feedback.axis_state == 6".into(),
            ],
        },
    ];
    let dir = std::env::temp_dir().join(format!("motion_msgs_defs_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = |i: usize, ext: &str| -> PathBuf { dir.join(format!("{i:02}.{ext}")) };
    for (i, s) in samples.iter().enumerate() {
        let def = message_definition(s.ty).unwrap_or_else(|| panic!("no definition of {}", s.ty));
        std::fs::write(path(i, "type"), s.ty).unwrap();
        std::fs::write(path(i, "def"), def).unwrap();
        std::fs::write(path(i, "cdr"), &s.cdr).unwrap();
        std::fs::write(path(i, "check"), s.checks.join("\n")).unwrap();
    }
    let all: String = MESSAGE_DEFINITIONS
        .iter()
        .map(|(name, text)| format!("{name}\x1f{text}\x1e"))
        .collect();
    std::fs::write(dir.join("all.tsv"), all).unwrap();
    let out = Command::new(&py)
        .args(["-c", PY])
        .arg(&dir)
        .output()
        .expect("run python");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.status.success(),
        "python failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        stdout.trim(),
        format!(
            "decoded {} parsed {}",
            samples.len(),
            MESSAGE_DEFINITIONS.len()
        )
    );
}
