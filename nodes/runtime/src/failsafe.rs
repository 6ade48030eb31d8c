//! Fail-safe (README "Operating it"): a panic in any thread of a node process (DDS, tokio,
//! cycle) brings every axis, mover and pick-and-place group to a controlled stop
//! ([`motion_core::Engine::fail_safe_stop`]), then ends the process with [`EXIT_CODE`] and one
//! log line, so that a supervisor (systemd, ros2 launch `respawn`) sees it and restarts it.
//! A node whose ROS side is gone must not keep moving silently.
//!
//! [`install`] sets the panic hook; binaries call it first thing (tests that run nodes
//! in-process do not, so a failing test does not end the test process). Each controller
//! registers its cycle thread; on a panic the hook wakes every cycle thread, each stops its
//! engine at its own period and reports back, and the hook waits at most [`STOP_WAIT`].

use std::cell::Cell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// Exit code after a fail-safe stop (EX_SOFTWARE: an internal software error).
pub const EXIT_CODE: i32 = 70;

/// Longest the hook waits for the cycles to bring everything to rest.
pub const STOP_WAIT: Duration = Duration::from_secs(10);

/// How long the state topics keep publishing after the stop, before the process exits.
pub const LINGER: Duration = Duration::from_millis(250);

static TRIGGERED: AtomicBool = AtomicBool::new(false);

thread_local! {
    /// The controller whose cycle runs on this thread (its engine is lost if it panics).
    static CYCLE_OF: Cell<Option<usize>> = const { Cell::new(None) };
}

/// One registered cycle: its name, how to wake it, and whether its stop has ended.
#[derive(Clone)]
struct Entry {
    id: usize,
    name: String,
    wake: Arc<dyn Fn() + Send + Sync>,
    done: Arc<AtomicBool>,
}

fn registry() -> &'static Mutex<Vec<Entry>> {
    static REG: OnceLock<Mutex<Vec<Entry>>> = OnceLock::new();
    REG.get_or_init(|| Mutex::new(Vec::new()))
}

/// True once a panic has started the fail-safe stop: cycles stop their engines and refuse
/// new commands.
pub fn triggered() -> bool {
    TRIGGERED.load(Ordering::Relaxed)
}

/// A cycle's registration; unregisters when dropped (the cycle thread ended).
pub(crate) struct Registration {
    id: usize,
    /// Set by the cycle when its engine is at rest after the fail-safe stop.
    pub done: Arc<AtomicBool>,
}

impl Registration {
    /// Marks the calling thread as this cycle's thread.
    pub fn enter_thread(&self) {
        CYCLE_OF.with(|c| c.set(Some(self.id)));
    }
}

impl Drop for Registration {
    fn drop(&mut self) {
        let mut reg = registry().lock().unwrap_or_else(|e| e.into_inner());
        reg.retain(|e| e.id != self.id);
    }
}

/// Registers a cycle (`wake` interrupts its idle wait in lockstep mode).
pub(crate) fn register(name: &str, wake: Arc<dyn Fn() + Send + Sync>) -> Registration {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(1);
    let id = NEXT.fetch_add(1, Ordering::Relaxed);
    let done = Arc::new(AtomicBool::new(false));
    registry()
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(Entry {
            id,
            name: name.to_string(),
            wake,
            done: done.clone(),
        });
    Registration { id, done }
}

/// Installs the panic hook of a node process (`program` names it in the log line).
pub fn install(program: &'static str) {
    std::panic::set_hook(Box::new(move |info| on_panic(program, info)));
}

fn on_panic(program: &str, info: &std::panic::PanicHookInfo<'_>) {
    let thread = std::thread::current();
    let thread = thread.name().unwrap_or("unnamed").to_string();
    let location = info
        .location()
        .map(|l| format!("{}:{}", l.file(), l.line()))
        .unwrap_or_default();
    let payload = info.payload();
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_default();
    if TRIGGERED.swap(true, Ordering::SeqCst) {
        // Already stopping: a second panic changes nothing (its thread just ends).
        return;
    }
    let started = Instant::now();
    let own = CYCLE_OF.with(|c| c.get());
    let entries: Vec<Entry> = registry().lock().unwrap_or_else(|e| e.into_inner()).clone();
    for e in &entries {
        (e.wake)();
    }
    let mut stopped = Vec::new();
    let mut lost = Vec::new();
    for Entry { id, name, done, .. } in &entries {
        if Some(*id) == own {
            lost.push(format!("{name} (its cycle panicked)"));
            continue;
        }
        while !done.load(Ordering::SeqCst) && started.elapsed() < STOP_WAIT {
            std::thread::sleep(Duration::from_millis(2));
        }
        if done.load(Ordering::SeqCst) {
            stopped.push(name.clone());
        } else {
            lost.push(format!(
                "{name} (not at rest after {} s)",
                STOP_WAIT.as_secs()
            ));
        }
    }
    let mut outcome = format!(
        "stopped at rest: [{}] in {:.3} s",
        stopped.join(", "),
        started.elapsed().as_secs_f64()
    );
    if !lost.is_empty() {
        outcome.push_str(&format!("; not stopped: [{}]", lost.join(", ")));
    }
    // Let the state topics carry the final state (at rest) before the participants vanish.
    std::thread::sleep(LINGER);
    // One line, on stderr (and so in the supervisor's journal).
    eprintln!(
        "{program}: FATAL: panic in thread '{thread}' at {location}: {message}; fail-safe: {outcome}; exiting with code {EXIT_CODE}"
    );
    std::process::exit(EXIT_CODE);
}
