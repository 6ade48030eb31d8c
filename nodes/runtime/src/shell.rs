//! The shared ROS 2 shell of every node: participant on loopback, node with parameters and
//! rosout, services and actions with the PLCopen handshake, state publishers, command status,
//! `/diagnostics`, `/clock` and the lockstep `~/step` service.
//!
//! API rules (README "ROS API"): one service or action call = one Execute rising edge of a
//! fresh FB instance. A service answers accepted/rejected at once with an error id; the
//! command's outputs then appear on `~/command_status`. An action goal runs until the command
//! ends: feedback while busy, result Done (Succeeded) / CommandAborted (Aborted, or Canceled
//! after a cancel) / Error (Aborted, with the error id in the result).

use crate::cycle::{ControllerHandle, Stamped};
use crate::record::RecordedPublisher;
use crate::stats::CycleStats;
use motion_core::{CmdId, CommandEvent, CommandState, Engine, ErrorId, Rejection};
use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus, KeyValue};
use motion_msgs::deps::rosgraph_msgs::msg::Clock;
use motion_msgs::deps::std_msgs::msg::Header;
use motion_msgs::msg::{CommandStatus, CycleStats as CycleStatsMsg};
use motion_msgs::srv::{StepCycles, StepCyclesRequest, StepCyclesResponse};
use ros2_client::action::{ActionServerQosPolicies, AsyncActionServer, GoalEndStatus};
use ros2_client::{
    ActionTypeName, Context, Message, MessageTypeName, Name, Node, NodeName, NodeOptions,
    ParameterValue, QosProfile, ServiceMapping, ServiceTypeName,
};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt;
use std::future::Future;
use std::net::Ipv4Addr;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio::sync::mpsc::UnboundedReceiver;
use tokio::task::JoinHandle;

/// Errors while setting up a node's ROS side (the process reports them and exits non-zero).
#[derive(Debug)]
pub struct ShellError(pub String);

impl fmt::Display for ShellError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ShellError {}

fn err<E: fmt::Debug>(what: &str) -> impl FnOnce(E) -> ShellError + '_ {
    move |e| ShellError(format!("{what}: {e:?}"))
}

/// Which addresses DDS discovery may use (`ROS_AUTOMATIC_DISCOVERY_RANGE`, as in ROS 2 Jazzy).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiscoveryRange {
    /// Default: loopback only (127.0.0.1). Nothing leaves the machine.
    Localhost,
    /// Explicit opt-in (`ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET`): all interfaces.
    Subnet,
}

impl DiscoveryRange {
    /// Reads `ROS_AUTOMATIC_DISCOVERY_RANGE`; anything but `SUBNET` keeps loopback only.
    pub fn from_env() -> Self {
        match std::env::var("ROS_AUTOMATIC_DISCOVERY_RANGE").as_deref() {
            Ok("SUBNET") => DiscoveryRange::Subnet,
            _ => DiscoveryRange::Localhost,
        }
    }
}

/// `ROS_DOMAIN_ID` (default 0). Values outside 0..=232 are a configuration error.
pub fn domain_id_from_env() -> Result<u16, ShellError> {
    match std::env::var("ROS_DOMAIN_ID") {
        Err(_) => Ok(0),
        Ok(s) if s.trim().is_empty() => Ok(0),
        Ok(s) => match s.trim().parse::<u16>() {
            Ok(d) if d <= 232 => Ok(d),
            _ => Err(ShellError(format!(
                "ROS_DOMAIN_ID: '{s}' is not a domain id (0..232)"
            ))),
        },
    }
}

/// The request/reply mapping: the `service_mapping` parameter (`cyclone`, `enhanced`, `basic`)
/// when given, else from `RMW_IMPLEMENTATION` as ROS users set it (rmw_cyclonedds_cpp ->
/// Cyclone; anything else, or unset as in Jazzy's default Fast DDS -> Enhanced).
pub fn service_mapping(param: Option<&str>) -> Result<ServiceMapping, ShellError> {
    match param.map(str::trim) {
        Some("cyclone") => Ok(ServiceMapping::Cyclone),
        Some("enhanced") => Ok(ServiceMapping::Enhanced),
        Some("basic") => Ok(ServiceMapping::Basic),
        Some("") | Some("auto") | None => {
            Ok(match std::env::var("RMW_IMPLEMENTATION").as_deref() {
                Ok("rmw_cyclonedds_cpp") => ServiceMapping::Cyclone,
                _ => ServiceMapping::Enhanced,
            })
        }
        Some(other) => Err(ShellError(format!(
            "service_mapping: '{other}' is not one of auto, cyclone, enhanced, basic"
        ))),
    }
}

/// One DDS participant (and ROS Context) per node, loopback-only unless the user opted in.
pub fn create_context(domain_id: u16) -> Result<Context, ShellError> {
    let mut b = rustdds::DomainParticipantBuilder::new(domain_id);
    if DiscoveryRange::from_env() == DiscoveryRange::Localhost {
        b = b.with_only_networks([Ipv4Addr::LOCALHOST]);
    }
    let dp = b.build().map_err(err("creating the DDS participant"))?;
    Context::from_domain_participant(dp).map_err(err("creating the ROS context"))
}

/// Settings of the ROS side of one node.
#[derive(Clone, Debug)]
pub struct ShellSettings {
    /// Node name (e.g. `axis_node`).
    pub node_name: String,
    /// Namespace (default `/`).
    pub namespace: String,
    /// Request/reply mapping of every server of this node.
    pub service_mapping: ServiceMapping,
    /// Rate of the state topics [Hz] (default 100).
    pub state_rate: f64,
    /// Lockstep mode: publish `/clock` and offer `~/step`.
    pub lockstep: bool,
    /// `use_sim_time`: the cycles follow an external `/clock` (the controller runs in lockstep).
    pub use_sim_time: bool,
    /// Parent frame of the node's frame on `/tf_static`.
    pub tf_parent: String,
    /// Pose of the node's frame in `tf_parent`: x, y, z [m], roll, pitch, yaw [rad].
    pub tf_pose: [f64; 6],
    /// How long an action keeps an ended goal's result for a client that has not asked yet.
    pub result_timeout: Duration,
    /// Simulated time: the state topics publish every snapshot of the cycle's lossless state
    /// stream (`state_publish_every_n_cycles`) instead of sampling at `state_rate`.
    pub state_stream: bool,
}

/// Names of the command behind a [`CmdId`], for `~/command_status`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CommandLabel {
    /// Axis, mover, group, part or belt name.
    pub object: String,
    /// FB name in snake_case.
    pub command: String,
}

/// A command name as `~/command_status` labels carry it: `MoveAbsolute` -> `move_absolute`.
pub fn snake_case(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    for (i, c) in name.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            out.push('_');
        }
        out.extend(c.to_lowercase());
    }
    out
}

/// Maps command ids to their labels until the command ends.
#[derive(Default)]
pub struct CommandRegistry {
    labels: Mutex<HashMap<CmdId, CommandLabel>>,
}

impl CommandRegistry {
    /// Remembers a command's label.
    pub fn insert(&self, id: CmdId, label: CommandLabel) {
        self.labels
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(id, label);
    }
    /// The label of a running command (empty if it has none).
    pub fn label_of(&self, id: CmdId) -> CommandLabel {
        self.labels
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&id)
            .cloned()
            .unwrap_or_default()
    }

    fn label(&self, ev: &CommandEvent) -> CommandLabel {
        let mut m = self.labels.lock().unwrap_or_else(|e| e.into_inner());
        if ev.state.is_final() {
            m.remove(&ev.id).unwrap_or_default()
        } else {
            m.get(&ev.id).cloned().unwrap_or_default()
        }
    }
}

/// Screens a request into an engine command and its label (a rejection answers at once).
pub type Decode<Req, C> = fn(Req) -> Result<(C, CommandLabel), Rejection>;

/// A node's ROS side: the node, the controller handle, and the tasks serving it.
pub struct NodeShell<E: Engine> {
    /// The ROS node (one Context per node).
    pub node: Node,
    /// The cycle's handle.
    pub handle: ControllerHandle<E>,
    /// Settings.
    pub settings: ShellSettings,
    /// Labels of running commands.
    pub registry: Arc<CommandRegistry>,
    tasks: TaskSet,
    spinner: Option<JoinHandle<()>>,
    /// Copies of the command events with their labels (see [`NodeShell::command_event_tap`]).
    taps: Vec<tokio::sync::mpsc::UnboundedSender<(CommandEvent, CommandLabel, i64)>>,
    /// The state topics and stream readers in stream mode, served in turn by one task (see
    /// [`NodeShell::start_common`]).
    streams: Vec<StreamReader<E>>,
    /// Stream mode: the cycle of the last snapshot all state topics and readers took + 1 (0: none
    /// yet).
    stream_published: tokio::sync::watch::Receiver<u64>,
    /// The stream task's side of `stream_published`.
    stream_done: Option<tokio::sync::watch::Sender<u64>>,
    /// Asks the statistics task to publish `/diagnostics` and `~/cycle_stats` now; it answers
    /// when they are out.
    stats_now: Option<tokio::sync::mpsc::UnboundedSender<tokio::sync::oneshot::Sender<()>>>,
}

/// What a reader of the state stream does with an item after its synchronous part (e.g. a
/// message to write to DDS).
pub type StreamWork = std::pin::Pin<Box<dyn Future<Output = ()> + Send>>;

/// A reader of the state stream in stream mode: a state topic (builds and records its message
/// at once, returns the DDS write) or a [`NodeShell::stream_reader`].
type StreamReader<E> = Box<dyn FnMut(&StreamItemOf<E>) -> Option<StreamWork> + Send>;

/// An item of an engine's state stream.
type StreamItemOf<E> = crate::cycle::StreamItem<<E as Engine>::Snapshot>;

/// A topic published from the state stream: `fill` writes its message of each streamed
/// snapshot into the message of the cycle before (kept while nothing takes it away, as in a
/// record-only run: a message of every cycle allocates nothing then), which is recorded at once;
/// the returned work writes it to DDS (none in a record-only run: no future is made per topic
/// and cycle).
fn stream_topic<E, M>(
    publisher: RecordedPublisher<M>,
    fill: impl Fn(&Stamped<E::Snapshot>, &mut M) + Send + Sync + 'static,
) -> StreamReader<E>
where
    E: Engine,
    M: serde::Serialize + motion_msgs::RosType + Default + fmt::Debug + Send + Sync + 'static,
{
    // Every streamed cycle's message is recorded (the stream, and so the cycle, waits).
    let publisher = Arc::new(publisher.lossless());
    let mut kept = M::default();
    Box::new(move |item| {
        if !publisher.wanted() {
            // A run that records other topics only: not even built.
            return None;
        }
        let snap = &item.state;
        fill(snap, &mut kept);
        if !publisher.record_ref(&kept, snap.ros_time_ns) {
            return None;
        }
        let msg = std::mem::take(&mut kept);
        let publisher = publisher.clone();
        Some(Box::pin(async move {
            if let Err(e) = publisher.publish_dds(msg).await {
                tracing::warn!("{} publish failed: {e:?}", M::ROS_TYPE_NAME);
            }
        }) as StreamWork)
    })
}

/// The node's ROS time now [ns]: the system clock in real time, the time of the last cycle in
/// simulated time (for messages that no cycle stamps: `/rosout`, an action's status).
pub fn ros_now<E: Engine>(handle: &ControllerHandle<E>) -> crate::logging::RosNow {
    let h = handle.clone();
    Arc::new(move || match h.clock().source() {
        crate::clock::TimeSource::System => crate::clock::system_ns(),
        crate::clock::TimeSource::Simulated => h.snapshot().ros_time_ns,
    })
}

/// The answer of a command service (README "ROS API rules"): accepted with the command id, or
/// rejected with the error id and message; `id` reads the command id from the engine's reply.
pub fn respond<R: motion_msgs::CommandResponse, T>(
    o: &Result<T, Rejection>,
    id: impl Fn(&T) -> CmdId,
) -> R {
    let mut r = R::default();
    match o {
        Ok(reply) => r.answer(true, id(reply).0, 0, String::new()),
        Err(e) => {
            tracing::info!("refused ({:#06x}): {}", e.error_id.0, e.message);
            r.answer(false, 0, e.error_id.0, e.message.clone())
        }
    }
    r
}

/// A message stamp from ROS time [ns since the epoch].
pub fn stamp_ns(ns: i64) -> Time {
    Time {
        sec: ns.div_euclid(1_000_000_000) as i32,
        nanosec: ns.rem_euclid(1_000_000_000) as u32,
    }
}

/// The rotation R = Rz(yaw)·Ry(pitch)·Rx(roll) (angles in rad) as a quaternion, as tf2's
/// `setRPY`: the one conversion of every node's frames, poses and markers.
pub fn quaternion_rpy(
    roll: f64,
    pitch: f64,
    yaw: f64,
) -> motion_msgs::deps::geometry_msgs::msg::Quaternion {
    let (sr, cr) = (roll / 2.0).sin_cos();
    let (sp, cp) = (pitch / 2.0).sin_cos();
    let (sy, cy) = (yaw / 2.0).sin_cos();
    motion_msgs::deps::geometry_msgs::msg::Quaternion {
        x: sr * cp * cy - cr * sp * sy,
        y: cr * sp * cy + sr * cp * sy,
        z: cr * cp * sy - sr * sp * cy,
        w: cr * cp * cy + sr * sp * sy,
    }
}

/// The stamp of a snapshot: the node's ROS time of its cycle (wall clock when free-running,
/// simulated time in lockstep or with `use_sim_time`; see [`crate::clock`]).
pub fn stamp<S>(s: &Stamped<S>) -> Time {
    stamp_ns(s.ros_time_ns)
}

/// The `std_msgs/Header` of the suite's own messages: `stamp`, and `frame_id` empty (their
/// values are in the manuals' units and the machine's own coordinates; poses in tf frames go
/// on the geometry and marker topics). With a header, Foxglove, Lichtblick and PlotJuggler
/// can plot them by their stamp rather than by the time they arrived.
pub fn header(stamp: Time) -> Header {
    Header {
        stamp,
        frame_id: String::new(),
    }
}

/// The absolute ROS name of a private (`~/rel`) name of this node (after `--ros-args -r`).
pub fn private_name(settings: &ShellSettings, rel: &str) -> Result<Name, ShellError> {
    let ns = settings.namespace.trim_end_matches('/');
    node_name(settings, &format!("{ns}/{}/{rel}", settings.node_name))
}

/// Resolves a topic name as ROS does: `~/x` private, `/x` absolute, `x` in the namespace;
/// then the command line's remaps.
pub fn resolve_name(settings: &ShellSettings, topic: &str) -> Result<Name, ShellError> {
    if let Some(rel) = topic.strip_prefix("~/") {
        private_name(settings, rel)
    } else if topic.starts_with('/') {
        node_name(settings, topic)
    } else {
        let ns = settings.namespace.trim_end_matches('/');
        node_name(settings, &format!("{ns}/{topic}"))
    }
}

/// A resolved name of this node after the remaps (`crate::ros_args`).
fn node_name(settings: &ShellSettings, full: &str) -> Result<Name, ShellError> {
    let full = crate::ros_args::remap(&settings.node_name, &settings.namespace, full);
    Name::parse(&full).map_err(err("name"))
}

/// A process-wide absolute name (`/clock`, `/tf_static`, `/diagnostics`) after the remaps
/// that name no node.
fn absolute_name(full: &str) -> Result<Name, ShellError> {
    Name::parse(&crate::ros_args::remap("", "/", full)).map_err(err("name"))
}

/// QoS of services and the goal/cancel/result services of actions: reliable, volatile as the
/// ROS 2 service default, but keep-all instead of keep-last 10, so a burst of requests is never
/// dropped inside DDS: every request reaches the node and gets an answer (accepted, or refused
/// with 0x7F04 when the command queue is full). The reader is drained at once into per-request
/// tasks, so what it holds stays bounded by the DDS resource limits (8192 samples per writer).
pub fn service_qos() -> QosProfile {
    use ros2_client::qos::{Durability, History};
    QosProfile::publisher_default()
        .durability(Durability::Volatile)
        .history(History::KeepAll)
}

/// QoS of state topics (reliable, volatile, keep last 10: the ROS 2 default profile).
pub fn topic_qos() -> QosProfile {
    use ros2_client::qos::{Durability, History};
    QosProfile::publisher_default()
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth: 10 })
}

/// QoS of action servers: services as `service_qos`, status transient-local keep-last 1 (as rcl_action).
pub fn action_server_qos() -> ActionServerQosPolicies {
    use ros2_client::qos::{Durability, History};
    let status = QosProfile::publisher_default()
        .history(History::KeepLast { depth: 1 })
        .durability(Durability::TransientLocal);
    ActionServerQosPolicies {
        goal_service: service_qos(),
        result_service: service_qos(),
        cancel_service: service_qos(),
        feedback_publisher: topic_qos(),
        status_publisher: status,
    }
}

/// `/parameter_events` as the recording and the live feed see it (one topic for every node).
fn parameter_events_topic() -> &'static crate::record::RecordedTopic {
    static TOPIC: std::sync::OnceLock<crate::record::RecordedTopic> = std::sync::OnceLock::new();
    TOPIC.get_or_init(|| {
        crate::record::RecordedTopic::new(
            "/parameter_events",
            motion_msgs::deps::rcl_interfaces::msg::ParameterEvent::ROS_TYPE_NAME,
        )
    })
}

impl<E: Engine> NodeShell<E>
where
    E::Command: Send,
{
    /// Creates the node in `context` with rosout and parameter services, and the declared
    /// read-only parameters (e.g. `cycle_period`, `state_rate`, per-object settings).
    pub fn new(
        context: &Context,
        settings: ShellSettings,
        handle: ControllerHandle<E>,
        parameters: Vec<(String, ParameterValue)>,
    ) -> Result<Self, ShellError> {
        // Parameter services speak the node's mapping (ros2 param works under rmw_cyclonedds
        // too) and describe each parameter as read-only with its meaning.
        let mut opts = NodeOptions::new()
            .enable_rosout(true)
            .start_parameter_services(true)
            .parameter_service_mapping(settings.service_mapping);
        let read_only: Arc<Vec<String>> =
            Arc::new(parameters.iter().map(|(n, _)| n.clone()).collect());
        for (n, v) in parameters {
            opts = opts
                .describe_parameter(&n, crate::host::parameter_description(&n), true)
                .declare_parameter(&n, v);
        }
        // `/parameter_events` (the declaration at creation, as rclcpp announces it) into the
        // recording and the live feed too: a recorded run carries the node's settings.
        let now = ros_now(&handle);
        opts = opts.parameter_event_observer(Box::new(move |event| {
            parameter_events_topic().take(event, now())
        }));
        let ro = read_only.clone();
        // Declaration goes through the validator too: refuse changes only once the node runs.
        let running = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let is_running = running.clone();
        opts = opts.parameter_validator(Box::new(move |name: &str, _v: &ParameterValue| {
            if is_running.load(std::sync::atomic::Ordering::SeqCst) && ro.iter().any(|n| n == name)
            {
                Err(format!(
                    "parameter '{name}' is read-only at run time (set it in the launch config)"
                ))
            } else {
                Ok(())
            }
        }));
        let name =
            NodeName::new(&settings.namespace, &settings.node_name).map_err(err("node name"))?;
        let node = context
            .new_node(name, opts)
            .map_err(err("creating the node"))?;
        running.store(true, std::sync::atomic::Ordering::SeqCst);
        let tasks = TaskSet::new(crate::logging::node_span(&settings.node_name));
        let (stream_done, stream_published) = tokio::sync::watch::channel(0);
        Ok(NodeShell {
            node,
            registry: handle.labels(),
            handle,
            settings,
            tasks,
            spinner: None,
            taps: Vec::new(),
            streams: Vec::new(),
            stream_published,
            stream_done: Some(stream_done),
            stats_now: None,
        })
    }

    /// Starts the spinner and the tasks every node has: `~/command_status`, `/diagnostics`
    /// (1 Hz), and in lockstep mode `/clock` and `~/step`.
    pub fn start_common(
        &mut self,
        events: UnboundedReceiver<crate::cycle::TimedEvent>,
    ) -> Result<(), ShellError> {
        let spinner = self.node.spinner().map_err(err("spinner"))?;
        self.spinner = Some(tokio::spawn(async move {
            if let Err(e) = spinner.spin().await {
                tracing::error!("spinner stopped: {e:?}");
            }
        }));
        self.spawn_command_status(events)?;
        self.spawn_diagnostics()?;
        if std::env::var("MOTION_FAULT_HOOKS").as_deref() == Ok("1") {
            self.spawn_fault_hook()?;
        }
        if self.settings.use_sim_time {
            self.spawn_clock_follower()?;
        } else if self.settings.lockstep {
            self.spawn_clock()?;
            self.spawn_step_service()?;
        }
        // Last: `/clock` is one of the stream's readers.
        self.spawn_state_stream();
        Ok(())
    }

    /// Stream mode: publishes every snapshot of the cycle's state stream on each state topic,
    /// in order, from one task (a slow publisher holds the stream, and so the lockstep cycle,
    /// back). One task for all topics: handing each snapshot to a task per topic cost more
    /// than building and recording the messages.
    fn spawn_state_stream(&mut self) {
        // Without a stream task the sender goes, so `states_flushed` does not wait for it.
        let Some(done) = self.stream_done.take() else {
            return;
        };
        if !self.settings.state_stream {
            return;
        }
        let Some(mut rx) = self.handle.take_state_stream() else {
            return;
        };
        let mut readers = std::mem::take(&mut self.streams);
        self.tasks.spawn(async move {
            // The cycle hands items over in bursts; `done` is told once per burst (it wakes
            // whoever waits in `states_flushed`), not once per item.
            let mut items = Vec::with_capacity(crate::cycle::STREAM_CAPACITY);
            while rx
                .recv_many(&mut items, crate::cycle::STREAM_CAPACITY)
                .await
                > 0
            {
                let mut published = 0;
                for item in items.drain(..) {
                    for read in &mut readers {
                        if let Some(work) = read(&item) {
                            work.await;
                        }
                    }
                    published = item.state.cycle + 1;
                }
                done.send_replace(published);
            }
        });
    }

    /// Stream mode (lockstep with a state stream, `settings.state_stream`): `read` gets every
    /// item of the stream (each snapshot with the command events before it) after the state
    /// topics, in the stream's task; the future it returns (if any) is awaited before the next
    /// item (the stream, and so the lockstep cycle, waits for it), and
    /// [`NodeShell::states_flushed`] covers it. Without a stream `read` is never called. Call
    /// before the node starts.
    pub fn stream_reader(
        &mut self,
        read: impl FnMut(&StreamItemOf<E>) -> Option<StreamWork> + Send + 'static,
    ) {
        self.streams.push(Box::new(read));
    }

    /// A copy of every command event, with its label and the ROS time of its cycle [ns], in
    /// the order `~/command_status` publishes them (e.g. for a node's own event stream). Call
    /// before the node starts.
    pub fn command_event_tap(
        &mut self,
    ) -> tokio::sync::mpsc::UnboundedReceiver<(CommandEvent, CommandLabel, i64)> {
        let (tx, rx) = tokio::sync::mpsc::unbounded_channel();
        self.taps.push(tx);
        rx
    }

    fn spawn_command_status(
        &mut self,
        mut events: UnboundedReceiver<crate::cycle::TimedEvent>,
    ) -> Result<(), ShellError> {
        let name = private_name(&self.settings, "command_status")?;
        let topic = self
            .node
            .create_topic(&name, CommandStatus::type_name(), &topic_qos())
            .map_err(err("topic"))?;
        let publisher = self
            .node
            .create_publisher::<CommandStatus>(&topic, None)
            .map_err(err("publisher"))?;
        let publisher = RecordedPublisher::new(publisher, name);
        let registry = self.registry.clone();
        let taps = std::mem::take(&mut self.taps);
        self.tasks.spawn(async move {
            while let Some(timed) = events.recv().await {
                let (ev, at) = (timed.event, timed.ros_time_ns);
                let label = registry.label(&ev);
                for t in &taps {
                    let _ = t.send((ev, label.clone(), at));
                }
                let o = motion_core::ExecuteOutputs::from(ev.state);
                let msg = CommandStatus {
                    header: header(stamp_ns(at)),
                    command_id: ev.id.0,
                    object: label.object,
                    command: label.command,
                    busy: o.busy,
                    active: o.active,
                    done: o.done,
                    command_aborted: o.command_aborted,
                    error: o.error,
                    error_id: o.error_id.0,
                    message: if o.error {
                        E::error_text(o.error_id)
                    } else {
                        String::new()
                    },
                };
                if let Err(e) = publisher.publish(msg, at).await {
                    tracing::warn!("command_status publish failed: {e:?}");
                }
            }
        });
        Ok(())
    }

    /// `~/sim/fault` (test-only, `MOTION_FAULT_HOOKS=1`): panics the request handler, i.e. a
    /// thread of the ROS side, to test the fail-safe stop.
    fn spawn_fault_hook(&mut self) -> Result<(), ShellError> {
        use motion_msgs::srv::{SimFault, SimFaultRequest, SimFaultResponse};
        tracing::warn!(
            "test fault hooks are on (MOTION_FAULT_HOOKS=1): ~/sim/fault panics the node"
        );
        self.service::<SimFaultRequest, SimFaultResponse, _, _>(
            "sim/fault",
            SimFault::service_type_name(),
            |req: SimFaultRequest| async move {
                if req.thread == "shell" {
                    panic!("test fault hook: ~/sim/fault {{thread: shell}}");
                }
                SimFaultResponse {
                    accepted: false,
                    message: format!("thread '{}': only 'shell' is known", req.thread),
                }
            },
        )
    }

    fn spawn_diagnostics(&mut self) -> Result<(), ShellError> {
        let topic = self
            .node
            .create_topic(
                &absolute_name("/diagnostics")?,
                DiagnosticArray::type_name(),
                &topic_qos(),
            )
            .map_err(err("topic"))?;
        let publisher = self
            .node
            .create_publisher::<DiagnosticArray>(&topic, None)
            .map_err(err("publisher"))?;
        let publisher = RecordedPublisher::new(publisher, "/diagnostics");
        let name = private_name(&self.settings, "cycle_stats")?;
        let topic = self
            .node
            .create_topic(&name, CycleStatsMsg::type_name(), &topic_qos())
            .map_err(err("topic"))?;
        let stats_publisher = self
            .node
            .create_publisher::<CycleStatsMsg>(&topic, None)
            .map_err(err("publisher"))?;
        let stats_publisher = RecordedPublisher::new(stats_publisher, name);
        let handle = self.handle.clone();
        let node_name = self.settings.node_name.clone();
        let (now_tx, mut now_rx) =
            tokio::sync::mpsc::unbounded_channel::<tokio::sync::oneshot::Sender<()>>();
        self.stats_now = Some(now_tx);
        self.tasks.spawn(async move {
            let mut tick = tokio::time::interval(Duration::from_secs(1));
            loop {
                let done = tokio::select! {
                    _ = tick.tick() => None,
                    asked = now_rx.recv() => asked,
                };
                let stats = handle.stats();
                let snap = handle.snapshot();
                let msg = diagnostics_message(&node_name, &stats, stamp(&snap));
                if let Err(e) = publisher.publish(msg, snap.ros_time_ns).await {
                    tracing::warn!("diagnostics publish failed: {e:?}");
                }
                let msg = cycle_stats_message(&stats, stamp(&snap));
                if let Err(e) = stats_publisher.publish(msg, snap.ros_time_ns).await {
                    tracing::warn!("cycle_stats publish failed: {e:?}");
                }
                if let Some(done) = done {
                    let _ = done.send(());
                }
            }
        });
        Ok(())
    }

    fn spawn_clock(&mut self) -> Result<(), ShellError> {
        let topic = self
            .node
            .create_topic(&absolute_name("/clock")?, Clock::type_name(), &topic_qos())
            .map_err(err("topic"))?;
        let publisher = self
            .node
            .create_publisher::<Clock>(&topic, None)
            .map_err(err("publisher"))?;
        let publisher = RecordedPublisher::new(publisher, "/clock");
        if self.settings.state_stream {
            // Every streamed cycle's time, in the stream's order (no wake-up per snapshot).
            self.streams
                .push(stream_topic::<E, _>(publisher, |snap, m: &mut Clock| {
                    m.clock = stamp_ns(snap.ros_time_ns);
                }));
            return Ok(());
        }
        let mut snaps = self.handle.snapshots();
        self.tasks.spawn(async move {
            while snaps.changed().await.is_ok() {
                let t = snaps.borrow_and_update().ros_time_ns;
                let _ = publisher.publish(Clock { clock: stamp_ns(t) }, t).await;
            }
        });
        Ok(())
    }

    /// Publishes the node's frame `child` on `/tf_static` (tf2_msgs/TFMessage, transient local
    /// as tf2's static broadcaster), placed at `tf_pose` in `tf_parent`, so that RViz shows
    /// every node's markers under one root.
    pub fn static_frame(&mut self, child: &str) -> Result<(), ShellError> {
        use motion_msgs::deps::geometry_msgs::msg::{Transform, TransformStamped, Vector3};
        use motion_msgs::deps::std_msgs::msg::Header;
        use motion_msgs::deps::tf2_msgs::msg::TFMessage;
        use ros2_client::qos::{Durability, History};
        let qos = QosProfile::publisher_default()
            .durability(Durability::TransientLocal)
            .history(History::KeepLast { depth: 1 });
        let topic = self
            .node
            .create_topic(&absolute_name("/tf_static")?, TFMessage::type_name(), &qos)
            .map_err(err("topic"))?;
        let publisher = self
            .node
            .create_publisher::<TFMessage>(&topic, None)
            .map_err(err("publisher"))?;
        // Latched on the live feed too: the apps' 3D panels need it from a client that
        // connects after the start.
        let publisher = RecordedPublisher::new(publisher, "/tf_static").latched();
        let [x, y, z, roll, pitch, yaw] = self.settings.tf_pose;
        let msg = TFMessage {
            transforms: vec![TransformStamped {
                header: Header {
                    stamp: stamp(&self.handle.snapshot()),
                    frame_id: self.settings.tf_parent.clone(),
                },
                child_frame_id: child.to_string(),
                transform: Transform {
                    translation: Vector3 { x, y, z },
                    rotation: quaternion_rpy(roll, pitch, yaw),
                },
            }],
        };
        let t = self.handle.snapshot().ros_time_ns;
        self.tasks.spawn(async move {
            if let Err(e) = publisher.publish(msg, t).await {
                tracing::warn!("/tf_static publish failed: {e:?}");
            }
            // Kept alive: a transient-local sample lives as long as its writer.
            std::future::pending::<()>().await;
        });
        Ok(())
    }

    /// `use_sim_time`: runs the cycles the external `/clock` has passed. The first `/clock`
    /// time seen becomes the ROS time of the current cycle; after that, a cycle runs when the
    /// clock passes its time. A clock that goes back is reported once and waited out.
    fn spawn_clock_follower(&mut self) -> Result<(), ShellError> {
        use ros2_client::qos::{Durability, History, Reliability};
        // As rclcpp's ClockQoS: best effort, keep last 1 (matches reliable publishers too).
        let qos = QosProfile::subscription_default()
            .reliability(Reliability::BestEffort)
            .durability(Durability::Volatile)
            .history(History::KeepLast { depth: 1 });
        let topic = self
            .node
            .create_topic(&absolute_name("/clock")?, Clock::type_name(), &qos)
            .map_err(err("topic"))?;
        let clocks = self
            .node
            .create_subscription::<Clock>(&topic, None)
            .map_err(err("subscription"))?;
        let handle = self.handle.clone();
        let period_ns = (handle.config().period * 1e9).round() as i64;
        self.tasks.spawn(async move {
            let mut origin: Option<(i64, u64)> = None; // (ROS time, cycle) at the first /clock
            let mut went_back = false;
            let mut last_ns = i64::MIN;
            loop {
                let ns = match clocks.async_take().await {
                    Ok((c, _)) => {
                        i64::from(c.clock.sec) * 1_000_000_000 + i64::from(c.clock.nanosec)
                    }
                    Err(e) => {
                        tracing::warn!("/clock: unreadable sample: {e:?}");
                        continue;
                    }
                };
                let (t0, c0) = match origin {
                    Some(o) => o,
                    None => {
                        let s = handle.snapshot();
                        handle
                            .clock()
                            .set_origin(ns - (s.sim_time * 1e9).round() as i64);
                        tracing::info!("following /clock from {:.3} s", ns as f64 * 1e-9);
                        let _ = handle.step(0).await; // state stamped with the new time
                        *origin.insert((ns, s.cycle))
                    }
                };
                if ns < last_ns {
                    if !went_back {
                        tracing::warn!(
                            "/clock went back; waiting until it passes this cycle again"
                        );
                        went_back = true;
                    }
                    continue;
                }
                went_back = false;
                last_ns = ns;
                // Cycles another request ran (an FB cycle) are not run twice.
                let due = c0 + ((ns - t0) / period_ns) as u64;
                let now = handle.snapshot().cycle;
                if due > now {
                    if let Err(r) = handle.step(due - now).await {
                        tracing::warn!("following /clock: {r}");
                    }
                }
            }
        });
        Ok(())
    }

    fn spawn_step_service(&mut self) -> Result<(), ShellError> {
        self.step_service("step")
    }

    /// Serves the lockstep step (`StepCycles`) under `~/<name>`; `~/step` is served by
    /// `start` in lockstep, a node may offer it under another name too (e.g. `sim/step`).
    pub fn step_service(&mut self, name: &str) -> Result<(), ShellError> {
        let handle = self.handle.clone();
        let period = handle.config().period;
        self.service::<StepCyclesRequest, StepCyclesResponse, _, _>(
            name,
            StepCycles::service_type_name(),
            move |req: StepCyclesRequest| {
                let handle = handle.clone();
                async move {
                    match handle.step(u64::from(req.cycles)).await {
                        Ok(c) => StepCyclesResponse {
                            accepted: true,
                            error_id: 0,
                            message: String::new(),
                            cycle_index: c,
                            sim_time: c as f64 * period,
                        },
                        Err(r) => StepCyclesResponse {
                            accepted: false,
                            error_id: r.error_id.0,
                            message: r.message,
                            cycle_index: 0,
                            sim_time: 0.0,
                        },
                    }
                }
            },
        )
    }

    /// Serves `~/<name>`: each request is handled in its own task, so a slow call never delays
    /// another one.
    pub fn service<Req, Resp, F, Fut>(
        &mut self,
        name: &str,
        type_name: ServiceTypeName,
        handler: F,
    ) -> Result<(), ShellError>
    where
        Req: Message + Clone + Send + Sync + 'static,
        Resp: Message + Send + Sync + 'static,
        F: Fn(Req) -> Fut + Send + Sync + 'static,
        Fut: Future<Output = Resp> + Send + 'static,
    {
        let server = self
            .node
            .create_server::<Req, Resp>(
                self.settings.service_mapping,
                &private_name(&self.settings, name)?,
                &type_name,
                service_qos(),
                service_qos(),
            )
            .map_err(err("service server"))?;
        let server = Arc::new(server);
        let handler = Arc::new(handler);
        let sname = name.to_string();
        let children = self.tasks.clone();
        self.tasks.spawn(async move {
            loop {
                match server.async_receive_request().await {
                    Ok((id, req)) => {
                        let server = server.clone();
                        let handler = handler.clone();
                        let sname = sname.clone();
                        children.spawn(async move {
                            let resp = handler(req).await;
                            if let Err(e) = server.async_send_response(id, resp).await {
                                tracing::warn!("{sname}: sending the response failed: {e:?}");
                            }
                        });
                    }
                    Err(e) => tracing::warn!("{sname}: bad request: {e:?}"),
                }
            }
        });
        Ok(())
    }

    /// Serves an Execute-edge command as a service: `decode` screens the request and builds the
    /// engine command (a rejection answers at once), `respond` builds the response.
    pub fn command_service<Req, Resp>(
        &mut self,
        name: &str,
        type_name: ServiceTypeName,
        decode: Decode<Req, E::Command>,
        respond: fn(Result<E::Reply, Rejection>) -> Resp,
    ) -> Result<(), ShellError>
    where
        Req: Message + Clone + Send + Sync + 'static,
        Resp: Message + Send + Sync + 'static,
        E::Reply: Send,
    {
        let handle = self.handle.clone();
        self.service::<Req, Resp, _, _>(name, type_name, move |req: Req| {
            let handle = handle.clone();
            async move {
                let result = match decode(req) {
                    Err(r) => Err(r),
                    Ok((cmd, label)) => handle.call_labeled(cmd, label).await,
                };
                respond(result)
            }
        })
    }

    /// Serves a motion command as an action (see the module doc for the mapping).
    pub fn action<B: ActionBinding<E>>(
        &mut self,
        name: &str,
        binding: B,
    ) -> Result<(), ShellError> {
        let server = self
            .node
            .create_action_server::<B::Goal, B::Result, B::Feedback>(
                self.settings.service_mapping,
                &private_name(&self.settings, name)?,
                &B::action_type_name(),
                action_server_qos(),
            )
            .map_err(err("action server"))?;
        let server = Arc::new(AsyncActionServer::new(server));
        server.set_result_timeout(self.settings.result_timeout);
        let action_name = private_name(&self.settings, name)?;
        // The status topic, which the server publishes itself, into the recording and the
        // live feed too.
        let status = crate::record::RecordedTopic::new(
            format!("{action_name}/_action/status"),
            "action_msgs/msg/GoalStatusArray",
        );
        let now = ros_now(&self.handle);
        server.set_status_observer(Box::new(move |s| status.take(s, now())));
        let binding = Arc::new(binding);
        let type_name = B::action_type_name();
        let book = Arc::new(GoalBook {
            feedback: crate::record::RecordedTopic::new(
                format!("{action_name}/_action/feedback"),
                format!(
                    "{}/action/{}_FeedbackMessage",
                    type_name.package_name(),
                    type_name.type_name()
                ),
            ),
            goals: Default::default(),
            canceled: Default::default(),
            instances: Default::default(),
        });
        let feedback_period = Duration::from_secs_f64(1.0 / self.settings.state_rate.max(1.0));

        // Result requests, per goal: answered when the goal ends (or at once when it has),
        // whatever other clients do; results are kept for `result_timeout`.
        {
            let server = server.clone();
            let aname = name.to_string();
            self.tasks.spawn(async move {
                if let Err(e) = server.serve_result_requests().await {
                    tracing::error!("{aname}: result requests cannot be read: {e:?}");
                }
            });
        }

        // Cancel requests: the engine applies the command's halt semantics; the goal then
        // ends as Canceled when the engine reports the command aborted.
        {
            let server = server.clone();
            let book = book.clone();
            let handle = self.handle.clone();
            let aname = name.to_string();
            self.tasks.spawn(async move {
                loop {
                    let cancel = match server.receive_cancel_request().await {
                        Ok(c) => c,
                        Err(e) => {
                            tracing::warn!("{aname}: bad cancel request: {e:?}");
                            continue;
                        }
                    };
                    let targets: Vec<(ros2_client::action::GoalId, CmdId)> = {
                        let g = book.goals.lock().unwrap_or_else(|e| e.into_inner());
                        cancel
                            .goals()
                            .filter_map(|gid| g.get(&gid).map(|c| (gid, *c)))
                            .collect()
                    };
                    let mut accepted = Vec::new();
                    for (gid, cid) in targets {
                        // Marked before the engine aborts the command: the goal task may see
                        // the Aborted event before this task sees the cancel's reply.
                        book.canceled
                            .lock()
                            .unwrap_or_else(|e| e.into_inner())
                            .insert(gid);
                        match handle.cancel(cid).await {
                            Ok(()) => accepted.push(gid),
                            Err(r) => {
                                book.canceled
                                    .lock()
                                    .unwrap_or_else(|e| e.into_inner())
                                    .remove(&gid);
                                tracing::warn!("{aname}: cancel of command {} refused: {r}", cid.0)
                            }
                        }
                    }
                    if let Err(e) = server
                        .respond_to_cancel_requests(&cancel, accepted.into_iter())
                        .await
                    {
                        tracing::warn!("{aname}: cancel response failed: {e:?}");
                    }
                }
            });
        }

        let handle = self.handle.clone();
        let aname = name.to_string();
        let children = self.tasks.clone();
        self.tasks.spawn(async move {
            loop {
                let new_goal = match server.receive_new_goal().await {
                    Ok(g) => g,
                    Err(e) => {
                        tracing::warn!("{aname}: bad goal request: {e:?}");
                        continue;
                    }
                };
                let Some(goal) = server.get_new_goal(new_goal.clone()) else {
                    continue;
                };
                let server = server.clone();
                let binding = binding.clone();
                let handle = handle.clone();
                let book = book.clone();
                let aname = aname.clone();
                children.spawn(async move {
                    let goal_id = new_goal.goal_id();
                    let accepted = match server.accept_goal(new_goal).await {
                        Ok(a) => a,
                        Err(e) => {
                            tracing::warn!("{aname}: accepting goal failed: {e:?}");
                            return;
                        }
                    };
                    let executing = match server.start_executing_goal(accepted).await {
                        Ok(x) => x,
                        Err(e) => {
                            tracing::warn!("{aname}: executing goal failed: {e:?}");
                            return;
                        }
                    };
                    let (status, result) = run_goal(
                        &*binding,
                        &goal,
                        goal_id,
                        &handle,
                        &book,
                        &server,
                        executing.clone(),
                        feedback_period,
                    )
                    .await;
                    book.goals
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .remove(&goal_id);
                    // Never waits for the client: the result is kept and served per goal.
                    if let Err(e) = server.send_result_response(executing, status, result).await {
                        tracing::warn!("{aname}: sending the result failed: {e:?}");
                    }
                });
            }
        });
        Ok(())
    }

    /// Publishes messages built from the latest snapshot at the state rate (only when the
    /// snapshot changed, i.e. the cycle ran). `build` returns one message per publisher.
    pub fn state_publisher<M, F>(
        &mut self,
        topic: &str,
        type_name: MessageTypeName,
        build: F,
    ) -> Result<(), ShellError>
    where
        M: Message + motion_msgs::RosType + Default + fmt::Debug + Send + Sync + 'static,
        F: Fn(&Stamped<E::Snapshot>) -> M + Send + Sync + 'static,
    {
        self.state_publisher_refill(topic, type_name, move |s, m: &mut M| *m = build(s))
    }

    /// [`NodeShell::state_publisher`] whose `fill` writes every field of the message it is
    /// given: an earlier cycle's message (or a default one), so that a stream of every cycle
    /// reuses the message's memory (names, arrays) instead of allocating it again.
    pub fn state_publisher_refill<M, F>(
        &mut self,
        topic: &str,
        type_name: MessageTypeName,
        fill: F,
    ) -> Result<(), ShellError>
    where
        M: Message + motion_msgs::RosType + Default + fmt::Debug + Send + Sync + 'static,
        F: Fn(&Stamped<E::Snapshot>, &mut M) + Send + Sync + 'static,
    {
        let name = resolve_name(&self.settings, topic)?;
        let t = self
            .node
            .create_topic(&name, type_name, &topic_qos())
            .map_err(err("topic"))?;
        let publisher = self
            .node
            .create_publisher::<M>(&t, None)
            .map_err(err("publisher"))?;
        let publisher = RecordedPublisher::new(publisher, name);
        if self.settings.state_stream {
            // Every streamed cycle, in order (see `spawn_state_stream`).
            self.streams.push(stream_topic::<E, _>(publisher, fill));
            return Ok(());
        }
        let handle = self.handle.clone();
        let period = Duration::from_secs_f64(1.0 / self.settings.state_rate.max(0.1));
        self.tasks.spawn(async move {
            let mut tick = tokio::time::interval(period);
            tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
            let mut last = u64::MAX;
            loop {
                tick.tick().await;
                let snap = handle.snapshot();
                if snap.cycle == last {
                    continue;
                }
                last = snap.cycle;
                let mut msg = M::default();
                fill(&snap, &mut msg);
                if let Err(e) = publisher.publish(msg, snap.ros_time_ns).await {
                    tracing::warn!("state publish failed: {e:?}");
                }
            }
        });
        Ok(())
    }

    /// Stream mode: a future that ends once every state publisher has published the snapshot
    /// of cycle `cycle` and the statistics went out once more (at most `timeout`), so that a
    /// recording holds the last statistics and a node stopped after its last lockstep
    /// step loses none of its cycles. Ends at once without a stream.
    pub fn states_flushed(
        &self,
        cycle: u64,
        timeout: Duration,
    ) -> impl Future<Output = ()> + Send + 'static {
        let mut published = self.stream_published.clone();
        let stats_now = self.stats_now.clone();
        async move {
            let all = async {
                // An ended or absent stream task has nothing more to publish.
                let _ = published.wait_for(|&c| c > cycle).await;
                // The statistics as they stand after the last cycle.
                if let Some(now) = stats_now {
                    let (tx, rx) = tokio::sync::oneshot::channel();
                    if now.send(tx).is_ok() {
                        let _ = rx.await;
                    }
                }
            };
            let _ = tokio::time::timeout(timeout, all).await;
        }
    }

    /// Spawns a task of this node (e.g. the publisher of a node-specific event stream); it is
    /// aborted and awaited with the node's other tasks when the node stops.
    pub fn spawn(&self, fut: impl Future<Output = ()> + Send + 'static) {
        self.tasks.spawn(fut);
    }

    /// Stops the node's tasks and waits until their servers and publishers are dropped (they
    /// must go before the node and the Context, or RustDDS reports orphaned entities).
    pub async fn stop(mut self) {
        self.tasks.shutdown().await;
        // Dropping the node signals its spinner, which then ends by itself.
        let spinner = self.spinner.take();
        drop(self);
        if let Some(s) = spinner {
            let _ = tokio::time::timeout(Duration::from_secs(1), s).await;
        }
    }
}

impl<E: Engine> Drop for NodeShell<E> {
    fn drop(&mut self) {
        self.tasks.abort_all();
        // The spinner ends when the node (dropped right after this) signals it.
    }
}

/// The tasks of a node, including per-request and per-goal children, so that shutdown can
/// abort and await all of them (each may hold a DDS server or publisher).
/// Every task runs in the node's span, so its log lines reach the node's `/rosout`.
#[derive(Clone)]
pub struct TaskSet(Arc<Mutex<Vec<JoinHandle<()>>>>, tracing::Span);

impl TaskSet {
    /// An empty set whose tasks run in `span`.
    pub fn new(span: tracing::Span) -> Self {
        TaskSet(Arc::default(), span)
    }

    /// Spawns a task on the current runtime and keeps its handle (finished ones are pruned).
    pub fn spawn(&self, fut: impl Future<Output = ()> + Send + 'static) {
        use tracing::Instrument;
        let h = tokio::spawn(fut.instrument(self.1.clone()));
        let mut v = self.0.lock().unwrap_or_else(|e| e.into_inner());
        v.retain(|t| !t.is_finished());
        v.push(h);
    }

    fn abort_all(&self) {
        for t in self.0.lock().unwrap_or_else(|e| e.into_inner()).iter() {
            t.abort();
        }
    }

    /// Aborts every task and waits until each is dropped.
    pub async fn shutdown(&self) {
        let tasks = std::mem::take(&mut *self.0.lock().unwrap_or_else(|e| e.into_inner()));
        for t in &tasks {
            t.abort();
        }
        for t in tasks {
            let _ = t.await;
        }
    }
}

/// How one action maps goal, feedback and result onto an engine command.
pub trait ActionBinding<E: Engine>: Send + Sync + 'static {
    /// Goal message.
    type Goal: Message + Clone + Send + Sync + 'static;
    /// Result message.
    type Result: Message + Clone + Default + Send + Sync + 'static;
    /// Feedback message.
    type Feedback: Message + Send + Sync + 'static;
    /// The ROS action type name.
    fn action_type_name() -> ActionTypeName;
    /// Screens the goal and builds the command (the Execute edge) and its label.
    fn command(&self, goal: &Self::Goal) -> Result<(E::Command, CommandLabel), Rejection>;
    /// Feedback from the latest snapshot while the command is busy.
    fn feedback(
        &self,
        goal: &Self::Goal,
        snap: &Stamped<E::Snapshot>,
        state: CommandState,
    ) -> Self::Feedback;
    /// The result: `end` is the final state; `rejection` is set when the command was refused.
    fn result(
        &self,
        goal: &Self::Goal,
        snap: &Stamped<E::Snapshot>,
        end: CommandState,
        rejection: Option<&Rejection>,
    ) -> Self::Result;
    /// [`Self::feedback`] knowing the engine's command id (for feedback that carries it);
    /// the default ignores the id.
    fn feedback_of(
        &self,
        goal: &Self::Goal,
        _id: CmdId,
        snap: &Stamped<E::Snapshot>,
        state: CommandState,
    ) -> Self::Feedback {
        self.feedback(goal, snap, state)
    }
    /// [`Self::result`] knowing the engine's command id (None: refused before an instance
    /// existed); the default ignores the id.
    fn result_of(
        &self,
        goal: &Self::Goal,
        _id: Option<CmdId>,
        snap: &Stamped<E::Snapshot>,
        end: CommandState,
        rejection: Option<&Rejection>,
    ) -> Self::Result {
        self.result(goal, snap, end, rejection)
    }
    /// The goal's FB instance name (`fb_instance`, plcopen_platform.md §12.1), if it names
    /// one: a goal accepted while an earlier goal of the same instance runs re-triggers the
    /// instance; the earlier goal then ends ABORTED (command_aborted) with "retriggered".
    /// Default: every goal is a fresh instance.
    fn instance(&self, _goal: &Self::Goal) -> Option<String> {
        None
    }
    /// For FBs whose Done-type output is reached while the command runs on (InVelocity,
    /// InEndVelocity, InTorque): the query of the running command's outputs, asked at the
    /// feedback rate. Default: none, the goal succeeds only at the final Done.
    fn reached_query(&self, _id: CmdId) -> Option<E::Command> {
        None
    }
    /// True when the reply to [`Self::reached_query`] shows the Done-type output: the goal
    /// then succeeds (result built with `CommandState::Done`) and the command runs on.
    fn reached(&self, _reply: &E::Reply) -> bool {
        false
    }
}

/// The running goal of an FB instance (re-trigger, §12.1): `marked` once a new goal of the
/// instance is being submitted, `end` signalled when it has been accepted.
#[derive(Default)]
struct Retrigger {
    marked: std::sync::atomic::AtomicBool,
    end: tokio::sync::Notify,
}

/// Running goals by FB instance name.
type Instances = Mutex<std::collections::HashMap<String, Arc<Retrigger>>>;

/// The running goals of one action server.
struct GoalBook {
    /// The feedback topic as the recording and the live feed see it.
    feedback: crate::record::RecordedTopic,
    /// Goal → the engine command it runs.
    goals: Mutex<BTreeMap<ros2_client::action::GoalId, CmdId>>,
    /// Goals whose cancel was accepted: they end as Canceled when the command is aborted.
    canceled: Mutex<BTreeSet<ros2_client::action::GoalId>>,
    /// Goals by FB instance name (re-trigger).
    instances: Instances,
}

/// An action's feedback as its topic carries it (`<Name>_FeedbackMessage`), for the recording.
#[derive(serde::Serialize)]
struct FeedbackMessage<'a, F> {
    goal_id: ros2_client::action::GoalId,
    feedback: &'a F,
}

#[allow(clippy::too_many_arguments)]
async fn run_goal<E: Engine, B: ActionBinding<E>>(
    binding: &B,
    goal: &B::Goal,
    goal_id: ros2_client::action::GoalId,
    handle: &ControllerHandle<E>,
    book: &GoalBook,
    server: &AsyncActionServer<B::Goal, B::Result, B::Feedback>,
    executing: ros2_client::action::ExecutingGoalHandle<B::Goal>,
    feedback_period: Duration,
) -> (GoalEndStatus, B::Result) {
    let refused = |r: Rejection| {
        let end = CommandState::Error(r.error_id);
        (
            GoalEndStatus::Aborted,
            binding.result_of(goal, None, &handle.snapshot(), end, Some(&r)),
        )
    };
    let (cmd, label) = match binding.command(goal) {
        Ok(c) => c,
        Err(r) => return refused(r),
    };
    // Re-trigger: the running goal of the same instance is marked before the new command
    // is submitted (its Aborted event may come in the same cycle), and ended once the new
    // command is accepted; a refused re-trigger leaves it running.
    let instance = binding.instance(goal).filter(|n| !n.is_empty());
    let own = Arc::new(Retrigger::default());
    let previous = instance.as_ref().and_then(|n| {
        book.instances
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(n)
            .cloned()
    });
    if let Some(p) = &previous {
        p.marked.store(true, std::sync::atomic::Ordering::SeqCst);
    }
    let (reply, mut events) = match handle.call_watched(cmd, Some(label)).await {
        Ok(x) => x,
        Err(r) => {
            if let Some(p) = &previous {
                p.marked.store(false, std::sync::atomic::Ordering::SeqCst);
            }
            return refused(r);
        }
    };
    if let Some(n) = &instance {
        book.instances
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(n.clone(), own.clone());
    }
    if let Some(p) = &previous {
        p.end.notify_one();
    }
    let release = |instances: &Instances| {
        if let Some(n) = &instance {
            let mut m = instances.lock().unwrap_or_else(|e| e.into_inner());
            if m.get(n).is_some_and(|r| Arc::ptr_eq(r, &own)) {
                m.remove(n);
            }
        }
    };
    let Some(id) = E::reply_id(&reply) else {
        release(&book.instances);
        // An instantaneous command: done at its edge.
        return (
            GoalEndStatus::Succeeded,
            binding.result_of(goal, None, &handle.snapshot(), CommandState::Done, None),
        );
    };
    book.goals
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(goal_id, id);
    let mut state = CommandState::Busy;
    let mut tick = tokio::time::interval(feedback_period);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let end = loop {
        tokio::select! {
            _ = own.end.notified() => break CommandState::Aborted,
            ev = events.recv() => match ev {
                Some(ev) => {
                    state = ev.state;
                    if state.is_final() {
                        break state;
                    }
                }
                None => break CommandState::Error(ErrorId::NOT_RUNNING),
            },
            _ = tick.tick() => {
                // The cycle sends a cycle's events before it publishes that cycle's snapshot:
                // events drained after reading the snapshot make the state at least as new
                // as the snapshot (feedback never shows a snapshot's values with an older
                // Busy/Active).
                let snap = handle.snapshot();
                let mut ended = None;
                while let Ok(ev) = events.try_recv() {
                    state = ev.state;
                    if state.is_final() {
                        ended = Some(state);
                        break;
                    }
                }
                if let Some(end) = ended {
                    break end;
                }
                let fb = binding.feedback_of(goal, id, &snap, state);
                book.feedback.take(
                    &FeedbackMessage {
                        goal_id,
                        feedback: &fb,
                    },
                    snap.ros_time_ns,
                );
                let _ = server.publish_feedback(executing.clone(), fb).await;
                if let Some(query) = binding.reached_query(id) {
                    if matches!(handle.call(query).await, Ok(r) if binding.reached(&r)) {
                        // The result is built from the snapshot: let it catch up with the
                        // cycle that showed the output (bounded: a paused lockstep node).
                        let mut snaps = handle.snapshots();
                        snaps.borrow_and_update();
                        let _ = tokio::time::timeout(feedback_period, snaps.changed()).await;
                        break CommandState::Done;
                    }
                }
            }
        }
    };
    release(&book.instances);
    // Let the snapshot catch up with the final cycle before building the result.
    let retriggered =
        end == CommandState::Aborted && own.marked.load(std::sync::atomic::Ordering::SeqCst);
    let reason = Rejection::new(ErrorId::NONE, "retriggered");
    let result = binding.result_of(
        goal,
        Some(id),
        &handle.snapshot(),
        end,
        retriggered.then_some(&reason),
    );
    // A goal whose cancel was accepted ends CANCELED (taken over by the halt, or Done: a jog
    // released by the cancel), unless it failed: the error id then comes with ABORTED.
    let was_canceled = book
        .canceled
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .remove(&goal_id);
    let status = match end {
        CommandState::Error(_) => GoalEndStatus::Aborted,
        _ if was_canceled => GoalEndStatus::Canceled,
        CommandState::Done => GoalEndStatus::Succeeded,
        _ => GoalEndStatus::Aborted,
    };
    (status, result)
}

/// `~/cycle_stats`: the controller's statistics with their histograms.
pub fn cycle_stats_message(s: &CycleStats, stamp: Time) -> CycleStatsMsg {
    CycleStatsMsg {
        header: header(stamp),
        node: s.node.clone(),
        period: s.period,
        cycles: s.cycles,
        overruns: s.overruns,
        exec_mean: s.exec_mean,
        exec_p99: s.exec_p99,
        exec_max: s.exec_max,
        jitter_mean: s.jitter_mean,
        jitter_p99: s.jitter_p99,
        jitter_max: s.jitter_max,
        lockstep: s.lockstep,
        jitter_p50: s.jitter_p50,
        exec_histogram: s.exec_histogram.clone(),
        jitter_histogram: s.jitter_histogram.clone(),
    }
}

/// `/diagnostics` message of a node's cycle statistics.
pub fn diagnostics_message(node: &str, s: &CycleStats, stamp: Time) -> DiagnosticArray {
    let us = |v: f64| format!("{:.1}", v * 1e6);
    let level = if s.overruns > 0 {
        DiagnosticStatus::WARN
    } else {
        DiagnosticStatus::OK
    };
    let message = if s.overruns > 0 {
        format!("{} overruns in {} cycles", s.overruns, s.cycles)
    } else {
        "cycle on time".to_string()
    };
    let kv = |k: &str, v: String| KeyValue {
        key: k.to_string(),
        value: v,
    };
    DiagnosticArray {
        header: header(stamp),
        status: vec![DiagnosticStatus {
            level,
            name: format!("{node}: cycle"),
            message,
            hardware_id: node.to_string(),
            values: vec![
                kv("period_us", us(s.period)),
                kv("lockstep", s.lockstep.to_string()),
                kv("cycles", s.cycles.to_string()),
                kv("overruns", s.overruns.to_string()),
                kv("exec_mean_us", us(s.exec_mean)),
                kv("exec_p99_us", us(s.exec_p99)),
                kv("exec_max_us", us(s.exec_max)),
                kv("jitter_mean_us", us(s.jitter_mean)),
                kv("jitter_p50_us", us(s.jitter_p50)),
                kv("jitter_p99_us", us(s.jitter_p99)),
                kv("jitter_max_us", us(s.jitter_max)),
            ],
        }],
    }
}
