//! Latency percentiles over a sliding window of recent samples.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

use protocol::LatencyMs;

/// Keeps the last `capacity` latency samples (milliseconds) and answers percentiles.
#[derive(Debug, Clone)]
pub struct LatencyWindow {
    capacity: usize,
    samples: VecDeque<f64>,
}

impl LatencyWindow {
    /// A window of the last `capacity` samples.
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity: capacity.max(1),
            samples: VecDeque::with_capacity(capacity.max(1)),
        }
    }

    /// Records one sample; the oldest falls out when the window is full.
    pub fn record(&mut self, millis: f64) {
        if !millis.is_finite() {
            return;
        }
        if self.samples.len() == self.capacity {
            self.samples.pop_front();
        }
        self.samples.push_back(millis);
    }

    /// Number of samples held.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// True when no sample was recorded.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The `q`-quantile (0 ≤ q ≤ 1, nearest rank) of the held samples; 0 when empty.
    pub fn percentile(&self, q: f64) -> f64 {
        if self.samples.is_empty() {
            return 0.0;
        }
        let mut sorted: Vec<f64> = self.samples.iter().copied().collect();
        sorted.sort_by(f64::total_cmp);
        let rank = (q.clamp(0.0, 1.0) * sorted.len() as f64).ceil() as usize;
        sorted[rank.saturating_sub(1).min(sorted.len() - 1)]
    }
}

/// A [`LatencyWindow`] shared between the publisher, which records each set's latency when the
/// tracks it updated are put on the wire, and the engine, which reports it in `Status`.
#[derive(Debug, Clone)]
pub struct SharedLatency(Arc<Mutex<LatencyWindow>>);

impl SharedLatency {
    /// A shared window of the last `capacity` samples.
    pub fn new(capacity: usize) -> Self {
        Self(Arc::new(Mutex::new(LatencyWindow::new(capacity))))
    }

    /// Records the latency of sets that arrived at `arrivals` and were published at `now`
    /// (seconds on one clock).
    pub fn record_published(&self, arrivals: &[f64], now: f64) {
        let mut window = self.0.lock().unwrap_or_else(|p| p.into_inner());
        for arrived in arrivals {
            window.record((now - arrived).max(0.0) * 1000.0);
        }
    }

    /// The median and 99th percentile, `None` before the first sample.
    pub fn summary(&self) -> LatencyMs {
        let window = self.0.lock().unwrap_or_else(|p| p.into_inner());
        LatencyMs {
            p50: (!window.is_empty()).then(|| window.percentile(0.5)),
            p99: (!window.is_empty()).then(|| window.percentile(0.99)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_percentiles() {
        let mut window = LatencyWindow::new(100);
        for i in 1..=100 {
            window.record(i as f64);
        }
        assert_eq!(window.percentile(0.5), 50.0);
        assert_eq!(window.percentile(0.99), 99.0);
        assert_eq!(window.percentile(1.0), 100.0);
    }

    #[test]
    fn old_samples_fall_out_and_empty_is_zero() {
        let mut window = LatencyWindow::new(2);
        assert_eq!(window.percentile(0.5), 0.0);
        window.record(100.0);
        window.record(1.0);
        window.record(2.0);
        window.record(f64::NAN);
        assert_eq!(window.len(), 2);
        assert_eq!(window.percentile(1.0), 2.0);
    }
}
