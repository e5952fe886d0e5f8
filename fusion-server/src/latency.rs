//! Latency percentiles over a sliding window of recent samples.

use std::collections::VecDeque;

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
