//! Request floods (issue 12 §3): clients that keep many requests in flight, as a burst of a
//! real client does, and count what came back. Used by the robustness tests (counts) and by
//! `bench flood` (counts and latencies).

use crate::{common, drive, unique_domain, ClientNode};
use motion_msgs::action::{
    MoveAbsolute as MoveAbsoluteAction, MoveAbsoluteFeedback, MoveAbsoluteGoal, MoveAbsoluteResult,
};
use motion_msgs::srv::{
    self, MoveAbsoluteRequest, MoveAbsoluteResponse, ReadStatus, ReadStatusRequest,
    ReadStatusResponse,
};
use ros2_client::action::{GetResultRequest, GoalId, SendGoalRequest};
use ros2_client::action_msgs::GoalStatusEnum;
use ros2_client::{Client, Message, ServiceMapping};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// 0x7F04: the command queue is full (an answer, not a loss).
pub const QUEUE_FULL: u32 = 0x7F04;

/// An axis node (one axis `x`, lockstep, Cyclone mapping) for floods.
pub fn axis_node(domain: u16, result_timeout: f64) -> axis_node::AxisNode {
    axis_node_of(domain, ServiceMapping::Cyclone, result_timeout)
}

/// The same axis node speaking `mapping`.
pub fn axis_node_with(domain: u16, mapping: ServiceMapping) -> axis_node::AxisNode {
    axis_node_of(domain, mapping, 900.0)
}

fn axis_node_of(domain: u16, mapping: ServiceMapping, result_timeout: f64) -> axis_node::AxisNode {
    let cfg: serde_yaml::Value = serde_yaml::from_str(
        "axes:\n  x:\n    max_velocity: 1000.0\n    acceleration: 10000.0\n    deceleration: 10000.0\n    jerk: 100000.0\n",
    )
    .unwrap();
    let mut c = common("axis_node", true, mapping);
    c.result_timeout = result_timeout;
    axis_node::start(&c, cfg, "test", domain).expect("axis node")
}

/// The `/axis_node/move_absolute` action client of `c`, once matched.
pub async fn move_absolute_client(
    c: &mut ClientNode,
) -> ros2_client::action::ActionClient<MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback> {
    c.action::<MoveAbsoluteGoal, MoveAbsoluteResult, MoveAbsoluteFeedback>(
        "/axis_node/move_absolute",
        &MoveAbsoluteAction::action_type_name(),
    )
    .await
}

/// A MoveAbsolute goal on `x` (velocity 500).
pub fn move_goal(position: f64) -> MoveAbsoluteGoal {
    MoveAbsoluteGoal {
        axis: "x".into(),
        position,
        velocity: 500.0,
        ..Default::default()
    }
}

/// What a flood got back.
#[derive(Clone, Debug, Default)]
pub struct FloodCount {
    /// Requests written.
    pub sent: usize,
    /// Requests answered.
    pub answered: usize,
    /// Round-trip times of the answered requests.
    pub latencies: Vec<Duration>,
}

impl FloodCount {
    /// Requests never answered.
    pub fn lost(&self) -> usize {
        self.sent - self.answered
    }

    /// Adds another client's count.
    pub fn merge(&mut self, o: FloodCount) {
        self.sent += o.sent;
        self.answered += o.answered;
        self.latencies.extend(o.latencies);
    }

    /// The `q` quantile (0..=1) of the latencies [ms].
    pub fn quantile_ms(&self, q: f64) -> f64 {
        if self.latencies.is_empty() {
            return f64::NAN;
        }
        let mut v: Vec<f64> = self
            .latencies
            .iter()
            .map(|d| d.as_secs_f64() * 1e3)
            .collect();
        v.sort_by(f64::total_cmp);
        v[((v.len() - 1) as f64 * q).round() as usize]
    }

    /// `sent N answered N lost N p50 .. p99 .. max .. ms`.
    pub fn summary(&self) -> String {
        format!(
            "sent {} answered {} lost {}  latency p50 {:.2} p99 {:.2} max {:.2} ms",
            self.sent,
            self.answered,
            self.lost(),
            self.quantile_ms(0.5),
            self.quantile_ms(0.99),
            self.quantile_ms(1.0)
        )
    }
}

/// Sends `requests` through `client` with up to `window` in flight, collecting every answer
/// (passed to `check`) until all are answered or `quiet` passes without any answer.
/// Answers are polled every millisecond, so latencies are quantised to about 1 ms.
pub async fn pipelined<Req, Resp>(
    client: &Client<Req, Resp>,
    requests: impl IntoIterator<Item = Req>,
    window: usize,
    quiet: Duration,
    mut check: impl FnMut(&Resp),
) -> FloodCount
where
    Req: Message + Clone + 'static,
    Resp: Message + 'static,
{
    let mut count = FloodCount::default();
    let mut in_flight: BTreeMap<i64, Instant> = BTreeMap::new();
    let mut requests = requests.into_iter().peekable();
    let mut last_answer = Instant::now();
    loop {
        while in_flight.len() < window.max(1) {
            let Some(req) = requests.next() else { break };
            match client.async_send_request(req).await {
                Ok(id) => {
                    in_flight.insert(id.sequence_number, Instant::now());
                    count.sent += 1;
                }
                Err(e) => panic!("request not written: {e:?}"),
            }
        }
        let mut got = false;
        while let Ok(Some((id, resp))) = client.receive_response() {
            if let Some(t0) = in_flight.remove(&id.sequence_number) {
                count.answered += 1;
                count.latencies.push(t0.elapsed());
                check(&resp);
                got = true;
            }
        }
        if got {
            last_answer = Instant::now();
        }
        if in_flight.is_empty() && requests.peek().is_none() {
            break;
        }
        if last_answer.elapsed() > quiet {
            break;
        }
        tokio::time::sleep(Duration::from_millis(1)).await;
    }
    count
}

/// §3: 4 clients x `calls` pipelined calls to a read service and to a motion service; every
/// request answered (accepted, refused by the engine, or 0x7F04 queue full), none lost.
pub async fn service_flood(calls: usize, window: usize) -> (FloodCount, FloodCount) {
    let domain = unique_domain();
    let node = axis_node(domain, 900.0);
    let _driver = drive(&node, 5);
    let mut read = FloodCount::default();
    let mut motion = FloodCount::default();
    let mut tasks = Vec::new();
    for k in 0..4 {
        tasks.push(tokio::spawn(async move {
            let mut c = ClientNode::new(domain, &format!("flood_{k}"), ServiceMapping::Cyclone);
            let rs = c
                .client::<ReadStatusRequest, ReadStatusResponse>(
                    "/axis_node/read_status",
                    ReadStatus::service_type_name(),
                )
                .await;
            let mv = c
                .client::<MoveAbsoluteRequest, MoveAbsoluteResponse>(
                    "/axis_node/move_absolute",
                    srv::MoveAbsolute::service_type_name(),
                )
                .await;
            let r = pipelined(
                &rs,
                (0..calls).map(|_| ReadStatusRequest { axis: "x".into() }),
                window,
                Duration::from_secs(10),
                |r: &ReadStatusResponse| {
                    assert!(r.accepted || r.error_id == QUEUE_FULL, "read_status {r:?}")
                },
            )
            .await;
            let m = pipelined(
                &mv,
                (0..calls).map(|i| MoveAbsoluteRequest {
                    axis: "x".into(),
                    position: i as f64,
                    velocity: 10.0,
                    ..Default::default()
                }),
                window,
                Duration::from_secs(10),
                // The axis is not powered: the engine refuses with its id; a full queue
                // refuses with 0x7F04. Both are answers.
                |r: &MoveAbsoluteResponse| assert!(r.error_id != 0 || r.accepted),
            )
            .await;
            (r, m)
        }));
    }
    for t in tasks {
        let (r, m) = t.await.unwrap();
        read.merge(r);
        motion.merge(m);
    }
    (read, motion)
}

/// §3: `goals` action goals sent at once by one client (keep-all QoS): every goal answered,
/// every accepted goal ended with a result. Returns (goal answers, results).
pub async fn goal_burst(goals: usize) -> (FloodCount, FloodCount) {
    let domain = unique_domain();
    let node = axis_node(domain, 900.0);
    let _driver = drive(&node, 5);
    let mut c = ClientNode::new(domain, "burst", ServiceMapping::Cyclone);
    let ac = move_absolute_client(&mut c).await;
    let ids: Vec<GoalId> = (0..goals).map(|_| GoalId::new_random()).collect();
    let mut accepted = 0;
    let sent = pipelined(
        ac.goal_client(),
        ids.iter().map(|&goal_id| SendGoalRequest {
            goal_id,
            goal: move_goal(5.0),
        }),
        goals,
        Duration::from_secs(20),
        |r| accepted += usize::from(r.accepted),
    )
    .await;
    assert_eq!(
        accepted, sent.answered,
        "every goal is accepted (screening ends it)"
    );
    let mut ended = 0;
    let results = pipelined(
        ac.result_client(),
        ids.iter().map(|&goal_id| GetResultRequest { goal_id }),
        goals,
        Duration::from_secs(20),
        |r| {
            ended += usize::from(matches!(
                r.status,
                GoalStatusEnum::Aborted | GoalStatusEnum::Succeeded
            ))
        },
    )
    .await;
    assert_eq!(ended, results.answered, "a result that is no end status");
    (sent, results)
}
