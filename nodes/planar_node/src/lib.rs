//! `planar_node`: Beckhoff-XPlanar-style planar movers (Tc3_Mc3PlanarMotion) over ROS 2.
//!
//! The engine ([`planar_engine`]) does the semantics; this crate maps ROS requests onto its
//! commands and its snapshots onto topics (README "ROS API", xplanar.md §9):
//! - services, one per method of MC_PlanarEnvironment / Mover / Group / Part (§3.1–§3.5),
//!   named `~/<object>_<method>` in snake_case (`~/mover_move_to_position`,
//!   `~/group_enable`, `~/part_activate_position`, ...), plus `~/sim/inject_error` (§6.2);
//!   tracks (§3.3), on-track mover methods and virtual master axes are in `tracks`
//!   (`~/track_append_line`, `~/mover_join_track`, `~/axis_power`, ...);
//! - actions `~/mover_move_to_position`, `~/mover_move_z|a|b|c`, `~/mover_join_track`,
//!   `~/mover_leave_track`, `~/mover_move_on_track`,
//!   `~/mover_gear_in_pos_on_track_with_master_mover` (cancel = the mover's Halt);
//! - topics `~/state` (motion_msgs/PlanarState), `~/mover_poses` (geometry_msgs/PoseArray)
//!   and `~/markers` (visualization_msgs/MarkerArray), both in frame `planar_env` in metres,
//!   plus the common `~/command_status` and `/diagnostics`.

mod actions;
mod convert;
mod services;
mod tracks;

pub use convert::{mover_poses, planar_state, Geometry, FRAME_ID};
pub use tracks::{axis_state, set_on_track, track_markers, track_state, TrackPaths};

use motion_runtime::host::{from_value, CommonConfig, ConfigError};
use motion_runtime::launch::{RunningNode, StartError};
use motion_runtime::{NodeHost, NodeKind, NodeShell, ShellError};
use planar_engine::{PlanarConfig, PlanarEngine};
use ros2_client::ParameterValue;
use std::sync::Arc;

/// The node kind in launch configs.
pub const KIND: &str = "planar_node";

/// The launcher's entry for this node.
pub const NODE_KIND: NodeKind = NodeKind {
    kind: KIND,
    start: start_boxed,
    check,
};

/// A running planar node.
pub type PlanarNode = NodeHost<PlanarEngine>;

/// Reads the engine part of a `planar_node` entry (xplanar.md §1.12: `coordinate_systems`,
/// `parts`, `environment`, `movers`, `groups`, `tracks` (`{name, oid, part_oid}` and the
/// §1.6 init parameters `starts_from`, `geometry`, `ends_at`, `closed_loop`, built at start-up
/// as the `~/track_*` services would), `axes` (virtual master axes `{name, oid}`),
/// state-transition times). The engine's
/// `cycle_time` is the node's `cycle_period`: it may be left out, and if given must match.
pub fn config_from_yaml(
    v: serde_yaml::Value,
    cycle_period: f64,
    location: &str,
) -> Result<PlanarConfig, ConfigError> {
    let v = if v.is_null() {
        serde_yaml::Value::Mapping(Default::default())
    } else {
        v
    };
    let given = v.get("cycle_time").cloned();
    let mut cfg: PlanarConfig = from_value(v, location)?;
    if let Some(t) = given {
        if t.as_f64() != Some(cycle_period) {
            return Err(ConfigError {
                location: format!("{location}.cycle_time"),
                message: format!(
                    "{} differs from the node's cycle_period {cycle_period} s (leave cycle_time out)",
                    serde_yaml::to_string(&t).unwrap_or_default().trim()
                ),
            });
        }
    }
    cfg.cycle_time = cycle_period;
    Ok(cfg)
}

fn engine(cfg: PlanarConfig, location: &str) -> Result<PlanarEngine, ConfigError> {
    // The message carries the spec's error id (e.g. a track's init geometry, §6.2).
    PlanarEngine::new(cfg).map_err(|r| ConfigError {
        location: location.to_string(),
        message: r.to_string(),
    })
}

/// Checks a `planar_node` entry's engine part (`--check`): parse and build the engine.
pub fn check(
    common: &CommonConfig,
    engine_cfg: serde_yaml::Value,
    location: &str,
) -> Result<(), ConfigError> {
    common.script_commands::<planar_engine::PlanarCommand>(location)?;
    let cycle = engine_cfg
        .get("cycle_time")
        .and_then(|t| t.as_f64())
        .unwrap_or(CommonConfig::default().cycle_period);
    engine(config_from_yaml(engine_cfg, cycle, location)?, location).map(|_| ())
}

/// Starts a planar node from its launch-config entry.
pub fn start(
    common: &CommonConfig,
    engine_cfg: serde_yaml::Value,
    location: &str,
    domain_id: u16,
) -> Result<PlanarNode, StartError> {
    let cfg = config_from_yaml(engine_cfg, common.cycle_period, location)?;
    let geometry = Arc::new(Geometry::from_config(&cfg));
    let names = |v: Vec<String>| ParameterValue::StringArray(v);
    let params = vec![
        (
            "movers".to_string(),
            names(cfg.movers.iter().map(|m| m.name.clone()).collect()),
        ),
        (
            "groups".to_string(),
            names(cfg.groups.iter().map(|g| g.name.clone()).collect()),
        ),
        (
            "parts".to_string(),
            names(cfg.parts.iter().map(|p| p.name.clone()).collect()),
        ),
        (
            "tracks".to_string(),
            names(cfg.tracks.iter().map(|t| t.name.clone()).collect()),
        ),
        (
            "axes".to_string(),
            names(cfg.axes.iter().map(|a| a.name.clone()).collect()),
        ),
        (
            "environment".to_string(),
            ParameterValue::String(cfg.environment.name.clone()),
        ),
    ];
    let env_name = cfg.environment.name.clone();
    let engine = engine(cfg, location)?;
    Ok(NodeHost::start(
        KIND,
        common,
        domain_id,
        engine,
        params,
        |shell| setup(shell, env_name, geometry),
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
    shell: &mut NodeShell<PlanarEngine>,
    env_name: String,
    geometry: Arc<Geometry>,
) -> Result<(), ShellError> {
    services::register(shell, env_name)?;
    tracks::register_services(shell)?;
    actions::register(shell)?;
    tracks::register_actions(shell)?;
    tracks::spawn_sampler(shell, geometry.track_paths.clone());
    convert::register_topics(shell, geometry)?;
    shell.static_frame(convert::FRAME_ID)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn yaml(s: &str) -> serde_yaml::Value {
        serde_yaml::from_str(s).unwrap()
    }

    #[test]
    fn cycle_time_follows_the_cycle_period() {
        let c = config_from_yaml(yaml("movers: [{name: m1}]"), 0.002, "f: nodes[0]").unwrap();
        assert_eq!(c.cycle_time, 0.002);
        let c =
            config_from_yaml(yaml("cycle_time: 0.002\nmovers: [{name: m1}]"), 0.002, "f").unwrap();
        assert_eq!(c.cycle_time, 0.002);
        let e = config_from_yaml(yaml("cycle_time: 0.001"), 0.002, "f: nodes[0]").unwrap_err();
        assert_eq!(e.location, "f: nodes[0].cycle_time");
        assert!(e.message.contains("cycle_period"), "{e}");
    }

    #[test]
    fn config_errors_name_the_key() {
        let e = config_from_yaml(yaml("movers: [{name: m1, widht: 3}]"), 0.001, "f: nodes[0]")
            .unwrap_err();
        assert!(e.to_string().contains("widht"), "{e}");
        let e = check(
            &CommonConfig::default(),
            yaml("movers: [{name: m1}, {name: m1}]"),
            "f: nodes[0]",
        )
        .unwrap_err();
        assert!(e.message.contains("movers[1].name"), "{e}");
        assert!(check(&CommonConfig::default(), yaml("movers: [{name: m1}]"), "f").is_ok());
    }

    #[test]
    fn tracks_and_axes_are_read_from_the_config() {
        let c = config_from_yaml(
            yaml("tracks: [{name: loop}, {name: t2, oid: 0x01010301}]\naxes: [{name: v1}]"),
            0.001,
            "f",
        )
        .unwrap();
        assert_eq!(c.tracks[1].oid, 0x01010301);
        assert_eq!(c.axes[0].name, "v1");
        let e = config_from_yaml(
            yaml("tracks: [{name: t, geometrie: []}]"),
            0.001,
            "f: nodes[0]",
        )
        .unwrap_err();
        assert!(e.to_string().contains("geometrie"), "{e}");
        assert!(e.location.starts_with("f: nodes[0]"), "{e}");
        assert!(check(
            &CommonConfig::default(),
            yaml("tracks: [{name: t}, {name: t}]"),
            "f"
        )
        .is_err());
    }

    #[test]
    fn track_init_geometry_errors_carry_the_id_key_and_track() {
        let ok = "tracks: [{name: a, geometry: [{line: {start: [0, 0], end: [100, 0]}}]}, \
                  {name: b, starts_from: [a], geometry: [{circle: {start: [300, 100], end: [300, 100], center: [300, 200]}}]}]";
        assert!(check(&CommonConfig::default(), yaml(ok), "f").is_ok());
        let e = check(
            &CommonConfig::default(),
            yaml("tracks: [{name: a, geometry: [{line: {start: [0, 0], end: [0, 0]}}]}]"),
            "f: nodes[1] (planar_node)",
        )
        .unwrap_err();
        assert_eq!(e.location, "f: nodes[1] (planar_node)");
        for n in [
            "0x4A0A",
            "E_GEOMETRY_INVALID",
            "tracks[0].geometry[0]",
            "track 'a'",
        ] {
            assert!(e.message.contains(n), "'{n}' not in {e}");
        }
        let e = check(
            &CommonConfig::default(),
            yaml("tracks: [{name: a, geometry: [{line: {start: [0, 0]}}]}]"),
            "f",
        )
        .unwrap_err();
        assert!(e.message.contains("end"), "{e}");
    }
}
