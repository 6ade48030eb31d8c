//! The node's ROS time, which stamps every header (issue 13): the system clock when the node
//! runs in real time; the simulated time in lockstep (the node is the clock and publishes
//! `/clock` from 0); with `use_sim_time` the external `/clock` (rosgraph_msgs/Clock) that the
//! simulated cycles follow: the first `/clock` time seen is the origin, and ROS time is that
//! origin plus the simulated time of the cycle.

use std::sync::atomic::{AtomicI64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

/// Where a node's ROS time comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeSource {
    /// The system clock (free-running nodes).
    System,
    /// Origin + simulated time (lockstep: origin 0; `use_sim_time`: the first `/clock`).
    Simulated,
}

/// A node's ROS time, shared by its cycle (stamps snapshots) and its ROS side (sets the origin).
#[derive(Debug)]
pub struct RosClock {
    source: TimeSource,
    origin_ns: AtomicI64,
}

impl RosClock {
    /// A clock reading `source`, with origin 0.
    pub fn new(source: TimeSource) -> Self {
        RosClock {
            source,
            origin_ns: AtomicI64::new(0),
        }
    }

    /// The source.
    pub fn source(&self) -> TimeSource {
        self.source
    }

    /// ROS time [ns since the epoch] of a cycle at simulated time `sim_time` [s], read now.
    pub fn at(&self, sim_time: f64) -> i64 {
        match self.source {
            TimeSource::System => system_ns(),
            TimeSource::Simulated => {
                self.origin_ns.load(Ordering::Relaxed) + (sim_time * 1e9).round() as i64
            }
        }
    }

    /// Sets the simulated origin (`use_sim_time`: the first `/clock` time, minus the simulated
    /// time already run).
    pub fn set_origin(&self, ns: i64) {
        self.origin_ns.store(ns, Ordering::Relaxed);
    }
}

/// The system clock [ns since the epoch].
pub fn system_ns() -> i64 {
    match SystemTime::now().duration_since(UNIX_EPOCH) {
        Ok(d) => d.as_nanos() as i64,
        Err(_) => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn system_time_is_now_and_simulated_time_is_origin_plus_sim_time() {
        let sys = RosClock::new(TimeSource::System);
        let before = system_ns();
        let t = sys.at(123.0);
        assert!(t >= before && t - before < 1_000_000_000, "{t} vs {before}");
        // After 2020-01-01: a stamp RViz and TF accept.
        assert!(t > 1_577_836_800_000_000_000);
        let sim = RosClock::new(TimeSource::Simulated);
        assert_eq!(sim.at(1.5), 1_500_000_000);
        sim.set_origin(1_000_000_000_000);
        assert_eq!(sim.at(0.25), 1_000_250_000_000);
    }
}
