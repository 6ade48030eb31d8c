//! The live feed's WebSocket handshake (regression test of the foxglove patch, vendor/README.md):
//! the Foxglove SDK's server speaks the protocol as `foxglove.sdk.v1` (and `v1.1`) only;
//! Lichtblick and `@foxglove/ws-protocol`'s client offer the same protocol under its former
//! name `foxglove.websocket.v1` and were refused with HTTP 400. Each name offered alone gets
//! the protocol under that name, and the server's first message (`serverInfo`); a client
//! offering none of them is refused.

use futures::StreamExt;
use motion_runtime::live::{start, LiveSettings};
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::Message;

#[test]
fn the_feed_speaks_to_current_and_legacy_foxglove_clients() {
    system_tests::require_netns();
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let settings = LiveSettings {
            port: 0,
            page_port: 0,
            ..Default::default()
        };
        let feed = start(&settings).await.expect("feed");
        let url = format!("ws://{}", feed.feed);
        let offer = |protocols: &str| {
            let mut req = url.as_str().into_client_request().expect("request");
            req.headers_mut()
                .insert("Sec-WebSocket-Protocol", protocols.parse().expect("header"));
            req
        };
        for (offered, answered) in [
            ("foxglove.websocket.v1", "foxglove.websocket.v1"),
            ("foxglove.sdk.v1", "foxglove.sdk.v1"),
            ("foxglove.websocket.v1, foxglove.sdk.v1", "foxglove.sdk.v1"),
            (
                "foxglove.sdk.v1.1, foxglove.websocket.v1",
                "foxglove.sdk.v1.1",
            ),
        ] {
            let (mut ws, resp) = tokio_tungstenite::connect_async(offer(offered))
                .await
                .unwrap_or_else(|e| panic!("{offered}: {e}"));
            assert_eq!(
                resp.headers()["sec-websocket-protocol"],
                answered,
                "offered {offered}"
            );
            let first = tokio::time::timeout(std::time::Duration::from_secs(5), ws.next())
                .await
                .expect("a first message");
            let Some(Ok(Message::Text(t))) = first else {
                panic!("{offered}: {first:?}");
            };
            let v: serde_json::Value = serde_json::from_str(t.as_str()).unwrap();
            assert_eq!(v["op"], "serverInfo", "{offered}: {v}");
        }
        let refused = tokio_tungstenite::connect_async(offer("foxglove.sdk.v2")).await;
        assert!(refused.is_err(), "an unknown protocol is refused");
    });
}
