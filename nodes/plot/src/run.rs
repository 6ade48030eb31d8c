//! A recorded run (MCAP, ROS 2 profile) read into the series the figures draw. Channels are
//! recognised by their schema (message type), not by topic names, so remapped and namespaced
//! nodes plot the same. Times are seconds from the first message of the recording.

use motion_msgs::deps::visualization_msgs::msg::MarkerArray;
use motion_msgs::msg::{
    AxisStateArray, CaGroupState, CommandStatus, CycleStats, PickPlaceState, PlanarState,
};
use ros2_client::dds::rustdds::serialization::deserialize_from_cdr_with_rep_id;
use ros2_client::dds::rustdds::RepresentationIdentifier;
use std::collections::BTreeMap;

/// Why a recording could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be read.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// Not an MCAP file, or a broken one.
    #[error("not a readable MCAP file: {0}")]
    Mcap(#[from] mcap::McapError),
    /// A message does not decode as its schema says.
    #[error("{topic}: message {index} does not decode as {ty}: {why}")]
    Decode {
        /// Channel topic.
        topic: String,
        /// Message index on the channel.
        index: usize,
        /// Schema name.
        ty: String,
        /// Decoder's message.
        why: String,
    },
}

/// One axis sample: SetPos, SetVelo, SetAcc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisSample {
    /// Time [s].
    pub t: f64,
    /// SetPos [u].
    pub pos: f64,
    /// SetVelo [u/s].
    pub velo: f64,
    /// SetAcc [u/s²].
    pub acc: f64,
}

/// A command's state change as `~/command_status` reported it.
#[derive(Clone, Debug, PartialEq)]
pub struct CommandMark {
    /// Time [s].
    pub t: f64,
    /// Axis, mover, group or belt.
    pub object: String,
    /// FB name.
    pub command: String,
    /// Active, Done, Aborted or Error.
    pub state: &'static str,
}

/// Gap of one CA axis to its predecessor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GapSample {
    /// Time [s].
    pub t: f64,
    /// Actual gap [mm] (NaN: no predecessor).
    pub actual: f64,
    /// Effective target gap [mm].
    pub target: f64,
}

/// A rectangle of the plane (stator tile, belt) [mm]: centre, size, rotation about z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Centre x, y.
    pub centre: (f64, f64),
    /// Length along its own x, width along its own y.
    pub size: (f64, f64),
    /// Rotation about z [rad].
    pub yaw: f64,
}

impl Rect {
    /// The corners, counter-clockwise.
    pub fn corners(&self) -> [(f64, f64); 4] {
        let (c, s) = (self.yaw.cos(), self.yaw.sin());
        let (hx, hy) = (self.size.0 / 2.0, self.size.1 / 2.0);
        [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
            .map(|(x, y)| (self.centre.0 + c * x - s * y, self.centre.1 + s * x + c * y))
    }
}

/// Everything the figures need from a run.
#[derive(Debug, Default)]
pub struct Run {
    /// Axis name → samples (every `AxisStateArray` of the run).
    pub axes: BTreeMap<String, Vec<AxisSample>>,
    /// Command marks per object.
    pub commands: Vec<CommandMark>,
    /// CA group → axis → gap samples.
    pub gaps: BTreeMap<String, BTreeMap<String, Vec<GapSample>>>,
    /// Mover name → (t, x, y) [s, mm].
    pub movers: BTreeMap<String, Vec<(f64, f64, f64)>>,
    /// Stator tiles of the XPlanar table (from its markers) [mm].
    pub stators: Vec<Rect>,
    /// Tracks of the XPlanar table as polylines (from its markers) [mm].
    pub tracks: Vec<Vec<(f64, f64)>>,
    /// TCP path: (t, x, y, z) [s, mm].
    pub tcp: Vec<(f64, f64, f64, f64)>,
    /// Belts of the pick-and-place cell (from its markers) [mm].
    pub belts: Vec<Rect>,
    /// Workpieces seen on the belts: (x, y, z) in MCS [mm].
    pub workpieces: Vec<(f64, f64, f64)>,
    /// Node → its last cycle statistics (histograms since start).
    pub cycle_stats: BTreeMap<String, CycleStats>,
    /// Messages read.
    pub messages: usize,
}

fn decode<T: serde::de::DeserializeOwned>(
    data: &[u8],
    topic: &str,
    ty: &str,
    index: usize,
) -> Result<T, ReadError> {
    let err = |why: String| ReadError::Decode {
        topic: topic.to_string(),
        index,
        ty: ty.to_string(),
        why,
    };
    if data.len() < 4 {
        return Err(err("shorter than the encapsulation header".into()));
    }
    let rep = match data[1] {
        1 => RepresentationIdentifier::CDR_LE,
        _ => RepresentationIdentifier::CDR_BE,
    };
    deserialize_from_cdr_with_rep_id::<T>(&data[4..], rep)
        .map(|(v, _)| v)
        .map_err(|e| err(e.to_string()))
}

fn state_name(s: &CommandStatus) -> &'static str {
    if s.error {
        "Error"
    } else if s.command_aborted {
        "Aborted"
    } else if s.done {
        "Done"
    } else {
        "Active"
    }
}

impl Run {
    /// Reads the run recorded in `bytes` (a whole MCAP file).
    pub fn read(bytes: &[u8]) -> Result<Run, ReadError> {
        let mut run = Run::default();
        let mut t0: Option<u64> = None;
        let mut counts: BTreeMap<String, usize> = BTreeMap::new();
        for m in mcap::MessageStream::new(bytes)? {
            let m = m?;
            let t0 = *t0.get_or_insert(m.log_time);
            let t = m.log_time.saturating_sub(t0) as f64 * 1e-9;
            let topic = m.channel.topic.as_str();
            let Some(schema) = &m.channel.schema else {
                continue;
            };
            let ty = schema.name.as_str();
            let index = counts.entry(topic.to_string()).or_default();
            *index += 1;
            let i = *index - 1;
            run.messages += 1;
            match ty {
                "motion_msgs/msg/AxisStateArray" => {
                    let a: AxisStateArray = decode(&m.data, topic, ty, i)?;
                    for s in a.axes {
                        run.axes.entry(s.name).or_default().push(AxisSample {
                            t,
                            pos: s.set_pos,
                            velo: s.set_velo,
                            acc: s.set_acc,
                        });
                    }
                }
                "motion_msgs/msg/CommandStatus" => {
                    let s: CommandStatus = decode(&m.data, topic, ty, i)?;
                    run.commands.push(CommandMark {
                        t,
                        state: state_name(&s),
                        object: s.object,
                        command: s.command,
                    });
                }
                "motion_msgs/msg/CaGroupState" => {
                    let g: CaGroupState = decode(&m.data, topic, ty, i)?;
                    let group = run.gaps.entry(g.name).or_default();
                    for a in g.axes {
                        group.entry(a.name).or_default().push(GapSample {
                            t,
                            actual: a.gap_actual,
                            target: a.gap_target,
                        });
                    }
                }
                "motion_msgs/msg/PlanarState" => {
                    let p: PlanarState = decode(&m.data, topic, ty, i)?;
                    for v in p.movers {
                        run.movers.entry(v.name).or_default().push((t, v.x, v.y));
                    }
                }
                "motion_msgs/msg/PickPlaceState" => {
                    let p: PickPlaceState = decode(&m.data, topic, ty, i)?;
                    run.tcp.push((t, p.tcp_x, p.tcp_y, p.tcp_z));
                    for b in &p.belts {
                        for w in b.workpieces.iter().filter(|w| w.visible) {
                            let q = (w.mcs_position[0], w.mcs_position[1], w.mcs_position[2]);
                            if run.workpieces.last() != Some(&q) {
                                run.workpieces.push(q);
                            }
                        }
                    }
                }
                "visualization_msgs/msg/MarkerArray" => {
                    let a: MarkerArray = decode(&m.data, topic, ty, i)?;
                    run.take_markers(&a);
                }
                "motion_msgs/msg/CycleStats" => {
                    let s: CycleStats = decode(&m.data, topic, ty, i)?;
                    run.cycle_stats.insert(s.node.clone(), s);
                }
                _ => {}
            }
        }
        Ok(run)
    }

    /// The static scenery from the first markers: stator tiles (ns `stators`) and belts (ns
    /// `belts`), metres to millimetres.
    fn take_markers(&mut self, a: &MarkerArray) {
        for m in &a.markers {
            let p = &m.pose.position;
            if m.ns == "stators" && self.stators.is_empty() {
                self.stators = m
                    .points
                    .iter()
                    .map(|q| Rect {
                        centre: ((p.x + q.x) * 1e3, (p.y + q.y) * 1e3),
                        size: (m.scale.x * 1e3, m.scale.y * 1e3),
                        yaw: 0.0,
                    })
                    .collect();
            }
            if m.ns == "tracks" && m.action == 0 && self.tracks.len() <= m.id.max(0) as usize {
                self.tracks.resize(m.id.max(0) as usize + 1, Vec::new());
            }
            if m.ns == "tracks" && m.action == 0 && self.tracks[m.id.max(0) as usize].is_empty() {
                self.tracks[m.id.max(0) as usize] = m
                    .points
                    .iter()
                    .map(|q| ((p.x + q.x) * 1e3, (p.y + q.y) * 1e3))
                    .collect();
            }
            let centre = (p.x * 1e3, p.y * 1e3);
            if m.ns == "belts" && m.action == 0 && !self.belts.iter().any(|b| b.centre == centre) {
                let q = &m.pose.orientation;
                self.belts.push(Rect {
                    centre,
                    size: (m.scale.x * 1e3, m.scale.y * 1e3),
                    yaw: (2.0 * (q.w * q.z + q.x * q.y)).atan2(1.0 - 2.0 * (q.y * q.y + q.z * q.z)),
                });
            }
        }
    }
}
