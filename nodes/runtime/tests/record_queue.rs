//! The recording's buffers (`motion_runtime::record`): while its writer is held up, a real-time
//! topic drops what finds them full (counted) and never waits, while a lossless topic (a
//! lockstep node's state stream) waits and loses nothing. The writer is held up by recording
//! into a FIFO whose reader starts reading only after a while. Own test binary: a process
//! records once.

use motion_msgs::deps::rosgraph_msgs::msg::Clock;
use motion_runtime::record::{self, RecordedTopic};
use motion_runtime::shell::stamp_ns;
use std::io::Read;
use std::time::{Duration, Instant};

fn clock(ns: i64) -> Clock {
    Clock {
        clock: stamp_ns(ns),
    }
}

#[test]
fn a_lossless_topic_waits_for_the_writer_a_real_time_topic_drops() {
    let dir = std::env::temp_dir().join(format!("record_queue_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("run.mcap");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0, "mkfifo");
    // The reader opens the FIFO (so the writer's open returns), then reads nothing until
    // `release`, so the writer blocks on the full pipe and the queue fills.
    let hold = Duration::from_secs(3);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut f = std::fs::File::open(&fifo).unwrap();
            std::thread::sleep(hold);
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes).unwrap();
            bytes
        })
    };
    // Uncompressed: compressed, the clock messages would hardly fill the pipe.
    record::start(&fifo, record::Topics::all(), record::Compression::None).expect("recording");
    let lossy = RecordedTopic::new("/lossy", "rosgraph_msgs/msg/Clock");
    let lossless = RecordedTopic::new("/lossless", "rosgraph_msgs/msg/Clock").lossless();
    // Twice what the recording's buffers hold (a clock message takes 12 bytes and 16 of
    // framing), far more than the writer's chunk and the pipe hold.
    let n = (2 * record::BATCHES * record::BATCH / 28) as i64;
    let t0 = Instant::now();
    for i in 0..n {
        lossy.take(&clock(i), i);
    }
    let lossy_took = t0.elapsed();
    assert!(
        lossy_took < hold,
        "the real-time topic waited for the writer ({lossy_took:?})"
    );
    for i in 0..n {
        lossless.take(&clock(i), i);
    }
    assert!(
        t0.elapsed() >= hold - Duration::from_millis(100),
        "the lossless topic did not wait for the held-up writer"
    );
    let (written, dropped) = record::finish().expect("recording on").expect("closed");
    // After the end, a lossless topic neither waits nor writes, and a second end is an error.
    let after = Instant::now();
    for i in 0..1000 {
        lossless.take(&clock(n + i), n + i);
    }
    assert!(
        after.elapsed() < Duration::from_secs(1),
        "waited after the end"
    );
    assert!(record::finish().expect("recording on").is_err());
    let bytes = reader.join().unwrap();
    let mut count = std::collections::HashMap::<String, i64>::new();
    let mut last = -1;
    for m in mcap::MessageStream::new(&bytes).expect("mcap") {
        let m = m.expect("message");
        if m.channel.topic == "/lossless" {
            // Every message, in order.
            assert_eq!(m.log_time as i64, last + 1);
            last = m.log_time as i64;
        }
        *count.entry(m.channel.topic.clone()).or_default() += 1;
    }
    assert_eq!(
        count.get("/lossless"),
        Some(&n),
        "lossless topic lost messages"
    );
    let lossy_n = count.get("/lossy").copied().unwrap_or(0);
    assert!(dropped > 0, "nothing dropped: the writer was not held up");
    assert_eq!(
        lossy_n + dropped as i64,
        n,
        "every lossy message written or counted"
    );
    assert_eq!(written as i64, n + lossy_n);
    let _ = std::fs::remove_dir_all(&dir);
}
