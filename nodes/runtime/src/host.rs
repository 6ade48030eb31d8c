//! Hosting one node: its common settings from the launch config, its Context, its cycle and
//! its ROS shell, kept alive together and shut down in the right order.

use crate::cycle::{ClockMode, Controller, ControllerHandle, CycleConfig};
use crate::shell::{self, NodeShell, ShellError, ShellSettings};
use motion_core::Engine;
use ros2_client::{Context, ParameterValue};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Settings every node entry of a launch config may give (all optional).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CommonConfig {
    /// Node name (default: the node kind, e.g. `axis_node`).
    pub name: String,
    /// Namespace (default `/`).
    pub namespace: String,
    /// Cycle period [s] (default 0.001).
    pub cycle_period: f64,
    /// State topic rate [Hz] (default 100).
    pub state_rate: f64,
    /// Lockstep mode: simulated time, the node is the clock (publishes `/clock`, cycles run on
    /// `~/step`). Default false.
    pub lockstep: bool,
    /// `use_sim_time` as in ROS: the node's time follows an external `/clock`
    /// (rosgraph_msgs/Clock), and its cycles run as that clock passes them. Default false;
    /// excludes `lockstep`.
    pub use_sim_time: bool,
    /// `auto` (from RMW_IMPLEMENTATION), `cyclone`, `enhanced` or `basic`.
    pub service_mapping: String,
    /// Capacity of the command queue into the cycle (default 256).
    pub queue_capacity: usize,
    /// Busy-wait before each deadline [s] (default 100 µs, at most half a period: a tenth of a
    /// core per node at 1 kHz buys a wake-up jitter below the kernel's sleep latency; 0 = sleep
    /// only).
    pub spin: f64,
    /// How long an action keeps an ended goal's result for a client that has not asked for it
    /// yet [s] (rcl_action's `result_timeout`, default 900 = 15 min); then it is dropped.
    pub result_timeout: f64,
    /// Parent frame of the node's own frame on `/tf_static` (default `world`): one root joins
    /// every node's markers in RViz.
    pub tf_parent: String,
    /// Pose of the node's frame in `tf_parent`: x, y, z [m], roll, pitch, yaw [rad] (default 0).
    pub tf_pose: [f64; 6],
    /// Simulated time only (lockstep, use_sim_time): the state topics publish the state of
    /// every n-th cycle, none left out, from cycle 0 on, instead of `state_rate` (default 1 in
    /// lockstep, off with use_sim_time; 0 = off). The cycle waits for slow publishers, never
    /// the other way round. Not available in real time (refused).
    pub state_publish_every_n_cycles: Option<u32>,
    /// A command script (`script:`): commands the node applies by itself at given simulated
    /// times, so a machine moves without a client (demos, `--cycles` runs, replays).
    pub script: Vec<ScriptStep>,
}

/// The `~/command_status` label of a script command, read off its YAML: the innermost variant
/// name in snake_case (`MoveAbsolute` -> `move_absolute`, as the services name FBs) and the
/// value of its first object field (axis, mover, group, track, belt, part).
fn script_label(command: &serde_yaml::Value) -> crate::shell::CommandLabel {
    use serde_yaml::Value;
    let mut label = crate::shell::CommandLabel::default();
    let mut v = command;
    loop {
        let (name, inner) = match v {
            Value::Tagged(t) => (
                t.tag.to_string().trim_start_matches('!').to_string(),
                &t.value,
            ),
            Value::Mapping(m) if m.len() == 1 => match m.iter().next() {
                Some((Value::String(k), inner)) if k.starts_with(char::is_uppercase) => {
                    (k.clone(), inner)
                }
                _ => break,
            },
            Value::String(k) if k.starts_with(char::is_uppercase) => (k.clone(), &Value::Null),
            _ => break,
        };
        label.command = crate::shell::snake_case(&name);
        v = inner;
    }
    if let Value::Mapping(m) = v {
        for key in ["axis", "mover", "group", "track", "belt", "part"] {
            match m.get(key) {
                Some(Value::String(o)) => label.object = o.clone(),
                Some(Value::Number(n)) => label.object = n.to_string(),
                _ => continue,
            }
            break;
        }
    }
    label
}

/// One step of a node's command script: at simulated time `at` [s] (the cycle
/// `round(at / cycle_period)`), the engine command `command` (as the engine spells it, in map
/// form `{MoveAbsolute: {axis: x, position: 100.0, velocity: 500.0, ...}}` or tag form
/// `!MoveAbsolute {...}`) is applied before that cycle's step, exactly as a client's call in
/// that cycle would be. Steps run in the order of
/// their times (the listed order among equal times); a rejected step is logged with its error
/// id and the script goes on.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ScriptStep {
    /// Simulated time [s] from the node's start.
    pub at: f64,
    /// The engine command.
    pub command: serde_yaml::Value,
}

impl Default for CommonConfig {
    fn default() -> Self {
        CommonConfig {
            name: String::new(),
            namespace: "/".into(),
            cycle_period: 0.001,
            state_rate: 100.0,
            lockstep: false,
            use_sim_time: false,
            service_mapping: "auto".into(),
            queue_capacity: 256,
            spin: 1e-4,
            result_timeout: 900.0,
            tf_parent: "world".into(),
            tf_pose: [0.0; 6],
            state_publish_every_n_cycles: None,
            script: Vec::new(),
        }
    }
}

/// The keys of [`CommonConfig`]; everything else in a node entry belongs to the engine.
pub const COMMON_KEYS: &[&str] = &[
    "kind",
    "name",
    "namespace",
    "cycle_period",
    "state_rate",
    "lockstep",
    "use_sim_time",
    "service_mapping",
    "queue_capacity",
    "spin",
    "result_timeout",
    "tf_parent",
    "tf_pose",
    "state_publish_every_n_cycles",
    "script",
];

/// A configuration error: where (file, key) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigError {
    /// Where: `file: nodes[0] (axis_node): axes.x.max_velocity`.
    pub location: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.message)
    }
}

impl std::error::Error for ConfigError {}

impl CommonConfig {
    /// Validates ranges and fills the default name. `location` prefixes error messages.
    pub fn validated(mut self, kind: &str, location: &str) -> Result<Self, ConfigError> {
        let bad = |key: &str, msg: String| ConfigError {
            location: format!("{location}.{key}"),
            message: msg,
        };
        if self.name.is_empty() {
            self.name = kind.to_string();
        }
        if ros2_client::NodeName::new(&self.namespace, &self.name).is_err() {
            return Err(bad(
                "name",
                format!(
                    "'{}' in namespace '{}' is not a valid ROS node name",
                    self.name, self.namespace
                ),
            ));
        }
        if !(self.cycle_period.is_finite() && self.cycle_period >= 1e-5 && self.cycle_period <= 1.0)
        {
            return Err(bad(
                "cycle_period",
                format!("{} s is outside 0.00001..1 s", self.cycle_period),
            ));
        }
        if !(self.state_rate.is_finite() && self.state_rate > 0.0 && self.state_rate <= 1000.0) {
            return Err(bad(
                "state_rate",
                format!("{} Hz is outside (0, 1000] Hz", self.state_rate),
            ));
        }
        if self.state_publish_every_n_cycles.is_some_and(|n| n > 0)
            && !self.lockstep
            && !self.use_sim_time
        {
            return Err(bad(
                "state_publish_every_n_cycles",
                "needs simulated time (lockstep or use_sim_time); in real time the state topics \
                 publish at state_rate"
                    .to_string(),
            ));
        }
        for (i, step) in self.script.iter().enumerate() {
            if !(step.at.is_finite() && (0.0..=1e7).contains(&step.at)) {
                return Err(bad(
                    &format!("script[{i}].at"),
                    format!("{} s is outside [0, 1e7] s", step.at),
                ));
            }
        }
        if self.queue_capacity == 0 || self.queue_capacity > 100_000 {
            return Err(bad(
                "queue_capacity",
                format!("{} is outside 1..100000", self.queue_capacity),
            ));
        }
        if !(self.spin.is_finite() && self.spin >= 0.0 && self.spin <= 0.01) {
            return Err(bad(
                "spin",
                format!("{} s is outside [0, 0.01] s", self.spin),
            ));
        }
        if !(self.result_timeout.is_finite()
            && self.result_timeout > 0.0
            && self.result_timeout <= 86_400.0)
        {
            return Err(bad(
                "result_timeout",
                format!("{} s is outside (0, 86400] s", self.result_timeout),
            ));
        }
        shell::service_mapping(Some(&self.service_mapping))
            .map_err(|e| bad("service_mapping", e.0))?;
        if ros2_client::Name::parse(&format!("/{}", self.tf_parent)).is_err()
            || self.tf_parent.starts_with('/')
        {
            return Err(bad(
                "tf_parent",
                format!("'{}' is not a valid frame id", self.tf_parent),
            ));
        }
        if let Some(v) = self.tf_pose.iter().find(|v| !v.is_finite()) {
            return Err(bad("tf_pose", format!("{v} is not a finite number")));
        }
        if self.use_sim_time && self.lockstep {
            return Err(bad(
                "use_sim_time",
                "use_sim_time (follow an external /clock) and lockstep (the node is the clock) \
                 exclude each other"
                    .to_string(),
            ));
        }
        Ok(self)
    }

    /// The cycle settings.
    pub fn cycle(&self) -> CycleConfig {
        CycleConfig {
            name: self.name.clone(),
            period: self.cycle_period,
            mode: if self.lockstep || self.use_sim_time {
                ClockMode::Lockstep
            } else {
                ClockMode::RealTime
            },
            queue_capacity: self.queue_capacity,
            snapshot_every: ((1.0 / self.state_rate / self.cycle_period).floor() as u32).max(1),
            // Never spin for more than half a period.
            spin: self.spin.min(self.cycle_period / 2.0),
            stream_every: self.stream_every(),
        }
    }

    /// The script as engine commands with the cycle each runs before and its label, in
    /// running order; a command the engine cannot read is a configuration error naming its
    /// step.
    pub fn script_commands<C: serde::de::DeserializeOwned>(
        &self,
        location: &str,
    ) -> Result<Vec<crate::cycle::ScriptedCommand<C>>, ConfigError> {
        let mut out = Vec::with_capacity(self.script.len());
        for (i, step) in self.script.iter().enumerate() {
            let at = format!("{location}.script[{i}].command");
            // `!Variant {..}` (serde_yaml's tag form) or `{Variant: {..}}` (the map form).
            let command = if matches!(step.command, serde_yaml::Value::Tagged(_)) {
                from_value(step.command.clone(), &at)?
            } else {
                serde_yaml::with::singleton_map_recursive::deserialize(step.command.clone())
                    .map_err(|e| ConfigError {
                        location: at,
                        message: e.to_string(),
                    })?
            };
            out.push(crate::cycle::ScriptedCommand {
                cycle: (step.at / self.cycle_period).round() as u64,
                command,
                label: script_label(&step.command),
            });
        }
        // Stable: equal times keep the listed order.
        out.sort_by_key(|s| s.cycle);
        Ok(out)
    }

    /// Every how many cycles the state topics publish in simulated time (0: at `state_rate`).
    pub fn stream_every(&self) -> u32 {
        match self.state_publish_every_n_cycles {
            Some(n) => n,
            None if self.lockstep => 1,
            None => 0,
        }
    }

    /// The ROS-side settings.
    pub fn shell(&self) -> Result<ShellSettings, ShellError> {
        Ok(ShellSettings {
            node_name: self.name.clone(),
            namespace: self.namespace.clone(),
            service_mapping: shell::service_mapping(Some(&self.service_mapping))?,
            state_rate: self.state_rate,
            lockstep: self.lockstep,
            use_sim_time: self.use_sim_time,
            tf_parent: self.tf_parent.clone(),
            tf_pose: self.tf_pose,
            result_timeout: std::time::Duration::from_secs_f64(self.result_timeout),
            state_stream: self.stream_every() > 0,
        })
    }

    /// The node-level ROS parameters (read-only at run time).
    pub fn parameters(&self) -> Vec<(String, ParameterValue)> {
        vec![
            (
                "cycle_period".into(),
                ParameterValue::Double(self.cycle_period),
            ),
            ("state_rate".into(), ParameterValue::Double(self.state_rate)),
            (
                "state_publish_every_n_cycles".into(),
                ParameterValue::Integer(i64::from(self.stream_every())),
            ),
            ("lockstep".into(), ParameterValue::Boolean(self.lockstep)),
            (
                "use_sim_time".into(),
                ParameterValue::Boolean(self.use_sim_time),
            ),
            (
                "service_mapping".into(),
                ParameterValue::String(self.service_mapping.clone()),
            ),
            (
                "queue_capacity".into(),
                ParameterValue::Integer(self.queue_capacity as i64),
            ),
            (
                "result_timeout".into(),
                ParameterValue::Double(self.result_timeout),
            ),
            (
                "tf_parent".into(),
                ParameterValue::String(self.tf_parent.clone()),
            ),
            (
                "tf_pose".into(),
                ParameterValue::DoubleArray(self.tf_pose.to_vec()),
            ),
        ]
    }
}

/// What `ros2 param describe` says of a node parameter (all are read-only at run time: they
/// come from the launch config). Node-specific names are described here too, so that the
/// text lives in one place.
pub fn parameter_description(name: &str) -> &'static str {
    match name {
        "cycle_period" => "cycle period of the node's controller [s] (launch config)",
        "state_rate" => "rate of the state topics [Hz] (launch config)",
        "state_publish_every_n_cycles" => {
            "simulated time: the state topics carry every n-th cycle from cycle 0 (0 = at state_rate)"
        }
        "lockstep" => "simulated time: cycles run on ~/step, the node publishes /clock",
        "service_mapping" => {
            "request/reply mapping of the node's services: auto (from RMW_IMPLEMENTATION), cyclone, enhanced, basic"
        }
        "queue_capacity" => "commands waiting for the next cycle; a full queue refuses with 0x7F04",
        "result_timeout" => "how long an ended action goal's result is kept for its client [s]",
        "tf_parent" => "parent frame of the node's frame on /tf_static",
        "tf_pose" => "pose of the node's frame in tf_parent: x, y, z [m], roll, pitch, yaw [rad]",
        "use_sim_time" => {
            "ROS time and the cycles follow an external /clock (rosgraph_msgs/Clock)"
        }
        "axes" => "names of the configured axes",
        "platform_profile" => "platform profile: tc2_mc2 (Beckhoff) or isg_mcp (ISG)",
        "ca_groups" => "names of the collision-avoidance groups",
        "persistent_parameter_file" => {
            "file of MC_Write(Bool)ParameterPersistent values, applied at start (empty: none)"
        }
        "movers" => "names of the configured movers",
        "groups" => "names of the configured groups",
        "parts" => "names of the configured parts",
        "tracks" => "names of the configured tracks",
        "environment" => "name of the XPlanar environment",
        "belts" => "numbers of the configured conveyor belts",
        "path_prep_cycles" => "cycles from the Execute edge to the first moving set point",
        "profile_queue_capacity" => "profiles that may wait behind the running one",
        _ => "node setting from the launch config (read-only at run time)",
    }
}

/// Splits a node entry of a launch config into its common settings and the engine's part.
pub fn split_entry(
    entry: &serde_yaml::Mapping,
    kind: &str,
    location: &str,
) -> Result<(CommonConfig, serde_yaml::Value), ConfigError> {
    let mut common = serde_yaml::Mapping::new();
    let mut engine = serde_yaml::Mapping::new();
    for (k, v) in entry {
        let key = k.as_str().unwrap_or_default();
        if key == "kind" {
            continue;
        }
        if COMMON_KEYS.contains(&key) {
            common.insert(k.clone(), v.clone());
        } else {
            engine.insert(k.clone(), v.clone());
        }
    }
    let common: CommonConfig = from_value(serde_yaml::Value::Mapping(common), location)?;
    Ok((
        common.validated(kind, location)?,
        serde_yaml::Value::Mapping(engine),
    ))
}

/// Deserializes part of a launch config with errors that name the key path.
pub fn from_value<T: serde::de::DeserializeOwned>(
    v: serde_yaml::Value,
    location: &str,
) -> Result<T, ConfigError> {
    // Going through text keeps serde_yaml's key path in the message ("axes.x: unknown field").
    let text = serde_yaml::to_string(&v).map_err(|e| ConfigError {
        location: location.into(),
        message: e.to_string(),
    })?;
    serde_yaml::from_str(&text).map_err(|e| {
        let msg = e.to_string();
        // Line numbers refer to the re-serialized fragment, not the file: drop them.
        let msg = match msg.find(" at line ") {
            Some(i) => msg[..i].to_string(),
            None => msg,
        };
        ConfigError {
            location: location.into(),
            message: msg,
        }
    })
}

/// One running node: Context, cycle and ROS shell. Dropping it stops the node in order.
pub struct NodeHost<E: Engine> {
    /// The ROS side (dropped first).
    pub shell: Option<NodeShell<E>>,
    /// The cycle (dropped second).
    pub controller: Option<Controller<E>>,
    /// The DDS participant (dropped last).
    pub context: Option<Context>,
}

impl<E: Engine> NodeHost<E>
where
    E::Command: Send,
    E::Reply: Send,
{
    /// Starts `engine` under `common` settings (`kind` is the node crate, e.g. `axis_node`,
    /// whose log events go to this node's rosout): a Context on the given domain (loopback-only
    /// by default), the cycle thread, the node, then `setup` registers the node's own services,
    /// actions and topics, and the common tasks start. Must run inside a tokio runtime.
    pub fn start(
        kind: &str,
        common: &CommonConfig,
        domain_id: u16,
        engine: E,
        extra_parameters: Vec<(String, ParameterValue)>,
        setup: impl FnOnce(&mut NodeShell<E>) -> Result<(), ShellError>,
    ) -> Result<Self, ShellError>
    where
        E::Command: serde::de::DeserializeOwned,
    {
        let context = shell::create_context(domain_id)?;
        let script = common
            .script_commands::<E::Command>(&format!("node '{}'", common.name))
            .map_err(|e| ShellError(format!("configuration error: {e}")))?;
        let (controller, events) = Controller::spawn(engine, common.cycle(), E::reply_id)
            .map_err(|e| ShellError(format!("starting the cycle thread: {e}")))?;
        // At once: in real time the cycles run already.
        controller
            .handle()
            .load_script(script)
            .map_err(|e| ShellError(format!("loading the script: {}", e.message)))?;
        let mut params = common.parameters();
        params.extend(extra_parameters);
        let mut shell = NodeShell::new(&context, common.shell()?, controller.handle(), params)?;
        let now = shell::ros_now(&controller.handle());
        crate::logging::route_to_rosout(&common.name, shell.node.logging_handle(), now);
        let span = crate::logging::node_span(&common.name);
        let _in_node = span.enter();
        // One `ros_discovery_info` sample for all the endpoints made here, not one per
        // endpoint: a 1000-axis node sent about 5000 samples of up to 24 kB, which readers
        // then had repaired for tens of seconds (vendor/README.md, ros2-client patch 7).
        shell.node.suppress_node_info_updates(true);
        setup(&mut shell)?;
        shell.start_common(events)?;
        shell.node.suppress_node_info_updates(false);
        tracing::info!(
            kind,
            period = common.cycle_period,
            lockstep = common.lockstep,
            use_sim_time = common.use_sim_time,
            "node started"
        );
        Ok(NodeHost {
            shell: Some(shell),
            controller: Some(controller),
            context: Some(context),
        })
    }

    /// The cycle's handle.
    pub fn handle(&self) -> ControllerHandle<E> {
        self.controller.as_ref().expect("running").handle()
    }
}

impl<E: Engine> NodeHost<E> {
    /// Stops in order: ROS tasks and node, then the cycle, then the DDS participant.
    pub async fn stop(mut self) {
        if let Some(s) = self.shell.take() {
            crate::logging::unroute(&s.settings.node_name);
            s.stop().await;
        }
        self.controller.take();
        // Let RustDDS's event loop see the removals before the participant goes.
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
        self.context.take();
    }
}

impl<E: Engine> crate::launch::Running for NodeHost<E> {
    fn stop(self: Box<Self>) -> std::pin::Pin<Box<dyn std::future::Future<Output = ()> + Send>> {
        Box::pin(NodeHost::stop(*self))
    }
    fn step(
        &self,
        n: u64,
    ) -> std::pin::Pin<Box<dyn std::future::Future<Output = Result<u64, String>> + Send>> {
        let h = self.handle();
        Box::pin(async move { h.step(n).await.map_err(|r| r.message) })
    }
    fn flush(&self, cycle: u64) -> std::pin::Pin<Box<dyn std::future::Future<Output = ()> + Send>> {
        match &self.shell {
            Some(s) => Box::pin(s.states_flushed(cycle, std::time::Duration::from_secs(5))),
            None => Box::pin(async {}),
        }
    }
    fn busy(&self) -> usize {
        self.handle().busy()
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Deserialize)]
    enum Cmd {
        Move { to: f64 },
        Stop,
    }

    fn script(text: &str) -> CommonConfig {
        CommonConfig {
            cycle_period: 0.002,
            script: serde_yaml::from_str(text).unwrap(),
            ..Default::default()
        }
    }

    /// Map and tag form, times rounded to cycles, running order by time (stable).
    #[test]
    fn script_steps_become_commands_at_their_cycles() {
        let c = script(
            "[{at: 0.1, command: {Move: {to: 5.0}}}, {at: 0.0031, command: !Move {to: 1.0}}, \
             {at: 0.1, command: Stop}]",
        );
        let steps: Vec<(u64, Cmd, String)> = c
            .script_commands::<Cmd>("f: nodes[0]")
            .unwrap()
            .into_iter()
            .map(|s| (s.cycle, s.command, s.label.command))
            .collect();
        assert_eq!(
            steps,
            vec![
                (2, Cmd::Move { to: 1.0 }, "move".into()),
                (50, Cmd::Move { to: 5.0 }, "move".into()),
                (50, Cmd::Stop, "stop".into())
            ]
        );
        // Labels: the innermost variant in snake_case and the object named in it.
        let l = script_label(
            &serde_yaml::from_str("{Ca: {MoveAbsolute: {axis: m1, position: 5}}}").unwrap(),
        );
        assert_eq!(
            (l.object.as_str(), l.command.as_str()),
            ("m1", "move_absolute")
        );
        let l = script_label(&serde_yaml::from_str("!MoverEnable {mover: m2}").unwrap());
        assert_eq!(
            (l.object.as_str(), l.command.as_str()),
            ("m2", "mover_enable")
        );
        let e = script("[{at: 0, command: {Jump: {}}}]")
            .script_commands::<Cmd>("f: nodes[0]")
            .unwrap_err();
        assert_eq!(e.location, "f: nodes[0].script[0].command");
        assert!(
            e.message.contains("unknown variant `Jump`"),
            "{}",
            e.message
        );
    }
}
