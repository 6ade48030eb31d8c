//! Benchmarks (not timed tests): figures are printed, with ratios against references measured
//! in the same run.
//!
//! `bench [--smoke] [runtime] [roundtrip] [axis] [ca] [planar] [tracks] [pickplace] [lockstep] [live] [node] [ruckig]` (default: all). `--smoke` runs short
//! versions (CI).
//! - runtime: cycle jitter p50/p99/max and overruns of the cyclic controller at 1 kHz with a
//!   trivial engine (60 s; smoke 2 s).
//! - roundtrip: service round trip through a node's command path (queue, cycle, reply) vs a
//!   bare ros2-client echo server of the same type, same process, same loopback DDS.
//!   Must run inside scripts/netns-run.
//! - axis: engine step cost per moving axis for 1, 100, 1000 axes (all moving), against the
//!   cost of evaluating their trajectories alone (the floor).
//! - ca: collision-avoidance group step cost for 10, 100, 1000 axes on a ring, against the
//!   plain single-axis step of as many axes.
//! - planar: engine step cost for 10, 100, 500 movers moving freely with the overlap guard,
//!   against evaluating their X/Y/C profiles alone; the snapshot built in an older one's
//!   buffers (as a lockstep stream takes it) against a fresh one.
//! - tracks: movers on a closed-loop track with gap control, 50, 200, 500 movers, against
//!   one profile evaluation per mover.
//! - pickplace: cell step mean and p99.9 (2 belts × 30 workpieces, blended ellipse) against the
//!   manual's module; cycles from an execute edge to the first moving set point.
//! - lockstep: the axis node with 10 moving axes in lockstep, every cycle published and
//!   recorded, as a ratio of simulated to wall time, against the bare engine, the node with
//!   nothing recorded, and the recording's floor (the same bytes written again by the MCAP
//!   writer alone, and to a plain file) (netns-run).
//! - live: cycle execution p99 of the axis node (10 moving axes, real time) serving the live
//!   feed, without a client and with a client reading every channel (netns-run).
//! - node: the axis node in real time at 1 kHz with 10, 100, 500 moving axes: cycle
//!   execution mean/p99/max, wake-up lateness p99 and overruns, against the bare engine's step
//!   and snapshot of as many axes (netns-run).
//! - ruckig: durations of random point-to-point moves from rest with random v/a/d/j divided by
//!   the time-optimal duration of the PyPI `ruckig` package; limits checked at 1 ms samples.

/// See [`motion_runtime::rt::Allocator`].
#[global_allocator]
static ALLOCATOR: motion_runtime::rt::Allocator = motion_runtime::rt::Allocator;

use motion_core::{CmdId, CommandEvent, Engine, Rejection, Tick};
use motion_msgs::srv::{Reset, ResetRequest, ResetResponse};
use motion_runtime::host::CommonConfig;
use motion_runtime::{ClockMode, CommandLabel, Controller, CycleConfig, NodeHost};
use ros2_client::ServiceMapping;
use std::time::{Duration, Instant};
use system_tests::ClientNode;

mod ca;
mod live;
mod lockstep;
mod node;
mod pickplace;
mod planar;
mod tracks;

/// A trivial engine: one integrator; a command is accepted at once.
struct Trivial {
    x: f64,
    next: u64,
}

impl Engine for Trivial {
    type Command = String;
    type Reply = CmdId;
    type Snapshot = f64;
    fn command(&mut self, _c: String) -> Result<CmdId, Rejection> {
        self.next += 1;
        Ok(CmdId(self.next))
    }
    fn step(&mut self, tick: Tick, _e: &mut Vec<CommandEvent>) {
        self.x += tick.dt;
    }
    fn snapshot(&self) -> f64 {
        self.x
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let smoke = args.iter().any(|a| a == "--smoke");
    let all = !args.iter().any(|a| {
        [
            "runtime",
            "roundtrip",
            "axis",
            "ca",
            "planar",
            "tracks",
            "pickplace",
            "ruckig",
            "flood",
            "lockstep",
            "live",
            "node",
        ]
        .contains(&a.as_str())
    });
    if all || args.iter().any(|a| a == "runtime") {
        let secs = if smoke { 2.0 } else { 60.0 };
        bare_sleep_reference(secs);
        runtime_jitter(secs, 0.0);
        runtime_jitter(secs, 100e-6);
    }
    if all || args.iter().any(|a| a == "roundtrip") {
        if std::env::var("MOTION_IN_NETNS").as_deref() != Ok("1") {
            eprintln!("roundtrip: run inside scripts/netns-run (it opens DDS sockets)");
            std::process::exit(2);
        }
        roundtrip(if smoke { 200 } else { 2000 });
    }
    if all || args.iter().any(|a| a == "flood") {
        if std::env::var("MOTION_IN_NETNS").as_deref() != Ok("1") {
            eprintln!("flood: run inside scripts/netns-run (it opens DDS sockets)");
            std::process::exit(2);
        }
        flood(
            if smoke { 500 } else { 5000 },
            if smoke { 200 } else { 2000 },
        );
    }
    if all || args.iter().any(|a| a == "axis") {
        axis_step_cost(
            if smoke { &[1, 100] } else { &[1, 100, 1000] },
            if smoke { 200 } else { 2000 },
        );
    }
    if all || args.iter().any(|a| a == "ca") {
        ca::step_cost(
            if smoke { &[10, 100] } else { &[10, 100, 1000] },
            if smoke { 200 } else { 2000 },
        );
    }
    if all || args.iter().any(|a| a == "planar") {
        planar::step_cost(
            if smoke { &[10, 100] } else { &[10, 100, 500] },
            if smoke { 200 } else { 2000 },
        );
        planar::snapshot_cost(
            if smoke { &[10, 100] } else { &[10, 100, 500] },
            if smoke { 200 } else { 5000 },
        );
    }
    if all || args.iter().any(|a| a == "tracks") {
        tracks::step_cost(
            if smoke { &[50] } else { &[50, 200, 500] },
            if smoke { 200 } else { 2000 },
        );
    }
    if all || args.iter().any(|a| a == "pickplace") {
        pickplace::step_cost(if smoke { 5_000 } else { 100_000 });
    }
    if all || args.iter().any(|a| a == "lockstep") {
        if std::env::var("MOTION_IN_NETNS").as_deref() != Ok("1") {
            eprintln!("lockstep: run inside scripts/netns-run (it opens DDS sockets)");
            std::process::exit(2);
        }
        lockstep::speed(if smoke { 2_000 } else { 100_000 });
    }
    if all || args.iter().any(|a| a == "live") {
        if std::env::var("MOTION_IN_NETNS").as_deref() != Ok("1") {
            eprintln!("live: run inside scripts/netns-run (it opens DDS sockets)");
            std::process::exit(2);
        }
        live::cycle_cost(if smoke { 1.0 } else { 10.0 });
    }
    if all || args.iter().any(|a| a == "node") {
        if std::env::var("MOTION_IN_NETNS").as_deref() != Ok("1") {
            eprintln!("node: run inside scripts/netns-run (it opens DDS sockets)");
            std::process::exit(2);
        }
        node::cycle_cost(
            if smoke { &[100] } else { &[10, 100, 500] },
            if smoke { 1.0 } else { 10.0 },
        );
    }
    if all || args.iter().any(|a| a == "ruckig") {
        ruckig_ratio(if smoke { 100 } else { 1000 });
    }
}

fn axis_config() -> axis_engine::AxisConfig {
    serde_json::from_str(
        r#"{"max_velocity":1000.0,"acceleration":5000.0,"deceleration":5000.0,"jerk":50000.0}"#,
    )
    .expect("axis config")
}

/// Engine step cost per moving axis: every axis runs a long move for the whole measurement.
fn axis_step_cost(counts: &[usize], steps: u64) {
    for &n in counts {
        let per = axis_step_seconds(n, steps);
        let floor = profile_floor(n, steps) / n as f64;
        println!(
            "axis engine step: {n:5} axes (all moving): {:7.1} ns per moving axis per step | profile evaluation alone {:5.1} ns (ratio {:.1}) | target <= 100 ns at 1000 axes",
            per * 1e9,
            floor * 1e9,
            per / floor
        );
    }
}

/// Seconds per axis and step of `n` powered axes, each running a long MoveAbsolute.
fn axis_step_seconds(n: usize, steps: u64) -> f64 {
    use axis_engine::{AxisCommand, AxisEngine, BufferMode, MoveAbsolute, MoveOptions, Power};
    let axes = (0..n).map(|i| (format!("a{i}"), axis_config())).collect();
    let mut e = AxisEngine::new(axes).expect("engine");
    let mut ev = Vec::with_capacity(4 * n);
    for i in 0..n {
        e.command(AxisCommand::Power(Power {
            axis: format!("a{i}"),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .expect("power");
    }
    let mut tick = 0;
    for _ in 0..5 {
        step(&mut e, &mut tick, &mut ev);
    }
    for i in 0..n {
        e.command(AxisCommand::MoveAbsolute(MoveAbsolute {
            axis: format!("a{i}"),
            position: 1.0e6 + i as f64,
            velocity: 1000.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }))
        .expect("move");
    }
    let t0 = Instant::now();
    for _ in 0..steps {
        step(&mut e, &mut tick, &mut ev);
    }
    let per = t0.elapsed().as_secs_f64() / (steps as f64 * n as f64);
    assert!(
        e.snapshot().axes.iter().all(|a| a.has_job),
        "all axes moved for the whole measurement"
    );
    per
}

/// One 1 ms cycle of an engine; its command events are dropped.
fn step<E: Engine>(e: &mut E, tick: &mut u64, ev: &mut Vec<CommandEvent>) {
    e.step(
        Tick {
            index: *tick,
            dt: 0.001,
        },
        ev,
    );
    ev.clear();
    *tick += 1;
}

/// Reference for the step benchmarks: seconds per evaluation of one planned jerk-limited
/// profile, `n` profiles per step (the floor of any set-point generator).
fn profile_floor(n: usize, steps: u64) -> f64 {
    let limits = motion_core::trajectory::Limits {
        velocity: 1000.0,
        acceleration: 5000.0,
        deceleration: 5000.0,
        jerk: 50000.0,
    };
    let profile = motion_core::trajectory::Profile1::to_position(
        motion_core::trajectory::State1::at_rest(0.0),
        1.0e6,
        0.0,
        &limits,
    )
    .expect("profile");
    let t0 = Instant::now();
    let mut acc = 0.0;
    for k in 0..steps {
        for i in 0..n {
            acc += profile.at((k as f64 + i as f64 * 1e-6) * 0.001).pos;
        }
    }
    std::hint::black_box(acc);
    t0.elapsed().as_secs_f64() / steps as f64
}

/// Our trajectory durations against the PyPI ruckig oracle, with a limit check.
fn ruckig_ratio(count: usize) {
    use motion_core::trajectory::{Limits, Profile1, State1};
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::SmallRng::seed_from_u64(
        std::env::var("BENCH_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(42),
    );
    let mut moves = Vec::with_capacity(count);
    let mut lines = String::new();
    for _ in 0..count {
        let p0: f64 = rng.gen_range(-500.0..500.0);
        let p1: f64 = rng.gen_range(-500.0..500.0);
        let l = Limits {
            velocity: rng.gen_range(10.0..2000.0),
            acceleration: rng.gen_range(50.0..20000.0),
            deceleration: rng.gen_range(50.0..20000.0),
            jerk: rng.gen_range(500.0..500000.0),
        };
        lines.push_str(&format!(
            "{{\"p0\":{p0:?},\"p1\":{p1:?},\"v\":{:?},\"a\":{:?},\"d\":{:?},\"j\":{:?}}}\n",
            l.velocity, l.acceleration, l.deceleration, l.jerk
        ));
        moves.push((p0, p1, l));
    }
    let python = std::env::var("MOTION_PYTHON").unwrap_or_else(|_| "python3".into());
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("peer/ruckig_oracle.py");
    let mut child = std::process::Command::new(&python)
        .arg(&script)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("python3 with the ruckig package (scripts/setup.sh installs it)");
    {
        use std::io::Write;
        child
            .stdin
            .take()
            .expect("stdin")
            .write_all(lines.as_bytes())
            .expect("write");
    }
    let out = child.wait_with_output().expect("oracle");
    let oracle: Vec<f64> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.trim().parse().unwrap_or(f64::NAN))
        .collect();
    assert_eq!(
        oracle.len(),
        count,
        "oracle answered {} of {count}",
        oracle.len()
    );
    let (mut max_ratio, mut sum, mut n, mut violations, mut failures) = (0.0f64, 0.0, 0, 0, 0);
    let tol = 1e-6;
    for ((p0, p1, l), t_ref) in moves.iter().zip(&oracle) {
        let p = match Profile1::to_position(State1::at_rest(*p0), *p1, 0.0, l) {
            Ok(p) => p,
            Err(_) => {
                failures += 1;
                continue;
            }
        };
        if !(t_ref.is_finite() && *t_ref > 0.0) {
            continue;
        }
        let r = p.duration() / t_ref;
        max_ratio = max_ratio.max(r);
        sum += r;
        n += 1;
        let mut t = 0.0;
        let mut prev = p.at(0.0);
        let mut bad = false;
        while t <= p.duration() {
            let s = p.at(t);
            let accelerating = s.acc * s.vel > 0.0;
            let a_lim = if accelerating {
                l.acceleration
            } else {
                l.deceleration.max(l.acceleration)
            };
            if s.vel.abs() > l.velocity * (1.0 + tol) || s.acc.abs() > a_lim * (1.0 + tol) {
                bad = true;
            }
            if t > 0.0 && ((s.acc - prev.acc) / 0.001).abs() > l.jerk * (1.0 + 1e-3) + 1e-9 {
                bad = true;
            }
            prev = s;
            t += 0.001;
        }
        let end = p.at(p.duration());
        if (end.pos - p1).abs() > 1e-9 {
            bad = true;
        }
        if bad {
            violations += 1;
        }
    }
    println!(
        "trajectory vs PyPI ruckig ({n} random moves from rest): duration ratio max {max_ratio:.6} mean {:.6} (target max <= 1.001) | limit violations {violations} | planning failures {failures}",
        sum / n.max(1) as f64
    );
}

/// The reference: a bare absolute-deadline `clock_nanosleep` loop on this machine, same length.
fn bare_sleep_reference(seconds: f64) {
    let period = Duration::from_millis(1);
    let n = (seconds * 1000.0) as usize;
    let mut late = Vec::with_capacity(n);
    motion_runtime::rt::prepare_cycle_thread();
    let mut deadline = Instant::now() + period;
    for _ in 0..n {
        motion_runtime::rt::sleep_until(deadline);
        late.push(
            Instant::now()
                .saturating_duration_since(deadline)
                .as_secs_f64(),
        );
        deadline += period;
    }
    let over = late.iter().filter(|l| **l > 1e-3).count();
    let max = late.iter().cloned().fold(0.0, f64::max);
    let (p50, p99) = (percentile(&mut late, 0.5), percentile(&mut late, 0.99));
    println!(
        "reference: bare clock_nanosleep loop @1 kHz, {seconds:.0} s: wake-up late p50 {:.1} us p99 {:.1} us max {:.1} us, later than one period: {over}",
        p50 * 1e6,
        p99 * 1e6,
        max * 1e6
    );
}

fn runtime_jitter(seconds: f64, spin: f64) {
    let cfg = CycleConfig {
        name: "bench".into(),
        period: 0.001,
        mode: ClockMode::RealTime,
        queue_capacity: 64,
        snapshot_every: 10,
        spin,
        stream_every: 0,
    };
    let (ctl, _events) =
        Controller::spawn(Trivial { x: 0.0, next: 0 }, cfg, |r| Some(*r)).expect("controller");
    std::thread::sleep(Duration::from_secs_f64(seconds));
    let h = ctl.handle();
    drop(ctl);
    let s = h.stats();
    let us = |v: f64| v * 1e6;
    println!(
        "runtime @1 kHz, {seconds:.0} s, trivial engine, spin {:.0} us: cycles {} overruns {} | jitter p50 {:.1} us p99 {:.1} us max {:.1} us | exec mean {:.2} us p99 {:.1} us max {:.1} us",
        us(spin),
        s.cycles,
        s.overruns,
        us(s.jitter_p50),
        us(s.jitter_p99),
        us(s.jitter_max),
        us(s.exec_mean),
        us(s.exec_p99),
        us(s.exec_max)
    );
    println!(
        "runtime targets: jitter p99 <= 50 us: {}; overruns = 0: {}",
        if s.jitter_p99 <= 50e-6 {
            "met"
        } else {
            "NOT met"
        },
        if s.overruns == 0 { "met" } else { "NOT met" }
    );
}

fn percentile(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1]
}

fn roundtrip(n: usize) {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("rt");
    rt.block_on(async move {
        let domain = 150;
        let mapping = ServiceMapping::Enhanced;
        // Our node: a trivial engine behind the full command path, 1 ms cycle.
        let common = CommonConfig { name: "bench_node".into(), service_mapping: "enhanced".into(), ..Default::default() };
        let node = NodeHost::start("system_tests", &common, domain, Trivial { x: 0.0, next: 0 }, vec![], |shell| {
            shell.command_service(
                "reset",
                Reset::service_type_name(),
                |r: ResetRequest| Ok((r.axis.clone(), CommandLabel { object: r.axis, command: "reset".into() })),
                |o: Result<CmdId, Rejection>| match o {
                    Ok(id) => ResetResponse { accepted: true, command_id: id.0, ..Default::default() },
                    Err(e) => ResetResponse { accepted: false, error_id: e.error_id.0, message: e.message, ..Default::default() },
                },
            )
        })
        .expect("node");
        // The reference: a bare ros2-client server of the same type in its own Context.
        let mut bare = ClientNode::new(domain, "bare_echo", mapping);
        let server = bare
            .node
            .create_server::<ResetRequest, ResetResponse>(
                mapping,
                &ClientNode::name("/bare_echo/reset"),
                &Reset::service_type_name(),
                motion_runtime::shell::service_qos(),
                motion_runtime::shell::service_qos(),
            )
            .expect("server");
        let echo = tokio::spawn(async move {
            loop {
                if let Ok((id, _req)) = server.async_receive_request().await {
                    let _ = server.async_send_response(id, ResetResponse { accepted: true, ..Default::default() }).await;
                }
            }
        });
        let mut c = ClientNode::new(domain, "bench_client", mapping);
        let node_client = c
            .client::<ResetRequest, ResetResponse>("/bench_node/reset", Reset::service_type_name())
            .await;
        let bare_client = c
            .client::<ResetRequest, ResetResponse>("/bare_echo/reset", Reset::service_type_name())
            .await;
        let mut t_node = Vec::with_capacity(n);
        let mut t_bare = Vec::with_capacity(n);
        // Interleaved, so both see the same machine load.
        for i in 0..n + 20 {
            let req = ResetRequest { axis: "a".into() };
            let t0 = Instant::now();
            let r = node_client.async_call_service(req.clone()).await.expect("node call");
            let dn = t0.elapsed().as_secs_f64();
            assert!(r.accepted);
            let t0 = Instant::now();
            bare_client.async_call_service(req).await.expect("bare call");
            let db = t0.elapsed().as_secs_f64();
            if i >= 20 {
                t_node.push(dn);
                t_bare.push(db);
            }
        }
        let period = common.cycle_period;
        let (n50, n99) = (percentile(&mut t_node, 0.5), percentile(&mut t_node, 0.99));
        let (b50, b99) = (percentile(&mut t_bare, 0.5), percentile(&mut t_bare, 0.99));
        let ms = |v: f64| v * 1e3;
        println!(
            "roundtrip ({n} calls, loopback): node p50 {:.3} ms p99 {:.3} ms | bare echo p50 {:.3} ms p99 {:.3} ms | ratio p50 {:.2} | node - 1.2 x bare at p50 = {:.3} ms (target <= one cycle = {:.3} ms): {}",
            ms(n50),
            ms(n99),
            ms(b50),
            ms(b99),
            n50 / b50,
            ms(n50 - 1.2 * b50),
            ms(period),
            if n50 <= 1.2 * b50 + period { "met" } else { "NOT met" }
        );
        echo.abort();
        drop(c);
        drop(bare);
        node.stop().await;
    });
}

/// `bench flood` (issue 12 §3): 4 clients x `calls` pipelined calls (64 in flight each) to a
/// read service and to a motion service of an axis node, and `goals` action goals sent at once
/// by one client. Prints what was sent, answered and lost, and the latencies (quantised to
/// about 1 ms by the clients' polling). Lost must be 0.
fn flood(calls: usize, goals: usize) {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("rt");
    rt.block_on(async {
        let (read, motion) = system_tests::flood::service_flood(calls, 64).await;
        println!("flood: 4 clients x {calls} calls, 64 in flight each");
        println!("  read_status    {}", read.summary());
        println!("  move_absolute  {}", motion.summary());
        let (sent, results) = system_tests::flood::goal_burst(goals).await;
        println!("flood: {goals} action goals at once (move_absolute)");
        println!("  goals          {}", sent.summary());
        println!("  results        {}", results.summary());
        let lost = read.lost() + motion.lost() + sent.lost() + results.lost();
        println!(
            "  lost requests: {lost}, goals without result: {}",
            results.lost()
        );
    });
}
