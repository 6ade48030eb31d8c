//! Benchmarks (not timed tests): figures are printed, with ratios against references measured
//! in the same run.
//!
//! `bench [--smoke] [runtime] [roundtrip]` (default: all). `--smoke` runs short versions (CI).
//! - runtime: cycle jitter p50/p99/max and overruns of the cyclic controller at 1 kHz with a
//!   trivial engine (60 s; smoke 2 s).
//! - roundtrip: service round trip through a node's command path (queue, cycle, reply) vs a
//!   bare ros2-client echo server of the same type, same process, same loopback DDS.
//!   Must run inside scripts/netns-run.

use motion_core::{CmdId, CommandEvent, Engine, Rejection, Tick};
use motion_msgs::srv::{Reset, ResetRequest, ResetResponse};
use motion_runtime::host::CommonConfig;
use motion_runtime::{ClockMode, CommandLabel, Controller, CycleConfig, NodeHost};
use ros2_client::ServiceMapping;
use std::time::{Duration, Instant};
use system_tests::ClientNode;

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
    let all = !args.iter().any(|a| a == "runtime" || a == "roundtrip");
    if all || args.iter().any(|a| a == "runtime") {
        let secs = if smoke { 2.0 } else { 60.0 };
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
}

fn runtime_jitter(seconds: f64, spin: f64) {
    let cfg = CycleConfig {
        name: "bench".into(),
        period: 0.001,
        mode: ClockMode::RealTime,
        queue_capacity: 64,
        snapshot_every: 10,
        spin,
    };
    let (ctl, _events) = Controller::spawn(Trivial { x: 0.0, next: 0 }, cfg, |r| Some(*r)).expect("controller");
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
        if s.jitter_p99 <= 50e-6 { "met" } else { "NOT met" },
        if s.overruns == 0 { "met" } else { "NOT met" }
    );
}

fn percentile(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1]
}

fn roundtrip(n: usize) {
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().expect("rt");
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
        let mut measure = |name: &'static str| {
            let cl = c
                .node
                .create_client::<ResetRequest, ResetResponse>(
                    mapping,
                    &ClientNode::name(name),
                    &Reset::service_type_name(),
                    motion_runtime::shell::service_qos(),
                    motion_runtime::shell::service_qos(),
                )
                .expect("client");
            cl
        };
        let node_client = measure("/bench_node/reset");
        let bare_client = measure("/bare_echo/reset");
        system_tests::within(20.0, "node service", node_client.wait_for_service(&c.node)).await;
        system_tests::within(20.0, "bare service", bare_client.wait_for_service(&c.node)).await;
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
