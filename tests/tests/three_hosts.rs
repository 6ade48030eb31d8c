//! Across machines (issue 13 §4): axis_node, planar_node and a real rclpy client each in a
//! network namespace of their own, joined by veth pairs on a bridge (10.77.0.1-3/24, the
//! namespaces' own addresses only), with `ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET`. The client
//! discovers both nodes over the subnet and drives an axis move and a mover move to their
//! targets (`tests/hosts/`). Needs the rclpy venv, like `rclpy_suite.rs`.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use system_tests::{launcher_bin, require_netns, workspace};

#[test]
fn a_client_on_a_third_host_drives_nodes_on_two_others() {
    require_netns();
    let root = workspace();
    if !root.join(".ros/venv/.stamp-motion_msgs").exists() {
        assert!(
            std::env::var("MOTION_REQUIRE_RCLPY").as_deref() != Ok("1"),
            "the rclpy venv is missing: run scripts/ros-venv.sh (scripts/test.sh does)"
        );
        println!("skipped: no .ros/venv (scripts/ros-venv.sh builds it)");
        return;
    }
    use std::os::unix::process::CommandExt;
    let launcher = launcher_bin();
    let mut child = Command::new(root.join("tests/hosts/three_hosts.sh"))
        .arg(&launcher)
        .arg(root.join("tests/hosts/axis_host.yaml"))
        .arg("--")
        .arg(&launcher)
        .arg(root.join("tests/hosts/planar_host.yaml"))
        .arg("--")
        .args([
            "bash",
            "-c",
            ". .ros/env.sh && exec python tests/hosts/client.py",
        ])
        .current_dir(&root)
        .env("ROS_DOMAIN_ID", "215")
        .process_group(0)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("three_hosts.sh");
    let out = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut { out }, &mut s);
        s
    });
    let end = Instant::now() + Duration::from_secs(180);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if Instant::now() > end {
            break None;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    // Whatever happened, nothing of the three hosts outlives the test.
    let _ = Command::new("kill")
        .args(["-KILL", "--", &format!("-{}", child.id())])
        .stderr(Stdio::null())
        .status();
    let _ = child.wait();
    let text = reader.join().unwrap_or_default();
    println!("{text}");
    let status = status.expect("three hosts still running after 180 s");
    assert!(status.success(), "client failed: {text}");
    assert!(text.contains("axis on host A at 42.0"), "{text}");
    assert!(text.contains("mover on host B at 200.0"), "{text}");
}
