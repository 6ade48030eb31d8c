//! Helpers of the system tests: the private-network guard, DDS domains, and a ROS client
//! node (ros2-client on its own loopback-only Context) to drive our nodes over real DDS.

pub mod docs;
pub mod flood;
pub mod foxglove;
pub mod fuzz;
pub mod moving_demo;

use motion_core::Engine;
use motion_runtime::host::CommonConfig;
use motion_runtime::shell::{create_context, service_qos, topic_qos};
use motion_runtime::NodeHost;
use ros2_client::action::{ActionClient, ActionClientQosPolicies};
use ros2_client::{
    Client, Context, Message, MessageTypeName, Name, Node, NodeName, NodeOptions, ServiceMapping,
    ServiceTypeName, Subscription,
};
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

/// The workspace root.
pub fn workspace() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace")
        .to_path_buf()
}

/// `target/<profile>/motion_launch`, next to the running test's `deps/` directory.
pub fn launcher_bin() -> std::path::PathBuf {
    let exe = std::env::current_exe().expect("test exe");
    let bin = exe
        .parent()
        .and_then(|d| d.parent())
        .expect("target dir")
        .join("motion_launch");
    assert!(
        bin.exists(),
        "{} missing: build the workspace first (scripts/test.sh does)",
        bin.display()
    );
    bin
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
            .new_node(
                NodeName::new("/", name).expect("name"),
                NodeOptions::new().enable_rosout(false),
            )
            .expect("client node");
        let spinner = node.spinner().expect("spinner");
        let spinner = Some(tokio::spawn(async move {
            let _ = spinner.spin().await;
        }));
        ClientNode {
            node,
            mapping,
            spinner,
            _context: context,
        }
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

/// Steps a lockstep node `cycles` cycles every millisecond until dropped (simulated time faster
/// than real time; a free-running cycle would starve DDS on 2 cores).
pub fn drive<E: Engine>(node: &NodeHost<E>, cycles: u64) -> AbortOnDrop
where
    E::Command: Send,
    E::Reply: Send,
{
    let handle = node.handle();
    AbortOnDrop(tokio::spawn(async move {
        while handle.step(cycles).await.is_ok() {
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
    }))
}

/// Waits for a match, re-checking every 0.5 s: ros2-client's `wait_for_service` watches a
/// bounded event channel and can miss the match event when a node with many endpoints floods
/// it; a fresh call sees the match state directly.
pub async fn discovered<F, Fut>(what: &str, f: F)
where
    F: Fn() -> Fut,
    Fut: std::future::Future<Output = ()>,
{
    within(20.0, &format!("{what} discovered"), async {
        while tokio::time::timeout(Duration::from_millis(500), f())
            .await
            .is_err()
        {}
    })
    .await
}

impl ClientNode {
    /// MC_Power with Enable TRUE on `axis` of `/axis_node` (asserts it was accepted).
    pub async fn power_on(&mut self, axis: &str) {
        use motion_msgs::srv::{Power, PowerRequest, PowerResponse};
        let power = self
            .client::<PowerRequest, PowerResponse>("/axis_node/power", Power::service_type_name())
            .await;
        let r = within(
            10.0,
            "power",
            power.async_call_service(PowerRequest {
                axis: axis.into(),
                enable: true,
                ..Default::default()
            }),
        )
        .await
        .expect("power reply");
        assert!(r.accepted, "power {axis}: {}", r.message);
    }

    /// A service client on `name`, once the server is matched.
    pub async fn client<Req, Resp>(&mut self, name: &str, ty: ServiceTypeName) -> Client<Req, Resp>
    where
        Req: Message + Clone + 'static,
        Resp: Message + 'static,
    {
        let cl = self
            .node
            .create_client::<Req, Resp>(
                self.mapping,
                &ClientNode::name(name),
                &ty,
                service_qos(),
                service_qos(),
            )
            .expect("client");
        discovered(&format!("service {name}"), || {
            cl.wait_for_service(&self.node)
        })
        .await;
        cl
    }

    /// A subscription on `name` with the state-topic QoS.
    pub fn subscribe<M: Message + 'static>(
        &mut self,
        name: &str,
        ty: MessageTypeName,
    ) -> Subscription<M> {
        let topic = self
            .node
            .create_topic(&ClientNode::name(name), ty, &topic_qos())
            .expect("topic");
        self.node
            .create_subscription::<M>(&topic, None)
            .expect("subscription")
    }

    /// An action client on `name`, once its goal, cancel and result services are matched.
    pub async fn action<G, R, F>(
        &mut self,
        name: &str,
        ty: &ros2_client::ActionTypeName,
    ) -> ActionClient<G, R, F>
    where
        G: Message + Clone + 'static,
        R: Message + Clone + 'static,
        F: Message + 'static,
    {
        let ac = self
            .node
            .create_action_client::<G, R, F>(
                self.mapping,
                &ClientNode::name(name),
                ty,
                action_client_qos(),
            )
            .expect("action client");
        discovered(&format!("{name} goal service"), || {
            ac.goal_client().wait_for_service(&self.node)
        })
        .await;
        discovered(&format!("{name} cancel service"), || {
            ac.cancel_client().wait_for_service(&self.node)
        })
        .await;
        discovered(&format!("{name} result service"), || {
            ac.result_client().wait_for_service(&self.node)
        })
        .await;
        ac
    }
}

/// QoS of action clients, matching rclpy's defaults (status transient-local).
pub fn action_client_qos() -> ActionClientQosPolicies {
    use ros2_client::qos::{Durability, History};
    let status = ros2_client::QosProfile::subscription_default()
        .history(History::KeepLast { depth: 1 })
        .durability(Durability::TransientLocal);
    ActionClientQosPolicies {
        goal_service: service_qos(),
        result_service: service_qos(),
        cancel_service: service_qos(),
        feedback_subscription: topic_qos(),
        status_subscription: status,
    }
}

/// Sends an action goal, retrying up to 3 times 10 s apart: a reply can be lost while DDS is
/// still matching the reply reader of a node with many endpoints (notes/dds.md); a retried goal
/// is a fresh Execute edge with the same inputs.
pub async fn send_goal<G, R, F>(
    ac: &ActionClient<G, R, F>,
    what: &str,
    goal: G,
) -> (
    ros2_client::action::GoalId,
    ros2_client::action::SendGoalResponse,
)
where
    G: Message + Clone + 'static,
    R: Message + Clone + 'static,
    F: Message + 'static,
{
    for _ in 0..3 {
        if let Ok(Ok(r)) =
            tokio::time::timeout(Duration::from_secs(10), ac.async_send_goal(goal.clone())).await
        {
            return r;
        }
    }
    panic!("{what}: no answer to 3 goal requests");
}

/// True when `tests/web`'s npm `packages` (and with `chromium` Debian's `/usr/bin/chromium`)
/// are installed (scripts/browser-setup.sh). Otherwise the caller skips with a message, unless
/// `MOTION_REQUIRE_BROWSER=1` (the test command), which makes it a failure.
pub fn web_tools_ready(packages: &[&str], chromium: bool) -> bool {
    let modules = workspace().join("tests/web/node_modules");
    let ok = packages.iter().all(|p| modules.join(p).exists())
        && (!chromium || std::path::Path::new("/usr/bin/chromium").exists());
    if !ok {
        assert!(
            std::env::var("MOTION_REQUIRE_BROWSER").as_deref() != Ok("1"),
            "{packages:?} (chromium: {chromium}) missing: run scripts/browser-setup.sh"
        );
        eprintln!("skipped: {packages:?} (chromium: {chromium}) missing: scripts/browser-setup.sh");
    }
    ok
}
