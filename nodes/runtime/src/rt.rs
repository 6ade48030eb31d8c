//! Real-time helpers for the cycle thread: absolute sleeps and scheduling hints.

use std::time::Instant;

/// The allocator of every binary of the suite (`#[global_allocator]` in each `main.rs`):
/// mimalloc. The cycle thread allocates each snapshot and the node's tasks free it; glibc's
/// malloc made the two threads take turns on the cycle thread's arena lock (a lockstep run of
/// 10 axes spent a third of its time in that lock: 205x real time with nothing recorded, 35x
/// with every topic; with mimalloc, whose frees from other threads need no lock, 340x and
/// 103x, the latter the recording's floor; `bench lockstep`).
pub use mimalloc::MiMalloc as Allocator;

/// Called once on the cycle thread: 1 ns timer slack (the Linux default of 50 µs would be
/// our jitter), and SCHED_FIFO when `MOTION_RT_PRIORITY` is set and permitted.
pub fn prepare_cycle_thread() {
    #[cfg(target_os = "linux")]
    unsafe {
        libc::prctl(libc::PR_SET_TIMERSLACK, 1 as libc::c_ulong, 0, 0, 0);
        if let Some(prio) = std::env::var("MOTION_RT_PRIORITY")
            .ok()
            .and_then(|p| p.parse::<i32>().ok())
        {
            let param = libc::sched_param {
                sched_priority: prio,
            };
            if libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) != 0 {
                tracing::warn!(
                    "SCHED_FIFO priority {prio} not permitted; running with normal scheduling"
                );
            }
        }
    }
}

/// Sleeps until `deadline - spin` on the monotonic clock (absolute: no drift from late
/// wake-ups), then busy-waits the last `spin` (the kernel's wake-up latency is the jitter
/// floor of a plain sleep; spinning trades CPU for it).
pub fn wait_until(deadline: Instant, spin: std::time::Duration) {
    if spin.is_zero() {
        return sleep_until(deadline);
    }
    if let Some(early) = deadline.checked_sub(spin) {
        sleep_until(early);
    }
    while Instant::now() < deadline {
        std::hint::spin_loop();
    }
}

/// Sleeps until `deadline` on the monotonic clock (absolute: no drift from late wake-ups).
pub fn sleep_until(deadline: Instant) {
    #[cfg(target_os = "linux")]
    {
        // Instant is CLOCK_MONOTONIC on Linux: convert the remaining time into an absolute
        // timespec of that clock.
        let now = Instant::now();
        if deadline <= now {
            return;
        }
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
        let rem = deadline - now;
        let mut sec = ts.tv_sec + rem.as_secs() as libc::time_t;
        let mut nsec = ts.tv_nsec + rem.subsec_nanos() as libc::c_long;
        if nsec >= 1_000_000_000 {
            sec += 1;
            nsec -= 1_000_000_000;
        }
        let target = libc::timespec {
            tv_sec: sec,
            tv_nsec: nsec,
        };
        loop {
            let r = unsafe {
                libc::clock_nanosleep(
                    libc::CLOCK_MONOTONIC,
                    libc::TIMER_ABSTIME,
                    &target,
                    std::ptr::null_mut(),
                )
            };
            if r != libc::EINTR {
                break;
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let now = Instant::now();
        if deadline > now {
            std::thread::sleep(deadline - now);
        }
    }
}
