//! Latency percentiles: an HDR histogram of milliseconds, and the window of recent sets the
//! server reports in `Status`.

use std::sync::{Arc, Mutex};

use hdrhistogram::Histogram;
use protocol::LatencyMs;

/// Largest latency a histogram holds, µs: one hour (longer ones count as one hour).
const MAX_MICROS: u64 = 3_600_000_000;
/// Significant decimal digits kept: quantiles are within 0.1 % of the true sample.
const SIGNIFICANT_DIGITS: u8 = 3;

/// Latencies in milliseconds, recorded with microsecond resolution to 3 significant digits.
#[derive(Debug, Clone)]
pub struct LatencyHistogram(Histogram<u64>);

impl Default for LatencyHistogram {
    fn default() -> Self {
        Self(
            Histogram::new_with_bounds(1, MAX_MICROS, SIGNIFICANT_DIGITS)
                .expect("constant histogram bounds are valid"),
        )
    }
}

impl LatencyHistogram {
    /// An empty histogram.
    pub fn new() -> Self {
        Self::default()
    }

    /// A histogram of `samples` (ms).
    pub fn of(samples: impl IntoIterator<Item = f64>) -> Self {
        let mut histogram = Self::new();
        for millis in samples {
            histogram.record(millis);
        }
        histogram
    }

    /// Records one latency; a negative or non-finite one is ignored (a clock step, not a set).
    pub fn record(&mut self, millis: f64) {
        if millis.is_finite() && millis >= 0.0 {
            self.0.saturating_record((millis * 1000.0).round() as u64);
        }
    }

    /// Adds every sample of `other`.
    pub fn add(&mut self, other: &Self) {
        // Both have the same bounds, so adding cannot fail.
        let _ = self.0.add(&other.0);
    }

    /// Number of samples recorded.
    pub fn len(&self) -> u64 {
        self.0.len()
    }

    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The `q`-quantile (0 ≤ q ≤ 1) in ms; `None` when empty.
    pub fn quantile(&self, q: f64) -> Option<f64> {
        (!self.is_empty()).then(|| self.0.value_at_quantile(q.clamp(0.0, 1.0)) as f64 / 1000.0)
    }
}

/// The latencies of the most recent sets: between `per_window` and `2 × per_window` of them.
/// Samples go into the current histogram; when it is full it replaces the previous one, so old
/// figures fall out without keeping every sample.
#[derive(Debug, Clone)]
pub struct LatencyWindow {
    per_window: u64,
    current: LatencyHistogram,
    previous: LatencyHistogram,
}

impl LatencyWindow {
    /// A window of the last `per_window` to `2 × per_window` samples.
    pub fn new(per_window: u64) -> Self {
        Self {
            per_window: per_window.max(1),
            current: LatencyHistogram::new(),
            previous: LatencyHistogram::new(),
        }
    }

    /// Records one sample (ms).
    pub fn record(&mut self, millis: f64) {
        if self.current.len() >= self.per_window {
            self.previous = std::mem::take(&mut self.current);
        }
        self.current.record(millis);
    }

    /// The median and 99th percentile of the window, `None` before the first sample.
    pub fn summary(&self) -> LatencyMs {
        let mut both = self.previous.clone();
        both.add(&self.current);
        LatencyMs {
            p50: both.quantile(0.5),
            p99: both.quantile(0.99),
        }
    }
}

/// A [`LatencyWindow`] shared between the publisher, which records each set's latency when the
/// tracks it updated are put on the wire, and the engine, which reports it in `Status`.
#[derive(Debug, Clone)]
pub struct SharedLatency(Arc<Mutex<LatencyWindow>>);

impl SharedLatency {
    /// A shared window of the last `per_window` to `2 × per_window` samples.
    pub fn new(per_window: u64) -> Self {
        Self(Arc::new(Mutex::new(LatencyWindow::new(per_window))))
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
        self.0.lock().unwrap_or_else(|p| p.into_inner()).summary()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() <= 1e-3 * b)
    }

    #[test]
    fn quantiles_within_a_thousandth() {
        let histogram = LatencyHistogram::of((1..=100).map(f64::from));
        assert!(close(histogram.quantile(0.5), 50.0));
        assert!(close(histogram.quantile(0.99), 99.0));
        assert!(close(histogram.quantile(1.0), 100.0));
        assert_eq!(LatencyHistogram::new().quantile(0.5), None);
    }

    #[test]
    fn bad_samples_are_ignored() {
        let histogram = LatencyHistogram::of([f64::NAN, -1.0, f64::INFINITY, 2.0]);
        assert_eq!(histogram.len(), 1);
    }

    #[test]
    fn old_samples_fall_out_of_the_window() {
        let mut window = LatencyWindow::new(2);
        assert_eq!(window.summary().p50, None);
        for millis in [100.0, 100.0, 1.0, 1.0, 2.0] {
            window.record(millis);
        }
        // The 100 ms samples were two windows ago: gone.
        assert!(close(window.summary().p99, 2.0));
    }
}
