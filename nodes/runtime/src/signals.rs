//! SIGINT/SIGTERM from the first instruction (README "Operating it"): [`Shutdown::install`]
//! blocks both signals in the calling thread before any other thread exists (so every thread
//! inherits the mask) and takes them on a dedicated thread with `sigwait`. The launcher checks
//! [`Shutdown::requested`] between node starts and waits on [`Shutdown::wait`] while running,
//! then stops its nodes in order. A watchdog ends the process with code 0 if that orderly stop
//! has not finished [`GRACE`] after the signal (e.g. a node still starting), and a second
//! signal ends it at once: a stop request is always honoured within 2 s.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Longest an orderly stop may take after SIGINT/SIGTERM before the process just exits (0).
pub const GRACE: Duration = Duration::from_millis(1500);

/// The stop request of a process.
#[derive(Clone)]
pub struct Shutdown {
    requested: Arc<AtomicBool>,
    notify: Arc<tokio::sync::Notify>,
}

impl Shutdown {
    /// Blocks SIGINT and SIGTERM for this thread and every thread it creates later, and starts
    /// the thread that receives them. Call first thing in `main`.
    pub fn install(program: &'static str) -> Shutdown {
        let s = Shutdown {
            requested: Arc::new(AtomicBool::new(false)),
            notify: Arc::new(tokio::sync::Notify::new()),
        };
        // SAFETY: plain libc signal-set calls on a local set; no handler is installed.
        let set = unsafe {
            let mut set: libc::sigset_t = std::mem::zeroed();
            libc::sigemptyset(&mut set);
            libc::sigaddset(&mut set, libc::SIGINT);
            libc::sigaddset(&mut set, libc::SIGTERM);
            libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
            set
        };
        let t = s.clone();
        let spawned = std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || loop {
                let mut sig: libc::c_int = 0;
                // SAFETY: `set` is a valid signal set; `sig` is a valid out pointer.
                if unsafe { libc::sigwait(&set, &mut sig) } != 0 {
                    continue;
                }
                if t.requested.swap(true, Ordering::SeqCst) {
                    // A second signal: the user insists.
                    std::process::exit(0);
                }
                tracing::info!("{program}: signal {sig} received, stopping");
                t.notify.notify_one();
                std::thread::spawn(move || {
                    std::thread::sleep(GRACE);
                    eprintln!(
                        "{program}: the orderly stop took longer than {} ms; exiting",
                        GRACE.as_millis()
                    );
                    std::process::exit(0);
                });
            });
        if let Err(e) = spawned {
            eprintln!("{program}: cannot start the signal thread: {e}");
        }
        s
    }

    /// True once SIGINT or SIGTERM arrived.
    pub fn requested(&self) -> bool {
        self.requested.load(Ordering::SeqCst)
    }

    /// Waits for SIGINT or SIGTERM (returns at once if one already arrived).
    pub async fn wait(&self) {
        while !self.requested() {
            self.notify.notified().await;
        }
    }
}
