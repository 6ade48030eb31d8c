//! The launch-config keys of the engine-level configuration (plcopen_platform.md):
//! `platform_profile: tc2_mc2 | isg_mcp`, `groups: [{name, axes: [..]}]`, `platform: {...}`,
//! read into the engine's [`EngineConfig`]; errors name the key and the problem.

use axis_engine::{AxisConfig, EngineConfig, PlatformProfile};
use motion_runtime::host::{from_value, ConfigError};

/// The keys of an `axis_node` entry that belong to [`EngineConfig`].
pub(crate) const KEYS: [&str; 3] = ["platform_profile", "groups", "platform"];

/// Checks one key on its own (so a serde error names it) and keeps it for [`finish`].
pub(crate) fn take_key(
    engine: &mut serde_yaml::Mapping,
    key: &str,
    val: serde_yaml::Value,
    location: &str,
) -> Result<(), ConfigError> {
    let one = serde_yaml::Mapping::from_iter([(key.into(), val.clone())]);
    from_value::<EngineConfig>(
        serde_yaml::Value::Mapping(one),
        &format!("{location}.{key}"),
    )?;
    engine.insert(key.into(), val);
    Ok(())
}

/// A group name becomes part of ROS names (`~/groups/<group>/...`): a name token.
fn ros_token(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The engine configuration of the kept keys, with group and platform axes checked against
/// the configured axes.
pub(crate) fn finish(
    engine: serde_yaml::Mapping,
    axes: &[(String, AxisConfig)],
    location: &str,
) -> Result<EngineConfig, ConfigError> {
    let bad = |key: &str, message: String| ConfigError {
        location: format!("{location}.{key}"),
        message,
    };
    let known = |a: &str| axes.iter().any(|(n, _)| n == a);
    let engine: EngineConfig = from_value(serde_yaml::Value::Mapping(engine), location)?;
    for (k, g) in engine.groups.iter().enumerate() {
        if !ros_token(&g.name) {
            return Err(bad(
                &format!("groups[{k}].name"),
                format!(
                    "'{}' is not a ROS name token (letters, digits, _; not starting with a digit)",
                    g.name
                ),
            ));
        }
        if let Some(a) = g.axes.iter().find(|a| !known(a)) {
            return Err(bad(
                &format!("groups[{k}].axes"),
                format!("'{a}' is not a configured axis"),
            ));
        }
    }
    if let Some(a) = engine.platform.axes.keys().find(|a| !known(a)) {
        return Err(bad(
            &format!("platform.axes.{a}"),
            "not a configured axis".into(),
        ));
    }
    Ok(engine)
}

/// The key of the entry an engine build error comes from (the engine names group or axis).
pub(crate) fn build_error_key(message: &str) -> &'static str {
    if message.starts_with("group") {
        "groups"
    } else if message.contains("platform config") {
        "platform"
    } else {
        "axes"
    }
}

/// `platform_profile` as the launch config spells it (the read-only ROS parameter).
pub(crate) fn profile_name(p: PlatformProfile) -> &'static str {
    match p {
        PlatformProfile::Tc2Mc2 => "tc2_mc2",
        PlatformProfile::IsgMcp => "isg_mcp",
    }
}
