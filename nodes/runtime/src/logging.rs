//! Logging: `tracing` to stderr, and events of our node crates also to `/rosout`
//! (rcl_interfaces/Log) through the node's logging handle, as rclcpp nodes do.

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

type Routes = Mutex<Vec<(String, NodeLoggingHandle)>>;

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

/// Sends events whose target starts with `target_prefix` (a crate name such as `axis_node`)
/// to that node's `/rosout`.
pub fn route_to_rosout(target_prefix: &str, handle: NodeLoggingHandle) {
    routes()
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((target_prefix.to_string(), handle));
}

struct RosoutLayer;

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

impl<S: Subscriber> Layer<S> for RosoutLayer {
    fn on_event(&self, event: &Event<'_>, _ctx: Context<'_, S>) {
        let meta = event.metadata();
        // ros2_client logs every rosout message to tracing too: never route it back.
        if meta.target().starts_with("ros2_client") || meta.target().starts_with("rustdds") {
            return;
        }
        let Ok(routes) = routes().try_lock() else {
            return;
        };
        let Some((_, handle)) = routes
            .iter()
            .find(|(p, _)| meta.target().starts_with(p.as_str()))
        else {
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
        let stamp = ros2_client::builtin_interfaces::Time::now();
        handle.rosout_raw(
            stamp,
            level,
            handle.base_name(),
            &v.0,
            meta.file().unwrap_or(""),
            meta.module_path().unwrap_or(""),
            meta.line().unwrap_or(0),
        );
    }
}
