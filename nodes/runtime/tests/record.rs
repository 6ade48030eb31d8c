//! A recording (`motion_runtime::record`) is an MCAP file of the ROS 2 profile that the PyPI
//! readers (`mcap` with `mcap-ros2-support`, what Foxglove's tooling uses) open and decode:
//! header profile `ros2`, one `ros2msg` schema per type, one `cdr` channel per topic, every
//! message with its time and sequence number, the values as written; its chunks uncompressed
//! (the default, as `ros2 bag record -s mcap` writes them) or compressed with zstd.
//!
//! Needs a python3 with `mcap_ros2` (`$MOTION_MSGS_PYTHON`, else `python3`); skipped with a
//! message when there is none, unless `MOTION_MSGS_REQUIRE_MCAP` is set (the test command).

use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::sensor_msgs::msg::JointState;
use motion_msgs::deps::std_msgs::msg::Header;
use motion_msgs::msg;
use motion_runtime::record::{Compression, RecordError, Recording};
use std::process::Command;

const PY: &str = r#"
import sys
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
with open(sys.argv[1], 'rb') as f:
    r = make_reader(f, decoder_factories=[DecoderFactory()])
    print('profile', r.get_header().profile)
    s = r.get_summary()
    print('channels', len(s.channels), 'schemas', len(s.schemas), 'messages', s.statistics.message_count)
    print('chunks', ' '.join(sorted({c.compression or '(none)' for c in s.chunk_indexes})))
    for schema, channel, message, m in r.iter_decoded_messages(log_time_order=True):
        if schema.name == 'sensor_msgs/msg/JointState':
            v = ' '.join('%g' % p for p in m.position)
        else:
            v = ' '.join('%s=%g' % (a.name, a.set_pos) for a in m.axes)
        print(channel.topic, schema.name, schema.encoding, channel.message_encoding,
              message.log_time, message.sequence, v)
"#;

fn python() -> Option<String> {
    let candidates = std::env::var("MOTION_MSGS_PYTHON")
        .into_iter()
        .chain(["python3".to_string()]);
    candidates.into_iter().find(|p| {
        Command::new(p)
            .args(["-c", "import mcap_ros2.decoder"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

fn joints(t_ms: u64, x: f64) -> JointState {
    JointState {
        header: Header {
            stamp: Time {
                sec: (t_ms / 1000) as i32,
                nanosec: ((t_ms % 1000) * 1_000_000) as u32,
            },
            frame_id: "axes_base".into(),
        },
        name: vec!["x".into(), "y".into()],
        position: vec![x, -x],
        ..Default::default()
    }
}

fn axes(names_pos: &[(&str, f64)]) -> msg::AxisStateArray {
    msg::AxisStateArray {
        header: Default::default(),
        axes: names_pos
            .iter()
            .map(|&(n, p)| msg::AxisState {
                name: n.into(),
                set_pos: p,
                ..Default::default()
            })
            .collect(),
    }
}

#[test]
fn an_uncompressed_recording_reads_back_with_the_pypi_readers() {
    reads_back(Compression::None, "(none)");
}

#[test]
fn a_zstd_recording_reads_back_with_the_pypi_readers() {
    reads_back(Compression::Zstd, "zstd");
}

/// Writes a short recording with `compression`, reads it back with the PyPI readers, which
/// must find its chunks compressed as `chunks` says.
fn reads_back(compression: Compression, chunks: &str) {
    let dir = std::env::temp_dir().join(format!("motion_record_{}_{chunks}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.mcap");
    let mut rec = Recording::create(&path, compression).expect("create");
    let js = "sensor_msgs/msg/JointState";
    let st = "motion_msgs/msg/AxisStateArray";
    rec.write("/joint_states", js, 1_000_000, &joints(1, 0.5))
        .unwrap();
    rec.write(
        "/axis_node/axis_states",
        st,
        1_000_000,
        &axes(&[("x", 0.5)]),
    )
    .unwrap();
    rec.write("/joint_states", js, 2_000_000, &joints(2, 0.75))
        .unwrap();
    rec.write(
        "/axis_node/axis_states",
        st,
        2_000_000,
        &axes(&[("x", 0.75), ("y", -1.0)]),
    )
    .unwrap();
    rec.write("/joint_states", js, 3_000_000, &joints(3, 1.0))
        .unwrap();
    // A type without a definition, and a topic that changes its type, are refused.
    assert!(matches!(
        rec.write("/x", "motion_msgs/msg/NoSuchType", 0, &0u8),
        Err(RecordError::UnknownType(_))
    ));
    assert!(matches!(
        rec.write("/joint_states", st, 4_000_000, &axes(&[])),
        Err(RecordError::TypeChanged { .. })
    ));
    rec.finish().expect("finish");

    let Some(py) = python() else {
        let msg = "no python3 with the mcap-ros2-support package (set MOTION_MSGS_PYTHON)";
        assert!(std::env::var("MOTION_MSGS_REQUIRE_MCAP").is_err(), "{msg}");
        eprintln!("SKIPPED: {msg}");
        return;
    };
    let out = Command::new(&py)
        .args(["-c", PY])
        .arg(&path)
        .output()
        .expect("run python");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.status.success(),
        "python failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let got = String::from_utf8_lossy(&out.stdout);
    let want = format!(
        "\
profile ros2
channels 2 schemas 2 messages 5
chunks {chunks}
/joint_states sensor_msgs/msg/JointState ros2msg cdr 1000000 1 0.5 -0.5
/axis_node/axis_states motion_msgs/msg/AxisStateArray ros2msg cdr 1000000 1 x=0.5
/joint_states sensor_msgs/msg/JointState ros2msg cdr 2000000 2 0.75 -0.75
/axis_node/axis_states motion_msgs/msg/AxisStateArray ros2msg cdr 2000000 2 x=0.75 y=-1
/joint_states sensor_msgs/msg/JointState ros2msg cdr 3000000 3 1 -1
"
    );
    assert_eq!(got, want);
}
