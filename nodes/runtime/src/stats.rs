//! Per-cycle execution time and wake-up jitter statistics (no allocation in the cycle).

use crate::cycle::ClockMode;
use std::time::Duration;

/// Bucket width of the histograms [s] (1 µs).
const BUCKET: f64 = 1e-6;
/// Buckets; values beyond the last land in it (max is tracked exactly).
const BUCKETS: usize = 5000;

/// Statistics of a controller since start, as published on `/diagnostics`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CycleStats {
    /// Node name.
    pub node: String,
    /// Nominal period [s].
    pub period: f64,
    /// True in lockstep mode (jitter is then meaningless and reported as 0).
    pub lockstep: bool,
    /// Cycles run.
    pub cycles: u64,
    /// Cycles that ended after the next deadline.
    pub overruns: u64,
    /// Execution time per cycle: mean, 99th percentile, maximum [s].
    pub exec_mean: f64,
    /// See `exec_mean`.
    pub exec_p99: f64,
    /// See `exec_mean`.
    pub exec_max: f64,
    /// Wake-up lateness against the absolute deadline: mean, p50, p99, maximum [s].
    pub jitter_mean: f64,
    /// See `jitter_mean`.
    pub jitter_p50: f64,
    /// See `jitter_mean`.
    pub jitter_p99: f64,
    /// See `jitter_mean`.
    pub jitter_max: f64,
    /// Cycles per 1 µs bucket of execution time from 0 (the last bucket also holds all longer
    /// ones); trailing empty buckets left out.
    pub exec_histogram: Vec<u32>,
    /// The same for the wake-up lateness.
    pub jitter_histogram: Vec<u32>,
}

impl CycleStats {
    /// Empty statistics for a node.
    pub fn new(node: &str, period: f64, mode: ClockMode) -> Self {
        CycleStats {
            node: node.to_string(),
            period,
            lockstep: mode == ClockMode::Lockstep,
            ..Default::default()
        }
    }
}

/// A fixed-size histogram with an exact maximum and sum.
pub struct Histogram {
    counts: Box<[u32; BUCKETS]>,
    n: u64,
    sum: f64,
    max: f64,
}

impl Default for Histogram {
    fn default() -> Self {
        Histogram {
            counts: Box::new([0; BUCKETS]),
            n: 0,
            sum: 0.0,
            max: 0.0,
        }
    }
}

impl Histogram {
    /// Adds one sample [s].
    pub fn add(&mut self, v: f64) {
        let i = ((v / BUCKET) as usize).min(BUCKETS - 1);
        self.counts[i] = self.counts[i].saturating_add(1);
        self.n += 1;
        self.sum += v;
        if v > self.max {
            self.max = v;
        }
    }

    /// Samples added.
    pub fn len(&self) -> u64 {
        self.n
    }

    /// True when no sample was added.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Mean [s].
    pub fn mean(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.sum / self.n as f64
        }
    }

    /// Maximum [s].
    pub fn max(&self) -> f64 {
        self.max
    }

    /// The bucket counts up to the last non-empty one, into `out` (which keeps its capacity:
    /// no allocation once it has grown).
    pub fn counts_into(&self, out: &mut Vec<u32>) {
        let end = self
            .counts
            .iter()
            .rposition(|&c| c > 0)
            .map_or(0, |i| i + 1);
        out.clear();
        out.extend_from_slice(&self.counts[..end]);
    }

    /// The q-quantile (0..1), as the upper edge of its bucket, never above the maximum.
    pub fn quantile(&self, q: f64) -> f64 {
        if self.n == 0 {
            return 0.0;
        }
        let rank = ((q * self.n as f64).ceil() as u64).max(1);
        let mut seen = 0u64;
        for (i, c) in self.counts.iter().enumerate() {
            seen += u64::from(*c);
            if seen >= rank {
                if i == BUCKETS - 1 {
                    return self.max; // overflow bucket: its only exact value is the maximum
                }
                return ((i + 1) as f64 * BUCKET).min(self.max);
            }
        }
        self.max
    }
}

/// Records cycles inside the controller thread.
pub struct StatsRecorder {
    exec: Histogram,
    jitter: Histogram,
    overruns: u64,
    publish_every: u64,
}

impl StatsRecorder {
    /// A recorder that publishes about every 100 ms of cycles.
    pub fn new(period: f64) -> Self {
        StatsRecorder {
            exec: Histogram::default(),
            jitter: Histogram::default(),
            overruns: 0,
            publish_every: ((0.1 / period).round() as u64).max(1),
        }
    }

    /// One cycle: its execution time, its wake-up lateness, and whether it overran.
    pub fn record(&mut self, exec: Duration, lateness: Duration, overrun: bool) {
        self.exec.add(exec.as_secs_f64());
        self.jitter.add(lateness.as_secs_f64());
        if overrun {
            self.overruns += 1;
        }
    }

    /// True when the shared copy should be refreshed after `cycle`.
    pub fn due_for_publish(&self, cycle: u64) -> bool {
        cycle.is_multiple_of(self.publish_every)
    }

    /// Writes the summary into the shared statistics.
    pub fn fill(&self, s: &mut CycleStats, cycles: u64) {
        s.cycles = cycles;
        s.overruns = self.overruns;
        s.exec_mean = self.exec.mean();
        s.exec_p99 = self.exec.quantile(0.99);
        s.exec_max = self.exec.max();
        s.jitter_mean = self.jitter.mean();
        s.jitter_p50 = self.jitter.quantile(0.5);
        s.jitter_p99 = self.jitter.quantile(0.99);
        s.jitter_max = self.jitter.max();
        self.exec.counts_into(&mut s.exec_histogram);
        self.jitter.counts_into(&mut s.jitter_histogram);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_of_a_known_distribution() {
        let mut h = Histogram::default();
        for i in 0..1000 {
            h.add(i as f64 * 1e-6 + 0.5e-6);
        }
        assert_eq!(h.len(), 1000);
        assert!(
            (h.quantile(0.5) - 500e-6).abs() < 1.5e-6,
            "{}",
            h.quantile(0.5)
        );
        assert!(
            (h.quantile(0.99) - 990e-6).abs() < 1.5e-6,
            "{}",
            h.quantile(0.99)
        );
        assert!((h.max() - 999.5e-6).abs() < 1e-12);
        assert!((h.mean() - 500e-6).abs() < 1e-9);
    }

    #[test]
    fn histogram_counts_end_at_the_last_sample() {
        let mut h = Histogram::default();
        for v in [0.2e-6, 0.7e-6, 3.5e-6] {
            h.add(v);
        }
        let mut out = vec![9; 10];
        h.counts_into(&mut out);
        assert_eq!(out, [2, 0, 0, 1]);
        h.add(1.0); // beyond the last bucket: counted there
        h.counts_into(&mut out);
        assert_eq!(out.len(), BUCKETS);
        assert_eq!(out[BUCKETS - 1], 1);
    }

    #[test]
    fn overflow_bucket_keeps_exact_max() {
        let mut h = Histogram::default();
        h.add(0.5);
        assert_eq!(h.quantile(0.99), 0.5);
    }
}
