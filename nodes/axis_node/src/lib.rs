//! `axis_node`: PLCopen single axes (Tc2_MC2) over ROS 2.
//!
//! The engine ([`axis_engine`]) does the semantics; this crate maps ROS requests onto its
//! commands and its snapshots onto topics (README "ROS API", table "axis_node"):
//! - one service per FB (`services`: power, reset, the basic moves, halt, stop, set_position,
//!   parameters; `fbs`: modulo/continuous moves, home, gearing, torque, superposition, touch
//!   probe, override, later inputs of running instances; `jog`: MC_Jog's level-held buttons;
//!   `reads`: read FBs and `~/get_outputs`), simulation hooks under `~/sim/`;
//! - actions for the motions that end (`actions`): Done, or the FB's Done-type output
//!   (InVelocity, InEndVelocity, InTorque, InGear); cancel = MC_Halt;
//! - topics `~/axis_states` (motion_msgs/AxisStateArray), `joint_states`
//!   (sensor_msgs/JointState), `~/command_status`, `/diagnostics`;
//! - PLCopen Part 4 axis groups under `~/groups/<group>/` (`groups`) and the platform
//!   profile's safety/simulation services and `~/platform/status` (`platform`), configured by
//!   the entry's `platform_profile`, `groups` and `platform` keys (plcopen_platform.md).

//! - collision-avoidance groups (`ca`, launch key `ca_groups`): services, actions and the
//!   state topic under `~/ca/<group>/`.

mod actions;
mod ca;
#[cfg(test)]
mod config_tests;
mod convert;
mod engine_config;
pub mod events;
mod extensions;
mod fb_cycle;
mod fbs;
mod groups;
mod jog;
mod platform;
mod reads;
mod services;

use axis_engine::ca::CaGroupConfig;
use axis_engine::{AxisConfig, AxisEngine, EngineConfig};
use motion_runtime::host::{from_value, CommonConfig, ConfigError};
use motion_runtime::launch::{RunningNode, StartError};
use motion_runtime::{NodeHost, NodeKind, NodeShell, ShellError};
use ros2_client::ParameterValue;

/// The node kind in launch configs.
pub const KIND: &str = "axis_node";

/// The launcher's entry for this node.
pub const NODE_KIND: NodeKind = NodeKind {
    kind: KIND,
    start: start_boxed,
    check,
};

/// Checks an `axis_node` entry's engine part (`--check`): parse and build the engine.
pub fn check(
    common: &CommonConfig,
    engine_cfg: serde_yaml::Value,
    location: &str,
) -> Result<(), ConfigError> {
    common.script_commands::<axis_engine::AxisCommand>(location)?;
    build_with_ca(parse(engine_cfg, location)?.0, location).map(|_| ())
}

fn parse(
    engine_cfg: serde_yaml::Value,
    location: &str,
) -> Result<(AxisNodeConfig, Vec<String>), ConfigError> {
    let cfg = AxisNodeConfig::from_yaml(engine_cfg, location)?;
    let names = cfg.axes.iter().map(|(n, _)| n.clone()).collect();
    Ok((cfg, names))
}

fn build(cfg: AxisNodeConfig, location: &str) -> Result<AxisEngine, ConfigError> {
    AxisEngine::with_config(cfg.axes, &cfg.engine).map_err(|r| ConfigError {
        location: format!("{location}.{}", engine_config::build_error_key(&r.message)),
        message: r.message,
    })
}

/// [`build`], then the collision-avoidance groups (collision_avoidance.md §3.1, validated by
/// the engine).
fn build_with_ca(mut cfg: AxisNodeConfig, location: &str) -> Result<AxisEngine, ConfigError> {
    let ca_groups = std::mem::take(&mut cfg.ca_groups);
    let mut engine = build(cfg, location)?;
    for (name, c) in ca_groups {
        engine
            .add_ca_group(name.clone(), c)
            .map_err(|r| ConfigError {
                location: format!("{location}.ca_groups.{name}"),
                message: r.message,
            })?;
    }
    Ok(engine)
}

/// Reads the `persistent_parameter_file` (if configured) and applies its lists to the engine
/// before the first cycle (MC_Write(Bool)ParameterPersistent's initialization list).
fn apply_persistent(
    engine: &mut AxisEngine,
    file: Option<&str>,
    location: &str,
) -> Result<extensions::Persistence, ConfigError> {
    let Some(file) = file else {
        return Ok(extensions::Persistence::default());
    };
    let bad = |message: String| ConfigError {
        location: format!("{location}.persistent_parameter_file"),
        message,
    };
    let path = std::path::PathBuf::from(file);
    let lists = extensions::read_persistent_file(&path).map_err(bad)?;
    for (axis, list) in &lists {
        engine
            .apply_persistent_parameters(axis, list)
            .map_err(|r| bad(format!("{file}: axis '{axis}': {}", r.message)))?;
    }
    Ok(extensions::Persistence::new(Some(path), lists))
}

/// The engine part of an `axis_node` entry of a launch config.
#[derive(Clone, Debug, Default)]
pub struct AxisNodeConfig {
    /// Axes in configuration order: name and parameters (single_axis.md §1.2 defaults).
    pub axes: Vec<(String, AxisConfig)>,
    /// `platform_profile`, `groups` and `platform` (plcopen_platform.md): the engine-level
    /// configuration.
    pub engine: EngineConfig,
    /// Collision-avoidance groups in configuration order: name and §3.1 parameters.
    pub ca_groups: Vec<(String, CaGroupConfig)>,
    /// `persistent_parameter_file`: where MC_Write(Bool)ParameterPersistent lists are stored
    /// and read back at start (optional).
    pub persistent_parameter_file: Option<String>,
    /// Each axis's `joint_type` (same order as `axes`): how `joint_states` converts it to SI.
    pub joints: Vec<convert::JointType>,
    /// Axes with `auto_power: true` (collision_avoidance.md §3.2, proposal): powered with both
    /// direction enables before the first cycle, STANDSTILL from cycle 1.
    pub auto_power: Vec<String>,
}

impl AxisNodeConfig {
    /// Reads `axes: { <name>: { <parameter>: value, ... }, ... }` (order kept), and optional
    /// `platform_profile: tc2_mc2 | isg_mcp` (default tc2_mc2), `groups: [{name, axes: [..]}]`,
    /// `platform: {...}` (the engine's `EngineConfig`).
    pub fn from_yaml(v: serde_yaml::Value, location: &str) -> Result<Self, ConfigError> {
        let bad = |key: &str, msg: &str| ConfigError {
            location: format!("{location}.{key}"),
            message: msg.into(),
        };
        let map = match v {
            serde_yaml::Value::Mapping(m) => m,
            serde_yaml::Value::Null => serde_yaml::Mapping::new(),
            _ => return Err(bad("", "expected a mapping")),
        };
        let mut axes = Vec::new();
        let mut engine = serde_yaml::Mapping::new();
        let mut ca_groups = Vec::new();
        let mut persistent_parameter_file = None;
        let mut joints = Vec::new();
        let mut missing_fast = Vec::new();
        let mut auto_power = Vec::new();
        for (k, val) in map {
            match k.as_str() {
                Some("ca_groups") => ca_groups = ca_groups_from_yaml(&val, location)?,
                Some("axes") => {
                    let m = val
                        .as_mapping()
                        .ok_or_else(|| bad("axes", "expected a mapping of axis names"))?;
                    for (name, cfg) in m {
                        let name = name
                            .as_str()
                            .ok_or_else(|| bad("axes", "axis names must be strings"))?;
                        let mut cfg = if cfg.is_null() {
                            serde_yaml::Value::Mapping(Default::default())
                        } else {
                            cfg.clone()
                        };
                        match cfg.as_mapping_mut().and_then(|m| m.remove("auto_power")) {
                            None | Some(serde_yaml::Value::Bool(false)) => {}
                            Some(serde_yaml::Value::Bool(true)) => auto_power.push(name.to_string()),
                            Some(_) => {
                                return Err(bad(
                                    &format!("axes.{name}.auto_power"),
                                    "expected true or false",
                                ))
                            }
                        }
                        // `joint_type` belongs to the ROS side (joint_states), not the engine.
                        let joint = match cfg.as_mapping_mut().and_then(|m| m.remove("joint_type")) {
                            None => convert::JointType::Prismatic,
                            Some(j) => convert::JointType::from_yaml(&j).ok_or_else(|| {
                                bad(
                                    &format!("axes.{name}.joint_type"),
                                    "expected prismatic (mm -> m) or revolute (deg -> rad)",
                                )
                            })?,
                        };
                        for key in ["fast_deceleration", "fast_jerk"] {
                            if cfg.get(key).is_none() {
                                missing_fast.push(format!("axes.{name}.{key}"));
                            }
                        }
                        let c: AxisConfig = from_value(cfg, &format!("{location}.axes.{name}"))?;
                        axes.push((name.to_string(), c));
                        joints.push(joint);
                    }
                }
                Some("persistent_parameter_file") => {
                    let path = val
                        .as_str()
                        .filter(|p| !p.is_empty())
                        .ok_or_else(|| bad("persistent_parameter_file", "expected a file path"))?;
                    persistent_parameter_file = Some(path.to_string());
                }
                Some(key) if engine_config::KEYS.contains(&key) => {
                    engine_config::take_key(&mut engine, key, val, location)?
                }
                Some(other) => {
                    return Err(bad(
                        other,
                        "unknown key (axis_node takes: axes, platform_profile, groups, platform, ca_groups, persistent_parameter_file)",
                    ))
                }
                None => return Err(bad("?", "keys must be strings")),
            }
        }
        if axes.is_empty() {
            return Err(bad("axes", "no axis configured"));
        }
        let engine = engine_config::finish(engine, &axes, location)?;
        // isg_mcp counts in µm: Tc2_MC2's fast defaults (5000 u/s², 1e5 u/s³) would make a
        // reaction-class-2 quick stop softer and longer than a class-1 stop (issue 17).
        if engine.platform_profile == axis_engine::PlatformProfile::IsgMcp {
            if let Some(a) = auto_power.first() {
                return Err(bad(
                    &format!("axes.{a}.auto_power"),
                    "not with platform_profile isg_mcp: its start-up powers the axes \
                     (platform.auto_power, R-INIT-1)",
                ));
            }
            if let Some(key) = missing_fast.first() {
                return Err(bad(
                    key,
                    "required with platform_profile isg_mcp: quick stops (reaction class 2, \
                     travel limits) use it, and the Tc2_MC2 default is far too soft in µm",
                ));
            }
        }
        Ok(AxisNodeConfig {
            axes,
            engine,
            ca_groups,
            persistent_parameter_file,
            joints,
            auto_power,
        })
    }
}

/// Reads `ca_groups: { <name>: { <CaGroupConfig field>: value, ... }, ... }` (order kept;
/// an empty entry takes the §3.1 defaults).
fn ca_groups_from_yaml(
    v: &serde_yaml::Value,
    location: &str,
) -> Result<Vec<(String, CaGroupConfig)>, ConfigError> {
    let bad = |msg: &str| ConfigError {
        location: format!("{location}.ca_groups"),
        message: msg.into(),
    };
    let m = v
        .as_mapping()
        .ok_or_else(|| bad("expected a mapping of CA group names"))?;
    let mut groups = Vec::new();
    for (name, cfg) in m {
        let name = name
            .as_str()
            .ok_or_else(|| bad("CA group names must be strings"))?;
        let cfg = if cfg.is_null() {
            serde_yaml::Value::Mapping(Default::default())
        } else {
            cfg.clone()
        };
        let c: CaGroupConfig = from_value(cfg, &format!("{location}.ca_groups.{name}"))?;
        groups.push((name.to_string(), c));
    }
    Ok(groups)
}

/// A running axis node.
pub type AxisNode = NodeHost<AxisEngine>;

/// Starts an axis node from its launch-config entry.
pub fn start(
    common: &CommonConfig,
    engine_cfg: serde_yaml::Value,
    location: &str,
    domain_id: u16,
) -> Result<AxisNode, StartError> {
    let (mut cfg, names) = parse(engine_cfg, location)?;
    let groups: Vec<String> = cfg.engine.groups.iter().map(|g| g.name.clone()).collect();
    let profile = engine_config::profile_name(cfg.engine.platform_profile);
    let file = cfg.persistent_parameter_file.clone();
    let joints = std::mem::take(&mut cfg.joints);
    let auto_power = std::mem::take(&mut cfg.auto_power);
    // AxisCycleTime (1050) reports the node's cycle: the engine integrates with its tick.
    for (_, c) in &mut cfg.axes {
        c.cycle_time = common.cycle_period;
    }
    let ca_names: Vec<String> = cfg.ca_groups.iter().map(|(n, _)| n.clone()).collect();
    let mut engine = build_with_ca(cfg, location)?;
    let persistence =
        std::sync::Arc::new(apply_persistent(&mut engine, file.as_deref(), location)?);
    for axis in auto_power {
        let power = axis_engine::Power {
            axis: axis.clone(),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: axis_engine::BufferMode::Aborting,
        };
        motion_core::Engine::command(&mut engine, axis_engine::AxisCommand::Power(power)).map_err(
            |r| ConfigError {
                location: format!("{location}.axes.{axis}.auto_power"),
                message: r.message,
            },
        )?;
    }
    let params = vec![
        (
            "axes".to_string(),
            ParameterValue::StringArray(names.clone()),
        ),
        (
            "platform_profile".to_string(),
            ParameterValue::String(profile.to_string()),
        ),
        // The CA groups' names (read-only, like `axes`).
        (
            "ca_groups".to_string(),
            ParameterValue::StringArray(ca_names),
        ),
        (
            "persistent_parameter_file".to_string(),
            ParameterValue::String(file.unwrap_or_default()),
        ),
    ];
    Ok(NodeHost::start(
        KIND,
        common,
        domain_id,
        engine,
        params,
        |shell| setup(shell, names, joints, groups, persistence),
    )?)
}

fn start_boxed(
    c: &CommonConfig,
    v: serde_yaml::Value,
    loc: &str,
    d: u16,
) -> Result<RunningNode, StartError> {
    Ok(Box::new(start(c, v, loc, d)?))
}

fn setup(
    shell: &mut NodeShell<AxisEngine>,
    names: Vec<String>,
    joints: Vec<convert::JointType>,
    groups: Vec<String>,
    persistence: std::sync::Arc<extensions::Persistence>,
) -> Result<(), ShellError> {
    services::register(shell)?;
    extensions::register(shell, persistence)?;
    reads::register(shell)?;
    jog::register(shell)?;
    actions::register(shell)?;
    ca::register(shell)?;
    convert::register_topics(shell, names, joints)?;
    shell.static_frame(convert::FRAME)?;
    groups::register(shell, &groups)?;
    platform::register(shell)?;
    events::register(shell)?;
    fb_cycle::register(shell)?;
    Ok(())
}
