//! A recording whose file cannot take its bytes (`/dev/full`: every write fails with "no
//! space left on device") stops recording with a clear error at the end and never holds the
//! publishers up, not even a lossless one (a lockstep node's state stream). Own test binary:
//! a process records once.

use motion_msgs::deps::rosgraph_msgs::msg::Clock;
use motion_runtime::record::{self, RecordedTopic};
use motion_runtime::shell::stamp_ns;
use std::time::{Duration, Instant};

#[test]
fn a_full_disk_ends_the_recording_with_an_error_and_no_publisher_waits() {
    record::start(
        std::path::Path::new("/dev/full"),
        record::Topics::all(),
        record::Compression::None,
    )
    .expect("the header is buffered: the file opens");
    let lossless = RecordedTopic::new("/lossless", "rosgraph_msgs/msg/Clock").lossless();
    // Four times what the recording's buffers hold: were the writer stuck, this would wait.
    let n = (4 * record::BATCHES * record::BATCH / 28) as i64;
    let t0 = Instant::now();
    for i in 0..n {
        lossless.take(&Clock { clock: stamp_ns(i) }, i);
    }
    assert!(
        t0.elapsed() < Duration::from_secs(20),
        "publishing took {:?}",
        t0.elapsed()
    );
    let err = record::finish()
        .expect("recording on")
        .expect_err("nothing could be written");
    assert!(
        err.to_string().contains("No space left on device"),
        "unclear error: {err}"
    );
}
