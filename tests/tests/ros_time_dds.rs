//! The node's ROS time over real DDS (issue 13): header stamps are the system clock while the
//! node runs in real time (RViz and TF compare them with their own clock), and with
//! `use_sim_time: true` the node follows an external `/clock` (rosgraph_msgs/Clock): its
//! cycles run as that clock passes them, and its stamps are that clock's time.

use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::deps::rosgraph_msgs::msg::Clock;
use motion_msgs::msg::AxisStateArray;
use motion_runtime::clock::system_ns;
use ros2_client::ServiceMapping;
use std::time::Duration;
use system_tests::{common, require_netns, unique_domain, within, ClientNode};

const CONFIG: &str = "axes:\n  x:\n    max_velocity: 1000.0\n    acceleration: 10000.0\n    deceleration: 10000.0\n    jerk: 100000.0\n";

fn ns(t: &Time) -> i64 {
    i64::from(t.sec) * 1_000_000_000 + i64::from(t.nanosec)
}

/// Free-running: every `~/axis_states` stamp is within 50 ms of the client's system clock.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn free_running_stamps_are_the_system_clock() {
    require_netns();
    let domain = unique_domain();
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    let c = common("axis_node", false, ServiceMapping::Cyclone);
    let _node = axis_node::start(&c, cfg, "test", domain).expect("axis node");
    let mut client = ClientNode::new(domain, "stamp_client", ServiceMapping::Cyclone);
    let states =
        client.subscribe::<AxisStateArray>("/axis_node/axis_states", AxisStateArray::type_name());
    // Every stamp is the system clock (not a time counted from the node's start); the median
    // age is within 50 ms (state rate 100 Hz plus delivery, on a loaded 2-core machine).
    let mut ages = Vec::new();
    for k in 0..20 {
        let (mut s, _) = within(20.0, "axis_states", states.async_take())
            .await
            .unwrap();
        // The newest sample: older ones may wait in the reader's history.
        while let Ok(Some((newer, _))) = states.take() {
            s = newer;
        }
        let age = system_ns() - ns(&s.header.stamp);
        assert!(
            (-5_000_000..1_000_000_000).contains(&age),
            "sample {k}: stamp is {} ms from the system clock",
            age as f64 * 1e-6
        );
        assert_eq!(ns(&s.axes[0].header.stamp), ns(&s.header.stamp));
        ages.push(age);
    }
    ages.sort_unstable();
    assert!(
        ages[10] < 50_000_000,
        "median stamp age {} ms",
        ages[10] as f64 * 1e-6
    );
}

/// `use_sim_time`: the first `/clock` (1000 s) becomes the time of the current cycle, and a
/// later `/clock` runs exactly the cycles it passed (250 of 1 ms); stamps are that clock's.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn use_sim_time_follows_an_external_clock() {
    require_netns();
    let domain = unique_domain();
    let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
    let mut c = common("axis_node", false, ServiceMapping::Cyclone);
    c.use_sim_time = true;
    let node = axis_node::start(&c, cfg, "test", domain).expect("axis node");
    let mut client = ClientNode::new(domain, "clock_client", ServiceMapping::Cyclone);
    let states =
        client.subscribe::<AxisStateArray>("/axis_node/axis_states", AxisStateArray::type_name());
    let topic = client
        .node
        .create_topic(
            &ClientNode::name("/clock"),
            Clock::type_name(),
            &motion_runtime::shell::topic_qos(),
        )
        .unwrap();
    let clock = client.node.create_publisher::<Clock>(&topic, None).unwrap();
    let at = |ns: i64| Clock {
        clock: Time {
            sec: (ns / 1_000_000_000) as i32,
            nanosec: (ns % 1_000_000_000) as u32,
        },
    };
    // Nothing runs before a clock: the node waits for its time source.
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert_eq!(node.handle().snapshot().cycle, 0);
    let t0 = 1_000_000_000_000;
    // Repeat the first tick until it is seen (discovery); the origin is set once.
    within(20.0, "the node takes the first /clock", async {
        loop {
            clock.async_publish(at(t0)).await.unwrap();
            tokio::time::sleep(Duration::from_millis(50)).await;
            if node.handle().snapshot().ros_time_ns == t0 {
                break;
            }
        }
    })
    .await;
    assert_eq!(node.handle().snapshot().cycle, 0);
    clock.async_publish(at(t0 + 250_000_000)).await.unwrap();
    within(10.0, "250 cycles run", async {
        while node.handle().snapshot().cycle < 250 {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    })
    .await;
    tokio::time::sleep(Duration::from_millis(100)).await;
    let s = node.handle().snapshot();
    assert_eq!((s.cycle, s.ros_time_ns), (250, t0 + 250_000_000));
    // The state topic carries the external clock's time.
    within(10.0, "a sample stamped 1000.25 s", async {
        loop {
            let (m, _) = states.async_take().await.unwrap();
            if ns(&m.header.stamp) == t0 + 250_000_000 {
                break;
            }
            assert!(
                ns(&m.header.stamp) >= t0,
                "stamp {:?} before the clock",
                m.header.stamp
            );
        }
    })
    .await;
}

/// Lockstep (issue 15.9): `~/step{cycles: n}` publishes the state of every cycle it ran on
/// the state topics (`state_publish_every_n_cycles`, lockstep default 1), none left out and
/// in order, so a client needing every cycle steps many at once; a node with n = 10 publishes
/// every tenth cycle.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn lockstep_publishes_every_cycle_of_a_step() {
    use motion_msgs::srv::{StepCycles, StepCyclesRequest, StepCyclesResponse};
    require_netns();
    for every in [None, Some(10u32)] {
        let domain = unique_domain();
        let cfg: serde_yaml::Value = serde_yaml::from_str(CONFIG).unwrap();
        let mut c = common("axis_node", true, ServiceMapping::Cyclone);
        c.state_publish_every_n_cycles = every;
        let n = u64::from(every.unwrap_or(1));
        let node = axis_node::start(&c, cfg, "test", domain).expect("axis node");
        let mut client = ClientNode::new(domain, "stream_client", ServiceMapping::Cyclone);
        // A client that needs every cycle reads with keep-all (the state topics' own writer
        // keeps every sample until it is acknowledged).
        let keep_all =
            motion_runtime::shell::topic_qos().history(ros2_client::qos::History::KeepAll);
        let topic = client
            .node
            .create_topic(
                &ClientNode::name("/axis_node/axis_states"),
                AxisStateArray::type_name(),
                &keep_all,
            )
            .unwrap();
        let states = client
            .node
            .create_subscription::<AxisStateArray>(&topic, Some(keep_all))
            .unwrap();
        let step = client
            .client::<StepCyclesRequest, StepCyclesResponse>(
                "/axis_node/step",
                StepCycles::service_type_name(),
            )
            .await;
        let cycle_of = |s: &AxisStateArray| ns(&s.header.stamp) / 1_000_000;
        // Step until the subscription is matched and a state arrives.
        let mut last = within(20.0, "first state", async {
            loop {
                let r = step
                    .async_send_request(StepCyclesRequest { cycles: n as u32 })
                    .await;
                assert!(r.is_ok());
                tokio::time::sleep(Duration::from_millis(50)).await;
                let mut got = None;
                while let Ok(Some((s, _))) = states.take() {
                    got = Some(cycle_of(&s));
                }
                if let Some(c) = got {
                    return c;
                }
            }
        })
        .await;
        // Drain what the matching steps still send, then one step of 200 × n cycles.
        tokio::time::sleep(Duration::from_millis(200)).await;
        while let Ok(Some((s, _))) = states.take() {
            last = cycle_of(&s);
        }
        let req = step
            .async_send_request(StepCyclesRequest {
                cycles: 200 * n as u32,
            })
            .await
            .expect("step request");
        let r = within(20.0, "step reply", step.async_receive_response(req))
            .await
            .expect("step reply");
        assert!(r.accepted, "{}", r.message);
        let end = r.cycle_index as i64;
        let mut seen = Vec::new();
        within(20.0, "every streamed cycle of the step", async {
            while seen.last().copied() != Some(end) {
                let (s, _) = states.async_take().await.expect("state");
                seen.push(cycle_of(&s));
            }
        })
        .await;
        let expected: Vec<i64> = (1..=200).map(|k| last + k * n as i64).collect();
        assert_eq!(seen, expected, "every {n}th cycle, none left out");
        drop(client);
        node.stop().await;
    }
}
