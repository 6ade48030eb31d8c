//! Recordings in MCAP's ROS 2 profile, as `ros2 bag record -s mcap` writes them: one schema per
//! message type (encoding `ros2msg`, the definition of [`motion_msgs::message_definition`]), one
//! channel per topic (message encoding `cdr`), and each message as it travels over DDS (the
//! 4-byte encapsulation header, then CDR). Foxglove, Lichtblick, PlotJuggler, rosbag2 and the
//! PyPI `mcap` readers open such a file.
//!
//! [`Recording`] is the writer; it knows nothing of nodes or cycles. Chunks are uncompressed by
//! default, as `ros2 bag record -s mcap` writes them, or compressed with zstd (see
//! [`Compression`]); a recording is finished (summary and index written) by
//! [`Recording::finish`], and a file whose writer was dropped without it is still readable
//! message by message. It may also go into a FIFO (read by another tool as the run goes), which
//! cannot seek: each chunk is then kept in memory until it is whole.

use ros2_client::dds::rustdds::serialization::to_writer_with_rep_id;
use ros2_client::dds::rustdds::RepresentationIdentifier;
use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

/// A message as it travels over DDS and is recorded: the 4-byte encapsulation header (CDR_LE,
/// no options), then the CDR body. `size`: the expected length (the buffer is allocated once).
fn serialized<M: serde::Serialize>(msg: &M, size: usize) -> Result<Vec<u8>, String> {
    let mut data = Vec::with_capacity(size.max(64));
    data.extend_from_slice(&[0x00, 0x01, 0x00, 0x00]);
    to_writer_with_rep_id(&mut data, msg, RepresentationIdentifier::CDR_LE)
        .map_err(|e| e.to_string())?;
    Ok(data)
}

/// Why a recording could not be written.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file could not be created or written.
    #[error("recording: {0}")]
    Io(#[from] std::io::Error),
    /// The MCAP writer refused (e.g. too many channels).
    #[error("recording: {0}")]
    Mcap(#[from] mcap::McapError),
    /// A message could not be serialized.
    #[error("recording: {0}")]
    Serialize(String),
    /// A message type without a definition in `motion_msgs` (no schema to record it with).
    #[error("recording: no message definition of type '{0}'")]
    UnknownType(String),
    /// The same topic was recorded with two types.
    #[error("recording: topic '{topic}' has type '{first}', not '{second}'")]
    TypeChanged {
        /// Topic name.
        topic: String,
        /// Type of its first message.
        first: String,
        /// Type now given.
        second: String,
    },
}

/// How a recording's chunks are compressed (`record_compression`, `--record-compression`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Compression {
    /// Uncompressed, the default of `ros2 bag record -s mcap` (rosbag2's MCAP plugin turns
    /// libmcap's zstd default off, for write throughput): the fastest to write.
    #[default]
    None,
    /// zstd at level 1 (libmcap's `Default` level for zstd; rosbag2's `zstd_fast` preset uses
    /// zstd's fastest, negative level, which this writer does not take). Measured with the
    /// 10-axis lockstep run recording every topic: the file about 7x smaller, the run about
    /// half as fast (the compression, on the recorder thread, is then what it waits for).
    Zstd,
}

impl Compression {
    /// The names a config or command line gives.
    pub const NAMES: &'static str = "none, zstd";
}

impl std::str::FromStr for Compression {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "zstd" => Ok(Compression::Zstd),
            "none" => Ok(Compression::None),
            _ => Err(format!(
                "unknown compression '{s}' (one of: {})",
                Compression::NAMES
            )),
        }
    }
}

/// Bytes gathered before they go to the file: one write call per MiB instead of per 8 KB (the
/// default), mostly whole pages. Measured by `bench lockstep` on the 2-core VM: the recording's
/// bytes written to a plain file went from about 130x to 190x real time, the node recording
/// every topic from about 112x to 135x.
pub const WRITE_BUFFER: usize = 1 << 20;

/// Where a recording goes: a file, or a pipe that cannot seek, for which the position the MCAP
/// writer asks for is counted here (it never seeks elsewhere when told not to).
struct Sink {
    out: BufWriter<File>,
    position: u64,
    seekable: bool,
}

impl std::io::Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.out.write(buf)?;
        self.position += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

impl std::io::Seek for Sink {
    fn seek(&mut self, to: std::io::SeekFrom) -> std::io::Result<u64> {
        if self.seekable {
            self.position = self.out.seek(to)?;
        } else if to != std::io::SeekFrom::Current(0) {
            return Err(std::io::Error::other("a recording into a pipe cannot seek"));
        }
        Ok(self.position)
    }
}

/// An MCAP file being written (see the module docs).
pub struct Recording {
    writer: mcap::Writer<Sink>,
    /// Topic → (channel id, type name, next sequence number).
    channels: HashMap<String, (u16, String, u32)>,
}

impl Recording {
    /// Creates (truncates) the file at `path`, with the MCAP header of the `ros2` profile; its
    /// chunks compressed as `compression` says.
    pub fn create(path: &Path, compression: Compression) -> Result<Self, RecordError> {
        let file = File::create(path)?;
        let seekable = file.metadata()?.is_file();
        let out = if seekable {
            BufWriter::with_capacity(WRITE_BUFFER, file)
        } else {
            // A pipe keeps the small default: a reader gets each chunk once it is whole.
            BufWriter::new(file)
        };
        let sink = Sink {
            out,
            position: 0,
            seekable,
        };
        let writer = mcap::WriteOptions::new()
            .profile("ros2")
            .library(concat!("motion_runtime ", env!("CARGO_PKG_VERSION")))
            .compression(match compression {
                Compression::Zstd => Some(mcap::Compression::Zstd),
                Compression::None => None,
            })
            .compression_level(1)
            // On the recorder thread: zstd's worker threads were slower (they take the cores
            // the nodes' cycles run on).
            .compression_threads(0)
            .disable_seeking(!seekable)
            .create(sink)?;
        Ok(Recording {
            writer,
            channels: HashMap::new(),
        })
    }

    /// Records `msg` of ROS type `ros_type` (`pkg/msg/Name`) on `topic` (an absolute ROS name)
    /// at ROS time `stamp_ns` (log and publish time).
    pub fn write<M: serde::Serialize>(
        &mut self,
        topic: &str,
        ros_type: &str,
        stamp_ns: u64,
        msg: &M,
    ) -> Result<(), RecordError> {
        let data =
            serialized(msg, 0).map_err(|e| RecordError::Serialize(format!("{topic}: {e}")))?;
        self.write_cdr(topic, ros_type, stamp_ns, &data)
    }

    /// Records an already serialized message (encapsulation header + CDR).
    pub fn write_cdr(
        &mut self,
        topic: &str,
        ros_type: &str,
        stamp_ns: u64,
        data: &[u8],
    ) -> Result<(), RecordError> {
        let (channel_id, sequence) = self.channel(topic, ros_type)?;
        self.writer.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id,
                sequence,
                log_time: stamp_ns,
                publish_time: stamp_ns,
            },
            data,
        )?;
        Ok(())
    }

    /// The channel of `topic`, added with its schema at the first message; the next sequence
    /// number on it.
    fn channel(&mut self, topic: &str, ros_type: &str) -> Result<(u16, u32), RecordError> {
        if let Some((id, ty, seq)) = self.channels.get_mut(topic) {
            if ty != ros_type {
                return Err(RecordError::TypeChanged {
                    topic: topic.into(),
                    first: ty.clone(),
                    second: ros_type.into(),
                });
            }
            *seq = seq.wrapping_add(1);
            return Ok((*id, *seq));
        }
        let definition = motion_msgs::message_definition(ros_type)
            .ok_or_else(|| RecordError::UnknownType(ros_type.into()))?;
        let schema = self
            .writer
            .add_schema(ros_type, "ros2msg", definition.as_bytes())?;
        let id = self
            .writer
            .add_channel(schema, topic, "cdr", &BTreeMap::new())?;
        self.channels.insert(topic.into(), (id, ros_type.into(), 1));
        Ok((id, 1))
    }

    /// Writes the summary and index and closes the file.
    pub fn finish(mut self) -> Result<(), RecordError> {
        self.writer.finish()?;
        Ok(())
    }
}

/// The process's recording (`motion_launch --record FILE`): a writer thread that owns the
/// [`Recording`], fed by every publisher of every node of the process through [`RecordedPublisher`].
/// Publishers never wait for it (a message that finds the queue full is dropped and counted),
/// except the state topics of lockstep nodes ([`RecordedPublisher::lossless`]) and every
/// publisher in a `--cycles` run: those wait.
struct Recorder {
    tx: std::sync::mpsc::SyncSender<Entry>,
    dropped: std::sync::atomic::AtomicU64,
    /// Only these topics (`--record-topics`); None: every topic.
    topics: Option<std::collections::HashSet<String>>,
}

enum Entry {
    Message {
        topic: std::sync::Arc<str>,
        ros_type: std::sync::Arc<str>,
        stamp_ns: u64,
        data: Vec<u8>,
    },
    Finish(std::sync::mpsc::Sender<Result<u64, RecordError>>),
}

static RECORDER: std::sync::OnceLock<Recorder> = std::sync::OnceLock::new();

/// Set for `--cycles` runs: the nodes' publishers record (and feed the live view) but do not
/// write to DDS, where no client of such a run listens; publishing there is most of a
/// lockstep cycle's cost.
static RECORD_ONLY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Publishers of this process stop (true) or resume (false) writing to DDS; recording and the
/// live feed go on.
pub fn set_record_only(on: bool) {
    RECORD_ONLY.store(on, std::sync::atomic::Ordering::Relaxed);
}

/// Messages the writer thread may hold before publishers drop instead of waiting.
const QUEUE: usize = 65_536;

/// Starts recording every published message of this process to `path` (once per process),
/// or with `topics` only those of these topics (absolute names), its chunks compressed as
/// `compression` says.
pub fn start(
    path: &Path,
    topics: Option<Vec<String>>,
    compression: Compression,
) -> Result<(), RecordError> {
    let mut rec = Recording::create(path, compression)?;
    let (tx, rx) = std::sync::mpsc::sync_channel::<Entry>(QUEUE);
    let recorder = Recorder {
        tx,
        dropped: std::sync::atomic::AtomicU64::new(0),
        topics: topics.map(|t| t.into_iter().collect()),
    };
    if RECORDER.set(recorder).is_err() {
        return Err(RecordError::Io(std::io::Error::other(
            "this process records already",
        )));
    }
    std::thread::Builder::new()
        .name("recorder".into())
        .spawn(move || {
            let mut written = 0u64;
            let mut failed: Option<RecordError> = None;
            let mut drained = false;
            loop {
                // Take what is queued; once the queue is empty, let it fill for a millisecond
                // before blocking again: a publisher then wakes this thread about once per
                // millisecond, not once per message (waking was most of a lockstep cycle).
                let entry = match rx.try_recv() {
                    Ok(e) => e,
                    Err(std::sync::mpsc::TryRecvError::Disconnected) => break,
                    Err(std::sync::mpsc::TryRecvError::Empty) if !drained => {
                        drained = true;
                        std::thread::sleep(std::time::Duration::from_millis(1));
                        continue;
                    }
                    Err(std::sync::mpsc::TryRecvError::Empty) => match rx.recv() {
                        Ok(e) => e,
                        Err(_) => break,
                    },
                };
                drained = false;
                match entry {
                    Entry::Message {
                        topic,
                        ros_type,
                        stamp_ns,
                        data,
                    } => {
                        if failed.is_none() {
                            match rec.write_cdr(&topic, &ros_type, stamp_ns, &data) {
                                Ok(()) => written += 1,
                                Err(e) => {
                                    tracing::error!("{e}; recording stopped");
                                    failed = Some(e);
                                }
                            }
                        }
                    }
                    Entry::Finish(done) => {
                        let r = match failed.take() {
                            Some(e) => Err(e),
                            None => rec.finish().map(|()| written),
                        };
                        let _ = done.send(r);
                        return;
                    }
                }
            }
        })?;
    Ok(())
}

/// True while this process records `topic`.
fn recording(topic: &str) -> bool {
    RECORDER
        .get()
        .is_some_and(|r| r.topics.as_ref().is_none_or(|t| t.contains(topic)))
}

/// Hands an already serialized message to the recording; waits for room only when `lossless`
/// or in a `--cycles` run.
fn record_serialized(
    topic: &std::sync::Arc<str>,
    ros_type: &std::sync::Arc<str>,
    stamp_ns: u64,
    data: Vec<u8>,
    lossless: bool,
) {
    let Some(r) = RECORDER.get() else {
        return;
    };
    let entry = Entry::Message {
        topic: topic.clone(),
        ros_type: ros_type.clone(),
        stamp_ns,
        data,
    };
    // A lockstep state topic and a `--cycles` run (record only) are lossless: they wait for
    // the writer, as simulated time waits for the stream. Otherwise a publisher never waits: a
    // full queue drops, counted.
    let sent = if lossless || RECORD_ONLY.load(std::sync::atomic::Ordering::Relaxed) {
        r.tx.send(entry).map_err(|_| ())
    } else {
        r.tx.try_send(entry).map_err(|_| ())
    };
    if sent.is_err() {
        r.dropped.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }
}

/// Ends the recording (after the nodes stopped): waits for the queue to be written, writes the
/// summary and closes the file. Returns the messages written and those dropped; None when this
/// process did not record.
pub fn finish() -> Option<Result<(u64, u64), RecordError>> {
    let r = RECORDER.get()?;
    let (tx, rx) = std::sync::mpsc::channel();
    if r.tx.send(Entry::Finish(tx)).is_err() {
        return Some(Err(RecordError::Io(std::io::Error::other(
            "the recorder thread ended",
        ))));
    }
    let dropped = r.dropped.load(std::sync::atomic::Ordering::Relaxed);
    Some(match rx.recv() {
        Ok(Ok(written)) => Ok((written, dropped)),
        Ok(Err(e)) => Err(e),
        Err(_) => Err(RecordError::Io(std::io::Error::other(
            "the recorder thread ended",
        ))),
    })
}

/// A message stamp (`builtin_interfaces/Time`) as nanoseconds of ROS time.
pub fn time_ns(t: &motion_msgs::deps::builtin_interfaces::msg::Time) -> i64 {
    i64::from(t.sec) * 1_000_000_000 + i64::from(t.nanosec)
}

/// A topic as the recording and the live feed ([`crate::live`]) see it: its name, type, the
/// live channel (looked up at the first message) and the length of its last message. One
/// per publisher ([`RecordedPublisher`]), or for messages that a dependency publishes (`/rosout`).
pub struct RecordedTopic {
    topic: std::sync::Arc<str>,
    ros_type: std::sync::Arc<str>,
    /// Length of the last serialized message (the next one is likely as long).
    size: std::sync::atomic::AtomicUsize,
    live: std::sync::OnceLock<Option<std::sync::Arc<foxglove::RawChannel>>>,
    /// Whether the recording takes this topic (decided at the first message).
    recorded: std::sync::OnceLock<bool>,
    /// Waits for the writer rather than dropping (see [`RecordedTopic::lossless`]).
    lossless: bool,
    /// Transient local: the last message is kept for live clients that subscribe later (see
    /// [`RecordedTopic::latched`]).
    latched: bool,
    latch: std::sync::OnceLock<Option<crate::live::Latch>>,
}

impl RecordedTopic {
    /// The topic named `topic` (its full ROS name) of type `ros_type` (`pkg/msg/Name`).
    pub fn new(topic: impl std::fmt::Display, ros_type: impl Into<std::sync::Arc<str>>) -> Self {
        RecordedTopic {
            topic: topic.to_string().into(),
            ros_type: ros_type.into(),
            size: std::sync::atomic::AtomicUsize::new(0),
            live: std::sync::OnceLock::new(),
            recorded: std::sync::OnceLock::new(),
            lossless: false,
            latched: false,
            latch: std::sync::OnceLock::new(),
        }
    }

    /// This topic is transient local (as `/tf_static`): its last message goes to each client
    /// of the live feed that subscribes later, as DDS gives it to a late reader.
    pub fn latched(mut self) -> Self {
        self.latched = true;
        self
    }

    /// This topic records every message: it waits for the recording's writer instead of
    /// dropping a message that finds its queue full. For the topics of a lockstep node's state
    /// stream, where simulated time waits for its observers (every cycle's state is recorded,
    /// also while a client steps the node over DDS); a real-time publisher must never wait.
    pub fn lossless(mut self) -> Self {
        self.lossless = true;
        self
    }

    /// True when the recording takes this topic.
    fn recorded(&self) -> bool {
        *self.recorded.get_or_init(|| recording(&self.topic))
    }

    /// The live feed's channel of this topic while a client subscribes to it.
    fn live_sink(&self) -> Option<&std::sync::Arc<foxglove::RawChannel>> {
        self.live
            .get_or_init(|| crate::live::channel(&self.topic, &self.ros_type))
            .as_ref()
            .filter(|c| c.has_sinks())
    }

    /// True when a message of this topic would go anywhere (recording or live feed).
    pub fn taken(&self) -> bool {
        self.recorded() || self.live_sink().is_some()
    }

    /// Records `msg` at ROS time `stamp_ns` (if this process records) and logs it to the live
    /// feed (if a client subscribed to the topic); serializes only when someone takes the
    /// message. Never waits, except for the writer when lossless or in a `--cycles` run.
    pub fn take<M: serde::Serialize>(&self, msg: &M, stamp_ns: i64) {
        let recorded = self.recorded();
        let latch = if self.latched {
            self.latch
                .get_or_init(|| crate::live::latch(&self.topic))
                .as_ref()
        } else {
            None
        };
        if !recorded && latch.is_none() && self.live_sink().is_none() {
            return;
        }
        let size = self.size.load(std::sync::atomic::Ordering::Relaxed);
        let Ok(data) = serialized(msg, size) else {
            return;
        };
        self.size
            .store(data.len(), std::sync::atomic::Ordering::Relaxed);
        let stamp = stamp_ns.max(0) as u64;
        // Kept before the feed is asked for subscribers: a client subscribing meanwhile gets
        // it replayed or live (at worst both), never not at all.
        if let Some(l) = latch {
            l.keep(&data, stamp);
        }
        if let Some(c) = self.live_sink() {
            c.log_with_meta(&data, foxglove::PartialMetadata::with_log_time(stamp));
        }
        if recorded {
            record_serialized(&self.topic, &self.ros_type, stamp, data, self.lossless);
        }
    }
}

/// A node's publisher whose messages also go to the process's recording and live feed, when
/// it has them: the one place where publishing, recording and the live feed meet (every
/// publisher of the shell and the nodes). A message is serialized once, and only when someone
/// takes it.
pub struct RecordedPublisher<M: serde::Serialize> {
    publisher: ros2_client::Publisher<M>,
    topic: RecordedTopic,
}

impl<M: serde::Serialize + motion_msgs::RosType> RecordedPublisher<M> {
    /// Wraps `publisher` of the topic named `topic` (its full ROS name).
    pub fn new(publisher: ros2_client::Publisher<M>, topic: impl std::fmt::Display) -> Self {
        RecordedPublisher {
            publisher,
            topic: RecordedTopic::new(topic, M::ROS_TYPE_NAME),
        }
    }

    /// This publisher records every message (see [`RecordedTopic::lossless`]).
    pub fn lossless(mut self) -> Self {
        self.topic = self.topic.lossless();
        self
    }

    /// This publisher is transient local (see [`RecordedTopic::latched`]).
    pub fn latched(mut self) -> Self {
        self.topic = self.topic.latched();
        self
    }

    /// Records `msg` at ROS time `stamp_ns` (if this process records) and logs it to the live
    /// feed (if a client subscribed to the topic), then publishes it.
    pub async fn publish(&self, msg: M, stamp_ns: i64) -> ros2_client::error::WriteResult<(), M> {
        match self.record(msg, stamp_ns) {
            Some(msg) => self.publish_dds(msg).await,
            None => Ok(()),
        }
    }

    /// The first half of [`RecordedPublisher::publish`], which does not wait for DDS: records
    /// `msg` (waiting for the writer only as [`RecordedTopic::take`] says) and logs it to the
    /// live feed; returns it when it is to be written to DDS too.
    pub fn record(&self, msg: M, stamp_ns: i64) -> Option<M> {
        self.record_ref(&msg, stamp_ns).then_some(msg)
    }

    /// [`RecordedPublisher::record`] of a borrowed message: true when it is to be written to
    /// DDS too (the caller then hands it over; a record-only run keeps it for a refill).
    pub fn record_ref(&self, msg: &M, stamp_ns: i64) -> bool {
        self.topic.take(msg, stamp_ns);
        !RECORD_ONLY.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// True when a message would go anywhere: DDS, the recording or the live feed (a state
    /// topic builds none otherwise).
    pub fn wanted(&self) -> bool {
        !RECORD_ONLY.load(std::sync::atomic::Ordering::Relaxed) || self.topic.taken()
    }

    /// The second half of [`RecordedPublisher::publish`]: writes `msg` to DDS.
    pub async fn publish_dds(&self, msg: M) -> ros2_client::error::WriteResult<(), M> {
        self.publisher.async_publish(msg).await
    }
}
