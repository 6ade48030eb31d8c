//! Fail-safe (issue 12 §1, README "Operating it"): a panic on the ROS side of a running
//! `motion_launch` mid-motion brings the axis to a controlled stop within its braking
//! distance (MC_Stop with AxisFastDec/AxisFastJerk), then the process exits with code 70 and
//! one FATAL log line. Driven over DDS as a user would; the panic comes from the test-only
//! fault hook `~/sim/fault` (`MOTION_FAULT_HOOKS=1`).

use motion_msgs::msg::AxisStateArray;
use motion_msgs::srv::{
    MoveVelocity, MoveVelocityRequest, MoveVelocityResponse, SimFault, SimFaultRequest,
    SimFaultResponse,
};
use ros2_client::ServiceMapping;
use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use system_tests::{launcher_bin, require_netns, unique_domain, within, ClientNode};

const V: f64 = 1000.0; // cruise [mm/s]
const FAST_DEC: f64 = 10_000.0; // AxisFastDec [mm/s²]
const FAST_JERK: f64 = 1_000_000.0; // AxisFastJerk [mm/s³]

const CONFIG: &str = r#"
nodes:
  - kind: axis_node
    service_mapping: cyclone
    axes:
      x:
        max_velocity: 2000.0
        acceleration: 5000.0
        deceleration: 5000.0
        jerk: 100000.0
        fast_deceleration: 10000.0
        fast_jerk: 1000000.0
"#;

/// Kills the child if the test fails before it exited.
struct Child(std::process::Child);

impl Drop for Child {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_panic_on_the_ros_side_stops_the_axis_and_ends_the_process() {
    require_netns();
    let domain = unique_domain() + 100;
    let dir = std::env::temp_dir().join(format!("failsafe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("failsafe.yaml");
    std::fs::write(&config, CONFIG).unwrap();
    let mut child = Child(
        Command::new(launcher_bin())
            .arg(&config)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("MOTION_FAULT_HOOKS", "1")
            .env("RUST_LOG", "error")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("motion_launch"),
    );

    let mut c = ClientNode::new(domain, "failsafe_client", ServiceMapping::Cyclone);
    let states =
        c.subscribe::<AxisStateArray>("/axis_node/axis_states", AxisStateArray::type_name());
    c.power_on("x").await;
    let mv = c
        .client::<MoveVelocityRequest, MoveVelocityResponse>(
            "/axis_node/move_velocity",
            MoveVelocity::service_type_name(),
        )
        .await;
    let fault = c
        .client::<SimFaultRequest, SimFaultResponse>(
            "/axis_node/sim/fault",
            SimFault::service_type_name(),
        )
        .await;
    let r = within(
        10.0,
        "move_velocity",
        mv.async_call_service(MoveVelocityRequest {
            axis: "x".into(),
            velocity: V,
            direction: 1,
            ..Default::default()
        }),
    )
    .await
    .unwrap();
    assert!(r.accepted, "{}", r.message);

    // At cruise velocity: the last sample before the fault.
    let (p0, v0) = within(10.0, "cruise", async {
        loop {
            let (s, _) = states.async_take().await.unwrap();
            let a = &s.axes[0];
            if (a.set_velo - V).abs() < 1e-6 {
                break (a.set_pos, a.set_velo);
            }
        }
    })
    .await;
    let t_fault = Instant::now();
    fault
        .async_send_request(SimFaultRequest {
            thread: "shell".into(),
        })
        .await
        .unwrap();

    // The axis brakes to standstill; samples keep coming while the process stops.
    let stopped = tokio::time::timeout(Duration::from_secs(10), async {
        let mut last_v = v0;
        loop {
            let (s, _) = states.async_take().await.unwrap();
            let a = &s.axes[0];
            assert!(a.set_velo <= last_v + 1e-9, "velocity rose while stopping");
            last_v = a.set_velo;
            if a.set_velo == 0.0 {
                break (a.set_pos, t_fault.elapsed());
            }
        }
    })
    .await;
    let Ok((pf, braking)) = stopped else {
        let _ = child.0.kill();
        let mut err = String::new();
        let _ = child.0.stderr.take().unwrap().read_to_string(&mut err);
        panic!("no standstill within 10 s of the fault; stderr:\n{err}");
    };
    // Braking distance with jerk-limited deceleration from v0, plus the way travelled
    // between the last cruise sample and the panic (state period 10 ms + the call).
    let brake = v0 * v0 / (2.0 * FAST_DEC) + v0 * FAST_DEC / (2.0 * FAST_JERK);
    let travelled = pf - p0;
    assert!(
        travelled <= brake + v0 * 0.1,
        "stopped {travelled:.1} mm after the last cruise sample (braking distance {brake:.1} mm)"
    );
    assert!(
        travelled >= brake * 0.9,
        "{travelled:.1} < {brake:.1}: no braking ramp?"
    );
    assert!(braking < Duration::from_secs(2), "stop took {braking:?}");

    // The process ends by itself with the fail-safe exit code and one FATAL line.
    let status = within(15.0, "process exit", async {
        loop {
            if let Some(s) = child.0.try_wait().unwrap() {
                break s;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    })
    .await;
    let mut err = String::new();
    child
        .0
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert_eq!(status.code(), Some(70), "stderr:\n{err}");
    let fatal: Vec<&str> = err.lines().filter(|l| l.contains("FATAL")).collect();
    assert_eq!(fatal.len(), 1, "stderr:\n{err}");
    assert!(
        fatal[0].contains("test fault hook") && fatal[0].contains("stopped at rest: [axis_node]"),
        "{}",
        fatal[0]
    );
    let _ = std::fs::remove_dir_all(&dir);
}
