//! What the Foxglove app makes of our recordings and live feed, decided by Foxglove's own
//! libraries (`tests/web/foxglove_decode.mjs`: @mcap/core with @mcap/support's decompressors,
//! @foxglove/ws-protocol, @foxglove/rosmsg, @foxglove/rosmsg2-serialization from npm, installed
//! by scripts/browser-setup.sh).

use std::collections::BTreeMap;
use std::process::Command;

/// One topic as Foxglove decoded it: schema name, messages, the last one as JSON.
#[derive(Debug)]
pub struct Topic {
    /// Schema (ROS type) name.
    pub schema: String,
    /// Messages decoded.
    pub count: u64,
    /// The last message.
    pub last: serde_json::Value,
}

/// True when the npm packages are installed; otherwise the caller skips, unless
/// `MOTION_REQUIRE_BROWSER=1` (the test command), which makes it a failure.
pub fn ready() -> bool {
    crate::web_tools_ready(&["@foxglove/rosmsg2-serialization"], false)
}

/// What the decoder took: the topics by name, and a recording's chunk compressions.
#[derive(Debug)]
pub struct Decoded {
    /// Topics by name.
    pub topics: BTreeMap<String, Topic>,
    /// A recording's chunk compressions, sorted (`zstd`, `(none)`); None for the live feed.
    pub chunks: Option<String>,
}

impl std::ops::Index<&str> for Decoded {
    type Output = Topic;

    fn index(&self, topic: &str) -> &Topic {
        self.topics
            .get(topic)
            .unwrap_or_else(|| panic!("no topic {topic} in {:?}", self.topics.keys()))
    }
}

/// Runs the decoder with `args` (`mcap FILE` or `live URL SECONDS`); panics when a schema
/// does not parse or a message does not decode.
pub fn decode(args: &[&str]) -> Decoded {
    let out = Command::new("node")
        .arg(crate::workspace().join("tests/web/foxglove_decode.mjs"))
        .args(args)
        .output()
        .expect("node");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "Foxglove's decoders refused {args:?}:\n{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let topics = text
        .lines()
        .filter_map(|l| {
            let mut f = l.splitn(4, '\t');
            let (topic, schema, count, last) = (f.next()?, f.next()?, f.next()?, f.next()?);
            Some((
                topic.to_string(),
                Topic {
                    schema: schema.to_string(),
                    count: count.parse().ok()?,
                    last: serde_json::from_str(last).ok()?,
                },
            ))
        })
        .collect();
    let chunks = text
        .lines()
        .find_map(|l| l.strip_prefix("chunks "))
        .map(str::to_string);
    Decoded { topics, chunks }
}
