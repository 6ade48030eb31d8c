//! Launch configs: a YAML file listing the nodes to run in one process, each with its own
//! cycle. Used by the `motion_launch` binary (all node kinds) and by each node's own binary
//! (only its kind).
//!
//! ```yaml
//! nodes:
//!   - kind: axis_node          # axis_node | planar_node | pickplace_node
//!     cycle_period: 0.001      # common keys: see host::CommonConfig
//!     axes: { x: {...} }       # the rest belongs to the node's engine
//! ```

use crate::host::{split_entry, CommonConfig, ConfigError};
use crate::ros_args::RosArgs;
use crate::shell::{self, ShellError};
use std::any::Any;
use std::fmt;
use std::path::Path;
use std::time::Duration;

/// Why a node could not start.
#[derive(Debug)]
pub enum StartError {
    /// The launch config is wrong (names file and key).
    Config(ConfigError),
    /// The ROS side could not be set up.
    Shell(ShellError),
}

impl fmt::Display for StartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StartError::Config(e) => write!(f, "configuration error: {e}"),
            StartError::Shell(e) => write!(f, "start-up error: {e}"),
        }
    }
}

impl std::error::Error for StartError {}

impl From<ConfigError> for StartError {
    fn from(e: ConfigError) -> Self {
        StartError::Config(e)
    }
}

impl From<ShellError> for StartError {
    fn from(e: ShellError) -> Self {
        StartError::Shell(e)
    }
}

/// A running node of any kind.
pub trait Running: Send {
    /// Stops the node in order (tasks, node, cycle, participant).
    fn stop(self: Box<Self>) -> std::pin::Pin<Box<dyn std::future::Future<Output = ()> + Send>>;
    /// Lockstep: runs `n` cycles (the state topics publish every cycle's state, see
    /// `state_publish_every_n_cycles`) and returns the cycle count afterwards.
    fn step(
        &self,
        n: u64,
    ) -> std::pin::Pin<Box<dyn std::future::Future<Output = Result<u64, String>> + Send>> {
        let _ = n;
        Box::pin(async { Err("not a lockstep node".to_string()) })
    }
    /// Waits until the node's state publishers have published the state of cycle `cycle`
    /// (lockstep stream); at once for nodes without a stream.
    fn flush(&self, cycle: u64) -> std::pin::Pin<Box<dyn std::future::Future<Output = ()> + Send>> {
        let _ = cycle;
        Box::pin(async {})
    }
    /// Commands running and script steps left, as of the last cycle (0: idle).
    fn busy(&self) -> usize {
        0
    }
    /// The concrete node, for tests.
    fn as_any(&self) -> &dyn Any;
}

/// A running node of any kind, boxed.
pub type RunningNode = Box<dyn Running>;

/// Starts one node of a kind: common settings, the engine's part of the entry, the location
/// for error messages, the DDS domain. Must run inside a tokio runtime.
pub type StartFn =
    fn(&CommonConfig, serde_yaml::Value, &str, u16) -> Result<RunningNode, StartError>;

/// Checks the engine part of an entry without starting anything (`--check`).
pub type CheckFn = fn(&CommonConfig, serde_yaml::Value, &str) -> Result<(), ConfigError>;

/// A node kind the launcher knows.
#[derive(Clone, Copy)]
pub struct NodeKind {
    /// `axis_node`, `planar_node` or `pickplace_node`.
    pub kind: &'static str,
    /// Its start function.
    pub start: StartFn,
    /// Its config check.
    pub check: CheckFn,
}

/// Every node kind of the suite: entries of these kinds that a binary does not run are
/// skipped (an `axis_node` binary ignores the `planar_node` entries of a shared config).
pub const SUITE_KINDS: &[&str] = &["axis_node", "planar_node", "pickplace_node"];

/// One validated node entry.
pub struct NodeEntry {
    /// Kind.
    pub kind: &'static str,
    /// Where it is, for messages: `file: nodes[i]`.
    pub location: String,
    /// Common settings.
    pub common: CommonConfig,
    /// The engine's part.
    pub engine: serde_yaml::Value,
}

/// Reads and checks a launch config: structure, node kinds, common settings, unique names.
/// Engine parts are checked when each node starts.
pub fn load(path: &Path, kinds: &[NodeKind]) -> Result<Vec<NodeEntry>, ConfigError> {
    load_with(path, kinds, &RosArgs::default())
}

/// [`load`] with the command line's `--ros-args` parameters applied to each node entry before
/// it is checked.
pub fn load_with(
    path: &Path,
    kinds: &[NodeKind],
    ros: &RosArgs,
) -> Result<Vec<NodeEntry>, ConfigError> {
    load_launch(path, kinds, ros).map(|(entries, _)| entries)
}

/// The launch config's keys beside `nodes`: what the whole process does.
#[derive(Debug, Default)]
struct LaunchKeys {
    /// `record: FILE.mcap`: record every published message of every node.
    record: Option<String>,
    /// `record_topics: [/a, /b]`: record only these topics (absolute names).
    record_topics: Option<Vec<String>>,
    /// `record_exclude_topics: [/a, /b]`: record none of these topics (absolute names).
    record_exclude_topics: Option<Vec<String>>,
    /// `record_compression: none | zstd`: how the recording's chunks are compressed.
    record_compression: Option<crate::record::Compression>,
    /// `live: true | false | {host, port, page_port}`: the live feed and page.
    live: Option<crate::live::LiveSettings>,
}

/// [`load_with`], also returning the config's process keys (see [`parse_launch`]).
fn load_launch(
    path: &Path,
    kinds: &[NodeKind],
    ros: &RosArgs,
) -> Result<(Vec<NodeEntry>, LaunchKeys), ConfigError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| ConfigError {
        location: file.clone(),
        message: format!("cannot read: {e}"),
    })?;
    parse_launch(&text, &file, kinds, ros)
}

/// [`load`] on text (`file` names it in messages).
pub fn parse(text: &str, file: &str, kinds: &[NodeKind]) -> Result<Vec<NodeEntry>, ConfigError> {
    parse_with(text, file, kinds, &RosArgs::default())
}

/// [`load_with`] on text.
pub fn parse_with(
    text: &str,
    file: &str,
    kinds: &[NodeKind],
    ros: &RosArgs,
) -> Result<Vec<NodeEntry>, ConfigError> {
    parse_launch(text, file, kinds, ros).map(|(entries, _)| entries)
}

/// [`parse_with`], also returning the config's process keys: `record` (record every published
/// message of every node to this MCAP file; `--record FILE` takes precedence) and `live` (the
/// live feed and page; `--live PORT` / `--no-live` take precedence).
fn parse_launch(
    text: &str,
    file: &str,
    kinds: &[NodeKind],
    ros: &RosArgs,
) -> Result<(Vec<NodeEntry>, LaunchKeys), ConfigError> {
    let root: serde_yaml::Value = serde_yaml::from_str(text).map_err(|e| ConfigError {
        location: file.into(),
        message: e.to_string(),
    })?;
    let map = root.as_mapping().ok_or_else(|| ConfigError {
        location: file.into(),
        message: "expected a mapping with key 'nodes'".into(),
    })?;
    for (k, v) in map {
        match k.as_str() {
            Some("nodes") => {}
            Some("record") if v.as_str().is_some_and(|f| !f.is_empty()) => {}
            Some("record") => {
                return Err(ConfigError {
                    location: format!("{file}: record"),
                    message: "expected a file name (e.g. run.mcap)".into(),
                })
            }
            Some("live")
            | Some("record_topics")
            | Some("record_exclude_topics")
            | Some("record_compression") => {}
            _ => {
                return Err(ConfigError {
                    location: format!("{file}: {}", k.as_str().unwrap_or("?")),
                    message: "unknown key (expected 'nodes' and optionally 'record', \
                              'record_topics', 'record_exclude_topics', 'record_compression', \
                              'live')"
                        .into(),
                })
            }
        }
    }
    let nodes = map
        .get("nodes")
        .and_then(|n| n.as_sequence())
        .ok_or_else(|| ConfigError {
            location: format!("{file}: nodes"),
            message: "missing or not a list".into(),
        })?;
    let mut out: Vec<NodeEntry> = Vec::new();
    for (i, n) in nodes.iter().enumerate() {
        let location = format!("{file}: nodes[{i}]");
        let m = n.as_mapping().ok_or_else(|| ConfigError {
            location: location.clone(),
            message: "expected a mapping".into(),
        })?;
        let kind_name = m
            .get("kind")
            .and_then(|k| k.as_str())
            .ok_or_else(|| ConfigError {
                location: format!("{location}.kind"),
                message: "missing (one of axis_node, planar_node, pickplace_node)".into(),
            })?;
        let Some(kind) = kinds.iter().find(|k| k.kind == kind_name) else {
            if SUITE_KINDS.contains(&kind_name) {
                continue; // another binary's node
            }
            return Err(ConfigError {
                location: format!("{location}.kind"),
                message: format!(
                    "unknown node kind '{kind_name}' (one of: {})",
                    SUITE_KINDS.join(", ")
                ),
            });
        };
        let location = format!("{location} ({kind_name})");
        let mut m = m.clone();
        ros.apply_params(&mut m, kind.kind);
        let (common, engine) = split_entry(&m, kind.kind, &location)?;
        if out
            .iter()
            .any(|e| e.common.name == common.name && e.common.namespace == common.namespace)
        {
            return Err(ConfigError {
                location: format!("{location}.name"),
                message: format!("node name '{}' is used twice", common.name),
            });
        }
        out.push(NodeEntry {
            kind: kind.kind,
            location,
            common,
            engine,
        });
    }
    let record = map
        .get("record")
        .and_then(|v| v.as_str())
        .map(str::to_string);
    let live = match map.get("live") {
        None => None,
        Some(serde_yaml::Value::Bool(on)) => Some(crate::live::LiveSettings {
            enabled: *on,
            ..Default::default()
        }),
        Some(v) => Some(serde_yaml::from_value(v.clone()).map_err(|e| ConfigError {
            location: format!("{file}: live"),
            message: format!("{e} (expected true, false or {{host, port, page_port}})"),
        })?),
    };
    let topic_list = |key: &str| match map.get(key) {
        None => Ok(None),
        Some(v) => serde_yaml::from_value::<Vec<String>>(v.clone())
            .map_err(|e| e.to_string())
            .and_then(record_topics)
            .map(Some)
            .map_err(|message| ConfigError {
                location: format!("{file}: {key}"),
                message,
            }),
    };
    let record_topics = topic_list("record_topics")?;
    let record_exclude_topics = topic_list("record_exclude_topics")?;
    let record_compression = match map.get("record_compression") {
        None => None,
        Some(v) => Some(
            v.as_str()
                .ok_or_else(|| format!("expected one of: {}", crate::record::Compression::NAMES))
                .and_then(str::parse)
                .map_err(|message| ConfigError {
                    location: format!("{file}: record_compression"),
                    message,
                })?,
        ),
    };
    Ok((
        out,
        LaunchKeys {
            record,
            record_topics,
            record_exclude_topics,
            record_compression,
            live,
        },
    ))
}

/// The value of `option` (`--record-topics`, `--record-exclude-topics`): comma-separated
/// topics as [`record_topics`] takes them; `example` for the error when it is missing.
fn topic_option(option: &str, value: Option<String>, example: &str) -> Result<Vec<String>, String> {
    let v = value.ok_or_else(|| format!("{option} needs topic names (e.g. {example})"))?;
    record_topics(v.split(',').map(|t| t.trim().to_string()).collect())
        .map_err(|e| format!("{option}: {e}"))
}

/// The topics of `record_topics` / `--record-topics` (and of the exclusions): absolute ROS
/// names, at least one.
fn record_topics(topics: Vec<String>) -> Result<Vec<String>, String> {
    if topics.is_empty() {
        return Err("expected at least one topic (e.g. [/joint_states])".into());
    }
    match topics.iter().find(|t| !t.starts_with('/') || t.len() < 2) {
        Some(t) => Err(format!(
            "'{t}' is not an absolute topic name (e.g. /joint_states, /axis_node/axis_states)"
        )),
        None => Ok(topics),
    }
}

/// Command line of the launcher and of each node binary.
#[derive(Debug, Default)]
pub struct Args {
    /// Launch config file.
    pub config: Option<String>,
    /// Stop after this many seconds (smoke tests); default: until Ctrl-C / SIGTERM.
    pub duration: Option<f64>,
    /// Only check the config, start nothing.
    pub check: bool,
    /// `--record FILE`: record every published message of every node to an MCAP file.
    pub record: Option<String>,
    /// `--record-topics /a,/b`: record only these topics.
    pub record_topics: Option<Vec<String>>,
    /// `--record-exclude-topics /a,/b`: record none of these topics.
    pub record_exclude_topics: Option<Vec<String>>,
    /// `--record-compression none|zstd`: how the recording's chunks are compressed.
    pub record_compression: Option<crate::record::Compression>,
    /// `--cycles N`: run N cycles of every (lockstep) node as fast as they go, then stop;
    /// no client needs to step them over DDS.
    pub cycles: Option<u64>,
    /// `--until-idle` (with `--cycles N`): stop at the first cycle after which no node has a
    /// command running or a script step left (at most N cycles).
    pub until_idle: bool,
    /// `--live PORT` (serve the live feed on PORT, the page on the config's page port) or
    /// `--no-live` (Some(None)).
    pub live: Option<Option<u16>>,
    /// `--ros-args ... [--]`.
    pub ros: RosArgs,
}

fn parse_args(usage: &str) -> Result<Args, String> {
    parse_args_from(std::env::args().skip(1), usage)
}

/// The command line `args` (without the program name), as the launcher and the node
/// binaries read it; `usage` is the text of `--help` and of the errors that show it.
pub fn parse_args_from(
    args: impl IntoIterator<Item = String>,
    usage: &str,
) -> Result<Args, String> {
    let mut a = Args::default();
    let mut it = args.into_iter();
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--ros-args" => {
                let tokens: Vec<String> = it.by_ref().take_while(|t| t != "--").collect();
                let more = RosArgs::parse(&tokens)?;
                a.ros.remaps.extend(more.remaps);
                a.ros.params.extend(more.params);
            }
            "--duration" => {
                let v = it.next().ok_or("--duration needs seconds")?;
                a.duration = Some(
                    v.parse::<f64>()
                        .map_err(|_| format!("--duration: '{v}' is not a number"))?,
                );
            }
            "--check" => a.check = true,
            "--cycles" => {
                let v = it.next().ok_or("--cycles needs a number of cycles")?;
                match v.parse::<u64>() {
                    Ok(n) if n > 0 => a.cycles = Some(n),
                    _ => return Err(format!("--cycles: '{v}' is not a positive whole number")),
                }
            }
            "--live" => {
                let v = it.next().ok_or("--live needs a port (e.g. 8765)")?;
                a.live =
                    Some(Some(v.parse::<u16>().map_err(|_| {
                        format!("--live: '{v}' is not a port number")
                    })?));
            }
            "--no-live" => a.live = Some(None),
            "--until-idle" => a.until_idle = true,
            "--record" => {
                let v = it
                    .next()
                    .ok_or("--record needs a file name (e.g. run.mcap)")?;
                a.record = Some(v);
            }
            "--record-topics" => {
                a.record_topics = Some(topic_option(&arg, it.next(), "/joint_states,/clock")?);
            }
            "--record-exclude-topics" => {
                a.record_exclude_topics =
                    Some(topic_option(&arg, it.next(), "/planar_node/markers")?);
            }
            "--record-compression" => {
                let v = it.next().ok_or_else(|| {
                    format!(
                        "--record-compression needs one of: {}",
                        crate::record::Compression::NAMES
                    )
                })?;
                a.record_compression = Some(
                    v.parse()
                        .map_err(|e| format!("--record-compression: {e}"))?,
                );
            }
            "-h" | "--help" => return Err(usage.to_string()),
            s if s.starts_with('-') => return Err(format!("unknown option {s}\n{usage}")),
            s => {
                if a.config.replace(s.to_string()).is_some() {
                    return Err(format!("only one config file\n{usage}"));
                }
            }
        }
    }
    Ok(a)
}

/// The `main` of the launcher and of the node binaries: runs the entries of `kinds` found in
/// the config (default `default_config`), until Ctrl-C/SIGTERM or `--duration`. Returns the
/// process exit code (2 for configuration errors).
pub fn main_with(program: &'static str, kinds: &[NodeKind], default_config: &str) -> i32 {
    // Before anything else (README "Operating it"): signals, then the fail-safe panic hook.
    let shutdown = crate::signals::Shutdown::install(program);
    crate::failsafe::install(program);
    crate::logging::init();
    let usage = format!("usage: {program} [CONFIG.yaml] [--duration SECONDS] [--check] [--record FILE.mcap [--record-topics /A,/B] [--record-exclude-topics /C,/D] [--record-compression none|zstd]] [--cycles N [--until-idle]] [--live PORT | --no-live] [--ros-args [-p [NODE:]NAME:=VALUE] [-r [NODE:]FROM:=TO] [--params-file FILE] [--]]\n  default config: {default_config}");
    let args = match parse_args(&usage) {
        Ok(a) => a,
        Err(msg) => {
            eprintln!("{msg}");
            return 2;
        }
    };
    let path = args.config.unwrap_or_else(|| default_config.to_string());
    crate::ros_args::install_remaps(args.ros.remaps.clone());
    let (entries, keys) = match load_launch(Path::new(&path), kinds, &args.ros) {
        Ok(e) => e,
        Err(e) => {
            eprintln!("{program}: configuration error: {e}");
            return 2;
        }
    };
    if entries.is_empty() {
        eprintln!(
            "{program}: configuration error: {path}: no node of kind {} in 'nodes'",
            kind_list(kinds)
        );
        return 2;
    }
    if args.until_idle && args.cycles.is_none() {
        eprintln!("{program}: --until-idle needs --cycles N (the most cycles to run)");
        return 2;
    }
    if let (Some(_), Some(e)) = (args.cycles, entries.iter().find(|e| !e.common.lockstep)) {
        eprintln!(
            "{program}: configuration error: {}: --cycles runs lockstep nodes only (set lockstep: true)",
            e.location
        );
        return 2;
    }
    let domain = match shell::domain_id_from_env() {
        Ok(d) => d,
        Err(e) => {
            eprintln!("{program}: configuration error: {e}");
            return 2;
        }
    };
    let record = args.record.clone().or(keys.record);
    let record_topics = crate::record::Topics {
        only: args
            .record_topics
            .clone()
            .or(keys.record_topics)
            .map(|t| t.into_iter().collect()),
        exclude: args
            .record_exclude_topics
            .clone()
            .or(keys.record_exclude_topics)
            .unwrap_or_default()
            .into_iter()
            .collect(),
    };
    let compression = args
        .record_compression
        .or(keys.record_compression)
        .unwrap_or_default();
    let live = match (args.live, keys.live) {
        (Some(None), _) | (None, None) => None,
        (Some(Some(port)), cfg) => Some(crate::live::LiveSettings {
            enabled: true,
            port,
            ..cfg.unwrap_or_default()
        }),
        (None, Some(cfg)) => cfg.enabled.then_some(cfg),
    };
    if let (Some(file), false) = (&record, args.check) {
        if let Err(e) = crate::record::start(Path::new(file), record_topics, compression) {
            eprintln!("{program}: cannot record to {file}: {e}");
            return 2;
        }
    }
    let rt = match tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("{program}: cannot start the async runtime: {e}");
            return 1;
        }
    };
    rt.block_on(async move {
        // The live feed first: every publisher finds it at its first message.
        let mut _feed = None;
        if let (Some(settings), false) = (&live, args.check) {
            match crate::live::start(settings).await {
                Ok(f) => {
                    println!(
                        "{program}: live feed ws://{} (Foxglove, Lichtblick: open connection); page http://{}/",
                        f.feed, f.page
                    );
                    _feed = Some(f);
                }
                // The machine runs without its feed (a second demo on the same ports, say).
                Err(e) => eprintln!(
                    "{program}: {e}; running without the live feed (choose another port with --live PORT)"
                ),
            }
        }
        let mut running: Vec<RunningNode> = Vec::new();
        for e in &entries {
            if shutdown.requested() {
                break;
            }
            let kind = kinds
                .iter()
                .find(|k| k.kind == e.kind)
                .expect("checked by load");
            if args.check {
                if let Err(err) = (kind.check)(&e.common, e.engine.clone(), &e.location) {
                    eprintln!("{program}: configuration error: {err}");
                    return 2;
                }
                continue;
            }
            match (kind.start)(&e.common, e.engine.clone(), &e.location, domain) {
                Ok(r) => running.push(r),
                Err(err) => {
                    eprintln!("{program}: {err}");
                    return if matches!(err, StartError::Config(_)) {
                        2
                    } else {
                        1
                    };
                }
            }
        }
        if args.check {
            println!("{path}: OK ({} nodes)", entries.len());
            return 0;
        }
        let mut code = 0;
        if !shutdown.requested() {
            if let Some(n) = args.cycles {
                let until_idle = args.until_idle;
                if let Err(e) =
                    run_cycles(program, &running, &entries, n, until_idle, &shutdown).await
                {
                    eprintln!("{program}: {e}");
                    code = 1;
                }
            } else {
                tracing::info!(
                    "{} node(s) running on ROS_DOMAIN_ID {domain}; Ctrl-C to stop",
                    running.len()
                );
                wait_for_stop(&shutdown, args.duration).await;
            }
        }
        for r in running {
            r.stop().await;
        }
        // The nodes are stopped: nothing publishes any more, the recording can be closed.
        match crate::record::finish() {
            Some(Ok((written, dropped))) => {
                tracing::info!("recording closed: {written} messages ({dropped} dropped)");
            }
            Some(Err(e)) => {
                eprintln!("{program}: {e}");
                return 1;
            }
            None => {}
        }
        code
    })
}

fn kind_list(kinds: &[NodeKind]) -> String {
    kinds.iter().map(|k| k.kind).collect::<Vec<_>>().join(", ")
}

/// `--cycles N`: steps every (lockstep) node N cycles, all nodes together in batches (so
/// Ctrl-C ends the run between batches), and prints how fast that was against real time.
async fn run_cycles(
    program: &str,
    running: &[RunningNode],
    entries: &[NodeEntry],
    n: u64,
    until_idle: bool,
    shutdown: &crate::signals::Shutdown,
) -> Result<(), String> {
    // Until idle: one cycle at a time, so the run ends at the exact (reproducible) cycle.
    let batch: u64 = if until_idle { 1 } else { 1000 };
    // No client listens to a run that steps itself: record and feed the live view only.
    crate::record::set_record_only(true);
    let t0 = std::time::Instant::now();
    let mut done = 0;
    let mut cycles = vec![0; running.len()];
    while done < n && !shutdown.requested() {
        let k = (n - done).min(batch);
        let steps: Vec<_> = running.iter().map(|r| tokio::spawn(r.step(k))).collect();
        for (s, c) in steps.into_iter().zip(&mut cycles) {
            *c = s.await.map_err(|e| format!("stepping: {e}"))??;
        }
        done += k;
        if until_idle && running.iter().all(|r| r.busy() == 0) {
            println!("{program}: every command ended and every script step ran after cycle {done}");
            break;
        }
    }
    // Every cycle's state is published (and recorded) before the nodes stop.
    for (r, &c) in running.iter().zip(&cycles) {
        r.flush(c).await;
    }
    let wall = t0.elapsed().as_secs_f64();
    for e in entries {
        let sim = done as f64 * e.common.cycle_period;
        println!(
            "{program}: {}: ran {done} cycles ({sim:.3} s simulated) in {wall:.3} s wall: {:.1}x real time",
            e.common.name,
            sim / wall.max(1e-9)
        );
    }
    Ok(())
}

async fn wait_for_stop(shutdown: &crate::signals::Shutdown, duration: Option<f64>) {
    let timer = async {
        match duration {
            Some(s) => tokio::time::sleep(Duration::from_secs_f64(s.max(0.0))).await,
            None => std::future::pending().await,
        }
    };
    tokio::select! {
        _ = shutdown.wait() => {}
        _ = timer => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Nothing;
    impl Running for Nothing {
        fn stop(
            self: Box<Self>,
        ) -> std::pin::Pin<Box<dyn std::future::Future<Output = ()> + Send>> {
            Box::pin(async {})
        }
        fn as_any(&self) -> &dyn Any {
            self
        }
    }
    fn dummy(
        _: &CommonConfig,
        _: serde_yaml::Value,
        _: &str,
        _: u16,
    ) -> Result<RunningNode, StartError> {
        Ok(Box::new(Nothing))
    }
    fn no_check(_: &CommonConfig, _: serde_yaml::Value, _: &str) -> Result<(), ConfigError> {
        Ok(())
    }
    const KINDS: &[NodeKind] = &[NodeKind {
        kind: "axis_node",
        start: dummy,
        check: no_check,
    }];

    #[test]
    fn other_suite_kinds_are_skipped() {
        let e = parse(
            "nodes:\n  - kind: planar_node\n  - kind: axis_node\n",
            "f.yaml",
            KINDS,
        )
        .unwrap();
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].kind, "axis_node");
    }

    #[test]
    fn good_config_fills_defaults() {
        let e = parse(
            "nodes:\n  - kind: axis_node\n    axes: {}\n",
            "f.yaml",
            KINDS,
        )
        .unwrap();
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].common.name, "axis_node");
        assert_eq!(e[0].common.cycle_period, 0.001);
        assert_eq!(e[0].common.state_rate, 100.0);
        assert!(e[0].engine.get("axes").is_some());
    }

    #[test]
    fn record_compression_defaults_to_none_and_can_be_zstd() {
        let keys = |text: &str| {
            parse_launch(text, "f.yaml", KINDS, &RosArgs::default())
                .unwrap()
                .1
                .record_compression
        };
        assert_eq!(keys("nodes: []\n"), None);
        assert_eq!(
            crate::record::Compression::default(),
            crate::record::Compression::None
        );
        assert_eq!(
            keys("nodes: []\nrecord_compression: none\n"),
            Some(crate::record::Compression::None)
        );
        assert_eq!(
            keys("nodes: []\nrecord_compression: zstd\n"),
            Some(crate::record::Compression::Zstd)
        );
    }

    #[test]
    fn errors_name_file_key_and_problem() {
        let cases = [
            (
                "nodes:\n  - kind: axis_nod\n",
                "f.yaml: nodes[0].kind",
                "unknown node kind 'axis_nod'",
            ),
            (
                "nodes:\n  - kind: axis_node\n    cycle_period: -1\n",
                "cycle_period",
                "outside",
            ),
            (
                "nodes:\n  - kind: axis_node\n    cycle_period: .nan\n",
                "cycle_period",
                "outside",
            ),
            (
                "nodes:\n  - kind: axis_node\n    state_rate: 0\n",
                "state_rate",
                "outside",
            ),
            (
                "nodes:\n  - kind: axis_node\n    state_publish_every_n_cycles: 5\n",
                "state_publish_every_n_cycles",
                "needs simulated time",
            ),
            (
                "nodes:\n  - kind: axis_node\n    state_publish_every_n_cycles: -1\n",
                "state_publish_every_n_cycles",
                "",
            ),
            (
                "nodes:\n  - kind: axis_node\n    service_mapping: zenoh\n",
                "service_mapping",
                "not one of",
            ),
            (
                "nodes:\n  - kind: axis_node\n    lockstep: maybe\n",
                "nodes[0] (axis_node)",
                "lockstep",
            ),
            (
                "nodes:\n  - kind: axis_node\n  - kind: axis_node\n",
                "name",
                "used twice",
            ),
            ("node: []\n", "f.yaml: node", "unknown key"),
            (
                "nodes: []\nrecord_compression: lz5\n",
                "f.yaml: record_compression",
                "unknown compression 'lz5' (one of: none, zstd)",
            ),
            (
                "nodes: []\nrecord_compression: [zstd]\n",
                "f.yaml: record_compression",
                "expected one of: none, zstd",
            ),
            ("nodes: [\n", "f.yaml", "line 2"),
        ];
        for (text, loc, msg) in cases {
            let e = parse(text, "f.yaml", KINDS)
                .err()
                .unwrap_or_else(|| panic!("accepted: {text}"));
            let s = e.to_string();
            assert!(
                e.location.contains(loc) || s.contains(loc),
                "{text:?}: location {s}"
            );
            assert!(s.contains(msg), "{text:?}: message {s}");
        }
    }
}
