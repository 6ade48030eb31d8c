//! The live view as a user meets it (issue 14 items 1, 2): `motion_launch` serves the Foxglove
//! WebSocket feed and the built-in page; Debian's chromium (headless, driven by playwright-core
//! from npm) loads the page inside the private network namespace. The page must connect, list
//! the demo's movers, axes and nodes, draw the scope, and two screenshots a second apart must
//! differ where the movers are and nowhere else. The screenshots stay in `target/live-view/`.
//! The same feed through the Foxglove app's own client and decoders (npm, `foxglove_decode.mjs`)
//! must parse every schema and decode every message.
//!
//! Needs `/usr/bin/chromium` and `tests/web/node_modules` (scripts/browser-setup.sh, which the
//! test command runs); without them the test is skipped unless MOTION_REQUIRE_BROWSER=1.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use system_tests::{launcher_bin, moving_demo, require_netns, unique_domain, workspace};

#[test]
fn the_page_shows_the_moving_demo_in_a_real_browser() {
    require_netns();
    if !system_tests::web_tools_ready(&["playwright-core"], true) {
        return;
    }
    let dir = std::env::temp_dir().join(format!("live_view_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("moving_demo.yaml");
    // Ports 0: any free ones (the launcher prints them).
    let live = serde_yaml::from_str("{port: 0, page_port: 0}").unwrap();
    std::fs::write(&config, moving_demo::config(120.0, Some(live), false)).unwrap();
    let mut launcher = Command::new(launcher_bin())
        .arg(&config)
        .args(["--duration", "120"])
        .env("ROS_DOMAIN_ID", unique_domain().to_string())
        .env("RUST_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("motion_launch");
    // "motion_launch: live feed ws://A (…); page http://B/"
    let out = launcher.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for l in BufReader::new(out).lines().map_while(Result::ok) {
            let _ = tx.send(l);
        }
    });
    let end = Instant::now() + Duration::from_secs(30);
    let (feed, page) = loop {
        let l = rx
            .recv_timeout(end.saturating_duration_since(Instant::now()))
            .expect("the launcher prints the page's address within 30 s");
        if let (Some(f), Some(i)) = (l.find("ws://"), l.find("page http://")) {
            let feed = l[f..].split([' ', ';']).next().unwrap_or("").to_string();
            break (feed, l[i + 5..].trim().to_string());
        }
    };
    assert!(
        page.starts_with("http://127.0.0.1:"),
        "loopback only: {page}"
    );
    // The feed as the Foxglove app takes it (its own client and decoders, 3 s): every channel's
    // schema parses, every message decodes, the three machines' topics arrive.
    let fox = system_tests::foxglove::decode(&["live", &feed, "3"]);
    for topic in [
        "/axis_node/axis_states",
        "/joint_states",
        "/planar_node/state",
        "/planar_node/markers",
        "/pickplace_node/state",
        "/pickplace_node/markers",
    ] {
        assert!(
            fox.topics.get(topic).is_some_and(|t| t.count > 0),
            "{topic} through Foxglove's client: {fox:?}"
        );
    }
    // `/tf_static` is latched: each node's static frame (published once, at its start, often
    // before this client subscribed) reaches the late subscriber, as a late DDS reader of a
    // transient-local writer gets it (without the latch: 2 of 3 here). A node that starts
    // just as the client subscribes may reach it twice (live and replayed).
    let tf = &fox["/tf_static"];
    assert!(
        (3..=4).contains(&tf.count),
        "one static transform per node: {tf:?}"
    );
    let child = tf.last["transforms"][0]["child_frame_id"].as_str();
    assert!(
        child.is_some_and(|c| ["axes_base", "planar_env", "pickplace_mcs"].contains(&c)),
        "{tf:?}"
    );
    let shots = workspace().join("target/live-view");
    let run = Command::new("node")
        .arg(workspace().join("tests/web/live_view.mjs"))
        .arg(&page)
        .arg(&shots)
        .output()
        .expect("node");
    let _ = Command::new("kill")
        .args(["-INT", &launcher.id().to_string()])
        .status();
    let _ = launcher.wait();
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "node failed: {stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let r: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap_or(""))
        .unwrap_or_else(|e| panic!("{e}: {stdout}"));
    assert!(r.get("failure").is_none(), "browser run failed: {r}");
    let list = |k: &str| -> Vec<String> {
        r[k].as_array()
            .unwrap_or_else(|| panic!("{k}: {r}"))
            .iter()
            .map(|v| v.as_str().unwrap_or_default().to_string())
            .collect()
    };
    assert_eq!(list("movers"), ["m1", "m2", "m3", "m4"], "{r}");
    assert_eq!(list("axes"), ["x", "y", "table"], "{r}");
    let mut nodes = list("nodes");
    nodes.sort();
    assert_eq!(nodes, ["axis_node", "pickplace_node", "planar_node"], "{r}");
    assert!(
        r["scope_pixels"].as_u64().unwrap() > 500,
        "the scope draws: {r}"
    );
    // m2 drives at 12 mm/s, one way during the test: in a second it moves visibly (about 6 px);
    // the picture changes around it only.
    assert!(r["moved_px"]["m2"].as_f64().unwrap() > 3.0, "m2 moves: {r}");
    assert!(r["changed_pixels"].as_u64().unwrap() > 50, "{r}");
    assert_eq!(
        r["stray_pixels"].as_u64(),
        Some(0),
        "changes away from the movers: {r}"
    );
    assert_eq!(
        r["errors"].as_array().map(Vec::len),
        Some(0),
        "page errors: {r}"
    );
    for f in ["live_view_1.png", "live_view_2.png"] {
        let bytes = std::fs::read(shots.join(f)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{f}");
    }
    assert_ne!(
        std::fs::read(shots.join("live_view_1.png")).unwrap(),
        std::fs::read(shots.join("live_view_2.png")).unwrap(),
        "two screenshots a second apart differ"
    );
}
