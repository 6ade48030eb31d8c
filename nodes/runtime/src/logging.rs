//! Logging: `tracing` to stderr, and every event logged on behalf of a node also to `/rosout`
//! (rcl_interfaces/Log, with the node's name) through the node's logging handle, as rclcpp
//! nodes do. "On behalf of a node" = inside that node's span ([`node_span`]): its ROS tasks,
//! its cycle thread and its start-up run in it, so runtime lines (start-up, refused commands,
//! errors) reach `/rosout` as well as the node crates' own. The same messages go to the
//! recording and the live feed ([`crate::record::RecordedTopic`]), logged at the node's ROS
//! time (simulated in lockstep), as `ros2 bag record --use-sim-time` would receive them; their
//! `stamp` is the system time, as rcl stamps `/rosout`.

use motion_msgs::deps::rcl_interfaces::msg::Log;
use ros2_client::log::LogLevel;
use ros2_client::rosout::{NodeLoggingHandle, RosoutRaw};
use std::sync::{Mutex, OnceLock};
use tracing::field::{Field, Visit};
use tracing::{Event, Level, Subscriber};
use tracing_subscriber::layer::{Context, SubscriberExt};
use tracing_subscriber::util::SubscriberInitExt;
use tracing_subscriber::{EnvFilter, Layer};

/// Default filter: our crates at info; RustDDS's per-packet warnings ("No locators",
/// "Message size") off: they fire many times a second on loopback.
pub const DEFAULT_FILTER: &str =
    "info,rustdds=error,ros2_client=warn,ros2_client::distributions=error";

/// A node's ROS time now [ns] (see [`crate::clock`]).
pub type RosNow = std::sync::Arc<dyn Fn() -> i64 + Send + Sync>;

type Routes = Mutex<Vec<(String, NodeLoggingHandle, RosNow)>>;

/// `/rosout` as the recording and the live feed see it (one topic for every node).
fn rosout_topic() -> &'static crate::record::RecordedTopic {
    static TOPIC: OnceLock<crate::record::RecordedTopic> = OnceLock::new();
    TOPIC.get_or_init(|| crate::record::RecordedTopic::new("/rosout", Log::ROS_TYPE_NAME))
}

/// The span of a node's work; events inside it go to that node's `/rosout`.
pub fn node_span(node_name: &str) -> tracing::Span {
    tracing::info_span!("node", name = %node_name)
}

fn routes() -> &'static Routes {
    static ROUTES: OnceLock<Routes> = OnceLock::new();
    ROUTES.get_or_init(|| Mutex::new(Vec::new()))
}

/// Installs the subscriber once per process (`RUST_LOG` overrides the default filter).
pub fn init() {
    let filter =
        EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(DEFAULT_FILTER));
    let _ = tracing_subscriber::registry()
        .with(filter)
        .with(tracing_subscriber::fmt::layer().with_writer(std::io::stderr))
        .with(RosoutLayer)
        .try_init();
}

/// Sends events inside the span of node `node_name` ([`node_span`]) to that node's `/rosout`;
/// `now` is the node's ROS time (the recording's log time).
pub fn route_to_rosout(node_name: &str, handle: NodeLoggingHandle, now: RosNow) {
    let mut r = routes().lock().unwrap_or_else(|e| e.into_inner());
    r.retain(|(n, _, _)| n != node_name); // a restarted node replaces its old handle
    r.push((node_name.to_string(), handle, now));
}

/// Stops routing to `node_name`'s `/rosout` (the node is going away).
pub fn unroute(node_name: &str) {
    routes()
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|(n, _, _)| n != node_name);
}

struct RosoutLayer;

/// The node name recorded on a node span.
struct NodeName(String);

struct MessageVisitor(String);

impl Visit for MessageVisitor {
    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        use std::fmt::Write;
        if field.name() == "message" {
            let _ = write!(self.0, "{value:?}");
        } else {
            let _ = write!(self.0, " {}={value:?}", field.name());
        }
    }
}

impl<S> Layer<S> for RosoutLayer
where
    S: Subscriber + for<'a> tracing_subscriber::registry::LookupSpan<'a>,
{
    fn on_new_span(
        &self,
        attrs: &tracing::span::Attributes<'_>,
        id: &tracing::span::Id,
        ctx: Context<'_, S>,
    ) {
        if attrs.metadata().name() != "node" {
            return;
        }
        let mut v = MessageVisitor(String::new());
        attrs.record(&mut NameVisitor(&mut v.0));
        if let Some(span) = ctx.span(id) {
            span.extensions_mut().insert(NodeName(v.0));
        }
    }

    fn on_event(&self, event: &Event<'_>, ctx: Context<'_, S>) {
        let meta = event.metadata();
        // ros2_client logs every rosout message to tracing too: never route it back.
        if meta.target().starts_with("ros2_client") || meta.target().starts_with("rustdds") {
            return;
        }
        let Some(scope) = ctx.event_scope(event) else {
            return;
        };
        let Some(span) = scope
            .from_root()
            .find(|span| span.extensions().get::<NodeName>().is_some())
        else {
            return;
        };
        let ext = span.extensions();
        let Some(NodeName(node)) = ext.get::<NodeName>() else {
            return;
        };
        let Ok(routes) = routes().try_lock() else {
            return;
        };
        let Some((_, handle, now)) = routes.iter().find(|(n, _, _)| n == node) else {
            return;
        };
        let mut v = MessageVisitor(String::new());
        event.record(&mut v);
        let level = match *meta.level() {
            Level::ERROR => LogLevel::Error,
            Level::WARN => LogLevel::Warn,
            Level::INFO => LogLevel::Info,
            _ => LogLevel::Debug,
        };
        let wall = crate::clock::system_ns();
        let log = Log {
            stamp: crate::shell::stamp_ns(wall),
            level: level as u8,
            name: handle.base_name().to_string(),
            msg: v.0,
            file: meta.file().unwrap_or("").to_string(),
            function: meta.module_path().unwrap_or("").to_string(),
            line: meta.line().unwrap_or(0),
        };
        rosout_topic().take(&log, now());
        handle.rosout_raw(
            ros2_client::builtin_interfaces::Time::from_nanos(wall),
            level,
            &log.name,
            &log.msg,
            &log.file,
            &log.function,
            log.line,
        );
    }
}

/// Reads the `name` field of a node span.
struct NameVisitor<'a>(&'a mut String);

impl Visit for NameVisitor<'_> {
    fn record_str(&mut self, field: &Field, value: &str) {
        if field.name() == "name" {
            self.0.push_str(value);
        }
    }
    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        use std::fmt::Write;
        if field.name() == "name" {
            let _ = write!(self.0, "{value:?}");
        }
    }
}
