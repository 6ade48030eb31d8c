//! Our interface parser (build.rs) against ROS's own (`rosidl_adapter.parser`, run through
//! `tools/rosidl_check.py`): both must describe every type identically.
//!
//! Skipped with a message when `/usr/bin/python3` lacks `rosidl_adapter`, except in CI
//! (`CI=true`), where that is a failure.

use std::path::Path;
use std::process::Command;

const PYTHON: &str = "/usr/bin/python3";

/// Output of `rosidl_check.py` with `args`, or `None` when the tool is unavailable here.
fn rosidl_description(args: &[&str]) -> Option<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let in_ci = std::env::var("CI").is_ok_and(|v| v == "true" || v == "1");
    let out = Command::new(PYTHON)
        .arg(dir.join("tools/rosidl_check.py"))
        .args(args)
        .arg(dir)
        .output();
    let out = match out {
        Ok(o) => o,
        Err(e) if !in_ci => {
            eprintln!("SKIPPED: cannot run {PYTHON}: {e}");
            return None;
        }
        Err(e) => panic!("CI: cannot run {PYTHON}: {e}"),
    };
    if out.status.code() == Some(3) {
        let msg = String::from_utf8_lossy(&out.stderr);
        assert!(
            !in_ci,
            "CI: {PYTHON} lacks rosidl_adapter (install python3-rosidl): {msg}"
        );
        eprintln!("SKIPPED: {PYTHON} lacks rosidl_adapter (apt install python3-rosidl): {msg}");
        return None;
    }
    assert!(
        out.status.success(),
        "rosidl_check.py failed ({}):\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    Some(String::from_utf8(out.stdout).expect("utf-8 output"))
}

/// Compares line by line (one type per line) so that a failure names the type.
fn assert_same(ours: &str, ros: &str) {
    let ours: Vec<&str> = ours.lines().collect();
    let ros: Vec<&str> = ros.lines().collect();
    for (a, b) in ours.iter().zip(&ros) {
        assert_eq!(
            a, b,
            "\nbuild.rs (left) and rosidl_adapter (right) disagree"
        );
    }
    assert_eq!(
        ours.len(),
        ros.len(),
        "different number of types: build.rs {} lines, rosidl_adapter {} lines",
        ours.len(),
        ros.len()
    );
}

#[test]
fn generator_matches_rosidl_for_all_interfaces() {
    let ours = motion_msgs::INTERFACE_DESCRIPTION_JSON;
    // Sanity: the description covers our files and the vendored packages.
    for name in [
        "\"motion_msgs/msg/AxisState\"",
        "\"motion_msgs/srv/MoveAbsolute_Request\"",
        "\"motion_msgs/action/MoveAbsolute_Feedback\"",
        "\"visualization_msgs/msg/Marker\"",
    ] {
        assert!(ours.contains(name), "{name} missing from the description");
    }
    if let Some(ros) = rosidl_description(&[]) {
        assert_same(ours, &ros);
    }
}

#[test]
fn generator_matches_rosidl_for_test_interfaces() {
    let ours = include_str!(concat!(env!("OUT_DIR"), "/test_interfaces.json"));
    assert!(ours.contains("\"idl_test_msgs/msg/Edge\""));
    if let Some(ros) = rosidl_description(&["--tests"]) {
        assert_same(ours, &ros);
    }
}

#[test]
#[should_panic(expected = "disagree")]
fn comparison_detects_a_difference() {
    assert_same(
        "[\n{\"name\":\"a\",\"default\":1.0}\n]",
        "[\n{\"name\":\"a\",\"default\":1.5}\n]",
    );
}
