//! `tools/gen_python_types.py` (cyclonedds types for a Python DDS test peer) must serialize the
//! same values to the same CDR bytes as the Rust types.
//!
//! Needs a python3 with the `cyclonedds` package: `$MOTION_MSGS_PYTHON`, else `python3` on PATH.
//! Skipped with a message when there is none (set `MOTION_MSGS_REQUIRE_CYCLONEDDS=1` to fail).

use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::geometry_msgs::msg::Point;
use motion_msgs::deps::visualization_msgs::msg::{Marker, UVCoordinate};
use motion_msgs::{action, msg, srv};
use ros2_client::dds::rustdds::serialization::to_writer_with_rep_id;
use ros2_client::dds::rustdds::RepresentationIdentifier;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

fn cdr<T: serde::Serialize>(v: &T) -> Vec<u8> {
    let mut buf = Vec::new();
    to_writer_with_rep_id(&mut buf, v, RepresentationIdentifier::CDR_LE).expect("serialize");
    buf
}

/// The same values as the Rust side below, built from the generated Python classes.
const PY: &str = r#"
import sys
sys.path.insert(0, sys.argv[1] + '/tools')
import gen_python_types
T = gen_python_types.load_types(sys.argv[1])
def out(name, obj):
    b = obj.serialize()
    assert b[:2] == b'\x00\x01', 'expected XCDR1 little endian, got %r' % b[:4]
    pad = b[3] & 3
    print(name, b[4:len(b) - pad].hex())
out('time', T['builtin_interfaces/msg/Time'](sec=-3, nanosec=7))
out('axis_state', T['motion_msgs/msg/AxisState'](name='x', motion_state=2, set_pos=1.25,
    override=100.0, power_status=True, cmd_no=513))
arr = T['motion_msgs/msg/AxisStateArray']()
arr.axes = [T['motion_msgs/msg/AxisState'](name='a'), T['motion_msgs/msg/AxisState'](name='bc')]
out('axis_state_array', arr)
out('power_request', T['motion_msgs/srv/Power_Request'](axis='ax'))
g = T['motion_msgs/action/MoveAbsolute_SendGoal_Request']()
g.goal.axis = 'y'
g.goal.position = -2.0
out('send_goal', g)
m = T['visualization_msgs/msg/Marker'](ns='n', id=4, text='t')
m.points = [T['geometry_msgs/msg/Point'](x=1.0, y=2.0, z=3.0)]
m.texture.data = [1, 2, 3]
m.uv_coordinates = [T['visualization_msgs/msg/UVCoordinate'](u=0.5, v=0.25)]
m.mesh_file.filename = 'f'
out('marker', m)
"#;

fn python() -> Option<String> {
    let candidates = std::env::var("MOTION_MSGS_PYTHON")
        .into_iter()
        .chain(["python3".to_string()]);
    for p in candidates {
        let ok = Command::new(&p)
            .args(["-c", "import cyclonedds.idl"])
            .output()
            .is_ok_and(|o| o.status.success());
        if ok {
            return Some(p);
        }
    }
    None
}

#[test]
fn python_cyclonedds_types_serialize_like_rust() {
    let Some(py) = python() else {
        let msg = "no python3 with the cyclonedds package (set MOTION_MSGS_PYTHON)";
        assert!(
            std::env::var("MOTION_MSGS_REQUIRE_CYCLONEDDS").is_err(),
            "{msg}"
        );
        eprintln!("SKIPPED: {msg}");
        return;
    };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(&py)
        .args(["-c", PY])
        .arg(dir)
        .output()
        .expect("run python");
    assert!(
        out.status.success(),
        "python failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).expect("utf-8");
    let got: BTreeMap<&str, &str> = stdout.lines().filter_map(|l| l.split_once(' ')).collect();

    let axis = |name: &str| msg::AxisState {
        name: name.into(),
        ..Default::default()
    };
    let mut marker = Marker {
        ns: "n".into(),
        id: 4,
        text: "t".into(),
        points: vec![Point {
            x: 1.0,
            y: 2.0,
            z: 3.0,
        }],
        uv_coordinates: vec![UVCoordinate { u: 0.5, v: 0.25 }],
        ..Default::default()
    };
    marker.texture.data = vec![1, 2, 3];
    marker.mesh_file.filename = "f".into();
    let expected: Vec<(&str, Vec<u8>)> = vec![
        (
            "time",
            cdr(&Time {
                sec: -3,
                nanosec: 7,
            }),
        ),
        (
            "axis_state",
            cdr(&msg::AxisState {
                name: "x".into(),
                motion_state: 2,
                set_pos: 1.25,
                r#override: 100.0,
                power_status: true,
                cmd_no: 513,
                ..Default::default()
            }),
        ),
        (
            "axis_state_array",
            cdr(&msg::AxisStateArray {
                header: Default::default(),
                axes: vec![axis("a"), axis("bc")],
            }),
        ),
        (
            "power_request",
            cdr(&srv::PowerRequest {
                axis: "ax".into(),
                ..Default::default()
            }),
        ),
        (
            "send_goal",
            // ros2-client's own action wrapper around our goal type.
            cdr(&ros2_client::action::SendGoalRequest {
                goal_id: ros2_client::unique_identifier_msgs::UUID::ZERO,
                goal: action::MoveAbsoluteGoal {
                    axis: "y".into(),
                    position: -2.0,
                    ..Default::default()
                },
            }),
        ),
        ("marker", cdr(&marker)),
    ];
    for (name, bytes) in &expected {
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(
            got.get(name).copied(),
            Some(hex.as_str()),
            "{name}: python (left) vs rust (right)"
        );
    }
}
