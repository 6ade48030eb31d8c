//! The generated types: IDL defaults, constants, names, and CDR bytes as rmw puts them on the
//! wire (checked against hand-computed bytes and against ros2-client's own definitions).

use motion_msgs::deps::builtin_interfaces::msg::{Duration, Time};
use motion_msgs::deps::std_msgs::msg::Header;
use motion_msgs::{action, deps, msg, srv, RosAction, RosService, RosType};
use ros2_client::dds::rustdds::serialization::{
    deserialize_from_cdr_with_rep_id, to_writer_with_rep_id,
};
use ros2_client::dds::rustdds::RepresentationIdentifier;

/// Test-only interfaces from `tests/interfaces/` (package `idl_test_msgs`); not all used.
#[allow(dead_code)]
mod idl_test {
    include!(concat!(env!("OUT_DIR"), "/test_interfaces.rs"));
}
use idl_test::idl_test_msgs::{action as t_action, msg as t_msg, srv as t_srv};

fn cdr<T: serde::Serialize>(v: &T) -> Vec<u8> {
    let mut buf = Vec::new();
    to_writer_with_rep_id(&mut buf, v, RepresentationIdentifier::CDR_LE).expect("serialize");
    buf
}

fn from_cdr<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> T {
    let (v, n) = deserialize_from_cdr_with_rep_id::<T>(bytes, RepresentationIdentifier::CDR_LE)
        .expect("deserialize");
    assert_eq!(n, bytes.len(), "all bytes consumed");
    v
}

#[test]
fn time_is_two_little_endian_words() {
    let t = Time { sec: 1, nanosec: 2 };
    assert_eq!(cdr(&t), [1, 0, 0, 0, 2, 0, 0, 0]);
    // Same bytes as ros2-client's own builtin_interfaces::Time.
    assert_eq!(
        cdr(&ros2_client::builtin_interfaces::Time::new(1, 2)),
        cdr(&t)
    );
    assert_eq!(from_cdr::<Time>(&cdr(&t)), t);
}

#[test]
fn joint_state_bytes_match_hand_computed_cdr() {
    let js = deps::sensor_msgs::msg::JointState {
        header: Header {
            stamp: Time { sec: 1, nanosec: 2 },
            frame_id: "ab".into(),
        },
        name: vec!["j1".into()],
        position: vec![1.5],
        velocity: vec![],
        effort: vec![],
    };
    #[rustfmt::skip]
    let expected: Vec<u8> = vec![
        1, 0, 0, 0, 2, 0, 0, 0,             // stamp
        3, 0, 0, 0, b'a', b'b', 0,          // frame_id: length incl. NUL, bytes, NUL
        0,                                  // pad to 4
        1, 0, 0, 0,                         // name: 1 element
        3, 0, 0, 0, b'j', b'1', 0,          // "j1"
        0,                                  // pad to 4
        1, 0, 0, 0,                         // position: 1 element (at 28, f64 at 32)
        0, 0, 0, 0, 0, 0, 0xf8, 0x3f,       // 1.5
        0, 0, 0, 0,                         // velocity: empty
        0, 0, 0, 0,                         // effort: empty
    ];
    assert_eq!(cdr(&js), expected);
    assert_eq!(
        from_cdr::<deps::sensor_msgs::msg::JointState>(&expected),
        js
    );
}

#[test]
fn goal_status_array_matches_ros2_client_action_msgs() {
    // ros2-client implements action_msgs itself; our vendored definitions must agree.
    let uuid = [7u8; 16];
    let ours = deps::action_msgs::msg::GoalStatusArray {
        status_list: vec![deps::action_msgs::msg::GoalStatus {
            goal_info: deps::action_msgs::msg::GoalInfo {
                goal_id: deps::unique_identifier_msgs::msg::UUID { uuid },
                stamp: Time { sec: 5, nanosec: 6 },
            },
            status: deps::action_msgs::msg::GoalStatus::STATUS_SUCCEEDED,
        }],
    };
    // Decode our bytes with ros2-client's types (they need the uuid crate to construct)...
    let theirs: ros2_client::action_msgs::GoalStatusArray = from_cdr(&cdr(&ours));
    let st = &theirs.status_list[0];
    assert_eq!(
        st.status,
        ros2_client::action_msgs::GoalStatusEnum::Succeeded
    );
    assert_eq!(st.goal_info.goal_id.uuid.as_bytes(), &uuid);
    assert_eq!(
        st.goal_info.stamp,
        ros2_client::builtin_interfaces::Time::new(5, 6)
    );
    // ... and their encoding of the same value is ours.
    assert_eq!(cdr(&ours), cdr(&theirs));
}

#[test]
fn axis_state_round_trips_and_has_its_constants() {
    let s = msg::AxisState {
        name: "x".into(),
        motion_state: msg::AxisState::MC_AXISSTATE_STANDSTILL,
        r#override: 100.0,
        power_status: true,
        ..Default::default()
    };
    assert_eq!(msg::AxisState::MC_AXISSTATE_SYNCHRONIZEDMOTION, 8);
    assert_eq!(from_cdr::<msg::AxisState>(&cdr(&s)), s);
    let arr = msg::AxisStateArray {
        header: Header::default(),
        axes: vec![s.clone(), s],
    };
    assert_eq!(from_cdr::<msg::AxisStateArray>(&cdr(&arr)), arr);
}

#[test]
fn service_and_action_defaults_follow_the_files() {
    let req = srv::MoveAbsoluteRequest::default();
    assert_eq!(req.acceleration, 0.0);
    assert_eq!(req.buffer_mode, srv::MoveAbsoluteRequest::MC_ABORTING);
    assert!(!req.enable_blending_position);
    let p = srv::PowerRequest::default();
    assert!(p.enable_positive && p.enable_negative);
    assert_eq!(p.r#override, 100.0);
    assert!(srv::StopRequest::default().execute);
    assert_eq!(action::MoveVelocityGoal::default().direction, 1);
    // Quaternion defaults to the identity (w = 1 in geometry_msgs).
    assert_eq!(deps::geometry_msgs::msg::Quaternion::default().w, 1.0);
}

#[test]
fn type_names_match_ros_and_ros2_client() {
    assert_eq!(msg::AxisState::ROS_TYPE_NAME, "motion_msgs/msg/AxisState");
    assert_eq!(
        msg::AxisState::type_name().dds_msg_type(),
        "motion_msgs::msg::dds_::AxisState_"
    );
    assert_eq!(
        <msg::AxisState as RosType>::DDS_TYPE_NAME,
        msg::AxisState::type_name().dds_msg_type()
    );
    let n = deps::visualization_msgs::msg::MarkerArray::type_name();
    assert_eq!(n.package_name(), "visualization_msgs");
    assert_eq!(
        n.dds_msg_type(),
        "visualization_msgs::msg::dds_::MarkerArray_"
    );
    assert_eq!(
        deps::tf2_msgs::msg::TFMessage::DDS_TYPE_NAME,
        "tf2_msgs::msg::dds_::TFMessage_"
    );

    let s = srv::MoveAbsolute::service_type_name();
    assert_eq!(
        (s.package_name(), s.type_name()),
        ("motion_msgs", "MoveAbsolute")
    );
    assert_eq!(
        <srv::MoveAbsolute as RosService>::Request::DDS_TYPE_NAME,
        "motion_msgs::srv::dds_::MoveAbsolute_Request_"
    );
    assert_eq!(
        srv::MoveAbsoluteResponse::DDS_TYPE_NAME,
        "motion_msgs::srv::dds_::MoveAbsolute_Response_"
    );
    assert_eq!(
        srv::MoveAbsolute::ROS_TYPE_NAME,
        "motion_msgs/srv/MoveAbsolute"
    );

    let a = action::MoveAbsolute::action_type_name();
    assert_eq!(
        (a.package_name(), a.type_name()),
        ("motion_msgs", "MoveAbsolute")
    );
    assert_eq!(
        <action::MoveAbsolute as RosAction>::Goal::DDS_TYPE_NAME,
        "motion_msgs::action::dds_::MoveAbsolute_Goal_"
    );
    assert_eq!(
        action::MoveAbsoluteFeedback::ROS_TYPE_NAME,
        "motion_msgs/action/MoveAbsolute_Feedback"
    );
}

#[test]
fn time_conversions_floor_like_rclcpp() {
    let t = Time::from_nanos(-1);
    assert_eq!((t.sec, t.nanosec), (-1, 999_999_999));
    assert_eq!(t.to_nanos(), -1);
    let rt = ros2_client::ROSTime::from_nanos(1_500_000_000);
    let t: Time = rt.into();
    assert_eq!((t.sec, t.nanosec), (1, 500_000_000));
    assert_eq!(ros2_client::ROSTime::from(t).to_nanos(), 1_500_000_000);
    let d = Duration::from_secs_f64(-0.25);
    assert_eq!((d.sec, d.nanosec), (-1, 750_000_000));
    assert_eq!(Time::from_nanos(i64::MAX).sec, i32::MAX);
}

#[test]
fn test_interfaces_defaults_and_constants() {
    let e = t_msg::Edge::default();
    assert!(e.b);
    assert_eq!((e.by, e.c, e.i8, e.u8), (0x7f, 66, -5, 255));
    assert_eq!(
        (e.i16, e.u16, e.i32, e.u32),
        (-300, 600, -70000, 4_000_000_000)
    );
    assert_eq!((e.i64, e.u64), (-5_000_000_000, 10_000_000_000_000_000_000));
    assert_eq!(e.f32, 0.1_f32);
    assert_eq!(e.f64, -2.5e-7);
    assert!(e.zero_neg == 0.0 && e.zero_neg.is_sign_negative());
    assert_eq!(e.big, 1e300);
    assert_eq!(e.pos_inf, f64::INFINITY);
    assert_eq!(e.s, "quoted \"string\" with, comma");
    assert_eq!(e.plain, "unquoted text");
    assert_eq!(e.bounded_s, "abc");
    assert_eq!(e.ws, motion_msgs::WString::from("wide text"));
    assert_eq!(e.r#type, 3);
    assert_eq!(e.r#override, 100.0);
    assert!(!e.self_);
    assert_eq!(e.xyz, [1, -2, 3]);
    assert_eq!(e.covariance, [0.0; 36]);
    assert_eq!(e.small, vec![1, 2]);
    assert_eq!(e.floats, vec![1.5, -0.25]);
    assert_eq!(e.names, vec!["a, b", "c", "d"]);
    assert_eq!(e.short_names, vec!["ab", "cd"]);
    assert_eq!(e.flags, [true, false]);
    assert_eq!(e.inner.id, 7);
    assert_eq!(e.inner_pair[1].label, "inner");
    assert!(e.inner_bounded.is_empty() && e.inner_list.is_empty());
    assert_eq!(e.t0, Time::default());
    assert_eq!(e.d0, Duration::default());

    assert_eq!(u8::from(t_msg::Edge::FLAG), 1);
    assert_eq!(t_msg::Edge::BYTE_MAX, 255);
    assert_eq!(t_msg::Edge::LETTER_A, b'A');
    assert_eq!(t_msg::Edge::I8_MIN, i8::MIN);
    assert_eq!(t_msg::Edge::U16_HEX, 0x1f);
    assert_eq!(t_msg::Edge::I64_MIN, i64::MIN);
    assert_eq!(t_msg::Edge::U64_MAX, u64::MAX);
    assert_eq!(t_msg::Edge::F32_HALF, 0.5);
    assert_eq!(t_msg::Edge::TINY, 1e-5);
    assert_eq!(t_msg::Edge::HUGE, 1e16);
    assert_eq!(t_msg::Edge::GREETING, "hello, world");
    assert_eq!(t_msg::Edge::SINGLE, "it's");
    assert_eq!(t_msg::Edge::WIDE, "wide");

    assert_eq!(t_srv::PingResponse::default().count, 1);
    assert_eq!(t_action::CountGoal::default().target, 10);
    assert_eq!(
        t_action::Count::action_type_name().package_name(),
        "idl_test_msgs"
    );
}

#[test]
fn test_interfaces_round_trip_through_cdr() {
    let mut e = t_msg::Edge::default();
    e.covariance[35] = 3.25;
    e.uuid[0] = 9;
    e.ws = "wide ü".into();
    e.inner_list.push(t_msg::Inner {
        id: 1,
        label: "l".into(),
        xy: [1.0, 2.0],
    });
    let bytes = cdr(&e);
    assert_eq!(from_cdr::<t_msg::Edge>(&bytes), e);
    // The fixed arrays carry no length: Inner = i32, string, 2 x f64 without a u32 in between.
    let inner = t_msg::Inner {
        id: 1,
        label: String::new(),
        xy: [0.5, 0.25],
    };
    #[rustfmt::skip]
    let expected: Vec<u8> = vec![
        1, 0, 0, 0,                          // id
        1, 0, 0, 0, 0,                       // "" = length 1 + NUL
        0, 0, 0, 0, 0, 0, 0,                 // pad to 8
        0, 0, 0, 0, 0, 0, 0xe0, 0x3f,        // 0.5
        0, 0, 0, 0, 0, 0, 0xd0, 0x3f,        // 0.25
    ];
    assert_eq!(cdr(&inner), expected);
}
