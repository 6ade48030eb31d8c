//! The live feed (issue 14): every topic of every node of the process over the Foxglove
//! WebSocket protocol (the `foxglove` SDK's server), channels named as the ROS topics, schemas
//! as ROS 2 message definitions (`ros2msg`, as in the recordings), data as CDR with its
//! encapsulation header, as the message travels over DDS. The Foxglove and Lichtblick apps
//! connect to `ws://HOST:PORT`; the built-in page ([`crate::page`]) reads the same feed.
//!
//! Loopback only unless the launch config names another address. Publishing never waits: a
//! message is serialized only when a client subscribed to its channel, and the server keeps a
//! bounded queue per client (the oldest messages are dropped when a client is too slow). The
//! cycle never touches the feed: the state publishers run on the node's async tasks. A
//! transient-local topic (`/tf_static`) is latched: each client that subscribes gets its
//! publishers' last messages (see [`latch`]).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// `live:` in the launch config (`--live PORT` / `--no-live` on the command line).
#[derive(Clone, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LiveSettings {
    /// Serve the feed (and the page) at all.
    pub enabled: bool,
    /// Address the servers listen on (default loopback).
    pub host: String,
    /// Port of the Foxglove WebSocket feed (default 8765, Foxglove's own default; 0 = any free).
    pub port: u16,
    /// Port of the built-in page (default 8080; 0 = any free).
    pub page_port: u16,
}

impl Default for LiveSettings {
    fn default() -> Self {
        LiveSettings {
            enabled: true,
            host: "127.0.0.1".into(),
            port: 8765,
            page_port: 8080,
        }
    }
}

/// Why the feed could not start.
#[derive(Debug, thiserror::Error)]
pub enum LiveError {
    /// The WebSocket server could not start (port taken, bad address).
    #[error("live feed: {0}")]
    Server(String),
    /// The page server could not listen.
    #[error("live page: {0}")]
    Page(#[from] std::io::Error),
    /// A second feed in one process.
    #[error("live feed: this process serves one already")]
    Twice,
}

/// The running feed: where it listens.
#[derive(Debug)]
pub struct LiveFeed {
    /// The Foxglove WebSocket server (kept: dropping the handle leaves it running).
    server: foxglove::WebSocketServerHandle,
    /// Address of the WebSocket feed.
    pub feed: std::net::SocketAddr,
    /// Address of the page.
    pub page: std::net::SocketAddr,
}

impl LiveFeed {
    /// Clients connected to the feed now.
    pub fn clients(&self) -> usize {
        self.server.client_count()
    }
}

/// The process's feed: its channels by topic, made at the first message of each topic.
struct Feed {
    channels: Mutex<HashMap<String, Arc<foxglove::RawChannel>>>,
    /// The last message of each transient-local publisher (`/tf_static` of every node), by
    /// topic: a client that subscribes later gets them at once, as a late DDS reader gets a
    /// transient-local writer's samples (the apps' 3D panels need the static frames).
    latched: Mutex<HashMap<String, Vec<Slot>>>,
}

/// A latched message: CDR bytes and log time [ns].
type Kept = (Vec<u8>, u64);

/// One publisher's last latched message (none before its first).
type Slot = Arc<Mutex<Option<Kept>>>;

/// One transient-local publisher's place on the feed ([`latch`]).
pub(crate) struct Latch {
    last: Slot,
}

impl Latch {
    /// Keeps `data` (logged at `log_time`) for clients that subscribe later.
    pub(crate) fn keep(&self, data: &[u8], log_time: u64) {
        let mut last = self.last.lock().unwrap_or_else(|p| p.into_inner());
        *last = Some((data.to_vec(), log_time));
    }
}

/// A place for a transient-local publisher of `topic` whose last message is replayed to each
/// client that subscribes to the topic; None when this process serves no feed.
pub(crate) fn latch(topic: &str) -> Option<Latch> {
    let feed = FEED.get()?;
    let last = Arc::new(Mutex::new(None));
    let mut latched = feed.latched.lock().unwrap_or_else(|p| p.into_inner());
    latched
        .entry(topic.to_string())
        .or_default()
        .push(last.clone());
    Some(Latch { last })
}

/// Replays the latched messages of a channel to the client that just subscribed to it (the
/// server calls this after the subscription is in place, so the client's sink takes them).
struct Replay;

impl foxglove::websocket::ServerListener for Replay {
    fn on_subscribe(
        &self,
        client: foxglove::websocket::Client,
        channel: foxglove::websocket::ChannelView,
    ) {
        let Some(feed) = FEED.get() else {
            return;
        };
        let kept: Vec<Kept> = {
            let latched = feed.latched.lock().unwrap_or_else(|p| p.into_inner());
            let Some(slots) = latched.get(channel.topic()) else {
                return;
            };
            slots
                .iter()
                .filter_map(|s| s.lock().unwrap_or_else(|p| p.into_inner()).clone())
                .collect()
        };
        let Some(ch) = feed
            .channels
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .get(channel.topic())
            .cloned()
        else {
            return;
        };
        for (data, log_time) in kept {
            ch.log_with_meta_to_sink(
                &data,
                foxglove::PartialMetadata::with_log_time(log_time),
                client.sink_id(),
            );
        }
    }
}

static FEED: OnceLock<Feed> = OnceLock::new();

/// Starts the feed and the page (once per process, inside the async runtime).
pub async fn start(settings: &LiveSettings) -> Result<LiveFeed, LiveError> {
    if FEED.get().is_some() {
        return Err(LiveError::Twice);
    }
    let server = foxglove::WebSocketServer::new()
        .name("motion_launch")
        .bind(settings.host.clone(), settings.port)
        .message_backlog_size(4096)
        .listener(Arc::new(Replay))
        .start()
        .await
        .map_err(|e| LiveError::Server(e.to_string()))?;
    let feed: std::net::SocketAddr = format!("{}:{}", settings.host, server.port())
        .parse()
        .map_err(|e| LiveError::Server(format!("address {}: {e}", settings.host)))?;
    let page = crate::page::serve(&settings.host, settings.page_port, feed.port()).await?;
    FEED.set(Feed {
        channels: Mutex::new(HashMap::new()),
        latched: Mutex::new(HashMap::new()),
    })
    .map_err(|_| LiveError::Twice)?;
    Ok(LiveFeed { server, feed, page })
}

/// The feed's channel of `topic` (made with its schema at the first call), or None when this
/// process serves no feed or the type has no definition.
pub(crate) fn channel(topic: &str, ros_type: &str) -> Option<Arc<foxglove::RawChannel>> {
    let feed = FEED.get()?;
    let mut channels = feed.channels.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(c) = channels.get(topic) {
        return Some(c.clone());
    }
    let definition = motion_msgs::message_definition(ros_type)?;
    let channel = foxglove::ChannelBuilder::new(topic)
        .message_encoding("cdr")
        .schema(foxglove::Schema::new(
            ros_type,
            "ros2msg",
            definition.as_bytes(),
        ))
        .build_raw()
        .map_err(|e| tracing::warn!("live feed: no channel for {topic}: {e}"))
        .ok()?;
    channels.insert(topic.to_string(), channel.clone());
    Some(channel)
}
