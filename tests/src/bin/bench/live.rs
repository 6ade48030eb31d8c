//! `live` (issue 14 item 1): does the live feed slow the cycle? The axis node with 10 moving
//! axes in real time at 1 kHz serves the Foxglove WebSocket feed; its cycle execution time p99
//! is measured over a window without a client, then over a window with a client subscribed to
//! every channel and reading all of it. Windows come from the controller's own 1 µs histogram
//! (`~/cycle_stats`), differenced between the window's ends. Must run inside scripts/netns-run.

use futures::{SinkExt, StreamExt};
use std::time::Duration;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::Message;

const AXES: usize = 10;

/// The cycles counted between two cumulative histograms (1 µs buckets), per bucket.
pub(crate) fn window(before: &[u32], after: &[u32]) -> Vec<u64> {
    after
        .iter()
        .enumerate()
        .map(|(i, &a)| u64::from(a) - u64::from(before.get(i).copied().unwrap_or(0)))
        .collect()
}

/// (cycles, `q` quantile [µs]) of a [`window`]: the upper edge of the bucket holding it.
pub(crate) fn quantile(d: &[u64], q: f64) -> (u64, f64) {
    let n: u64 = d.iter().sum();
    let rank = ((q * n as f64).ceil() as u64).max(1);
    let mut seen = 0;
    for (i, c) in d.iter().enumerate() {
        seen += c;
        if seen >= rank {
            return (n, (i + 1) as f64);
        }
    }
    (n, d.len() as f64)
}

/// p99 [µs] of the cycles counted between two cumulative histograms.
fn window_p99(before: &[u32], after: &[u32]) -> (u64, f64) {
    quantile(&window(before, after), 0.99)
}

/// A Foxglove client: subscribes to every advertised channel and reads until `stop`; returns
/// (channels, messages, bytes) received.
async fn client(port: u16, stop: tokio::sync::oneshot::Receiver<()>) -> (usize, u64, u64) {
    let mut req = format!("ws://127.0.0.1:{port}")
        .into_client_request()
        .expect("request");
    req.headers_mut().insert(
        "Sec-WebSocket-Protocol",
        "foxglove.sdk.v1".parse().expect("header"),
    );
    let (mut ws, _) = tokio_tungstenite::connect_async(req)
        .await
        .expect("feed connects");
    let (mut channels, mut messages, mut bytes) = (0usize, 0u64, 0u64);
    let mut next_id = 1u64;
    tokio::pin!(stop);
    loop {
        tokio::select! {
            _ = &mut stop => break,
            m = ws.next() => match m {
                Some(Ok(Message::Text(t))) => {
                    let v: serde_json::Value = serde_json::from_str(t.as_str()).unwrap_or_default();
                    if v["op"] == "advertise" {
                        let subs: Vec<serde_json::Value> = v["channels"]
                            .as_array()
                            .into_iter()
                            .flatten()
                            .map(|c| {
                                next_id += 1;
                                serde_json::json!({"id": next_id, "channelId": c["id"]})
                            })
                            .collect();
                        channels += subs.len();
                        let msg = serde_json::json!({"op": "subscribe", "subscriptions": subs});
                        ws.send(Message::Text(msg.to_string().into())).await.expect("subscribe");
                    }
                }
                Some(Ok(Message::Binary(b))) => {
                    messages += 1;
                    bytes += b.len() as u64;
                }
                Some(Ok(_)) => {}
                _ => break,
            },
        }
    }
    (channels, messages, bytes)
}

pub fn cycle_cost(window: f64) {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("rt");
    rt.block_on(async {
        let feed = motion_runtime::live::start(&motion_runtime::live::LiveSettings {
            port: 0,
            page_port: 0,
            ..Default::default()
        })
        .await
        .expect("live feed");
        let node = super::lockstep::axis_node_of(AXES, false, "bench live", 153);
        let h = node.handle();
        let [power, moving]: [Vec<_>; 2] =
            [0, 1].map(|k| (0..AXES).map(|i| super::lockstep::orders(i)[k].clone()).collect());
        for p in power {
            h.call(p).await.expect("power");
        }
        // Enabled a cycle after MC_Power.
        tokio::time::sleep(Duration::from_millis(50)).await;
        for m in moving {
            h.call(m).await.expect("move");
        }
        let wait = Duration::from_secs_f64(window);
        tokio::time::sleep(Duration::from_millis(300)).await;
        let a = h.stats().exec_histogram;
        tokio::time::sleep(wait).await;
        let b = h.stats().exec_histogram;
        let (stop_tx, stop_rx) = tokio::sync::oneshot::channel();
        let reader = tokio::spawn(client(feed.feed.port(), stop_rx));
        tokio::time::sleep(Duration::from_millis(300)).await;
        let clients = feed.clients();
        let c = h.stats().exec_histogram;
        tokio::time::sleep(wait).await;
        let d = h.stats().exec_histogram;
        let _ = stop_tx.send(());
        let (channels, messages, bytes) = reader.await.expect("client");
        let (n0, p0) = window_p99(&a, &b);
        let (n1, p1) = window_p99(&c, &d);
        println!(
            "live feed @1 kHz, axis node, {AXES} moving axes: cycle exec p99 {p0:.0} µs without a client ({n0} cycles) | {p1:.0} µs with {clients} client subscribed to {channels} channels, reading {messages} messages ({:.1} MB) ({n1} cycles) | ratio {:.2}",
            bytes as f64 / 1e6,
            p1 / p0
        );
        Box::new(node).stop().await;
    });
}
