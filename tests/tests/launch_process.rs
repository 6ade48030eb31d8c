//! `motion_launch` as a process, as a supervisor sees it (issue 12 §5): the demo starts under
//! `ulimit -n 1024` and holds at most 256 open files; SIGINT/SIGTERM at any moment, during
//! start-up too, ends it with exit code 0 within 2 s.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use system_tests::{launcher_bin, require_netns, unique_domain, workspace};

/// The demo under `ulimit -n 1024`, its stderr lines on a channel.
struct Demo {
    child: std::process::Child,
    lines: mpsc::Receiver<String>,
}

impl Demo {
    /// The demo under `ulimit -n 1024` (through `sh`).
    fn start(domain: u16) -> Demo {
        let mut cmd = Command::new("sh");
        cmd.arg("-c")
            .arg("ulimit -n 1024 && exec \"$0\" \"$1\"")
            .arg(launcher_bin())
            .arg(workspace().join("launch-configs/demo.yaml"));
        Demo::spawn(cmd, domain)
    }

    /// The demo started directly (its pid is motion_launch's from the exec on).
    fn start_direct(domain: u16) -> Demo {
        let mut cmd = Command::new(launcher_bin());
        cmd.arg(workspace().join("launch-configs/demo.yaml"));
        Demo::spawn(cmd, domain)
    }

    fn spawn(mut cmd: Command, domain: u16) -> Demo {
        let mut child = cmd
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("RUST_LOG", "info,rustdds=error,ros2_client=error")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("motion_launch");
        let (tx, lines) = mpsc::channel();
        let err = child.stderr.take().unwrap();
        std::thread::spawn(move || {
            for l in BufReader::new(err).lines().map_while(Result::ok) {
                if tx.send(l).is_err() {
                    break;
                }
            }
        });
        Demo { child, lines }
    }

    /// Waits for the "node(s) running" line; panics with the log on exit or timeout.
    fn wait_running(&mut self, secs: f64) {
        let end = Instant::now() + Duration::from_secs_f64(secs);
        let mut log = Vec::new();
        while Instant::now() < end {
            match self.lines.recv_timeout(Duration::from_millis(50)) {
                Ok(l) if l.contains("node(s) running") => return,
                Ok(l) => log.push(l),
                Err(_) => {
                    if let Some(s) = self.child.try_wait().unwrap() {
                        panic!("demo exited with {s} during start:\n{}", log.join("\n"));
                    }
                }
            }
        }
        panic!("demo not running after {secs} s:\n{}", log.join("\n"));
    }

    /// Waits until the process blocks SIGINT and SIGTERM (its first instructions ran): the
    /// earliest moment a program can handle a signal; before it, the kernel's default applies
    /// while the dynamic loader runs.
    fn wait_signals_taken(&self) {
        let status = format!("/proc/{}/status", self.child.id());
        let end = Instant::now() + Duration::from_secs(5);
        while Instant::now() < end {
            let blocked = std::fs::read_to_string(&status)
                .ok()
                .and_then(|s| {
                    s.lines()
                        .find_map(|l| l.strip_prefix("SigBlk:"))
                        .and_then(|h| u64::from_str_radix(h.trim(), 16).ok())
                })
                .unwrap_or(0);
            let want = (1u64 << (2 - 1)) | (1u64 << (15 - 1)); // SIGINT, SIGTERM
            if blocked & want == want {
                return;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        panic!("motion_launch did not block SIGINT/SIGTERM within 5 s");
    }

    fn signal(&self, sig: &str) {
        let ok = Command::new("kill")
            .arg(format!("-{sig}"))
            .arg(self.child.id().to_string())
            .status()
            .unwrap()
            .success();
        assert!(ok, "kill -{sig}");
    }

    /// The exit status within `secs`, or None.
    fn exit_within(&mut self, secs: f64) -> Option<std::process::ExitStatus> {
        let end = Instant::now() + Duration::from_secs_f64(secs);
        while Instant::now() < end {
            if let Some(s) = self.child.try_wait().unwrap() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        None
    }
}

impl Drop for Demo {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn the_demo_runs_under_ulimit_1024_with_at_most_256_open_files() {
    require_netns();
    let mut demo = Demo::start(unique_domain() + 120);
    demo.wait_running(30.0);
    std::thread::sleep(Duration::from_millis(500));
    let fds = std::fs::read_dir(format!("/proc/{}/fd", demo.child.id()))
        .unwrap()
        .count();
    println!("demo: {fds} open files");
    assert!(fds <= 256, "the demo holds {fds} open files");
    demo.signal("TERM");
    let status = demo.exit_within(2.0).expect("exit within 2 s of SIGTERM");
    assert_eq!(status.code(), Some(0));
}

#[test]
fn sigterm_or_sigint_at_any_moment_exits_0_within_2_s() {
    require_netns();
    // Moments after the program's first instructions (the signal mask is in place), across
    // the start-up of the three nodes and after it.
    let moments = [0.0, 0.05, 0.15, 0.3, 0.5, 0.8, 1.2, 2.0];
    for (k, &at) in moments.iter().enumerate() {
        let sig = if k % 2 == 0 { "TERM" } else { "INT" };
        let mut demo = Demo::start_direct(unique_domain() + 120);
        demo.wait_signals_taken();
        std::thread::sleep(Duration::from_secs_f64(at));
        let sent = Instant::now();
        demo.signal(sig);
        let status = demo
            .exit_within(2.0)
            .unwrap_or_else(|| panic!("SIG{sig} {at} s after the start: still running 2 s later"));
        println!(
            "SIG{sig} at {at} s: exit {status} after {:?}",
            sent.elapsed()
        );
        assert_eq!(
            status.code(),
            Some(0),
            "SIG{sig} {at} s after the start: {status}"
        );
    }
}
