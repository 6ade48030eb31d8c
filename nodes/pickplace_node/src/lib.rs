//! `pickplace_node`: the Track Pick & Place technology module (`L_TT1P_TrackPickAndPlaceBase`)
//! over ROS 2 (pick_and_place.md §18).
//!
//! The engine ([`pickplace_engine`]) does the semantics; this crate maps ROS requests onto its
//! inputs and its snapshots and events onto topics (README "ROS API"):
//! - level services `~/set_enable`, `~/set_regulator_on`, `~/set_internal_control`,
//!   `~/set_stop_inputs`, `~/set_override`, `~/jog`, `~/belt_input`, `~/service_request`;
//!   pulse services `~/execute`, `~/reset_error`, `~/abort`, `~/ack_gripper`, `~/group_home`;
//!   parameters `~/set_params`, `~/set_belt_params` (partial, merged onto the current values),
//!   `~/get_params`; `~/detect_workpiece`; simulation hooks `~/sim/set_belt_velocity`,
//!   `~/sim/set_digital_inputs`, `~/sim/inject_fault`; the visualisation's commands under
//!   Internal Control `~/hmi/*`;
//! - actions `~/pick_and_place` (cancel = halt, then abort at standstill) and `~/home`;
//! - topics `~/state` (motion_msgs/PickPlaceState), `~/workpieces`, `~/events` (every cell
//!   event as the cycle reports it), `~/markers` (visualization_msgs/MarkerArray),
//!   `~/command_status`, `/diagnostics`.

mod actions;
pub mod cell;
pub mod convert;
mod services;

use cell::Cell;
use motion_runtime::host::{from_value, CommonConfig, ConfigError};
use motion_runtime::launch::{RunningNode, StartError};
use motion_runtime::{NodeHost, NodeKind, NodeShell, ShellError};
use pickplace_engine::{PickPlaceConfig, PickPlaceEngine};
use ros2_client::ParameterValue;

/// The node kind in launch configs.
pub const KIND: &str = "pickplace_node";

/// The launcher's entry for this node.
pub const NODE_KIND: NodeKind = NodeKind {
    kind: KIND,
    start: start_boxed,
    check,
};

/// Checks a `pickplace_node` entry's engine part (`--check`): parse and build the engine (with
/// the default cycle; the node's `cycle_period` is checked when it starts).
pub fn check(
    common: &CommonConfig,
    engine_cfg: serde_yaml::Value,
    location: &str,
) -> Result<(), ConfigError> {
    common.script_commands::<cell::CellCommand>(location)?;
    let cfg = config(engine_cfg, location)?;
    engine(cfg, location).map(|_| ())
}

/// Reads the engine part of an entry: the keys of [`PickPlaceConfig`] except `cycle_time_s`,
/// which is the node's `cycle_period`.
pub fn config(v: serde_yaml::Value, location: &str) -> Result<PickPlaceConfig, ConfigError> {
    let v = if v.is_null() {
        serde_yaml::Value::Mapping(Default::default())
    } else {
        v
    };
    if v.get("cycle_time_s").is_some() {
        return Err(ConfigError {
            location: format!("{location}.cycle_time_s"),
            message: "set the node's cycle_period instead (the engine's cycle time follows it)"
                .into(),
        });
    }
    from_value(v, location)
}

fn engine(cfg: PickPlaceConfig, location: &str) -> Result<PickPlaceEngine, ConfigError> {
    PickPlaceEngine::new(cfg).map_err(|r| {
        // "config <key> = ...": point at the key; the cycle time is the node's cycle_period.
        let key = r
            .message
            .strip_prefix("config ")
            .and_then(|m| m.split([' ', ':']).next())
            .unwrap_or("");
        let key = if key == "cycle_time_s" {
            "cycle_period"
        } else {
            key
        };
        ConfigError {
            location: format!("{location}.{key}"),
            message: r.message,
        }
    })
}

/// A running pick-and-place node.
pub type PickPlaceNode = NodeHost<Cell>;

/// Starts a pick-and-place node from its launch-config entry.
pub fn start(
    common: &CommonConfig,
    engine_cfg: serde_yaml::Value,
    location: &str,
    domain_id: u16,
) -> Result<PickPlaceNode, StartError> {
    let mut cfg = config(engine_cfg, location)?;
    cfg.cycle_time_s = common.cycle_period;
    let belts: Vec<String> = cfg.belts.keys().cloned().collect();
    let params = vec![
        ("belts".to_string(), ParameterValue::StringArray(belts)),
        (
            "path_prep_cycles".to_string(),
            ParameterValue::Integer(i64::from(cfg.path_prep_cycles)),
        ),
        (
            "profile_queue_capacity".to_string(),
            ParameterValue::Integer(cfg.profile_queue_capacity as i64),
        ),
    ];
    let engine = engine(cfg, location)?;
    let (tx, rx) = tokio::sync::mpsc::unbounded_channel();
    let cell = Cell::new(engine, Some(tx));
    Ok(NodeHost::start(
        KIND,
        common,
        domain_id,
        cell,
        params,
        |shell| setup(shell, rx),
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
    shell: &mut NodeShell<Cell>,
    events: tokio::sync::mpsc::UnboundedReceiver<cell::EventBatch>,
) -> Result<(), ShellError> {
    services::register(shell)?;
    actions::register(shell)?;
    convert::register_topics(shell, events)?;
    shell.static_frame(convert::FRAME)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn yaml(s: &str) -> serde_yaml::Value {
        serde_yaml::from_str(s).unwrap()
    }

    #[test]
    fn config_errors_name_the_key() {
        let e = check(
            &CommonConfig::default(),
            yaml("cycle_time_s: 0.002"),
            "f: nodes[0]",
        )
        .unwrap_err();
        assert_eq!(e.location, "f: nodes[0].cycle_time_s");
        let e = check(
            &CommonConfig::default(),
            yaml("belts: {\"1\": {params: {z_dist_belt: -1}}}"),
            "f: nodes[0]",
        )
        .unwrap_err();
        assert!(e.to_string().contains("lrZDistBelt"), "{e}");
        let e = check(
            &CommonConfig::default(),
            yaml("path_prep_cycles: 40"),
            "f: nodes[0]",
        )
        .unwrap_err();
        assert_eq!(e.location, "f: nodes[0].path_prep_cycles", "{e}");
        let e = check(&CommonConfig::default(), yaml("bogus: 1"), "f: nodes[0]").unwrap_err();
        assert!(e.message.contains("bogus"), "{e}");
        check(&CommonConfig::default(), yaml("{}"), "f").unwrap();
        check(&CommonConfig::default(), serde_yaml::Value::Null, "f").unwrap();
    }

    #[test]
    fn the_demo_entry_is_valid() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../launch-configs/demo.yaml"
        ))
        .unwrap();
        let entries = motion_runtime::launch::parse(&text, "demo.yaml", &[NODE_KIND]).unwrap();
        assert_eq!(entries.len(), 1, "one pickplace_node entry");
        let mut cfg = config(entries[0].engine.clone(), &entries[0].location).unwrap();
        cfg.cycle_time_s = entries[0].common.cycle_period;
        engine(cfg, "demo").unwrap();
    }

    /// The demo cell picks what arrives on CV1 (mode 2) once enabled and started: through the
    /// node's engine wrapper, with the events the node publishes on `~/events`.
    #[test]
    fn the_demo_cell_picks_and_places() {
        use motion_core::{Engine, Tick};
        use pickplace_engine::belt::WorkpieceEventKind;
        use pickplace_engine::{CellEvent, GripperEvent, PickPlaceCommand};
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../launch-configs/demo.yaml"
        ))
        .unwrap();
        let entries = motion_runtime::launch::parse(&text, "demo.yaml", &[NODE_KIND]).unwrap();
        let cfg = config(entries[0].engine.clone(), "demo").unwrap();
        let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel();
        let mut c = Cell::new(engine(cfg, "demo").unwrap(), Some(tx));
        let cmd =
            |c: &mut Cell, x: PickPlaceCommand| c.command(cell::CellCommand::Engine(x)).unwrap();
        cmd(&mut c, PickPlaceCommand::SetEnable(true));
        cmd(&mut c, PickPlaceCommand::SetRegulatorOn(true));
        cmd(
            &mut c,
            PickPlaceCommand::DetectWorkpiece {
                belt: 1,
                position: [100.0, 0.0, 10.0, 0.0, 0.0, 0.0],
                valid_delay_cycles: 0,
            },
        );
        let mut ev = Vec::new();
        for index in 0..5 {
            c.step(Tick { index, dt: 0.001 }, &mut ev);
        }
        cmd(&mut c, PickPlaceCommand::Execute { set_target: 0 });
        let mut saw_path = false;
        for index in 5..6000 {
            c.step(Tick { index, dt: 0.001 }, &mut ev);
            if index % 100 == 0 {
                saw_path |= c.snapshot().path.len() == cell::PATH_SAMPLES + 1;
            }
        }
        let mut all = Vec::new();
        while let Ok((_, b)) = rx.try_recv() {
            all.extend(b);
        }
        let picked = all.iter().any(|e| {
            matches!(
                e,
                CellEvent::Workpiece {
                    belt: 1,
                    kind: WorkpieceEventKind::Picked,
                    ..
                }
            )
        });
        let pulses: Vec<GripperEvent> = all
            .iter()
            .filter_map(|e| {
                if let CellEvent::GripperPulse { kind, .. } = e {
                    Some(*kind)
                } else {
                    None
                }
            })
            .collect();
        assert!(picked, "{all:?}");
        assert_eq!(pulses.first(), Some(&GripperEvent::Close), "{pulses:?}");
        assert!(pulses.contains(&GripperEvent::Open), "placed: {pulses:?}");
        assert!(saw_path, "a running leg has a path to draw");
        let m = convert::markers(&motion_runtime::cycle::Stamped {
            cycle: 0,
            sim_time: 0.0,
            ros_time_ns: 0,
            state: c.snapshot(),
        });
        let belt1 = &m.markers[0];
        assert_eq!((belt1.ns.as_str(), belt1.id, belt1.action), ("belts", 1, 0));
        // Working area 200 … 800 along belt X = −MCS X from origin X 400: centre at MCS X −100.
        assert!(
            (belt1.pose.position.x + 0.1).abs() < 1e-9
                && (belt1.pose.position.y - 0.5).abs() < 1e-9
        );
        assert!((belt1.scale.x - 0.6).abs() < 1e-12);
        assert_eq!(m.markers[1].action, 2, "belt 2 is not configured: deleted");
    }
}
