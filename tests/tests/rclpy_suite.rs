//! Real rclpy (ROS 2 Jazzy from PyPI, rmw_fastrtps_cpp: the Enhanced request/reply mapping)
//! drives our nodes as a ROS user does (issue 13): `tests/rclpy/test_*.py` under pytest, in
//! the venv that `scripts/ros-venv.sh` builds (`scripts/test.sh` runs it). Without that venv
//! the suite is skipped with a note, unless `MOTION_REQUIRE_RCLPY=1` (the test command sets
//! it), which makes a missing venv a failure.

use std::process::Command;
use system_tests::{launcher_bin, require_netns, workspace};

#[test]
fn rclpy_suite() {
    require_netns();
    let root = workspace();
    let venv = root.join(".ros/venv");
    if !venv.join(".stamp-motion_msgs").exists() {
        assert!(
            std::env::var("MOTION_REQUIRE_RCLPY").as_deref() != Ok("1"),
            "the rclpy venv is missing: run scripts/ros-venv.sh (scripts/test.sh does)"
        );
        println!("rclpy suite skipped: no .ros/venv (scripts/ros-venv.sh builds it)");
        return;
    }
    let out = Command::new("bash")
        .arg("-c")
        .arg(". .ros/env.sh && exec python -m pytest tests/rclpy -q -p no:cacheprovider -rA 2>&1")
        .current_dir(&root)
        .env("MOTION_LAUNCH_BIN", launcher_bin())
        .env("ROS_DOMAIN_ID", "210")
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .expect("bash");
    let text = String::from_utf8_lossy(&out.stdout);
    println!("{text}");
    assert!(out.status.success(), "rclpy suite failed:\n{text}");
}
