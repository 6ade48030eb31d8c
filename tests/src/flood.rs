//! Request floods (issue 12 §3): clients that keep many requests in flight, as a burst of a
//! real client does, and count what came back. Used by the robustness tests (counts) and by
//! `bench flood` (counts and latencies).

use ros2_client::{Client, Message};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

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
