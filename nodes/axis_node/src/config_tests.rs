//! The launch-config keys of Part 4 groups and the platform profile: parsed into the engine's
//! `EngineConfig`, errors naming the key and the problem.

use crate::{build, AxisNodeConfig};
use axis_engine::PlatformProfile;

const AXES: &str = "axes:\n  x: {}\n  y: {}\n";

fn parse(extra: &str) -> Result<AxisNodeConfig, motion_runtime::host::ConfigError> {
    let v: serde_yaml::Value = serde_yaml::from_str(&format!("{AXES}{extra}")).unwrap();
    AxisNodeConfig::from_yaml(v, "f.yaml: nodes[0] (axis_node)")
}

fn error(extra: &str) -> (String, String) {
    let e = match parse(extra).and_then(|c| build(c, "f.yaml: nodes[0] (axis_node)").map(|_| ())) {
        Err(e) => e,
        Ok(()) => panic!("{extra:?} was accepted"),
    };
    (e.location, e.message)
}

#[test]
fn defaults_are_tc2_mc2_without_groups() {
    let c = parse("").unwrap();
    assert_eq!(c.engine.platform_profile, PlatformProfile::Tc2Mc2);
    assert!(c.engine.groups.is_empty());
    build(c, "f").unwrap();
}

#[test]
fn groups_profile_and_platform_reach_the_engine() {
    let v: serde_yaml::Value = serde_yaml::from_str(
        "axes:\n  x: {fast_deceleration: 5.0e6, fast_jerk: 1.0e9}\n  y: {fast_deceleration: 5.0e6, fast_jerk: 1.0e9}\nplatform_profile: isg_mcp\ngroups:\n  - {name: g, axes: [y, x]}\nplatform:\n  lease_cycles: 50\n  axes:\n    x: {referenced: false}\n",
    )
    .unwrap();
    let c = AxisNodeConfig::from_yaml(v, "f").unwrap();
    assert_eq!(c.engine.platform_profile, PlatformProfile::IsgMcp);
    assert_eq!(c.engine.groups[0].axes, ["y", "x"]);
    assert_eq!(c.engine.platform.lease_cycles, 50);
    let e = build(c, "f").unwrap();
    let g = e.group("g").unwrap();
    assert_eq!(g.axes, ["y", "x"]);
    assert_eq!(g.idents, [1, 2]);
}

#[test]
fn errors_name_the_key_and_the_problem() {
    let (loc, msg) = error("platform_profile: beckhoff\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).platform_profile");
    assert!(msg.contains("beckhoff"), "{msg}");
    let (loc, msg) = error("groups:\n  - {name: g, axes: [x, q]}\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).groups[0].axes");
    assert!(msg.contains("'q'"), "{msg}");
    let (loc, msg) = error("groups:\n  - {name: a-b, axes: [x]}\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).groups[0].name");
    assert!(msg.contains("a-b"), "{msg}");
    let (loc, msg) = error("groups:\n  - {name: g, axes: [x], speed: 1}\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).groups");
    assert!(msg.contains("speed"), "{msg}");
    let (loc, msg) = error("platform:\n  lease: 5\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).platform");
    assert!(msg.contains("lease"), "{msg}");
    let (loc, _) = error("platform:\n  axes:\n    z: {}\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).platform.axes.z");
    // The engine's own checks: a group configured twice, an axis in two groups.
    let (loc, msg) = error("groups:\n  - {name: g, axes: [x]}\n  - {name: g, axes: [y]}\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).groups");
    assert!(msg.contains("twice"), "{msg}");
    let (loc, msg) = error("groups:\n  - {name: g, axes: [x]}\n  - {name: h, axes: [x]}\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).groups");
    assert!(msg.contains("already in group"), "{msg}");
    let (loc, _) = error("colour: red\n");
    assert_eq!(loc, "f.yaml: nodes[0] (axis_node).colour");
}

/// `joint_type` (ROS side: joint_states in SI) is taken per axis; prismatic by default; any
/// other value names the key.
#[test]
fn joint_types_default_to_prismatic_and_bad_ones_name_the_key() {
    use crate::convert::JointType;
    let v: serde_yaml::Value =
        serde_yaml::from_str("axes:\n  x: {}\n  t: {joint_type: revolute, modulo_value: 360.0}\n")
            .unwrap();
    let c = AxisNodeConfig::from_yaml(v, "f").unwrap();
    assert_eq!(c.joints, [JointType::Prismatic, JointType::Revolute]);
    build(c, "f").unwrap();
    let v: serde_yaml::Value = serde_yaml::from_str("axes:\n  x: {joint_type: linear}\n").unwrap();
    let e = AxisNodeConfig::from_yaml(v, "f").unwrap_err();
    assert_eq!(e.location, "f.axes.x.joint_type");
    assert!(e.message.contains("prismatic"), "{}", e.message);
}

/// isg_mcp counts in µm: the fast (quick-stop) limits must be configured (issue 17).
#[test]
fn isg_mcp_requires_the_fast_limits() {
    let e = parse("platform_profile: isg_mcp\n").unwrap_err();
    assert_eq!(
        e.location,
        "f.yaml: nodes[0] (axis_node).axes.x.fast_deceleration"
    );
    assert!(e.message.contains("isg_mcp"), "{}", e.message);
    let v: serde_yaml::Value =
        serde_yaml::from_str("axes:\n  x: {fast_deceleration: 5.0e6}\nplatform_profile: isg_mcp\n")
            .unwrap();
    let e = AxisNodeConfig::from_yaml(v, "f").unwrap_err();
    assert_eq!(e.location, "f.axes.x.fast_jerk");
    // tc2_mc2 keeps its documented defaults.
    parse("platform_profile: tc2_mc2\n").unwrap();
}

/// `auto_power` per axis (collision_avoidance.md §3.2, proposal; default false here, as a
/// Tc2_MC2 axis starts disabled): taken out of the engine's keys; not with isg_mcp.
#[test]
fn auto_power_is_an_axis_key() {
    let v: serde_yaml::Value =
        serde_yaml::from_str("axes:\n  x: {auto_power: true}\n  y: {auto_power: false}\n").unwrap();
    let c = AxisNodeConfig::from_yaml(v, "f").unwrap();
    assert_eq!(c.auto_power, ["x"]);
    let v: serde_yaml::Value = serde_yaml::from_str("axes:\n  x: {auto_power: 1}\n").unwrap();
    assert_eq!(
        AxisNodeConfig::from_yaml(v, "f").unwrap_err().location,
        "f.axes.x.auto_power"
    );
}
