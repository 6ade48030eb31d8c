//! Helpers of the system tests: the private-network guard, DDS domains, and a ROS client
//! node (ros2-client on its own loopback-only Context) to drive our nodes over real DDS.

use motion_runtime::host::CommonConfig;
use motion_runtime::shell::create_context;
use ros2_client::{Context, Name, Node, NodeName, NodeOptions, ServiceMapping};
use std::sync::atomic::{AtomicU16, Ordering};
use std::time::Duration;

/// Panics unless the test runs inside the private network namespace of `scripts/netns-run`
/// (the network rule: no DDS packet may leave loopback).
pub fn require_netns() {
    assert_eq!(
        std::env::var("MOTION_IN_NETNS").as_deref(),
        Ok("1"),
        "this test opens DDS sockets: run it through scripts/test.sh (or scripts/netns-run cargo test)"
    );
}

/// A DDS domain id no other test of this process uses (each test binary is its own process
/// inside its own network namespace).
pub fn unique_domain() -> u16 {
    static NEXT: AtomicU16 = AtomicU16::new(1);
    let d = NEXT.fetch_add(1, Ordering::SeqCst);
    assert!(d < 200, "out of DDS domains");
    d
}

/// Common settings of a node under test.
pub fn common(name: &str, lockstep: bool, mapping: ServiceMapping) -> CommonConfig {
    CommonConfig {
        name: name.into(),
        lockstep,
        service_mapping: match mapping {
            ServiceMapping::Cyclone => "cyclone",
            ServiceMapping::Basic => "basic",
            _ => "enhanced",
        }
        .into(),
        ..CommonConfig::default()
    }
}

/// A client node in its own Context (like a separate ROS process), with a running spinner.
pub struct ClientNode {
    /// The node.
    pub node: Node,
    /// The mapping the client speaks.
    pub mapping: ServiceMapping,
    spinner: Option<tokio::task::JoinHandle<()>>,
    _context: Context,
}

impl ClientNode {
    /// Creates the client on `domain` (loopback only). Must run inside a tokio runtime.
    pub fn new(domain: u16, name: &str, mapping: ServiceMapping) -> Self {
        let context = create_context(domain).expect("client context");
        let mut node = context
            .new_node(NodeName::new("/", name).expect("name"), NodeOptions::new().enable_rosout(false))
            .expect("client node");
        let spinner = node.spinner().expect("spinner");
        let spinner = Some(tokio::spawn(async move {
            let _ = spinner.spin().await;
        }));
        ClientNode { node, mapping, spinner, _context: context }
    }

    /// An absolute name.
    pub fn name(full: &str) -> Name {
        Name::parse(full).expect("name")
    }
}

impl Drop for ClientNode {
    fn drop(&mut self) {
        if let Some(s) = self.spinner.take() {
            s.abort();
        }
    }
}

/// Awaits `f` for at most `secs` seconds, panicking with `what` on timeout.
pub async fn within<T>(secs: f64, what: &str, f: impl std::future::Future<Output = T>) -> T {
    match tokio::time::timeout(Duration::from_secs_f64(secs), f).await {
        Ok(v) => v,
        Err(_) => panic!("timed out after {secs} s: {what}"),
    }
}

/// Aborts a background task when dropped.
pub struct AbortOnDrop(pub tokio::task::JoinHandle<()>);

impl Drop for AbortOnDrop {
    fn drop(&mut self) {
        self.0.abort();
    }
}
