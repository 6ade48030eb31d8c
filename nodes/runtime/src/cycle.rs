//! The cyclic controller: one thread owns the engine and runs its cycle.
//!
//! Real time: absolute deadlines on `CLOCK_MONOTONIC` (`clock_nanosleep(TIMER_ABSTIME)`), so the
//! schedule never drifts. A late wake-up runs the cycle at once and keeps the schedule: no
//! skipped cycle, no doubled period, and the engine always gets the nominal `dt`.
//! Lockstep: simulated time; cycles run only when asked (`step(n)`) or as fast as possible
//! (`free_run`). Either way the cycle never blocks on the ROS side: commands arrive through a
//! bounded queue (full = an immediate rejection), replies and events leave through non-blocking
//! channels, snapshots through a `watch` channel (a short lock, never held across DDS calls).
//!
//! Read-only queries ([`ControllerHandle::query`]) run on the cycle thread between cycles, never
//! inside the timed part of a step: no command id, no event, no effect on the engine (`&E`).

use crate::clock::{RosClock, TimeSource};
use crate::shell::{CommandLabel, CommandRegistry};
use crate::stats::{CycleStats, StatsRecorder};
use motion_core::{CmdId, CommandEvent, Engine, ErrorId, Rejection, Tick};
use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tokio::sync::{mpsc as tmpsc, oneshot, watch};

/// How the cycle is clocked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClockMode {
    /// Wall-clock period with absolute deadlines.
    RealTime,
    /// Simulated time: cycles run on request (`step`) or as fast as possible (`free_run`).
    Lockstep,
}

/// Settings of one controller (from the launch config / ROS parameters).
#[derive(Clone, Debug)]
pub struct CycleConfig {
    /// Node name, for thread names and diagnostics.
    pub name: String,
    /// Nominal period [s] (default 1 ms).
    pub period: f64,
    /// Real time or lockstep.
    pub mode: ClockMode,
    /// Capacity of the command queue into the cycle.
    pub queue_capacity: usize,
    /// A snapshot is taken every this many cycles (and after every lockstep batch).
    pub snapshot_every: u32,
    /// Real time: busy-wait this long before each deadline instead of sleeping [s]
    /// (default 0: sleep only). Lowers jitter to below the kernel's wake-up latency.
    pub spin: f64,
    /// Lockstep: every this many cycles (and at cycle 0) a snapshot goes to the state stream
    /// ([`ControllerHandle::take_state_stream`]), none dropped: the cycle waits while the
    /// stream is full. 0 = no stream.
    pub stream_every: u32,
}

impl Default for CycleConfig {
    fn default() -> Self {
        CycleConfig {
            name: "node".into(),
            period: 0.001,
            mode: ClockMode::RealTime,
            queue_capacity: 256,
            snapshot_every: 10,
            spin: 0.0,
            stream_every: 0,
        }
    }
}

/// A state snapshot with the cycle it was taken after.
#[derive(Clone, Debug)]
pub struct Stamped<S> {
    /// Cycles run when the snapshot was taken.
    pub cycle: u64,
    /// Simulated time [s] = cycle × period (the engine's time base).
    pub sim_time: f64,
    /// The node's ROS time of this snapshot [ns since the epoch] (see [`crate::clock`]).
    pub ros_time_ns: i64,
    /// The engine's snapshot.
    pub state: S,
}

impl<S> Stamped<S> {
    /// ROS time [ns] of simulated time `t` (e.g. an event of an earlier cycle).
    pub fn ros_time_at(&self, t: f64) -> i64 {
        self.ros_time_ns + ((t - self.sim_time) * 1e9).round() as i64
    }
}

type CommandReply<E> = oneshot::Sender<Result<<E as Engine>::Reply, Rejection>>;
/// Finds the command id in an engine's reply, so events can be routed to the caller.
pub type ReplyId<E> = fn(&<E as Engine>::Reply) -> Option<CmdId>;

enum Request<E: Engine> {
    Command {
        cmd: E::Command,
        reply: CommandReply<E>,
        watcher: Option<tmpsc::UnboundedSender<CommandEvent>>,
        /// Registered in the cycle at acceptance, before the command's first event.
        label: Option<CommandLabel>,
    },
    Cancel {
        id: CmdId,
        reply: oneshot::Sender<Result<(), Rejection>>,
    },
    /// A custom cycle: runs instead of the next plain `step` (see
    /// [`ControllerHandle::cycle_with`]).
    Cycle(CustomStep<E>),
    /// The node's command script: (cycle, command) in running order (see
    /// [`ControllerHandle::load_script`]).
    Script(Vec<ScriptedCommand<E::Command>>),
}

/// A command of a node's script: applied before the step of cycle `cycle`; its events carry
/// `label` on `~/command_status` like a client's call.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptedCommand<C> {
    /// The cycle it runs before.
    pub cycle: u64,
    /// The engine command.
    pub command: C,
    /// Object and command name for `~/command_status`.
    pub label: CommandLabel,
}

/// A cycle run by the caller's closure instead of `Engine::step`: it gets the engine, the
/// cycle's tick and the event vector, and must advance the engine by exactly that tick.
type CustomStep<E> = Box<dyn FnOnce(&mut E, Tick, &mut Vec<CommandEvent>) + Send>;

/// A read-only query: runs on the cycle thread with the engine between two cycles.
type Query<E> = Box<dyn FnOnce(&E) + Send>;

/// Queries run at most this many per cycle, so a burst spreads over cycles.
const QUERIES_PER_CYCLE: usize = 16;

/// Lockstep control, on its own unbounded channel so commands stay in the bounded queue.
enum Control {
    /// Run `n` cycles, then answer with the cycle count.
    Step { n: u64, reply: oneshot::Sender<u64> },
    /// Run continuously (true) or only on request (false).
    FreeRun(bool),
}

/// The ROS side's handle on a running controller. Cheap to clone.
pub struct ControllerHandle<E: Engine> {
    queue: SyncSender<Request<E>>,
    queries: SyncSender<Query<E>>,
    control: mpsc::Sender<Control>,
    wake: Arc<Wake>,
    snapshots: watch::Receiver<Arc<Stamped<E::Snapshot>>>,
    stats: Arc<Mutex<CycleStats>>,
    config: Arc<CycleConfig>,
    stop: Arc<AtomicBool>,
    labels: Arc<CommandRegistry>,
    clock: Arc<RosClock>,
    stream: Arc<Mutex<Option<StateStream<E>>>>,
    busy: Arc<std::sync::atomic::AtomicUsize>,
}

/// The lossless stream of lockstep snapshots (see [`CycleConfig::stream_every`]).
pub type StateStream<E> = tmpsc::Receiver<StreamItem<<E as Engine>::Snapshot>>;

/// One item of the lockstep state stream: a snapshot, and the command events of the cycles
/// since the previous item, with their labels, in the order they happened. Readers that merge
/// commands and states (the axis node's `~/events`) get both in one order, the same on every
/// run.
#[derive(Debug)]
pub struct StreamItem<S> {
    /// The snapshot.
    pub state: Arc<Stamped<S>>,
    /// Command events since the previous item, each with its label.
    pub events: Vec<(TimedEvent, CommandLabel)>,
}

/// Snapshots in flight on the state stream before the cycle waits.
pub(crate) const STREAM_CAPACITY: usize = 256;

/// Snapshots kept for reuse in stream mode: more than can be in flight (the stream, the
/// items not yet handed over, the watch's and a reader's previous one).
const SPARE_SNAPSHOTS: usize = 2 * STREAM_CAPACITY;

impl<E: Engine> Clone for ControllerHandle<E> {
    fn clone(&self) -> Self {
        ControllerHandle {
            queue: self.queue.clone(),
            queries: self.queries.clone(),
            control: self.control.clone(),
            wake: self.wake.clone(),
            snapshots: self.snapshots.clone(),
            stats: self.stats.clone(),
            config: self.config.clone(),
            stop: self.stop.clone(),
            busy: self.busy.clone(),
            labels: self.labels.clone(),
            clock: self.clock.clone(),
            stream: self.stream.clone(),
        }
    }
}

/// Owns the controller thread; dropping it stops the cycle and joins the thread.
pub struct Controller<E: Engine> {
    handle: ControllerHandle<E>,
    thread: Option<JoinHandle<E>>,
}

/// Wakes a lockstep controller waiting for requests.
#[derive(Default)]
struct Wake {
    flag: Mutex<bool>,
    cv: std::sync::Condvar,
}

impl Wake {
    fn notify(&self) {
        let mut f = self.flag.lock().unwrap_or_else(|e| e.into_inner());
        *f = true;
        self.cv.notify_one();
    }
    fn wait(&self) {
        let mut f = self.flag.lock().unwrap_or_else(|e| e.into_inner());
        while !*f {
            f = self.cv.wait(f).unwrap_or_else(|e| e.into_inner());
        }
        *f = false;
    }
}

/// Where the cycle sends command events: every event to the status stream, and each command's
/// events also to the caller that asked to watch it (an action goal, a test).
pub struct EventSink {
    all: tmpsc::UnboundedSender<TimedEvent>,
}

/// A command event with the ROS time of the cycle it happened in (the stamp of that cycle's
/// state): stamps of `~/command_status` do not depend on when a task gets to publish them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimedEvent {
    /// The event.
    pub event: CommandEvent,
    /// ROS time of the state after the cycle that produced it [ns].
    pub ros_time_ns: i64,
}

impl<E: Engine> Controller<E> {
    /// Starts the controller thread with `engine`. Returns the controller and the receiver of
    /// all command events (for the command-status topic).
    pub fn spawn(
        engine: E,
        config: CycleConfig,
        reply_id: ReplyId<E>,
    ) -> std::io::Result<(Self, tmpsc::UnboundedReceiver<TimedEvent>)> {
        assert!(
            config.period.is_finite() && config.period > 0.0,
            "period validated by config"
        );
        let (queue, rx) = mpsc::sync_channel(config.queue_capacity.max(1));
        let (queries, query_rx) = mpsc::sync_channel(config.queue_capacity.max(1));
        let (control, control_rx) = mpsc::channel();
        let clock = Arc::new(RosClock::new(match config.mode {
            ClockMode::RealTime => TimeSource::System,
            ClockMode::Lockstep => TimeSource::Simulated,
        }));
        let first = Arc::new(Stamped {
            cycle: 0,
            sim_time: 0.0,
            ros_time_ns: clock.at(0.0),
            state: engine.snapshot(),
        });
        let (stream_tx, stream_rx) =
            if config.stream_every > 0 && config.mode == ClockMode::Lockstep {
                let (tx, rx) = tmpsc::channel(STREAM_CAPACITY);
                // The first state is cycle 0's.
                let _ = tx.try_send(StreamItem {
                    state: first.clone(),
                    events: Vec::new(),
                });
                (Some(tx), Some(rx))
            } else {
                (None, None)
            };
        let (snap_tx, snapshots) = watch::channel(first.clone());
        let (all_tx, all_rx) = tmpsc::unbounded_channel();
        let stats = Arc::new(Mutex::new(CycleStats::new(
            &config.name,
            config.period,
            config.mode,
        )));
        let stop = Arc::new(AtomicBool::new(false));
        let wake = Arc::new(Wake::default());
        let labels = Arc::new(CommandRegistry::default());
        let busy = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let config = Arc::new(config);
        let failsafe = {
            let wake = wake.clone();
            crate::failsafe::register(&config.name, Arc::new(move || wake.notify()))
        };
        let mut cycle = CycleThread {
            engine,
            rx,
            query_rx,
            control_rx,
            snap_tx,
            latest: first,
            sink: EventSink { all: all_tx },
            watchers: HashMap::new(),
            events: Vec::with_capacity(64),
            recorder: StatsRecorder::new(config.period),
            stats: stats.clone(),
            config: config.clone(),
            reply_id,
            labels: labels.clone(),
            cycle: 0,
            stop: stop.clone(),
            wake: wake.clone(),
            free_run: false,
            failsafe,
            clock: clock.clone(),
            held: None,
            stream: stream_tx,
            stream_events: Vec::new(),
            stream_buffer: Vec::new(),
            spare: VecDeque::new(),
            script: VecDeque::new(),
            open: Default::default(),
            busy: busy.clone(),
        };
        let thread = std::thread::Builder::new()
            .name(format!("cycle-{}", config.name))
            .spawn(move || {
                let _in_node = crate::logging::node_span(&cycle.config.name).entered();
                cycle.failsafe.enter_thread();
                cycle.run();
                cycle.engine
            })?;
        let handle = ControllerHandle {
            queue,
            queries,
            control,
            wake,
            snapshots,
            stats,
            config,
            stop,
            labels,
            clock,
            stream: Arc::new(Mutex::new(stream_rx)),
            busy,
        };
        Ok((
            Controller {
                handle,
                thread: Some(thread),
            },
            all_rx,
        ))
    }

    /// A handle for the ROS side.
    pub fn handle(&self) -> ControllerHandle<E> {
        self.handle.clone()
    }

    /// Stops the cycle and returns the engine (for tests that inspect it afterwards).
    pub fn shutdown(mut self) -> Option<E> {
        self.stop_thread()
    }

    fn stop_thread(&mut self) -> Option<E> {
        self.handle.stop.store(true, Ordering::SeqCst);
        self.handle.wake.notify();
        self.thread.take().and_then(|t| t.join().ok())
    }
}

impl<E: Engine> Drop for Controller<E> {
    fn drop(&mut self) {
        self.stop_thread();
    }
}

impl<E: Engine> ControllerHandle<E> {
    /// Queues a command for the next cycle without waiting. A full queue is an immediate
    /// rejection (`QUEUE_FULL`), never a block.
    pub fn submit(
        &self,
        cmd: E::Command,
        watcher: Option<tmpsc::UnboundedSender<CommandEvent>>,
    ) -> Result<oneshot::Receiver<Result<E::Reply, Rejection>>, Rejection> {
        self.submit_labeled(cmd, watcher, None)
    }

    fn submit_labeled(
        &self,
        cmd: E::Command,
        watcher: Option<tmpsc::UnboundedSender<CommandEvent>>,
        label: Option<CommandLabel>,
    ) -> Result<oneshot::Receiver<Result<E::Reply, Rejection>>, Rejection> {
        let (reply, rx) = oneshot::channel();
        self.push(Request::Command {
            cmd,
            reply,
            watcher,
            label,
        })?;
        Ok(rx)
    }

    /// Submits a command and waits for the cycle's answer (accepted or rejected).
    pub async fn call(&self, cmd: E::Command) -> Result<E::Reply, Rejection> {
        let rx = self.submit(cmd, None)?;
        rx.await.unwrap_or_else(|_| Err(not_running()))
    }

    /// [`Self::call`] with the label its events carry on `~/command_status`: the cycle
    /// registers it when it accepts the command, so no event goes out unlabeled.
    pub async fn call_labeled(
        &self,
        cmd: E::Command,
        label: CommandLabel,
    ) -> Result<E::Reply, Rejection> {
        let rx = self.submit_labeled(cmd, None, Some(label))?;
        rx.await.unwrap_or_else(|_| Err(not_running()))
    }

    /// The labels of running commands (shared with the cycle).
    pub fn labels(&self) -> Arc<CommandRegistry> {
        self.labels.clone()
    }

    /// Submits a command and, once accepted, returns its events (Busy/Active/.../final state);
    /// `label` as in [`Self::call_labeled`].
    pub async fn call_watched(
        &self,
        cmd: E::Command,
        label: Option<CommandLabel>,
    ) -> Result<(E::Reply, tmpsc::UnboundedReceiver<CommandEvent>), Rejection> {
        let (tx, rx_events) = tmpsc::unbounded_channel();
        let rx = self.submit_labeled(cmd, Some(tx), label)?;
        let reply = rx.await.unwrap_or_else(|_| Err(not_running()))?;
        Ok((reply, rx_events))
    }

    /// Asks the engine to apply the halt semantics of a command (action cancel).
    pub async fn cancel(&self, id: CmdId) -> Result<(), Rejection> {
        let (reply, rx) = oneshot::channel();
        self.push(Request::Cancel { id, reply })?;
        rx.await.unwrap_or_else(|_| Err(not_running()))
    }

    /// Reads the engine without commanding it: `f` runs on the cycle thread between two cycles
    /// (never inside a step's timed part) and its result comes back. No command id, no event on
    /// `~/command_status`, no effect on the engine. Served in lockstep too, without a step.
    ///
    /// Budget: at most [`QUERIES_PER_CYCLE`] queries per cycle, and in real time a query starts
    /// only while at least half a period is left before the next deadline, so queries never
    /// delay a cycle by more than one query's own run time; keep `f` short (microseconds).
    /// The query queue has the command queue's capacity; full = `QUEUE_FULL`, never a block.
    pub async fn query<R, F>(&self, f: F) -> Result<R, Rejection>
    where
        F: FnOnce(&E) -> R + Send + 'static,
        R: Send + 'static,
    {
        if self.stop.load(Ordering::Relaxed) {
            return Err(not_running());
        }
        let (tx, rx) = oneshot::channel();
        let q: Query<E> = Box::new(move |e: &E| {
            let _ = tx.send(f(e));
        });
        match self.queries.try_send(q) {
            Ok(()) => self.wake.notify(),
            Err(TrySendError::Full(_)) => {
                return Err(Rejection::new(
                    ErrorId::QUEUE_FULL,
                    format!(
                        "query queue of {} is full ({} entries); query not queued",
                        self.config.name, self.config.queue_capacity
                    ),
                ))
            }
            Err(TrySendError::Disconnected(_)) => return Err(not_running()),
        }
        rx.await.map_err(|_| not_running())
    }

    /// Runs the next cycle with `f` instead of `Engine::step` (e.g. a PLC cycle that calls
    /// FB instances and then steps the engine, plcopen_platform.md §12.2): commands queued
    /// before are applied first; `f` must advance the engine by the tick it gets; events it
    /// appends are routed as usual. Returns `f`'s result after that cycle. In lockstep mode
    /// the request itself runs that one cycle.
    pub async fn cycle_with<R, F>(&self, f: F) -> Result<R, Rejection>
    where
        F: FnOnce(&mut E, Tick, &mut Vec<CommandEvent>) -> R + Send + 'static,
        R: Send + 'static,
    {
        let (tx, rx) = oneshot::channel();
        self.push(Request::Cycle(Box::new(move |e, t, ev| {
            let _ = tx.send(f(e, t, ev));
        })))?;
        if self.config.mode == ClockMode::Lockstep {
            let (reply, _done) = oneshot::channel();
            self.push_control(Control::Step { n: 1, reply })?;
        }
        rx.await.map_err(|_| not_running())
    }

    /// Loads the node's command script: each (cycle, command) is applied before that cycle's
    /// step (steps already due run before the next cycle), in the given order.
    pub fn load_script(&self, steps: Vec<ScriptedCommand<E::Command>>) -> Result<(), Rejection> {
        if steps.is_empty() {
            return Ok(());
        }
        self.push(Request::Script(steps))
    }

    /// Accepted commands that have not ended, plus the script steps still to run, as of the
    /// last cycle: 0 = every goal ended (`motion_launch --cycles N --until-idle`).
    pub fn busy(&self) -> usize {
        self.busy.load(std::sync::atomic::Ordering::Acquire)
    }

    /// Lockstep: runs `n` cycles and returns the cycle count afterwards.
    /// In real-time mode the request is rejected.
    pub async fn step(&self, n: u64) -> Result<u64, Rejection> {
        if self.config.mode != ClockMode::Lockstep {
            return Err(Rejection::new(
                ErrorId::VALUE_OUT_OF_RANGE,
                "step is only available in lockstep mode (use_sim_time / lockstep: true)",
            ));
        }
        let (reply, rx) = oneshot::channel();
        self.push_control(Control::Step { n, reply })?;
        rx.await.map_err(|_| not_running())
    }

    /// Lockstep: run continuously as fast as possible (true) or only on `step` (false).
    pub fn free_run(&self, on: bool) -> Result<(), Rejection> {
        self.push_control(Control::FreeRun(on))
    }

    fn push_control(&self, c: Control) -> Result<(), Rejection> {
        if self.stop.load(Ordering::Relaxed) {
            return Err(not_running());
        }
        self.control.send(c).map_err(|_| not_running())?;
        self.wake.notify();
        Ok(())
    }

    /// The lossless lockstep state stream (see [`CycleConfig::stream_every`]); the first
    /// caller gets it, later ones `None`. Read it without pause: the cycle waits for it.
    pub fn take_state_stream(&self) -> Option<StateStream<E>> {
        self.stream.lock().unwrap_or_else(|e| e.into_inner()).take()
    }

    /// The latest snapshot.
    pub fn snapshot(&self) -> Arc<Stamped<E::Snapshot>> {
        self.snapshots.borrow().clone()
    }

    /// A receiver that is notified on each new snapshot.
    pub fn snapshots(&self) -> watch::Receiver<Arc<Stamped<E::Snapshot>>> {
        self.snapshots.clone()
    }

    /// The cycle statistics so far.
    pub fn stats(&self) -> CycleStats {
        self.stats.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// The node's ROS time (its origin is set by a `use_sim_time` node's `/clock` follower).
    pub fn clock(&self) -> &Arc<RosClock> {
        &self.clock
    }

    /// The controller's configuration.
    pub fn config(&self) -> &CycleConfig {
        &self.config
    }

    fn push(&self, req: Request<E>) -> Result<(), Rejection> {
        if self.stop.load(Ordering::Relaxed) {
            return Err(not_running());
        }
        match self.queue.try_send(req) {
            Ok(()) => {
                self.wake.notify();
                Ok(())
            }
            Err(TrySendError::Full(_)) => Err(Rejection::new(
                ErrorId::QUEUE_FULL,
                format!(
                    "command queue of {} is full ({} entries); command not queued",
                    self.config.name, self.config.queue_capacity
                ),
            )),
            Err(TrySendError::Disconnected(_)) => Err(not_running()),
        }
    }
}

fn not_running() -> Rejection {
    Rejection::new(ErrorId::NOT_RUNNING, "the node's cycle is not running")
}

struct CycleThread<E: Engine> {
    engine: E,
    rx: Receiver<Request<E>>,
    query_rx: Receiver<Query<E>>,
    control_rx: Receiver<Control>,
    snap_tx: watch::Sender<Arc<Stamped<E::Snapshot>>>,
    /// The newest snapshot taken; the state stream takes one every cycle, the watch only
    /// every `snapshot_every` cycles of them (waking its receivers costs more than a cycle).
    latest: Arc<Stamped<E::Snapshot>>,
    sink: EventSink,
    watchers: HashMap<CmdId, tmpsc::UnboundedSender<CommandEvent>>,
    events: Vec<CommandEvent>,
    recorder: StatsRecorder,
    stats: Arc<Mutex<CycleStats>>,
    config: Arc<CycleConfig>,
    reply_id: ReplyId<E>,
    labels: Arc<CommandRegistry>,
    cycle: u64,
    stop: Arc<AtomicBool>,
    wake: Arc<Wake>,
    free_run: bool,
    /// This cycle's part in the process's fail-safe stop.
    failsafe: crate::failsafe::Registration,
    /// The node's ROS time (stamps snapshots).
    clock: Arc<RosClock>,
    /// Lockstep: a custom cycle taken from the queue between steps; it runs at the next step,
    /// and requests behind it wait for that step too (order of arrival).
    held: Option<CustomStep<E>>,
    /// The lossless state stream (lockstep with `stream_every` > 0); dropped when its reader
    /// is gone.
    stream: Option<tmpsc::Sender<StreamItem<E::Snapshot>>>,
    /// Stream mode: the command events since the last streamed snapshot, with their labels.
    stream_events: Vec<(TimedEvent, CommandLabel)>,
    /// Stream items not handed over yet (see `flush_stream`).
    stream_buffer: Vec<StreamItem<E::Snapshot>>,
    /// Stream mode: the snapshots handed out, oldest first, for reuse (see `build_snapshot`).
    spare: VecDeque<Arc<Stamped<E::Snapshot>>>,
    /// The command script's steps still to run: (cycle, command), in running order.
    script: VecDeque<ScriptedCommand<E::Command>>,
    /// Accepted commands that have not ended yet.
    open: std::collections::HashSet<CmdId>,
    /// `open` plus the script steps left, as of the last cycle (see [`ControllerHandle::busy`]).
    busy: Arc<std::sync::atomic::AtomicUsize>,
}

/// Lockstep step requests not yet served: (cycles still to run, reply).
type Steps = VecDeque<(u64, oneshot::Sender<u64>)>;

impl<E: Engine> CycleThread<E> {
    fn run(&mut self) {
        match self.config.mode {
            ClockMode::RealTime => self.run_realtime(),
            ClockMode::Lockstep => self.run_lockstep(),
        }
        if crate::failsafe::triggered() {
            self.fail_safe_run();
        }
        self.publish_stats();
    }

    /// The fail-safe stop (see [`crate::failsafe`]): the engine's controlled stop, cycled at
    /// the nominal period in both clock modes (so subscribers see it happen) until it is at
    /// rest, at most [`crate::failsafe::STOP_WAIT`]; new commands are refused meanwhile. Then
    /// idles until the process ends.
    fn fail_safe_run(&mut self) {
        self.engine.fail_safe_stop();
        let period = Duration::from_secs_f64(self.config.period);
        let started = Instant::now();
        let mut deadline = started;
        while !self.engine.at_rest() && started.elapsed() < crate::failsafe::STOP_WAIT {
            deadline += period;
            crate::rt::wait_until(deadline, Duration::ZERO);
            self.refuse_commands();
            self.cycle_once();
            self.snapshot_if_due();
        }
        self.take_snapshot();
        self.failsafe.done.store(true, Ordering::SeqCst);
        while !self.stop.load(Ordering::Relaxed) {
            self.refuse_commands();
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Answers every queued request with "not running" (fail-safe: nothing new may start).
    fn refuse_commands(&mut self) {
        // A custom cycle held between lockstep steps must not run in the fail-safe stop;
        // dropping it answers its caller "not running".
        self.held = None;
        while let Ok(req) = self.rx.try_recv() {
            match req {
                Request::Command { reply, .. } => {
                    let _ = reply.send(Err(not_running()));
                }
                Request::Cancel { reply, .. } => {
                    let _ = reply.send(Err(not_running()));
                }
                Request::Cycle(_) | Request::Script(_) => {}
            }
        }
    }

    fn run_realtime(&mut self) {
        crate::rt::prepare_cycle_thread();
        let period = Duration::from_secs_f64(self.config.period);
        let spin = Duration::from_secs_f64(self.config.spin.clamp(0.0, self.config.period));
        let mut deadline = Instant::now() + period;
        while !self.stop.load(Ordering::Relaxed) && !crate::failsafe::triggered() {
            crate::rt::wait_until(deadline, spin);
            let woke = Instant::now();
            let lateness = woke.saturating_duration_since(deadline);
            self.cycle_once();
            self.snapshot_if_due();
            let end = Instant::now();
            // The next deadline keeps the schedule, whatever happened to this cycle.
            deadline += period;
            self.recorder.record(end - woke, lateness, end > deadline);
            if self.recorder.due_for_publish(self.cycle) {
                self.publish_stats();
            }
            // Queries after the timed part, only while half a period is left.
            let latest = deadline.checked_sub(period / 2);
            self.serve_queries(|| latest.is_some_and(|l| Instant::now() <= l));
        }
    }

    /// Runs queued read-only queries while `may_start` allows, at most [`QUERIES_PER_CYCLE`].
    /// Returns true when it stopped with the cap reached (more may be waiting).
    fn serve_queries(&mut self, may_start: impl Fn() -> bool) -> bool {
        for _ in 0..QUERIES_PER_CYCLE {
            if !may_start() {
                return false;
            }
            match self.query_rx.try_recv() {
                Ok(q) => q(&self.engine),
                Err(_) => return false,
            }
        }
        true
    }

    fn run_lockstep(&mut self) {
        let mut pending: Steps = VecDeque::new();
        while !self.stop.load(Ordering::Relaxed) && !crate::failsafe::triggered() {
            if pending.is_empty() && !self.free_run {
                self.flush_stream();
                self.wake.wait();
                self.drain_control(&mut pending);
                self.admit_between_steps();
                // Queries need no step: served while idle (the loop comes back for more).
                if self.serve_queries(|| true) {
                    self.wake.notify();
                }
                continue;
            }
            self.drain_control(&mut pending);
            let t0 = Instant::now();
            self.cycle_once();
            self.recorder.record(t0.elapsed(), Duration::ZERO, false);
            self.stream_if_due();
            match pending.front_mut() {
                Some(front) => {
                    front.0 -= 1;
                    if front.0 == 0 {
                        self.snapshot_current();
                        self.flush_stream();
                        // The statistics of a finished step count every cycle of it.
                        self.publish_stats();
                        if let Some((_, reply)) = pending.pop_front() {
                            let _ = reply.send(self.cycle);
                        }
                    }
                }
                None => self.snapshot_if_due(),
            }
            if self.recorder.due_for_publish(self.cycle) {
                self.publish_stats();
            }
            self.serve_queries(|| true);
        }
        self.flush_stream();
    }

    /// Lockstep, between steps: commands and cancels are admitted at once (accepted with
    /// their id or refused), as a PLC's FB call is before the NC cycle, and take effect in
    /// the next cycle; so a service call answers without waiting for a `~/step`. A custom
    /// cycle is held for the next step, and whatever arrived after it waits with it.
    fn admit_between_steps(&mut self) {
        while self.held.is_none() {
            match self.rx.try_recv() {
                Ok(req) => self.held = self.apply(req),
                Err(_) => break,
            }
        }
    }

    /// Lockstep: takes step and free-run requests (commands wait in their queue).
    fn drain_control(&mut self, pending: &mut Steps) {
        while let Ok(c) = self.control_rx.try_recv() {
            match c {
                Control::Step { n: 0, reply } => {
                    // No cycle, a fresh snapshot (e.g. the ROS time's origin moved).
                    self.take_snapshot();
                    let _ = reply.send(self.cycle);
                }
                Control::Step { n, reply } => pending.push_back((n, reply)),
                Control::FreeRun(on) => self.free_run = on,
            }
        }
    }

    /// One cycle: commands in arrival order, then `step` (or a custom cycle that came with
    /// them; commands behind it wait for the next cycle), then events and snapshot.
    fn cycle_once(&mut self) {
        let mut custom = self.held.take();
        while custom.is_none() {
            match self.rx.try_recv() {
                Ok(req) => custom = self.apply(req),
                Err(_) => break,
            }
        }
        self.run_script();
        let tick = Tick {
            index: self.cycle,
            dt: self.config.period,
        };
        match custom {
            Some(f) => f(&mut self.engine, tick, &mut self.events),
            None => self.engine.step(tick, &mut self.events),
        }
        self.cycle += 1;
        // A command that ends is reported with the state it ended in: results built from the
        // snapshot (action results) must not see an older cycle.
        if self.events.iter().any(|e| e.state.is_final()) {
            self.take_snapshot();
        }
        // The clock is read only in cycles that report something (in real time it is a
        // system call).
        let ros_time_ns = if self.events.is_empty() {
            0
        } else {
            self.clock.at(self.cycle as f64 * self.config.period)
        };
        for ev in self.events.drain(..) {
            if ev.state.is_final() {
                self.open.remove(&ev.id);
            }
            let timed = TimedEvent {
                event: ev,
                ros_time_ns,
            };
            if self.stream.is_some() {
                // Labelled here, before `~/command_status` forgets the label of an end.
                self.stream_events
                    .push((timed, self.labels.label_of(ev.id)));
            }
            let _ = self.sink.all.send(timed);
            if let Some(w) = self.watchers.get(&ev.id) {
                let _ = w.send(ev);
                if ev.state.is_final() {
                    self.watchers.remove(&ev.id);
                }
            }
        }
        self.busy.store(
            self.open.len() + self.script.len(),
            std::sync::atomic::Ordering::Release,
        );
    }

    /// The periodic snapshot (every `snapshot_every` cycles), for cycles that no step request
    /// of a lockstep client waits for.
    fn snapshot_if_due(&mut self) {
        if self
            .cycle
            .is_multiple_of(u64::from(self.config.snapshot_every.max(1)))
        {
            self.snapshot_current();
        }
    }

    /// Lockstep: every `stream_every`-th cycle's snapshot to the state stream, waiting while
    /// it is full (simulated time waits for its observers; nothing is dropped).
    fn stream_if_due(&mut self) {
        let n = u64::from(self.config.stream_every);
        if self.stream.is_none() || n == 0 || !self.cycle.is_multiple_of(n) {
            return;
        }
        self.snapshot_latest();
        self.snapshot_if_due();
        // By value: the item is two pointers' worth, nothing to allocate per cycle.
        self.stream_buffer.push(StreamItem {
            state: self.latest.clone(),
            events: std::mem::take(&mut self.stream_events),
        });
        if self.stream_buffer.len() >= STREAM_CAPACITY / 2 {
            self.flush_stream();
        }
    }

    /// Hands the buffered stream items over in one burst (a reader that had caught up is
    /// woken once per burst, not once per cycle), waiting until the stream has room for all
    /// of them (at most half a stream: a slower reader and the cycle take turns once per half
    /// stream). Runs at every half stream, before a step is answered and before the cycle idles.
    fn flush_stream(&mut self) {
        let (Some(tx), n @ 1..) = (self.stream.as_ref(), self.stream_buffer.len()) else {
            return;
        };
        let Ok(permits) = futures::executor::block_on(tx.reserve_many(n)) else {
            // Nobody reads the stream any more (the node is stopping).
            self.stream = None;
            self.stream_buffer.clear();
            return;
        };
        for (permit, item) in permits.zip(self.stream_buffer.drain(..)) {
            permit.send(item);
        }
    }

    /// Applies a command or cancel; a custom cycle is handed back to run instead of `step`.
    fn apply(&mut self, req: Request<E>) -> Option<CustomStep<E>> {
        match req {
            Request::Command {
                cmd,
                reply,
                watcher,
                label,
            } => {
                let result = self.engine.command(cmd);
                if let Some(id) = result.as_ref().ok().and_then(self.reply_id) {
                    self.open.insert(id);
                    if let Some(w) = watcher {
                        self.watchers.insert(id, w);
                    }
                    if let Some(l) = label {
                        self.labels.insert(id, l);
                    }
                }
                let _ = reply.send(result);
            }
            Request::Cancel { id, reply } => {
                let _ = reply.send(self.engine.cancel(id));
            }
            Request::Cycle(f) => return Some(f),
            Request::Script(steps) => self.script = steps.into(),
        }
        None
    }

    /// The script's steps due before this cycle's step, applied as a client's calls would be
    /// (their events go to `~/command_status` like any other command's).
    fn run_script(&mut self) {
        while self.script.front().is_some_and(|s| s.cycle <= self.cycle) {
            let Some(step) = self.script.pop_front() else {
                break;
            };
            match self.engine.command(step.command) {
                Ok(reply) => {
                    if let Some(id) = (self.reply_id)(&reply) {
                        self.open.insert(id);
                        self.labels.insert(id, step.label);
                    }
                }
                Err(r) => {
                    tracing::warn!(
                        node = %self.config.name,
                        cycle = self.cycle,
                        error_id = r.error_id.0,
                        "script step rejected: {}",
                        r.message
                    );
                }
            }
        }
    }

    /// The current cycle's snapshot in the watch, taken unless one was already (the stream, a
    /// command's end and the end of a step all want the same one; the engine's snapshot is the
    /// costly part of a lockstep cycle).
    fn snapshot_current(&mut self) {
        self.snapshot_latest();
        if self.snap_tx.borrow().cycle != self.cycle {
            self.snap_tx.send_replace(self.latest.clone());
        }
    }

    /// `latest` of the current cycle, not (yet) in the watch (see `latest`).
    fn snapshot_latest(&mut self) {
        if self.latest.cycle != self.cycle {
            self.latest = self.build_snapshot();
        }
    }

    /// A fresh snapshot of the current cycle, into the watch.
    fn take_snapshot(&mut self) {
        self.latest = self.build_snapshot();
        self.snap_tx.send_replace(self.latest.clone());
    }

    fn build_snapshot(&mut self) -> Arc<Stamped<E::Snapshot>> {
        let sim_time = self.cycle as f64 * self.config.period;
        let ros_time_ns = self.clock.at(sim_time);
        // Stream mode: the oldest snapshot handed out is refilled in place once no one else
        // holds it (its memory is reused while warm; nothing allocated or freed per cycle).
        if let Some(mut old) = self.spare.pop_front() {
            if let Some(s) = Arc::get_mut(&mut old) {
                s.cycle = self.cycle;
                s.sim_time = sim_time;
                s.ros_time_ns = ros_time_ns;
                self.engine.snapshot_into(&mut s.state);
                self.spare.push_back(old.clone());
                return old;
            }
            // Still held (in flight, or kept by a reader): behind the others, so that one
            // snapshot held long does not stop the reuse of those after it.
            self.spare.push_back(old);
        }
        let fresh = Arc::new(Stamped {
            cycle: self.cycle,
            sim_time,
            ros_time_ns,
            state: self.engine.snapshot(),
        });
        if self.stream.is_some() && self.spare.len() < SPARE_SNAPSHOTS {
            self.spare.push_back(fresh.clone());
        }
        fresh
    }

    fn publish_stats(&mut self) {
        // try_lock: a reader holding the lock costs this cycle nothing; stats come next time.
        if let Ok(mut s) = self.stats.try_lock() {
            self.recorder.fill(&mut s, self.cycle);
        }
    }
}
