//! The cyclic controller with a trivial engine: lockstep determinism, command ordering,
//! queue-full rejection, events routed to watchers, real-time schedule without drift.

use motion_core::{CmdId, CommandEvent, CommandState, Engine, ErrorId, Rejection, Tick};
use motion_runtime::{ClockMode, Controller, CycleConfig};
use std::time::{Duration, Instant};

/// Integrates a velocity; a "move" command runs for `cycles` cycles then reports Done.
struct Counter {
    next_id: u64,
    pos: f64,
    vel: f64,
    dts: Vec<f64>,
    job: Option<(CmdId, u64)>,
    started: bool,
}

enum Cmd {
    SetVel(f64),
    Move(u64),
}

impl Engine for Counter {
    type Command = Cmd;
    type Reply = Option<CmdId>;
    type Snapshot = (f64, usize);

    fn command(&mut self, cmd: Cmd) -> Result<Self::Reply, Rejection> {
        match cmd {
            Cmd::SetVel(v) if !v.is_finite() => Err(Rejection::not_finite("counter", "vel", v)),
            Cmd::SetVel(v) => {
                self.vel = v;
                Ok(None)
            }
            Cmd::Move(n) => {
                self.next_id += 1;
                let id = CmdId(self.next_id);
                self.job = Some((id, n));
                self.started = false;
                Ok(Some(id))
            }
        }
    }

    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        self.pos += self.vel * tick.dt;
        if self.dts.len() < 100_000 {
            self.dts.push(tick.dt);
        }
        if let Some((id, n)) = self.job.as_mut() {
            if !self.started {
                events.push(CommandEvent {
                    id: *id,
                    state: CommandState::Active,
                });
                self.started = true;
            }
            *n = n.saturating_sub(1);
            if *n == 0 {
                events.push(CommandEvent {
                    id: *id,
                    state: CommandState::Done,
                });
                self.job = None;
            }
        }
    }

    fn snapshot(&self) -> (f64, usize) {
        (self.pos, self.dts.len())
    }
}

fn counter() -> Counter {
    Counter {
        next_id: 0,
        pos: 0.0,
        vel: 0.0,
        dts: Vec::new(),
        job: None,
        started: false,
    }
}

fn lockstep(period: f64, queue: usize) -> CycleConfig {
    CycleConfig {
        name: "test".into(),
        period,
        mode: ClockMode::Lockstep,
        queue_capacity: queue,
        snapshot_every: 1,
        spin: 0.0,
        stream_every: 0,
    }
}

fn rt() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap()
}

#[test]
fn lockstep_runs_exactly_the_requested_cycles_with_nominal_dt() {
    rt().block_on(async {
        let (ctl, _events) = Controller::spawn(counter(), lockstep(0.002, 8), |r| *r).unwrap();
        let h = ctl.handle();
        let set = h.submit(Cmd::SetVel(10.0), None).unwrap();
        assert_eq!(h.step(500).await.unwrap(), 500);
        assert!(set.await.unwrap().is_ok());
        let snap = h.snapshot();
        assert_eq!(snap.cycle, 500);
        assert!((snap.sim_time - 1.0).abs() < 1e-12);
        // 500 cycles of 2 ms at 10 u/s: exactly 10 u, whatever the wall clock did.
        assert!((snap.state.0 - 10.0).abs() < 1e-9, "{}", snap.state.0);
        let engine = ctl.shutdown().unwrap();
        assert!(engine.dts.iter().all(|dt| *dt == 0.002));
    });
}

#[test]
fn lockstep_is_deterministic() {
    let run = || {
        rt().block_on(async {
            let (ctl, _e) = Controller::spawn(counter(), lockstep(0.001, 8), |r| *r).unwrap();
            let h = ctl.handle();
            for k in 0..20 {
                drop(h.submit(Cmd::SetVel(k as f64 * 0.37), None).unwrap());
                h.step(7).await.unwrap();
            }
            h.snapshot().state.0.to_bits()
        })
    };
    assert_eq!(run(), run());
}

#[test]
fn full_queue_is_an_immediate_rejection_and_the_cycle_keeps_going() {
    rt().block_on(async {
        let (ctl, _e) = Controller::spawn(counter(), lockstep(0.001, 2), |r| *r).unwrap();
        let h = ctl.handle();
        let _a = h.submit(Cmd::SetVel(1.0), None).unwrap();
        let _b = h.submit(Cmd::SetVel(2.0), None).unwrap();
        let t0 = Instant::now();
        let err = h.submit(Cmd::SetVel(3.0), None).err();
        // The controller thread may already have taken requests off the queue while idle;
        // keep pushing until full, which must happen without blocking.
        let err = match err {
            Some(e) => e,
            None => loop {
                if let Err(e) = h.submit(Cmd::SetVel(3.0), None) {
                    break e;
                }
            },
        };
        assert!(t0.elapsed() < Duration::from_millis(500));
        assert_eq!(err.error_id, ErrorId::QUEUE_FULL);
        assert!(h.step(10).await.is_ok());
        assert_eq!(h.snapshot().cycle, 10);
    });
}

#[test]
fn bad_command_is_rejected_with_its_error_id_and_state_is_kept() {
    rt().block_on(async {
        let (ctl, _e) = Controller::spawn(counter(), lockstep(0.001, 8), |r| *r).unwrap();
        let h = ctl.handle();
        h.free_run(true).unwrap();
        let err = h.call(Cmd::SetVel(f64::NAN)).await.unwrap_err();
        assert_eq!(err.error_id, ErrorId::NOT_FINITE);
        assert!(err.message.contains("vel"));
        h.free_run(false).unwrap();
        assert_eq!(h.snapshot().state.0, 0.0);
    });
}

#[test]
fn events_reach_the_watcher_and_the_status_stream() {
    rt().block_on(async {
        let (ctl, mut all) = Controller::spawn(counter(), lockstep(0.001, 8), |r| *r).unwrap();
        let h = ctl.handle();
        let fut = h.call_watched(Cmd::Move(5), None);
        let stepper = async {
            h.step(1).await.unwrap();
        };
        let ((reply, mut events), ()) = tokio::join!(async { fut.await.unwrap() }, stepper);
        let id = reply.unwrap();
        h.step(10).await.unwrap();
        assert_eq!(
            events.recv().await.unwrap(),
            CommandEvent {
                id,
                state: CommandState::Active
            }
        );
        assert_eq!(
            events.recv().await.unwrap(),
            CommandEvent {
                id,
                state: CommandState::Done
            }
        );
        // The watcher is dropped after the final event.
        assert!(events.recv().await.is_none());
        assert_eq!(all.recv().await.unwrap().event.state, CommandState::Active);
        assert_eq!(all.recv().await.unwrap().event.state, CommandState::Done);
    });
}

#[test]
fn realtime_keeps_the_schedule_without_drift() {
    let cfg = CycleConfig {
        name: "rt".into(),
        period: 0.001,
        mode: ClockMode::RealTime,
        queue_capacity: 8,
        snapshot_every: 1,
        spin: 0.0,
        stream_every: 0,
    };
    let (ctl, _e) = Controller::spawn(counter(), cfg, |r| *r).unwrap();
    let h = ctl.handle();
    let t0 = Instant::now();
    let c0 = h.snapshot().cycle;
    std::thread::sleep(Duration::from_millis(300));
    let c1 = h.snapshot().cycle;
    let wall = t0.elapsed().as_secs_f64();
    // Absolute deadlines: the cycle count follows the wall clock (±10 cycles for the
    // snapshot lag and thread start), never fewer because of sleep overshoot.
    let expected = wall / 0.001;
    let got = (c1 - c0) as f64;
    assert!(
        (got - expected).abs() < 15.0,
        "cycles {got} vs wall {expected}"
    );
    // Snapshots carry the node's ROS time: the system clock while free-running.
    let wall_ns = motion_runtime::clock::system_ns();
    let stamp = h.snapshot().ros_time_ns;
    assert!(
        (wall_ns - stamp).abs() < 50_000_000,
        "stamp {stamp} vs system clock {wall_ns}"
    );
    let engine = ctl.shutdown().unwrap();
    assert!(engine.dts.iter().all(|dt| *dt == 0.001));
    assert!(h.step(1).now_or_never_is_rejected());
}

/// In lockstep the node is the clock: ROS time is the simulated time from 0; a `use_sim_time`
/// follower moves the origin to the external clock.
#[test]
fn lockstep_ros_time_is_simulated_time_plus_origin() {
    rt().block_on(async {
        let (ctl, _events) = Controller::spawn(counter(), lockstep(0.002, 8), |r| *r).unwrap();
        let h = ctl.handle();
        assert_eq!(h.step(250).await.unwrap(), 250);
        assert_eq!(h.snapshot().ros_time_ns, 500_000_000);
        h.clock().set_origin(1_700_000_000_000_000_000);
        h.step(1).await.unwrap();
        let s = h.snapshot();
        assert_eq!(s.ros_time_ns, 1_700_000_000_502_000_000);
        // An event of an earlier cycle is stamped back by its simulated age.
        assert_eq!(s.ros_time_at(0.5), 1_700_000_000_500_000_000);
        ctl.shutdown().unwrap();
    });
}

trait NowOrNever {
    fn now_or_never_is_rejected(self) -> bool;
}

impl<F: std::future::Future<Output = Result<u64, Rejection>>> NowOrNever for F {
    fn now_or_never_is_rejected(self) -> bool {
        rt().block_on(self).is_err()
    }
}

/// Read-only queries (`ControllerHandle::query`): answered between cycles, in lockstep without
/// any step, with no command id, no event and no effect on the engine.
#[test]
fn query_reads_the_engine_without_a_step_an_id_or_an_event() {
    let run = |with_queries: bool| {
        rt().block_on(async {
            let (ctl, mut all) = Controller::spawn(counter(), lockstep(0.001, 8), |r| *r).unwrap();
            let h = ctl.handle();
            drop(h.submit(Cmd::SetVel(10.0), None).unwrap());
            h.step(100).await.unwrap();
            if with_queries {
                let q = tokio::time::timeout(
                    Duration::from_secs(5),
                    h.query(|e: &Counter| (e.pos, e.next_id, e.dts.len())),
                )
                .await
                .expect("answered in lockstep without a step")
                .unwrap();
                assert!((q.0 - 1.0).abs() < 1e-9, "engine data: {q:?}");
                assert_eq!((q.1, q.2), (0, 100));
                // More than one cycle's share, sequentially and as a burst of a full queue.
                for k in 0..40 {
                    let n = h.query(|e: &Counter| e.dts.len()).await.unwrap();
                    assert_eq!(n, 100, "query {k}");
                }
                let burst = futures_join(&h).await;
                assert!(burst.iter().all(|r| *r == Ok(100)), "{burst:?}");
                // No cycle ran for them, and no event left the cycle.
                assert_eq!(h.snapshot().cycle, 100);
                assert!(all.try_recv().is_err());
            }
            // No command id was used: the next command gets the first one.
            let fut = h.call(Cmd::Move(3));
            let (id, _) = tokio::join!(fut, h.step(1));
            assert_eq!(id.unwrap(), Some(CmdId(1)));
            h.step(50).await.unwrap();
            let e = ctl.shutdown().unwrap();
            (e.pos.to_bits(), e.dts.len())
        })
    };
    // The engine is unchanged by the queries: the same trajectory bit for bit.
    assert_eq!(run(true), run(false));
}

/// Eight queries at once (the queue's capacity), all answered.
async fn futures_join(h: &motion_runtime::ControllerHandle<Counter>) -> Vec<Result<usize, u32>> {
    let q = || async {
        h.query(|e: &Counter| e.dts.len())
            .await
            .map_err(|r| r.error_id.0)
    };
    let (a, b, c, d) = tokio::join!(q(), q(), q(), q());
    let (e, f, g, i) = tokio::join!(q(), q(), q(), q());
    vec![a, b, c, d, e, f, g, i]
}

#[test]
fn queries_run_in_real_time_between_cycles_and_a_full_queue_rejects() {
    rt().block_on(async {
        // 0.3 s period: the first cycle (and the first chance to serve a query) is 0.3 s away.
        let mut cfg = lockstep(0.3, 2);
        cfg.mode = ClockMode::RealTime;
        let (ctl, _e) = Controller::spawn(counter(), cfg, |r| *r).unwrap();
        let h = ctl.handle();
        // Capacity 2: the third query in the same instant is refused at once, never blocks.
        let q = || h.query(|e: &Counter| e.dts.len());
        let t0 = Instant::now();
        let (a, b, c) = tokio::join!(q(), q(), q());
        let results = [a, b, c];
        let refused: Vec<_> = results.iter().filter_map(|r| r.as_ref().err()).collect();
        assert_eq!(refused.len(), 1, "{results:?}");
        assert_eq!(refused[0].error_id, ErrorId::QUEUE_FULL);
        // The two queued ones are answered after the first cycle, with its whole count.
        for r in results.iter().filter_map(|r| r.as_ref().ok()) {
            assert_eq!(*r, 1);
        }
        assert!(t0.elapsed() < Duration::from_secs(2));
        let cycles = h.snapshot().cycle;
        let n = h.query(|e: &Counter| e.dts.len()).await.unwrap() as u64;
        assert!(n >= cycles && n <= cycles + 2, "{n} vs {cycles}");
        drop(ctl);
    });
}

/// `cycle_with`: a custom cycle replaces exactly one `step`, after the commands queued before
/// it; in lockstep it runs that cycle itself; its events are routed like a step's.
#[test]
fn a_custom_cycle_replaces_one_step_after_the_commands_before_it() {
    rt().block_on(async {
        let (ctl, mut events) = Controller::spawn(counter(), lockstep(0.001, 8), |r| *r).unwrap();
        let h = ctl.handle();
        let set = h.submit(Cmd::SetVel(100.0), None).unwrap();
        // The closure sees the velocity set before it, steps twice as far, reports an event.
        let (pos, tick) = h
            .cycle_with(|e: &mut Counter, t: Tick, ev: &mut Vec<CommandEvent>| {
                let v = e.vel;
                e.step(
                    Tick {
                        index: t.index,
                        dt: 2.0 * t.dt,
                    },
                    ev,
                );
                ev.push(CommandEvent {
                    id: CmdId(77),
                    state: CommandState::Done,
                });
                (e.pos, (t.index, v))
            })
            .await
            .unwrap();
        assert!(set.await.unwrap().is_ok());
        assert_eq!(tick, (0, 100.0));
        assert!((pos - 0.2).abs() < 1e-12, "{pos}");
        // Exactly one cycle ran.
        assert_eq!(h.step(0).await.unwrap(), 1);
        // Stamped with the time of the state after the cycle that produced it.
        let ev = events.recv().await.unwrap();
        assert_eq!(ev.event.id, CmdId(77));
        assert_eq!(h.snapshot().cycle, 1);
        assert_eq!(ev.ros_time_ns, h.snapshot().ros_time_ns);
        // A normal step afterwards.
        h.step(1).await.unwrap();
        assert!((h.snapshot().state.0 - 0.3).abs() < 1e-12);
        let engine = ctl.shutdown().unwrap();
        assert_eq!(engine.dts, vec![0.002, 0.001]);
    });
}

/// Lockstep (issue 15 item 8): a command is admitted between steps at once (its reply comes
/// without any `step`), and takes effect in the next cycle; commands keep their order.
#[test]
fn lockstep_admits_commands_between_steps_and_applies_them_at_the_next_step() {
    rt().block_on(async {
        let (ctl, _events) = Controller::spawn(counter(), lockstep(0.002, 8), |r| *r).unwrap();
        let h = ctl.handle();
        let a = h.submit(Cmd::SetVel(10.0), None).unwrap();
        let b = h.submit(Cmd::SetVel(20.0), None).unwrap();
        let refused = h.submit(Cmd::SetVel(f64::NAN), None).unwrap();
        let answered = tokio::time::timeout(std::time::Duration::from_secs(2), async {
            (a.await, b.await, refused.await)
        })
        .await
        .expect("answered without a step");
        assert!(answered.0.unwrap().is_ok() && answered.1.unwrap().is_ok());
        assert!(answered.2.unwrap().is_err(), "refused at once");
        assert_eq!(h.snapshot().cycle, 0, "no cycle ran");
        h.step(100).await.unwrap();
        // The last admitted velocity (20, in arrival order) for all 100 cycles.
        assert!((h.snapshot().state.0 - 20.0 * 0.2).abs() < 1e-9);
        ctl.shutdown().unwrap();
    });
}

/// A lockstep counter at 1 ms whose state stream carries every `n`-th cycle, and the stream.
fn streaming(
    n: u32,
) -> (
    Controller<Counter>,
    motion_runtime::cycle::StateStream<Counter>,
) {
    let cfg = CycleConfig {
        stream_every: n,
        ..lockstep(0.001, 8)
    };
    let (ctl, _events) = Controller::spawn(counter(), cfg, |r| *r).unwrap();
    let stream = ctl.handle().take_state_stream().expect("stream");
    (ctl, stream)
}

/// Stream mode reuses the snapshots its reader let go of (issue 14, speed): each item still
/// shows its own cycle when the reader keeps some of them far longer than the stream is long
/// (a held snapshot is never refilled), over many more cycles than the reuse pool holds.
#[test]
fn lockstep_stream_reuse_never_touches_a_held_snapshot() {
    rt().block_on(async {
        let (ctl, mut stream) = streaming(1);
        let h = ctl.handle();
        let reader = tokio::spawn(async move {
            let (mut kept, mut seen) = (Vec::new(), 0u64);
            while let Some(item) = stream.recv().await {
                let s = item.state.clone();
                // The counter's snapshot counts its steps: it equals the item's cycle.
                assert_eq!(s.state.1 as u64, s.cycle, "item of cycle {}", s.cycle);
                assert_eq!(s.cycle, seen, "in order, none left out");
                seen += 1;
                if s.cycle % 97 == 0 {
                    kept.push(s);
                }
                if seen > 5000 {
                    break;
                }
            }
            kept
        });
        h.submit(Cmd::SetVel(1.0), None).unwrap();
        assert_eq!(h.step(5000).await.unwrap(), 5000);
        let kept = reader.await.unwrap();
        assert_eq!(kept.len(), 52);
        for s in &kept {
            assert_eq!(s.state.1 as u64, s.cycle, "a kept snapshot was refilled");
            assert!((s.state.0 - s.cycle as f64 * 0.001).abs() < 1e-9);
        }
        assert_eq!(h.snapshot().cycle, 5000);
        assert_eq!(h.snapshot().state.1, 5000);
        drop(ctl);
    });
}

/// Lockstep state stream (`state_publish_every_n_cycles`, issue 15.9): every n-th cycle from
/// cycle 0, none dropped, in order, although one step runs far more cycles than the stream
/// holds; the cycle waits for the reader. Each item carries the command events of the cycles
/// since the item before, with their labels and the ROS time of their cycle (issue 14: the
/// axis node's `~/events` merges both in this one order).
#[test]
fn lockstep_state_stream_carries_every_nth_cycle() {
    rt().block_on(async {
        let (ctl, mut stream) = streaming(3);
        let h = ctl.handle();
        assert!(h.take_state_stream().is_none(), "one reader");
        let reader = tokio::spawn(async move {
            let mut seen = Vec::new();
            let mut events = Vec::new();
            while let Some(item) = stream.recv().await {
                let s = &item.state;
                seen.push((s.cycle, s.sim_time));
                for (ev, label) in &item.events {
                    events.push((
                        s.cycle,
                        ev.event.state,
                        ev.ros_time_ns,
                        label.command.clone(),
                    ));
                }
                if s.cycle >= 300 {
                    break;
                }
            }
            (seen, events)
        });
        h.submit(Cmd::SetVel(1.0), None).unwrap();
        let label = motion_runtime::CommandLabel {
            object: "counter".into(),
            command: "move".into(),
        };
        let call = h.call_labeled(Cmd::Move(4), label);
        let (id, _) = tokio::join!(call, h.step(150));
        assert!(id.unwrap().is_some());
        assert_eq!(h.step(150).await.unwrap(), 300);
        let (seen, events) = reader.await.unwrap();
        let cycles: Vec<u64> = seen.iter().map(|s| s.0).collect();
        assert_eq!(cycles, (0..=300).step_by(3).collect::<Vec<u64>>());
        assert!(seen
            .iter()
            .all(|(c, t)| (*c as f64 * 0.001 - t).abs() < 1e-12));
        // The move: Active in cycle 1 (item of cycle 3), Done in cycle 4 (item of cycle 6),
        // stamped with the ROS time after their cycle.
        let t0 = h.snapshot().ros_time_ns - 300 * 1_000_000;
        assert_eq!(
            events,
            vec![
                (3, CommandState::Active, t0 + 1_000_000, "move".to_string()),
                (6, CommandState::Done, t0 + 4_000_000, "move".to_string()),
            ]
        );
        drop(ctl);
    });
}
