//! `motion_launch CONFIG --record FILE` (issue 14 item 3): the demo's three nodes recorded to an
//! MCAP file of the ROS 2 profile that the PyPI readers (`mcap` + `mcap-ros2-support`) decode
//! message by message, every state topic of every node on its own channel with its ROS type.
//! A file that cannot be created is a configuration error (exit 2) before any node starts; one
//! that fails while the run goes ends it with exit 1 and the cause.
//! `--cycles N` runs lockstep nodes N cycles without any client and records every cycle
//! (issue 14 item 4).
//!
//! Needs a python3 with `mcap_ros2` (`$MOTION_MSGS_PYTHON`, else `python3`); skipped with a
//! message when there is none, unless `MOTION_MSGS_REQUIRE_MCAP` is set (the test command).

use motion_msgs::action::{
    MoveAbsolute as MoveAbsoluteAction, MoveAbsoluteFeedback, MoveAbsoluteGoal, MoveAbsoluteResult,
};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::ServiceMapping;
use std::process::Command;
use system_tests::{launcher_bin, require_netns, unique_domain, within, workspace, ClientNode};

const PY: &str = concat!(
    include_str!("../../msgs/tests/feedback_names.py"),
    r#"
import sys
from collections import Counter
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from mcap_ros2._dynamic import generate_dynamic

class Factory(DecoderFactory):
    """mcap_ros2's decoder, which also takes an action's feedback (see `parsable`)."""
    def decoder_for(self, message_encoding, schema):
        if schema is None or not schema.name.endswith('_FeedbackMessage'):
            return super().decoder_for(message_encoding, schema)
        assert message_encoding == 'cdr' and schema.encoding == 'ros2msg'
        name, text = parsable(schema.name, schema.data.decode())
        return generate_dynamic(name, text)[name]

count = Counter()
joints = set()
feedback = None
params = {}
with open(sys.argv[1], 'rb') as f:
    r = make_reader(f, decoder_factories=[Factory()])
    print('profile', r.get_header().profile)
    chunks = {c.compression or '(none)' for c in r.get_summary().chunk_indexes}
    print('chunks', ' '.join(sorted(chunks)))
    for schema, channel, message, m in r.iter_decoded_messages(log_time_order=True):
        assert schema.encoding == 'ros2msg' and channel.message_encoding == 'cdr'
        count[(channel.topic, schema.name)] += 1
        if channel.topic == '/joint_states':
            joints.update(m.name)
        if channel.topic.endswith('/_action/feedback'):
            feedback = (bytes(m.goal_id.uuid).hex(), m.feedback.position)
        if channel.topic == '/parameter_events':
            for p in m.new_parameters:
                v = p.value
                value = [None, v.bool_value, v.integer_value, v.double_value, v.string_value][v.type] if v.type <= 4 else v.type
                params.setdefault(m.node, []).append(f'{p.name}={value}')
for (topic, ty), n in sorted(count.items()):
    print(topic, ty, n)
print('joints', ' '.join(sorted(joints)))
for node, ps in sorted(params.items()):
    print('parameters', node, ' '.join(ps))
if feedback:
    print('feedback', feedback[0], feedback[1])
"#
);

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

/// `dir/ten_axes.yaml`: one lockstep axis node with axes a0 … a9 and the entry lines `extra`.
fn ten_axes_config(dir: &std::path::Path, extra: &str) -> std::path::PathBuf {
    let config = dir.join("ten_axes.yaml");
    let axes: Vec<String> = (0..10).map(|i| format!("a{i}: {{}}")).collect();
    std::fs::write(
        &config,
        format!(
            "nodes:\n  - kind: axis_node\n    lockstep: true\n{extra}    axes: {{{}}}\n",
            axes.join(", ")
        ),
    )
    .unwrap();
    config
}

/// A fresh directory for this test process's files (`name` + pid under the temp dir).
fn scratch_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `motion_launch CONFIG ARGS…` in this test's domain, logging warnings only.
fn launch(config: &std::path::Path, args: &[&str]) -> std::process::Output {
    Command::new(launcher_bin())
        .arg(config)
        .args(args)
        .env("ROS_DOMAIN_ID", unique_domain().to_string())
        .env("RUST_LOG", "warn")
        .output()
        .expect("motion_launch")
}

/// What the PyPI readers make of the recording (`PY`'s lines); None when there is no python
/// with them (skipped, unless `MOTION_MSGS_REQUIRE_MCAP` is set).
fn read_back(file: &std::path::Path) -> Option<String> {
    read_back_with(file, PY)
}

/// [`read_back`] with another script (`sys.argv[1]` is the file).
fn read_back_with(file: &std::path::Path, script: &str) -> Option<String> {
    let Some(py) = python() else {
        let msg = "no python3 with the mcap-ros2-support package (set MOTION_MSGS_PYTHON)";
        assert!(std::env::var("MOTION_MSGS_REQUIRE_MCAP").is_err(), "{msg}");
        eprintln!("SKIPPED: {msg}");
        return None;
    };
    let read = Command::new(&py)
        .args(["-c", script])
        .arg(file)
        .output()
        .expect("run python");
    assert!(
        read.status.success(),
        "python failed:\n{}",
        String::from_utf8_lossy(&read.stderr)
    );
    Some(String::from_utf8_lossy(&read.stdout).into_owned())
}

#[test]
fn the_demo_records_every_state_topic_to_mcap() {
    require_netns();
    let dir = scratch_dir("motion_recording");
    let file = dir.join("demo.mcap");
    let out = Command::new(launcher_bin())
        .arg(workspace().join("launch-configs/demo.yaml"))
        .args(["--duration", "2", "--record"])
        .arg(&file)
        .env("ROS_DOMAIN_ID", unique_domain().to_string())
        .env("RUST_LOG", "info,rustdds=error,ros2_client=error")
        .output()
        .expect("motion_launch");
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "motion_launch failed:\n{log}");
    assert!(
        log.contains("recording closed:") && log.contains("(0 dropped)"),
        "{log}"
    );

    let got = read_back(&file);
    let _ = std::fs::remove_dir_all(&dir);
    let Some(got) = got else { return };
    assert!(got.starts_with("profile ros2\n"), "{got}");
    // Chunks uncompressed, as `ros2 bag record -s mcap` writes them by default.
    assert!(got.contains("\nchunks (none)\n"), "{got}");
    let count = |topic: &str, ty: &str| -> u64 {
        got.lines()
            .find_map(|l| {
                let mut w = l.split(' ');
                (w.next() == Some(topic) && w.next() == Some(ty))
                    .then(|| w.next().and_then(|n| n.parse().ok()))
                    .flatten()
            })
            .unwrap_or(0)
    };
    // Every node's state topics, at their state rate over about 2 s (the demo publishes at
    // 100 Hz on the axis node and 50 Hz on the others; at least a third of that is asked).
    for (topic, ty, at_least) in [
        (
            "/axis_node/axis_states",
            "motion_msgs/msg/AxisStateArray",
            60,
        ),
        ("/joint_states", "sensor_msgs/msg/JointState", 60),
        ("/planar_node/state", "motion_msgs/msg/PlanarState", 30),
        (
            "/planar_node/markers",
            "visualization_msgs/msg/MarkerArray",
            30,
        ),
        (
            "/pickplace_node/state",
            "motion_msgs/msg/PickPlaceState",
            30,
        ),
        (
            "/pickplace_node/markers",
            "visualization_msgs/msg/MarkerArray",
            30,
        ),
        ("/diagnostics", "diagnostic_msgs/msg/DiagnosticArray", 3),
        ("/tf_static", "tf2_msgs/msg/TFMessage", 3),
        // Each node's "node started" line at least.
        ("/rosout", "rcl_interfaces/msg/Log", 3),
        // Each node's declaration of its parameters.
        ("/parameter_events", "rcl_interfaces/msg/ParameterEvent", 3),
    ] {
        let n = count(topic, ty);
        assert!(
            n >= at_least,
            "{topic}: {n} messages, expected >= {at_least}:\n{got}"
        );
    }
    assert!(got.contains("joints table x y"), "{got}");
    // The declarations carry the launch config's settings (demo.yaml: the axis node cycles
    // every 1 ms and publishes at 100 Hz; the planar node's movers).
    let parameters = |node: &str| -> Vec<&str> {
        got.lines()
            .find_map(|l| l.strip_prefix(&format!("parameters {node} ")))
            .map(|l| l.split(' ').collect())
            .unwrap_or_default()
    };
    let axis = parameters("/axis_node");
    for p in ["cycle_period=0.001", "state_rate=100.0", "lockstep=False"] {
        assert!(axis.contains(&p), "/axis_node declared {axis:?}:\n{got}");
    }
    assert!(
        parameters("/planar_node")
            .iter()
            .any(|p| p.starts_with("movers=")),
        "{got}"
    );
    assert!(!parameters("/pickplace_node").is_empty(), "{got}");
}

#[test]
fn a_recording_that_cannot_be_created_is_a_configuration_error() {
    require_netns();
    let out = Command::new(launcher_bin())
        .arg(workspace().join("launch-configs/demo.yaml"))
        .args(["--duration", "1", "--record", "/nonexistent-dir/run.mcap"])
        .env("ROS_DOMAIN_ID", unique_domain().to_string())
        .output()
        .expect("motion_launch");
    let log = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{log}");
    assert!(
        log.contains("cannot record to /nonexistent-dir/run.mcap"),
        "{log}"
    );
    assert!(!log.contains("node started"), "{log}");
}

/// A recording that fails while the run goes (`/dev/full`: no space left on the device) stops
/// recording, lets the run end (a lockstep run's cycles wait for the recording: they must not
/// wait for a writer that has given up) and ends it with exit 1 and the cause.
#[test]
fn a_recording_that_cannot_be_written_ends_the_run_with_its_cause() {
    require_netns();
    let dir = scratch_dir("motion_recording_full");
    let config = ten_axes_config(&dir, "");
    let out = launch(&config, &["--cycles", "3000", "--record", "/dev/full"]);
    let _ = std::fs::remove_dir_all(&dir);
    let log = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("axis_node: ran 3000 cycles"),
        "{stdout}\n{log}"
    );
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(
        log.contains("motion_launch: recording: ") && log.contains("No space left on device"),
        "{log}"
    );
}

/// The config key `record:` records too (here with `record_compression: zstd`); with a
/// client's orders the node's `~/events`, `~/command_status`, `/rosout`, an action's feedback
/// (`<Name>_FeedbackMessage`: the goal's id and the feedback) and its status are in the
/// recording as well, and the Foxglove app's reader decompresses and decodes every channel.
#[test]
fn the_launch_config_key_records_events_and_command_status() {
    require_netns();
    let dir = scratch_dir("motion_recording_key");
    let file = dir.join("key.mcap");
    let config = dir.join("one_axis.yaml");
    std::fs::write(
        &config,
        format!(
            "record: {}\nrecord_compression: zstd\nnodes:\n  - kind: axis_node\n    service_mapping: enhanced\n    state_rate: 50\n    axes: {{x: {{}}}}\n",
            file.display()
        ),
    )
    .unwrap();
    let domain = unique_domain();
    let child = Command::new(launcher_bin())
        .arg(&config)
        .args(["--duration", "10"])
        .env("ROS_DOMAIN_ID", domain.to_string())
        .env("RUST_LOG", "info,rustdds=error,ros2_client=error")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("motion_launch");
    let rt = tokio::runtime::Runtime::new().unwrap();
    let goal_id = rt.block_on(async {
        use motion_msgs::srv::{Reset, ResetRequest, ResetResponse};
        let mut c = ClientNode::new(domain, "recording_client", ServiceMapping::Enhanced);
        c.power_on("x").await;
        let reset = c
            .client::<ResetRequest, ResetResponse>("/axis_node/reset", Reset::service_type_name())
            .await;
        let r = within(
            10.0,
            "reset",
            reset.async_call_service(ResetRequest { axis: "x".into() }),
        )
        .await
        .expect("reset reply");
        assert!(r.accepted, "reset: {}", r.message);
        let ac = c
            .action::<MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback>(
                "/axis_node/move_absolute",
                &MoveAbsoluteAction::action_type_name(),
            )
            .await;
        let goal = MoveAbsoluteGoal {
            axis: "x".into(),
            position: 50.0,
            velocity: 100.0,
            ..Default::default()
        };
        let (gid, resp) = system_tests::send_goal(&ac, "move_absolute", goal).await;
        assert!(resp.accepted, "goal accepted");
        let (status, result) = within(20.0, "move result", ac.async_request_result(gid))
            .await
            .expect("result");
        assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
        gid.uuid.simple().to_string()
    });
    let out = child.wait_with_output().expect("motion_launch");
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "motion_launch failed:\n{log}");
    assert!(log.contains("recording closed:"), "{log}");
    let head = std::fs::read(&file).expect("the recording exists");
    // MCAP magic, then the Header record (op 0x01) whose profile is "ros2".
    assert_eq!(&head[..8], b"\x89MCAP0\r\n");
    assert_eq!(head[8], 0x01);
    assert_eq!(&head[17..21], &4u32.to_le_bytes());
    assert_eq!(&head[21..25], b"ros2");
    // The Foxglove app's own decoders take every message of every channel, the action's
    // feedback included.
    if system_tests::foxglove::ready() {
        let fox = system_tests::foxglove::decode(&["mcap", &file.to_string_lossy()]);
        assert_eq!(fox.chunks.as_deref(), Some("zstd"), "{fox:?}");
        let fb = &fox["/axis_node/move_absolute/_action/feedback"];
        assert_eq!(fb.schema, "motion_msgs/action/MoveAbsolute_FeedbackMessage");
        assert!(
            fb.count > 0 && fb.last["feedback"]["position"].as_f64() > Some(0.0),
            "{fb:?}"
        );
        assert!(
            fox["/rosout"].count > 0 && fox["/axis_node/events"].count > 0,
            "{fox:?}"
        );
        // The action's status as the server published it last: the goal SUCCEEDED (4).
        let status = &fox["/axis_node/move_absolute/_action/status"];
        assert_eq!(status.schema, "action_msgs/msg/GoalStatusArray");
        let ours = status.last["status_list"].as_array().and_then(|l| {
            l.iter().find(|g| {
                let uuid = g["goal_info"]["goal_id"]["uuid"].as_array();
                let hex: String = uuid
                    .into_iter()
                    .flatten()
                    .map(|b| format!("{:02x}", b.as_u64().unwrap_or(256)))
                    .collect();
                hex == goal_id
            })
        });
        assert_eq!(
            ours.map(|g| g["status"].clone()),
            Some(4.into()),
            "{status:?}"
        );
        assert_eq!(fox["/axis_node/axis_states"].last["axes"][0]["name"], "x");
    }
    let got = read_back(&file);
    let _ = std::fs::remove_dir_all(&dir);
    let Some(got) = got else { return };
    for topic in [
        "/axis_node/events motion_msgs/msg/AxisEvent ",
        "/axis_node/command_status motion_msgs/msg/CommandStatus ",
        "/axis_node/axis_states motion_msgs/msg/AxisStateArray ",
        "/rosout rcl_interfaces/msg/Log ",
        "/axis_node/move_absolute/_action/feedback motion_msgs/action/MoveAbsolute_FeedbackMessage ",
        "/axis_node/move_absolute/_action/status action_msgs/msg/GoalStatusArray ",
    ] {
        assert!(got.contains(topic), "{topic}missing:\n{got}");
    }
    // The last feedback of the goal: its id, the axis on the way to 50 mm or there.
    let fb: Vec<&str> = got
        .lines()
        .find(|l| l.starts_with("feedback "))
        .map(|l| l.split(' ').collect())
        .unwrap_or_default();
    assert_eq!(fb.get(1), Some(&goal_id.as_str()), "{got}");
    let position: f64 = fb.get(2).and_then(|p| p.parse().ok()).unwrap_or(f64::NAN);
    assert!(position > 0.0 && position <= 50.0 + 1e-9, "{got}");
}

/// The stamps of `~/axis_states` in the recording: count, first, smallest and largest step
/// [ns].
const PY_STAMPS: &str = r#"
import sys
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
t = []
with open(sys.argv[1], 'rb') as f:
    r = make_reader(f, decoder_factories=[DecoderFactory()])
    for schema, channel, message, m in r.iter_decoded_messages(topics=['/axis_node/axis_states'], log_time_order=True):
        t.append(m.header.stamp.sec * 1000000000 + m.header.stamp.nanosec)
        assert len(m.axes) == 10
d = [b - a for a, b in zip(t, t[1:])]
print(len(t), t[0], min(d), max(d))
"#;

/// Issue 14 item 4: a lockstep node runs `--cycles N` with no client stepping it over DDS, and
/// every cycle's state is recorded, whatever `state_rate` says: the states of cycles 0 … N,
/// 1 ms apart in simulated time from 0, none lost when the run ends.
#[test]
fn cycles_run_lockstep_nodes_without_a_client_and_record_every_cycle() {
    require_netns();
    let dir = scratch_dir("motion_recording_cycles");
    let file = dir.join("cycles.mcap");
    let config = ten_axes_config(&dir, "    state_rate: 10\n");
    let n = 3000;
    let out = Command::new(launcher_bin())
        .arg(&config)
        .args(["--cycles", &n.to_string(), "--record"])
        .arg(&file)
        .env("ROS_DOMAIN_ID", unique_domain().to_string())
        .env("RUST_LOG", "info,rustdds=error,ros2_client=error")
        .output()
        .expect("motion_launch");
    let log = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "motion_launch failed:\n{log}");
    assert!(
        stdout.contains(&format!("axis_node: ran {n} cycles (3.000 s simulated)")),
        "{stdout}"
    );
    eprintln!("{stdout}");
    assert!(log.contains("(0 dropped)"), "{log}");
    let got = read_back_with(&file, PY_STAMPS);
    let _ = std::fs::remove_dir_all(&dir);
    let Some(got) = got else { return };
    let v: Vec<i64> = got.split_whitespace().map(|x| x.parse().unwrap()).collect();
    let (count, first, dmin, dmax) = (v[0], v[1], v[2], v[3]);
    assert_eq!(count, n + 1, "states of cycles 0 ..= {n}");
    assert_eq!(
        (dmin, dmax),
        (1_000_000, 1_000_000),
        "stamps not 1 ms apart"
    );
    assert_eq!(first, 0, "first stamp");
}

/// `--record-topics` (config key `record_topics`) records only the topics named, every cycle
/// of them; the others are not even built in such a run. Names must be absolute (also those
/// of `--record-exclude-topics`), lists not empty.
/// `--record-compression zstd` (config key `record_compression`) compresses the chunks; a
/// compression other than none or zstd is refused.
#[test]
fn record_topics_take_only_the_topics_named() {
    require_netns();
    let dir = scratch_dir("motion_record_topics");
    let file = dir.join("some.mcap");
    let config = ten_axes_config(&dir, "");
    let run = |args: &[&str]| launch(&config, args);
    let f = file.to_string_lossy().to_string();
    let out = run(&[
        "--cycles",
        "500",
        "--record",
        &f,
        "--record-topics",
        "/joint_states,/axis_node/axes/a3/state",
        "--record-compression",
        "zstd",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (args, needle) in [
        (
            vec!["--check", "--record-topics", "joint_states"],
            "'joint_states' is not an absolute topic name",
        ),
        (
            vec!["--check", "--record-topics"],
            "--record-topics needs topic names",
        ),
        (
            vec!["--check", "--record-compression", "lz4"],
            "--record-compression: unknown compression 'lz4' (one of: none, zstd)",
        ),
        (
            vec!["--check", "--record-compression"],
            "--record-compression needs one of: none, zstd",
        ),
        (
            vec!["--check", "--record-exclude-topics", "joint_states"],
            "--record-exclude-topics: 'joint_states' is not an absolute topic name",
        ),
        (
            vec!["--check", "--record-exclude-topics"],
            "--record-exclude-topics needs topic names",
        ),
    ] {
        let bad = run(&args);
        let log = String::from_utf8_lossy(&bad.stderr);
        assert_eq!(bad.status.code(), Some(2), "{args:?}: {log}");
        assert!(log.contains(needle), "{args:?}: {log}");
    }
    for (key, needle) in [
        (
            "record_topics: []",
            "record_topics: expected at least one topic",
        ),
        (
            "record_compression: 3",
            "record_compression: expected one of: none, zstd",
        ),
        (
            "record_exclude_topics: []",
            "record_exclude_topics: expected at least one topic",
        ),
    ] {
        std::fs::write(
            dir.join("key.yaml"),
            format!("{key}\nnodes:\n  - kind: axis_node\n    axes: {{x: {{}}}}\n"),
        )
        .unwrap();
        let bad = launch(&dir.join("key.yaml"), &["--check"]);
        let log = String::from_utf8_lossy(&bad.stderr);
        assert_eq!(bad.status.code(), Some(2), "{key}: {log}");
        assert!(log.contains(needle), "{key}: {log}");
    }
    let got = read_back(&file);
    let _ = std::fs::remove_dir_all(&dir);
    let Some(got) = got else { return };
    let topics: Vec<&str> = got.lines().filter(|l| l.starts_with('/')).collect();
    assert_eq!(
        topics,
        [
            "/axis_node/axes/a3/state motion_msgs/msg/AxisState 501",
            "/joint_states sensor_msgs/msg/JointState 501",
        ],
        "{got}"
    );
    assert!(got.contains("\nchunks zstd\n"), "{got}");
}

/// `--record-exclude-topics` (config key `record_exclude_topics`, as `ros2 bag record
/// --exclude-topics`) records every topic but those named (bad names and lists: in the test of
/// `--record-topics`).
#[test]
fn record_exclude_topics_leave_out_the_topics_named() {
    require_netns();
    let dir = scratch_dir("motion_record_exclude");
    let file = dir.join("most.mcap");
    let config = ten_axes_config(&dir, "");
    let f = file.to_string_lossy().to_string();
    let out = launch(
        &config,
        &[
            "--cycles",
            "200",
            "--record",
            &f,
            "--record-exclude-topics",
            "/axis_node/axis_states,/joint_states",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let got = read_back(&file);
    let _ = std::fs::remove_dir_all(&dir);
    let Some(got) = got else { return };
    let topics: Vec<&str> = got.lines().filter(|l| l.starts_with('/')).collect();
    for left_out in ["/axis_node/axis_states ", "/joint_states "] {
        assert!(
            !topics.iter().any(|t| t.starts_with(left_out)),
            "{left_out}recorded: {got}"
        );
    }
    for kept in [
        "/axis_node/axes/a0/state motion_msgs/msg/AxisState 201",
        "/axis_node/axes/a9/state motion_msgs/msg/AxisState 201",
        "/clock rosgraph_msgs/msg/Clock 201",
    ] {
        assert!(topics.contains(&kept), "{kept} missing: {got}");
    }
}

/// `--cycles` needs lockstep nodes: a real-time node is a configuration error (exit 2).
#[test]
fn cycles_refuse_real_time_nodes() {
    let dir = scratch_dir("motion_cycles_rt");
    let config = dir.join("rt.yaml");
    std::fs::write(&config, "nodes:\n  - kind: axis_node\n    axes: {x: {}}\n").unwrap();
    for (args, needle) in [
        (vec!["--cycles", "10"], "--cycles runs lockstep nodes only"),
        (vec!["--cycles", "0"], "is not a positive whole number"),
        (vec!["--cycles", "x"], "is not a positive whole number"),
        (vec!["--until-idle"], "--until-idle needs --cycles N"),
    ] {
        let out = Command::new(launcher_bin())
            .arg(&config)
            .args(&args)
            .output()
            .expect("motion_launch");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Per channel of a recording: message count and a SHA-256 over (log time, bytes) of every
/// message in order; then the largest SetPos of axis `x` and the last x of mover `m2`.
const PY_DIGEST: &str = r#"
import hashlib, sys
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
digests, counts, last = {}, {}, {}
with open(sys.argv[1], "rb") as f:
    for schema, channel, message, ros in make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages():
        h = digests.setdefault(channel.topic, hashlib.sha256())
        h.update(message.log_time.to_bytes(8, "little"))
        # A parameter event without its stamp (the CDR header's 4 bytes, then the Time's 8):
        # the node stamps it with the system time at its creation.
        h.update(message.data[12:] if channel.topic == "/parameter_events" else message.data)
        counts[channel.topic] = counts.get(channel.topic, 0) + 1
        if channel.topic == "/axis_node/axis_states":
            last["x"] = max(last.get("x", 0.0), [a.set_pos for a in ros.axes if a.name == "x"][0])
        if channel.topic == "/planar_node/state":
            last["m2"] = [m.x for m in ros.movers if m.name == "m2"][0]
for t in sorted(digests):
    print(t, counts[t], digests[t].hexdigest())
print("max x", last.get("x"), "last m2", last.get("m2"))
"#;

/// Item 4 of issue 14: a lockstep run with a command script (the demo machine moving by
/// itself) recorded twice gives the same messages, bit for bit (stamps included), on every
/// channel but those paced by the wall clock: `/diagnostics` and `~/cycle_stats` (measured
/// execution times, 1 Hz) and `/rosout` (stamped with the system time, as rcl does; at this
/// log level empty anyway). `/parameter_events` (each node's declaration, stamped with the
/// system time at its creation) is compared without its stamp. The axis node's `~/events`
/// (the script's acknowledgements, plcopen_platform.md §12.1) and `/clock` are among the
/// equal ones: in a stream they follow the cycles, not the wall clock.
#[test]
fn a_scripted_lockstep_run_replays_bit_identically() {
    require_netns();
    let dir = scratch_dir("motion_replay");
    let config = dir.join("moving_demo.yaml");
    std::fs::write(&config, system_tests::moving_demo::config(4.0, None, true)).unwrap();
    let mut digests = Vec::new();
    for run in 0..2 {
        let file = dir.join(format!("run{run}.mcap"));
        let out = Command::new(launcher_bin())
            .arg(&config)
            .args(["--cycles", "4000", "--record"])
            .arg(&file)
            .env("ROS_DOMAIN_ID", unique_domain().to_string())
            .env("RUST_LOG", "warn,rustdds=error,ros2_client=error")
            .output()
            .expect("motion_launch");
        assert!(
            out.status.success(),
            "run {run}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let Some(d) = read_back_with(&file, PY_DIGEST) else {
            return;
        };
        digests.push(d);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let strip = |d: &str| -> Vec<String> {
        d.lines()
            .filter(|l| {
                !["/diagnostics ", "/rosout "]
                    .iter()
                    .any(|t| l.starts_with(t))
                    && !l.split(' ').next().unwrap_or("").ends_with("/cycle_stats")
            })
            .map(str::to_string)
            .collect()
    };
    let (a, b) = (strip(&digests[0]), strip(&digests[1]));
    assert!(a.len() > 10, "channels recorded: {a:?}");
    assert_eq!(a, b, "the two runs differ");
    let events = a.iter().find(|l| l.starts_with("/axis_node/events "));
    let acks: u32 = events
        .and_then(|l| l.split(' ').nth(1))
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    // The table's MoveVelocity (ACCEPTED; it never ends), x's two legs (ACCEPTED, DONE each);
    // MC_Power has no acknowledgements.
    assert_eq!(
        acks, 5,
        "the script's orders acknowledged on ~/events: {events:?}"
    );
    // The script moved the machine: x went to 200 (and back; a leg every 2 s at 150 mm/s),
    // m2 left x = 240 mm for 480 mm at 12 mm/s (3 s after its start at 1 s: about 276 mm).
    let last = a.last().unwrap();
    let v: Vec<&str> = last.split_whitespace().collect();
    let (x, m2): (f64, f64) = (v[2].parse().unwrap(), v[5].parse().unwrap());
    assert!((x - 200.0).abs() < 1e-9, "x reached 200: {last}");
    assert!(m2 > 255.0 && m2 < 300.0, "m2 moves: {last}");
}

/// `--cycles N --until-idle`: the run stops after the first cycle in which every command has
/// ended and every script step ran. One axis, powered at 0 s, MoveAbsolute to 100 mm at
/// 100 mm/s from 0.1 s (axis defaults: acceleration and jerk limited, about 1.1 s): the run
/// ends at the cycle the move reports Done, the same cycle in two runs, far before N, with
/// the axis at 100 mm.
#[test]
fn until_idle_stops_when_every_command_ended() {
    require_netns();
    let dir = scratch_dir("motion_until_idle");
    let config = dir.join("one_move.yaml");
    std::fs::write(
        &config,
        "nodes:\n  - kind: axis_node\n    lockstep: true\n    axes: {x: {}}\n    script:\n      - {at: 0, command: {Power: {axis: x, enable: true, enable_positive: true, enable_negative: true, override_percent: 100.0, buffer_mode: Aborting}}}\n      - {at: 0.1, command: {MoveAbsolute: {axis: x, position: 100.0, velocity: 100.0, acceleration: 0, deceleration: 0, jerk: 0, buffer_mode: Aborting, options: {}}}}\n",
    )
    .unwrap();
    let mut ends = Vec::new();
    for run in 0..2 {
        let file = dir.join(format!("run{run}.mcap"));
        let out = Command::new(launcher_bin())
            .arg(&config)
            .args(["--no-live", "--cycles", "20000", "--until-idle", "--record"])
            .arg(&file)
            .env("ROS_DOMAIN_ID", unique_domain().to_string())
            .env("RUST_LOG", "warn,rustdds=error,ros2_client=error")
            .output()
            .expect("motion_launch");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "{stdout}\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let end: u64 = stdout
            .split("every command ended and every script step ran after cycle ")
            .nth(1)
            .and_then(|r| r.split_whitespace().next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{stdout}"));
        assert!(
            stdout.contains(&format!("axis_node: ran {end} cycles")),
            "{stdout}"
        );
        assert!(
            (1000..3000).contains(&end),
            "ended after {end} cycles: {stdout}"
        );
        let last = read_back_with(&file, PY_DIGEST);
        if let Some(last) = last {
            let x: f64 = last
                .lines()
                .last()
                .and_then(|l| l.split_whitespace().nth(2))
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("{last}"));
            assert!((x - 100.0).abs() < 1e-9, "x at {x}");
        }
        ends.push(end);
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(ends[0], ends[1], "the same cycle in both runs");
}
