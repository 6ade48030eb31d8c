//! Recordings in MCAP's ROS 2 profile, as `ros2 bag record -s mcap` writes them: one schema per
//! message type (encoding `ros2msg`, the definition of [`motion_msgs::message_definition`]), one
//! channel per topic (message encoding `cdr`), and each message as it travels over DDS (the
//! 4-byte encapsulation header, then CDR). Foxglove, Lichtblick, PlotJuggler, rosbag2 and the
//! PyPI `mcap` readers open such a file.
//!
//! [`Recording`] is the writer; it knows nothing of nodes or cycles. Chunks are not compressed
//! (no C library needed); a recording is finished (summary and index written) by
//! [`Recording::finish`], and a file whose writer was dropped without it is still readable
//! message by message.

use ros2_client::dds::rustdds::serialization::to_writer_with_rep_id;
use ros2_client::dds::rustdds::RepresentationIdentifier;
use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

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

/// An MCAP file being written (see the module docs).
pub struct Recording {
    writer: mcap::Writer<BufWriter<File>>,
    /// Topic → (channel id, type name, next sequence number).
    channels: HashMap<String, (u16, String, u32)>,
}

impl Recording {
    /// Creates (truncates) the file at `path`, with the MCAP header of the `ros2` profile.
    pub fn create(path: &Path) -> Result<Self, RecordError> {
        let file = BufWriter::new(File::create(path)?);
        let writer = mcap::WriteOptions::new()
            .profile("ros2")
            .library(concat!("motion_runtime ", env!("CARGO_PKG_VERSION")))
            .compression(None)
            .create(file)?;
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
        let mut data = vec![0x00, 0x01, 0x00, 0x00]; // CDR_LE encapsulation, no options
        to_writer_with_rep_id(&mut data, msg, RepresentationIdentifier::CDR_LE)
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
