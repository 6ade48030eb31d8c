//! ROS 2 interfaces of the motion suite, generated at build time from the interface files.
//!
//! `msg/*.msg`, `srv/*.srv` and `action/*.action` are the single source of truth: `build.rs`
//! parses them (a port of ROS's `rosidl_adapter` parser) and generates
//!
//! * [`msg`]: one struct per message, e.g. `msg::AxisState`;
//! * [`srv`]: `XRequest`, `XResponse` and a marker `X` (implementing [`RosService`]);
//! * [`action`]: `XGoal`, `XResult`, `XFeedback` and a marker `X` (implementing [`RosAction`]);
//! * [`deps`]: the standard ROS 2 Jazzy packages we use, vendored under `ros_deps/`
//!   (`deps::builtin_interfaces::msg::Time`, `deps::std_msgs::msg::Header`, ...).
//!
//! Every struct derives `Clone, Debug, PartialEq, Serialize, Deserialize` with the fields in file
//! order (so serde's CDR encoding matches rmw's), implements `Default` with the IDL defaults and
//! [`ros2_client::Message`], and carries its constants as associated consts together with
//! `ROS_TYPE_NAME` / `DDS_TYPE_NAME`. Messages have `type_name()`, service markers
//! `service_type_name()`, action markers `action_type_name()` for ros2-client.
//!
//! [`INTERFACE_DESCRIPTION_JSON`] is the parser's canonical view of every type; the test
//! `tests/rosidl_check.rs` compares it with what ROS's own parser makes of the same files.
//! `tools/gen_python_types.py` generates matching Python `cyclonedds` types from the same files
//! (for a Python DDS test peer); `tests/python_types.rs` checks that both encode alike.
//! Interfaces only used by tests live in `tests/interfaces/<pkg>/`.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

include!(concat!(env!("OUT_DIR"), "/interfaces.rs"));

/// Canonical JSON description of every generated type (one type per line, sorted by ROS name);
/// `tools/rosidl_check.py` prints the same from `rosidl_adapter`.
pub const INTERFACE_DESCRIPTION_JSON: &str =
    include_str!(concat!(env!("OUT_DIR"), "/interfaces.json"));

/// The `ros2msg` definition of a message type (`pkg/msg/Name`), as rosbag2 stores it in an
/// MCAP schema and Foxglove reads it: the type's `.msg` text followed by every type it uses,
/// each after a line of 80 `=` and `MSG: pkg/Name`. None for unknown names.
pub fn message_definition(ros_type_name: &str) -> Option<&'static str> {
    MESSAGE_DEFINITIONS
        .binary_search_by(|(name, _)| (*name).cmp(ros_type_name))
        .ok()
        .map(|i| MESSAGE_DEFINITIONS[i].1)
}

/// ROS 2 type names of a generated message struct (also service / action parts).
pub trait RosType {
    /// e.g. `motion_msgs/msg/AxisState`, `motion_msgs/srv/Halt_Request`.
    const ROS_TYPE_NAME: &'static str;
    /// e.g. `motion_msgs::msg::dds_::AxisState_`.
    const DDS_TYPE_NAME: &'static str;
}

/// A command service's response: the answer every command service gives at once (README "ROS
/// API rules"). Generated for every response with `bool accepted`, `uint64 command_id`,
/// `uint32 error_id` and `string message`.
pub trait CommandResponse: Default {
    /// Sets the four answer fields.
    fn answer(&mut self, accepted: bool, command_id: u64, error_id: u32, message: String);
}

/// A visitor of the types clients send to the nodes ([`visit_inbound`]).
pub trait InboundVisitor {
    /// Called once per type, with its ROS type name (`pkg/srv/X_Request`, `pkg/action/X_Goal`).
    fn visit<T: serde::de::DeserializeOwned + Serialize + Default + std::fmt::Debug>(
        &mut self,
        ros_type_name: &'static str,
    );
}

/// A service: request and response types and the ros2-client type name.
pub trait RosService {
    /// Request message.
    type Request: ros2_client::Message + RosType + Clone + Default;
    /// Response message.
    type Response: ros2_client::Message + RosType + Clone + Default;
    /// e.g. `motion_msgs/srv/MoveAbsolute`.
    const ROS_TYPE_NAME: &'static str;
    /// Service type name for ros2-client.
    fn service_type_name() -> ros2_client::ServiceTypeName;
}

/// An action: goal, result and feedback types and the ros2-client type name.
pub trait RosAction {
    /// Goal message.
    type Goal: ros2_client::Message + RosType + Clone + Default;
    /// Result message.
    type Result: ros2_client::Message + RosType + Clone + Default;
    /// Feedback message.
    type Feedback: ros2_client::Message + RosType + Clone + Default;
    /// e.g. `motion_msgs/action/MoveAbsolute`.
    const ROS_TYPE_NAME: &'static str;
    /// Action type name for ros2-client.
    fn action_type_name() -> ros2_client::ActionTypeName;
}

/// ROS `wstring`: on the wire a sequence of UTF-16 code units (as ros2-client's `WString`).
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct WString(pub String);

impl From<&str> for WString {
    fn from(s: &str) -> Self {
        WString(s.to_string())
    }
}

impl Serialize for WString {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let units: Vec<u16> = self.0.encode_utf16().collect();
        units.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for WString {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let units = Vec::<u16>::deserialize(deserializer)?;
        String::from_utf16(&units)
            .map(WString)
            .map_err(serde::de::Error::custom)
    }
}

/// Serde for fixed-size arrays of any length as CDR wants them: the elements without a length
/// (serde's own impls stop at 32 elements).
#[doc(hidden)]
pub mod fixed_array {
    use serde::de::{Error, SeqAccess, Visitor};
    use serde::ser::SerializeTuple;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use std::marker::PhantomData;

    /// Serializes `[T; N]` as a tuple of N elements.
    pub fn serialize<S: Serializer, T: Serialize, const N: usize>(
        a: &[T; N],
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        let mut t = serializer.serialize_tuple(N)?;
        for e in a {
            t.serialize_element(e)?;
        }
        t.end()
    }

    struct ArrayVisitor<T, const N: usize>(PhantomData<T>);

    impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for ArrayVisitor<T, N> {
        type Value = [T; N];

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "an array of {N} elements")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[T; N], A::Error> {
            let mut v = Vec::with_capacity(N);
            for i in 0..N {
                v.push(
                    seq.next_element()?
                        .ok_or_else(|| A::Error::invalid_length(i, &self))?,
                );
            }
            v.try_into()
                .map_err(|_| A::Error::custom("fixed array length"))
        }
    }

    /// Deserializes `[T; N]` from a tuple of N elements.
    pub fn deserialize<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        deserializer: D,
    ) -> Result<[T; N], D::Error> {
        deserializer.deserialize_tuple(N, ArrayVisitor::<T, N>(PhantomData))
    }
}

// builtin_interfaces/Time <-> ros2-client's time types (same arithmetic as rclcpp: the
// nanoseconds part is always in [0, 1e9), seconds are floored and saturate at i32).

impl deps::builtin_interfaces::msg::Time {
    /// From nanoseconds since the epoch.
    pub fn from_nanos(nanos: i64) -> Self {
        let sec = nanos.div_euclid(1_000_000_000);
        let nanosec = nanos.rem_euclid(1_000_000_000) as u32;
        match i32::try_from(sec) {
            Ok(sec) => Self { sec, nanosec },
            Err(_) if sec > 0 => Self {
                sec: i32::MAX,
                nanosec: 999_999_999,
            },
            Err(_) => Self {
                sec: i32::MIN,
                nanosec: 0,
            },
        }
    }

    /// Nanoseconds since the epoch.
    pub fn to_nanos(&self) -> i64 {
        i64::from(self.sec) * 1_000_000_000 + i64::from(self.nanosec)
    }
}

impl From<ros2_client::ROSTime> for deps::builtin_interfaces::msg::Time {
    fn from(t: ros2_client::ROSTime) -> Self {
        Self::from_nanos(t.to_nanos())
    }
}

impl From<deps::builtin_interfaces::msg::Time> for ros2_client::ROSTime {
    fn from(t: deps::builtin_interfaces::msg::Time) -> Self {
        ros2_client::ROSTime::from_nanos(t.to_nanos())
    }
}

impl From<ros2_client::builtin_interfaces::Time> for deps::builtin_interfaces::msg::Time {
    fn from(t: ros2_client::builtin_interfaces::Time) -> Self {
        Self::from_nanos(t.to_nanos())
    }
}

impl From<deps::builtin_interfaces::msg::Time> for ros2_client::builtin_interfaces::Time {
    fn from(t: deps::builtin_interfaces::msg::Time) -> Self {
        ros2_client::builtin_interfaces::Time::from_nanos(t.to_nanos())
    }
}

impl deps::builtin_interfaces::msg::Duration {
    /// From signed nanoseconds (negative durations have sec < 0 and nanosec in [0, 1e9)).
    pub fn from_nanos(nanos: i64) -> Self {
        let t = deps::builtin_interfaces::msg::Time::from_nanos(nanos);
        Self {
            sec: t.sec,
            nanosec: t.nanosec,
        }
    }

    /// Signed nanoseconds.
    pub fn to_nanos(&self) -> i64 {
        i64::from(self.sec) * 1_000_000_000 + i64::from(self.nanosec)
    }

    /// From seconds (rounded to the nearest nanosecond).
    pub fn from_secs_f64(secs: f64) -> Self {
        Self::from_nanos((secs * 1e9).round() as i64)
    }
}
