//! What was seen and good (issue 12 §6), kept as regression tests: two clients commanding the
//! same axis resolve as the manual says; SIGKILL during persistent-parameter writes never
//! leaves a broken file. (Malformed CDR on request topics: tests/peer/test_malformed_cdr.py;
//! broken launch configs: launch_configs.rs.)

use motion_msgs::action::MoveAbsoluteGoal;
use motion_msgs::srv::{
    WriteParameterPersistent, WriteParameterPersistentRequest, WriteParameterPersistentResponse,
};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::ServiceMapping;
use std::process::{Command, Stdio};
use std::time::Duration;
use system_tests::flood::{move_absolute_client, pipelined};
use system_tests::{
    drive, launcher_bin, require_netns, send_goal, unique_domain, within, ClientNode,
};

/// Client A moves x to 500; client B then moves x to -200 (MC_Aborting): A's goal ends
/// ABORTED with CommandAborted, B's succeeds at -200 (single_axis.md §3.6).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_clients_on_one_axis_resolve_as_the_manual_says() {
    require_netns();
    let domain = unique_domain();
    let node = system_tests::flood::axis_node(domain, 900.0);
    let _driver = drive(&node, 5);
    let mut a = ClientNode::new(domain, "client_a", ServiceMapping::Cyclone);
    let mut b = ClientNode::new(domain, "client_b", ServiceMapping::Cyclone);
    a.power_on("x").await;
    let ac_a = move_absolute_client(&mut a).await;
    let ac_b = move_absolute_client(&mut b).await;
    let goal = |position| MoveAbsoluteGoal {
        axis: "x".into(),
        position,
        velocity: 200.0,
        ..Default::default()
    };
    let (gid_a, acc) = send_goal(&ac_a, "goal A", goal(500.0)).await;
    assert!(acc.accepted);
    tokio::time::sleep(Duration::from_millis(200)).await;
    let (gid_b, acc) = send_goal(&ac_b, "goal B", goal(-200.0)).await;
    assert!(acc.accepted);
    let (status, result) = within(20.0, "A's result", ac_a.async_request_result(gid_a))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Aborted, "{result:?}");
    assert!(result.command_aborted && !result.error, "{result:?}");
    let (status, result) = within(30.0, "B's result", ac_b.async_request_result(gid_b))
        .await
        .unwrap();
    assert_eq!(status, GoalStatusEnum::Succeeded, "{result:?}");
    assert!(
        (result.position + 200.0).abs() < 1e-6,
        "{}",
        result.position
    );
}

/// SIGKILL at five moments of a flood of MC_WriteParameterPersistent: the file is always
/// whole (write-then-rename), and the next start applies it.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sigkill_during_persistent_writes_never_breaks_the_file() {
    require_netns();
    let dir = std::env::temp_dir().join(format!("persist-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("params.yaml");
    let config = dir.join("persist.yaml");
    std::fs::write(
        &config,
        format!(
            "nodes:\n  - kind: axis_node\n    service_mapping: cyclone\n    persistent_parameter_file: {}\n    axes:\n      x: {{max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}}\n",
            file.display()
        ),
    )
    .unwrap();
    for (k, kill_after_ms) in [50u64, 120, 200, 330, 500].into_iter().enumerate() {
        let domain = unique_domain() + 140;
        let mut child = Command::new(launcher_bin())
            .arg(&config)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("RUST_LOG", "error")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("motion_launch");
        let mut c = ClientNode::new(domain, &format!("persist_{k}"), ServiceMapping::Cyclone);
        let wpp = c
            .client::<WriteParameterPersistentRequest, WriteParameterPersistentResponse>(
                "/axis_node/write_parameter_persistent",
                WriteParameterPersistent::service_type_name(),
            )
            .await;
        let flood = tokio::spawn(async move {
            pipelined(
                &wpp,
                (0..5000).map(|i| WriteParameterPersistentRequest {
                    axis: "x".into(),
                    parameter_number: 1002,
                    value: 100.0 + i as f64,
                }),
                16,
                Duration::from_secs(2),
                |_| {},
            )
            .await
        });
        tokio::time::sleep(Duration::from_millis(kill_after_ms)).await;
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        flood.abort();
        drop(c);
        if file.exists() {
            let text = std::fs::read_to_string(&file).unwrap();
            let v: serde_yaml::Value = serde_yaml::from_str(&text)
                .unwrap_or_else(|e| panic!("kill #{k}: broken file ({e}):\n{text}"));
            let list = v.get("x").and_then(|l| l.as_sequence());
            assert!(list.is_some(), "kill #{k}: no list for x:\n{text}");
        }
    }
    assert!(
        file.exists(),
        "no persistent write was stored before the kills"
    );
    // The next start reads the file (a broken one would stop it with exit code 2).
    let out = Command::new(launcher_bin())
        .arg(&config)
        .arg("--duration")
        .arg("0.5")
        .env("ROS_DOMAIN_ID", (unique_domain() + 140).to_string())
        .env("RUST_LOG", "error")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "restart: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
