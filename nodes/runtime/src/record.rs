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
/// no options), then the CDR body, into `data` (cleared first).
fn serialize_into<M: serde::Serialize>(data: &mut Vec<u8>, msg: &M) -> Result<(), String> {
    data.clear();
    data.extend_from_slice(&[0x00, 0x01, 0x00, 0x00]);
    to_writer_with_rep_id(&mut *data, msg, RepresentationIdentifier::CDR_LE)
        .map_err(|e| e.to_string())
}

/// Why a recording could not be written.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file could not be created or written.
    #[error("recording: {0}")]
    Io(#[from] std::io::Error),
    /// The MCAP writer refused (e.g. too many channels) or could not write (e.g. no space
    /// left on the device).
    #[error("recording: {}", with_cause(.0))]
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

/// An error and its cause: the MCAP writer's I/O error says only "I/O error from writing",
/// its cause what went wrong (e.g. "No space left on device").
fn with_cause(e: &dyn std::error::Error) -> String {
    match e.source() {
        Some(cause) => format!("{e}: {cause}"),
        None => e.to_string(),
    }
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
    /// Topic → its index in `channels`.
    topics: HashMap<String, usize>,
    channels: Vec<Channel>,
}

/// A channel of a [`Recording`].
struct Channel {
    id: u16,
    ros_type: String,
    /// Sequence number of the last message.
    sequence: u32,
}

/// A topic's channel in a [`Recording`] ([`Recording::channel`]), to write to without looking
/// the topic up by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChannelRef(usize);

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
            topics: HashMap::new(),
            channels: Vec::new(),
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
        let mut data = Vec::new();
        serialize_into(&mut data, msg)
            .map_err(|e| RecordError::Serialize(format!("{topic}: {e}")))?;
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
        let channel = self.channel(topic, ros_type)?;
        self.write_on(channel, stamp_ns, data)
    }

    /// The channel of `topic`, of type `ros_type`: added with its schema when new; an error
    /// when the topic was recorded with another type.
    pub fn channel(&mut self, topic: &str, ros_type: &str) -> Result<ChannelRef, RecordError> {
        if let Some(&i) = self.topics.get(topic) {
            let first = &self.channels[i].ros_type;
            if first != ros_type {
                return Err(RecordError::TypeChanged {
                    topic: topic.into(),
                    first: first.clone(),
                    second: ros_type.into(),
                });
            }
            return Ok(ChannelRef(i));
        }
        let definition = motion_msgs::message_definition(ros_type)
            .ok_or_else(|| RecordError::UnknownType(ros_type.into()))?;
        let schema = self
            .writer
            .add_schema(ros_type, "ros2msg", definition.as_bytes())?;
        let id = self
            .writer
            .add_channel(schema, topic, "cdr", &BTreeMap::new())?;
        self.channels.push(Channel {
            id,
            ros_type: ros_type.into(),
            sequence: 0,
        });
        self.topics.insert(topic.into(), self.channels.len() - 1);
        Ok(ChannelRef(self.channels.len() - 1))
    }

    /// Records an already serialized message on `channel` (of this recording) at ROS time
    /// `stamp_ns`; its sequence number is the channel's next (from 1).
    pub fn write_on(
        &mut self,
        channel: ChannelRef,
        stamp_ns: u64,
        data: &[u8],
    ) -> Result<(), RecordError> {
        let c = &mut self.channels[channel.0];
        c.sequence = c.sequence.wrapping_add(1);
        self.writer.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: c.id,
                sequence: c.sequence,
                log_time: stamp_ns,
                publish_time: stamp_ns,
            },
            data,
        )?;
        Ok(())
    }

    /// Writes the summary and index and closes the file.
    pub fn finish(mut self) -> Result<(), RecordError> {
        self.writer.finish()?;
        Ok(())
    }
}

/// The process's recording (`motion_launch --record FILE`): a writer thread that owns the
/// [`Recording`], fed by every publisher of every node of the process through
/// [`RecordedPublisher`]. Publishers append their serialized messages to a batch (a buffer of
/// [`BATCH`] bytes); a full batch goes to the writer, which writes its messages and hands the
/// buffer back. So a message costs a copy under a short lock, not an allocation and a queue
/// entry of its own (those, with the page faults of a queue of many small buffers, were a third
/// of a lockstep cycle's recording cost), and the writer wakes once per batch. At most
/// [`BATCHES`] buffers exist: a publisher that needs a fresh one when none is free drops its
/// message (counted) and never waits, except the state topics of lockstep nodes
/// ([`RecordedPublisher::lossless`]) and every publisher in a `--cycles` run: those wait.
struct Recorder {
    shared: std::sync::Mutex<Batches>,
    /// The writer waits here for a full batch (or the end).
    to_writer: std::sync::Condvar,
    /// Lossless publishers wait here for a free buffer.
    to_publishers: std::sync::Condvar,
    /// Which topics are recorded.
    topics: Topics,
}

/// Which topics a recording takes (absolute names): every topic, or only those named
/// (`--record-topics`, `record_topics`), less those excluded (`--record-exclude-topics`,
/// `record_exclude_topics`, as `ros2 bag record --exclude-topics`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Topics {
    /// Only these topics; None: every topic.
    pub only: Option<std::collections::HashSet<String>>,
    /// Not these topics.
    pub exclude: std::collections::HashSet<String>,
}

impl Topics {
    /// Every topic.
    pub fn all() -> Self {
        Topics::default()
    }

    /// True when `topic` is recorded.
    pub fn takes(&self, topic: &str) -> bool {
        self.only.as_ref().is_none_or(|t| t.contains(topic)) && !self.exclude.contains(topic)
    }
}

/// The recorder's buffers and topics (under its lock).
struct Batches {
    /// Messages being gathered: per message its [`Frame`], then its bytes.
    current: Vec<u8>,
    /// Full batches, oldest first, for the writer.
    full: std::collections::VecDeque<Vec<u8>>,
    /// Buffers the writer gave back, empty.
    free: Vec<Vec<u8>>,
    /// Buffers that may still be made (of [`BATCHES`]).
    unmade: usize,
    /// Topic and type of each recorded topic, by the index its frames carry.
    topics: Vec<(std::sync::Arc<str>, std::sync::Arc<str>)>,
    /// Messages dropped for want of a free buffer.
    dropped: u64,
    /// Set by [`finish`]: the writer writes what is left, closes the file and answers here.
    finish: Option<std::sync::mpsc::Sender<Result<u64, RecordError>>>,
    /// The writer has ended: messages are dropped (counted), nobody waits.
    ended: bool,
}

/// Bytes a batch gathers before it goes to the writer (a message longer than that makes a
/// batch of its own).
pub const BATCH: usize = 256 << 10;

/// Buffers of [`BATCH`] bytes the recording may hold (about 8 MiB in all): what a held-up
/// writer lets publishers queue before real-time ones drop and lossless ones wait.
pub const BATCHES: usize = 32;

/// How long the writer lets a batch fill before it takes it unfilled: the most a message
/// waits in memory when publishers are slow to fill a batch.
const BATCH_AGE: std::time::Duration = std::time::Duration::from_millis(5);

/// What precedes each message in a batch: its topic's index, its length and its stamp.
struct Frame {
    topic: u32,
    len: u32,
    stamp_ns: u64,
}

impl Frame {
    const SIZE: usize = 16;

    fn put(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.topic.to_ne_bytes());
        out.extend_from_slice(&self.len.to_ne_bytes());
        out.extend_from_slice(&self.stamp_ns.to_ne_bytes());
    }

    fn get(b: &[u8]) -> Frame {
        let word = |i: usize| u32::from_ne_bytes(b[i..i + 4].try_into().expect("4 bytes"));
        Frame {
            topic: word(0),
            len: word(4),
            stamp_ns: u64::from_ne_bytes(b[8..16].try_into().expect("8 bytes")),
        }
    }
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

fn lock(m: &std::sync::Mutex<Batches>) -> std::sync::MutexGuard<'_, Batches> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Starts recording every published message of this process to `path` (once per process) on
/// the topics that `topics` takes, its chunks compressed as `compression` says.
pub fn start(path: &Path, topics: Topics, compression: Compression) -> Result<(), RecordError> {
    let rec = Recording::create(path, compression)?;
    let recorder = Recorder {
        shared: std::sync::Mutex::new(Batches {
            // The first of the BATCHES buffers.
            current: Vec::with_capacity(BATCH),
            full: std::collections::VecDeque::new(),
            free: Vec::new(),
            unmade: BATCHES - 1,
            topics: Vec::new(),
            dropped: 0,
            finish: None,
            ended: false,
        }),
        to_writer: std::sync::Condvar::new(),
        to_publishers: std::sync::Condvar::new(),
        topics,
    };
    if RECORDER.set(recorder).is_err() {
        return Err(RecordError::Io(std::io::Error::other(
            "this process records already",
        )));
    }
    let recorder = RECORDER.get().expect("set above");
    std::thread::Builder::new()
        .name("recorder".into())
        .spawn(move || recorder.write(rec))?;
    Ok(())
}

impl Recorder {
    /// The writer thread: writes each batch as it fills (or once its first message is
    /// [`BATCH_AGE`] old), until [`finish`].
    fn write(&self, rec: Recording) {
        let mut out = Writer {
            rec,
            topics: Vec::new(),
            channels: Vec::new(),
            written: 0,
            failed: None,
        };
        let mut shared = lock(&self.shared);
        loop {
            let batch = match shared.full.pop_front() {
                Some(b) => b,
                None if shared.finish.is_some() => {
                    let last = std::mem::take(&mut shared.current);
                    let done = shared.finish.take().expect("checked");
                    shared.ended = true;
                    out.learn_topics(&shared);
                    drop(shared);
                    self.to_publishers.notify_all();
                    out.batch(&last);
                    let _ = done.send(out.finish());
                    return;
                }
                None if shared.current.is_empty() => {
                    // Nothing gathered: the first message (or the end) wakes this thread.
                    shared = self
                        .to_writer
                        .wait(shared)
                        .unwrap_or_else(|p| p.into_inner());
                    continue;
                }
                None => {
                    let (s, waited) = self
                        .to_writer
                        .wait_timeout(shared, BATCH_AGE)
                        .unwrap_or_else(|p| p.into_inner());
                    shared = s;
                    if !waited.timed_out() || shared.current.is_empty() {
                        continue;
                    }
                    // Publishers are slow to fill it: take the batch as it is.
                    match fresh(&mut shared) {
                        Some(b) => std::mem::replace(&mut shared.current, b),
                        None => continue,
                    }
                }
            };
            out.learn_topics(&shared);
            drop(shared);
            out.batch(&batch);
            let mut batch = batch;
            batch.clear();
            shared = lock(&self.shared);
            shared.free.push(batch);
            self.to_publishers.notify_all();
        }
    }

    /// The index of `topic` in the frames (registered at its first message).
    fn register(&self, topic: &std::sync::Arc<str>, ros_type: &std::sync::Arc<str>) -> u32 {
        let mut shared = lock(&self.shared);
        shared.topics.push((topic.clone(), ros_type.clone()));
        (shared.topics.len() - 1) as u32
    }

    /// Appends a message to the current batch; a full batch goes to the writer. Waits for a
    /// free buffer only when `lossless` or in a `--cycles` run; otherwise drops (counted).
    fn append(&self, topic: u32, stamp_ns: u64, data: &[u8], lossless: bool) {
        let wait = lossless || RECORD_ONLY.load(std::sync::atomic::Ordering::Relaxed);
        let need = Frame::SIZE + data.len();
        let mut shared = lock(&self.shared);
        loop {
            if shared.ended {
                shared.dropped += 1;
                return;
            }
            if shared.current.is_empty() || shared.current.len() + need <= BATCH {
                break;
            }
            if let Some(b) = fresh(&mut shared) {
                let full = std::mem::replace(&mut shared.current, b);
                shared.full.push_back(full);
                self.to_writer.notify_one();
            } else if wait {
                shared = self
                    .to_publishers
                    .wait(shared)
                    .unwrap_or_else(|p| p.into_inner());
            } else {
                shared.dropped += 1;
                return;
            }
        }
        if shared.current.is_empty() {
            // The writer sleeps until a batch has a first message.
            self.to_writer.notify_one();
        }
        Frame {
            topic,
            len: data.len() as u32,
            stamp_ns,
        }
        .put(&mut shared.current);
        shared.current.extend_from_slice(data);
    }
}

/// The writer thread's side: the recording, the topics it knows and their channels.
struct Writer {
    rec: Recording,
    /// Topic and type by frame index (a copy of [`Batches::topics`] as far as known).
    topics: Vec<(std::sync::Arc<str>, std::sync::Arc<str>)>,
    /// The MCAP channel by frame index, made at the topic's first message.
    channels: Vec<Option<ChannelRef>>,
    written: u64,
    /// The first error; nothing is written after it.
    failed: Option<RecordError>,
}

impl Writer {
    /// Takes the topics registered since the last batch (their frames may be in it); their
    /// channels are made at their first message.
    fn learn_topics(&mut self, shared: &Batches) {
        self.topics
            .extend_from_slice(&shared.topics[self.topics.len()..]);
        self.channels.resize(self.topics.len(), None);
    }

    /// Writes the messages of one batch (nothing once writing failed).
    fn batch(&mut self, batch: &[u8]) {
        let mut at = 0;
        while at < batch.len() && self.failed.is_none() {
            let frame = Frame::get(&batch[at..at + Frame::SIZE]);
            let data = &batch[at + Frame::SIZE..at + Frame::SIZE + frame.len as usize];
            at += Frame::SIZE + frame.len as usize;
            let i = frame.topic as usize;
            let channel = match self.channels[i] {
                Some(c) => Ok(c),
                None => {
                    let (topic, ros_type) = &self.topics[i];
                    self.rec.channel(topic, ros_type)
                }
            };
            match channel.and_then(|c| {
                self.channels[i] = Some(c);
                self.rec.write_on(c, frame.stamp_ns, data)
            }) {
                Ok(()) => self.written += 1,
                Err(e) => {
                    tracing::error!("{e}; recording stopped");
                    self.failed = Some(e);
                }
            }
        }
    }

    /// Closes the file: the messages written, or the first error.
    fn finish(self) -> Result<u64, RecordError> {
        match self.failed {
            Some(e) => Err(e),
            None => self.rec.finish().map(|()| self.written),
        }
    }
}

/// A free (or new) buffer, if the recording may have one more.
fn fresh(shared: &mut Batches) -> Option<Vec<u8>> {
    if let Some(b) = shared.free.pop() {
        return Some(b);
    }
    if shared.unmade == 0 {
        return None;
    }
    shared.unmade -= 1;
    Some(Vec::with_capacity(BATCH))
}

/// Ends the recording (after the nodes stopped): waits for what is gathered to be written,
/// writes the summary and closes the file. Returns the messages written and those dropped;
/// None when this process did not record.
pub fn finish() -> Option<Result<(u64, u64), RecordError>> {
    let r = RECORDER.get()?;
    let (tx, rx) = std::sync::mpsc::channel();
    let dropped = {
        let mut shared = lock(&r.shared);
        if shared.ended {
            return Some(Err(RecordError::Io(std::io::Error::other(
                "the recording is closed already",
            ))));
        }
        shared.finish = Some(tx);
        r.to_writer.notify_one();
        shared.dropped
    };
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
/// live channel and its index in the recording (both looked up at the first message). One
/// per publisher ([`RecordedPublisher`]), or for messages that a dependency publishes (`/rosout`).
pub struct RecordedTopic {
    topic: std::sync::Arc<str>,
    ros_type: std::sync::Arc<str>,
    live: std::sync::OnceLock<Option<std::sync::Arc<foxglove::RawChannel>>>,
    /// The topic's index in the recording's frames; None when the recording does not take
    /// it (decided at the first message).
    recorded: std::sync::OnceLock<Option<u32>>,
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
    /// dropping a message that finds its buffers full. For the topics of a lockstep node's state
    /// stream, where simulated time waits for its observers (every cycle's state is recorded,
    /// also while a client steps the node over DDS); a real-time publisher must never wait.
    pub fn lossless(mut self) -> Self {
        self.lossless = true;
        self
    }

    /// The recording and this topic's index in it, when the recording takes this topic.
    fn recorded(&self) -> Option<(&'static Recorder, u32)> {
        let r = RECORDER.get()?;
        let index = self.recorded.get_or_init(|| {
            r.topics
                .takes(&self.topic)
                .then(|| r.register(&self.topic, &self.ros_type))
        });
        index.map(|i| (r, i))
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
        self.recorded().is_some() || self.live_sink().is_some()
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
        if recorded.is_none() && latch.is_none() && self.live_sink().is_none() {
            return;
        }
        let stamp = stamp_ns.max(0) as u64;
        let send = |data: &mut Vec<u8>| {
            if serialize_into(data, msg).is_err() {
                return;
            }
            // Kept before the feed is asked for subscribers: a client subscribing meanwhile
            // gets it replayed or live (at worst both), never not at all.
            if let Some(l) = latch {
                l.keep(data, stamp);
            }
            if let Some(c) = self.live_sink() {
                c.log_with_meta(data, foxglove::PartialMetadata::with_log_time(stamp));
            }
            if let Some((r, index)) = recorded {
                r.append(index, stamp, data, self.lossless);
            }
        };
        SCRATCH.with(|scratch| match scratch.try_borrow_mut() {
            Ok(mut data) => send(&mut data),
            // Taken again on this thread while a message is out (`/rosout` of a warning that
            // the live feed logs): a buffer of its own.
            Err(_) => send(&mut Vec::new()),
        });
    }
}

thread_local! {
    /// Each thread's buffer that messages are serialized into, for the recording and the live
    /// feed (which copy them): no allocation per message.
    static SCRATCH: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) };
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
